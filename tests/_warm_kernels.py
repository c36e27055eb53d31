"""Compile the numba kernels that tests on BOTH xdist workers need, once, before the workers start.

Why: the kernels are ``cache=True`` (frictionkit._jit). In a clean clone (CI: no cache) two xdist
workers that reach the same kernel at about the same time both compile it — measured in a clean
clone at 23584bd: ``kernels.machine.run`` 51 s + 54 s CPU and ``kernels.lugre.lugre_force``
40 s + 38 s CPU, each compiled on both workers with the same signature. tests/conftest.py runs this
script on the xdist controller before the workers start (jobs split over up to 2 processes); the
workers then load the kernels from numba's cache. Each job calls the public API at a tiny size, so
the signatures are the ones the package's own callers produce (a job that no longer matches the
tests only costs its compile, never a wrong result). A failing job prints one line and is skipped:
the warm-up never decides a test's outcome.

Usage: ``python tests/_warm_kernels.py JOB [JOB ...]`` (``--list``: the jobs and their weights).
"""

from __future__ import annotations

import sys
import time
import traceback

import numpy as np

#: job -> cold-compile CPU seconds, for splitting the jobs over processes (longest first); measured
#: in an empty NUMBA_CACHE_DIR, split as :func:`split` does (machine load 9-17, so +-15 %): the two
#: processes [lugre sens gmsbatch] and [machine axis gms] took 108.8 / 107.1 s CPU.
#: Kernels compiled by one xdist group only are left out: they compile once anyway (kernels.batch's
#: fixed-step kernel: test_batch.py's group, which the two other tests calling it join). "sens" and
#: the batch kernels of "lugre"/"gms" (``simulate_batch``, adaptive: the fits' batched start costs):
#: reached by identification tests on both workers (clean clone at 327ee71: ``lugre_force_sens``
#: 36.7 s CPU in the sdss_axes group's setup). The batch kernels call the scalar kernel of their
#: job, which is why they run in its process (typed once there, not compiled beside it); the GMS
#: one types its own specialisation of ``_drive``, so it is a job of its own.
WEIGHTS = {
    "machine": 55.0,  # kernels.machine.run (multi-DOF loop)
    "lugre": 42.0,  # kernels.lugre.lugre_force (+ lugre_motion, lugre_batch_sse 4 s)
    "gms": 37.0,  # kernels.gms.gms_force (+ gms_motion, sensitivity_gms.gms_motion_sens)
    "gmsbatch": 35.0,  # kernels.gms.gms_force_batch_sse (parallel; its own _drive specialisation)
    "axis": 17.0,  # kernels.machine_axis.run_axis (one-DOF fast path, static law)
    "sens": 32.0,  # kernels.sensitivity.lugre_force_sens, lugre_motion_sens
}


def _t(T: float, dt: float) -> np.ndarray:
    return np.arange(int(round(T / dt)) + 1) * dt


def job_machine() -> None:
    """Multi-DOF general loop: two DOFs coupled by a spring, LuGre contact."""
    import frictionkit as fk
    from frictionkit.machines import Machine, simulate_machine

    m = Machine("warm two-mass")
    a = m.dof("a", inertia=1.0)
    b = m.dof("b", inertia=1.0)
    m.spring(a, b, k=1e4)
    m.damper(a, b, c=10.0)
    m.friction("contact", b, law=fk.LuGre(fk.Stribeck(Fc=1.0, Fs=1.5, vs=1e-3), sigma0=1e5, sigma1=300.0))
    m.actuator("u", a)
    dt = 1e-3
    simulate_machine(m, dt=dt, inputs={"u": 2.0 * np.sin(np.pi * _t(0.05, dt))})


def job_lugre() -> None:
    """Force- and motion-driven LuGre (kernels.lugre.lugre_force, lugre_motion), batch (lugre_batch_sse)."""
    import frictionkit as fk

    law = fk.LuGre(fk.Stribeck(Fc=1.0, Fs=1.5, vs=1e-3, sigma2=0.4), sigma0=1e5, sigma1=300.0)
    dt = 1e-3
    t = _t(0.05, dt)
    fk.simulate(law, dt=dt, plant=fk.Mass(1.0), force=2.0 * np.sin(np.pi * t))
    fk.simulate(law, dt=dt, position=1e-4 * np.sin(np.pi * t))
    _batch(law)


def job_gms() -> None:
    """Force- and motion-driven GMS (kernels.gms.gms_force, gms_motion), the motion fit's exact Jacobian
    (kernels.sensitivity_gms.gms_motion_sens)."""
    import frictionkit as fk

    law = fk.GMS(fk.Stribeck(Fc=1.0, Fs=1.5, vs=1e-3, sigma2=0.4), k=[1e4, 1e5], xi=[0.5, 0.5], C=20.0)
    dt = 1e-3
    t = _t(0.05, dt)
    fk.simulate(law, dt=dt, plant=fk.Mass(1.0), force=2.0 * np.sin(np.pi * t))
    fk.simulate(law, dt=dt, position=1e-4 * np.sin(np.pi * t))
    _fit_motion(law)


def job_gmsbatch() -> None:
    """``simulate_batch`` of GMS laws (kernels.gms.gms_force_batch_sse)."""
    import frictionkit as fk

    _batch(fk.GMS(fk.Stribeck(Fc=1.0, Fs=1.5, vs=1e-3, sigma2=0.4), k=[1e4, 1e5], xi=[0.5, 0.5], C=20.0))


def _batch(law) -> None:
    """``simulate_batch`` (adaptive) of two copies of ``law``: kernels.lugre.lugre_batch_sse or
    kernels.gms.gms_force_batch_sse (parallel). No other kernel: the target is a plain sine."""
    import frictionkit as fk

    t, u, _ = _records()
    fk.simulate_batch([law, law], masses=1.0, force=u, dt=float(t[1]), target=1e-3 * u, compare="v")


def _fit_motion(law) -> None:
    """An exact-Jacobian motion-drive fit of ``law`` (kernels.sensitivity / sensitivity_gms)."""
    import frictionkit as fk
    from frictionkit.identify import fit_motion_error

    t, _, x = _records()
    F = fk.simulate(law, position=x, dt=float(t[1])).friction
    free = ("k",) if isinstance(law, fk.GMS) else ("sigma0", "sigma1")
    fit_motion_error({"t": t, "x": x, "F": F}, law, free=free, starts=1, refine=1, profile=False,
                     jacobian="sensitivity")


def job_axis() -> None:
    """One-DOF fast path, Coulomb-viscous law and an input-array actuator (kernels.machine_axis.run_axis)."""
    import frictionkit as fk
    from frictionkit.machines import Machine, simulate_machine

    m = Machine("warm axis")
    x = m.dof("x", inertia=1.0)
    m.friction("contact", x, law=fk.CoulombViscous(Fc=1.0, sigma2=0.4))
    m.actuator("u", x)
    dt = 1e-3
    simulate_machine(m, dt=dt, inputs={"u": 2.0 * np.sin(np.pi * _t(0.05, dt))})


def _records():
    """A short record: times, a force input (t, u) and a position input (x)."""
    t = _t(0.3, 1e-3)
    return t, 2.0 * np.sin(2 * np.pi * 5.0 * t), 2e-5 * np.sin(2 * np.pi * 5.0 * t)


def job_sens() -> None:
    """Exact Jacobians of the LuGre fits, force and motion drive (kernels.sensitivity)."""
    import frictionkit as fk
    from frictionkit.identify.output_error import fit_output_error

    law = fk.LuGre(fk.Stribeck(Fc=1.0, Fs=1.5, vs=1e-3, sigma2=0.4), sigma0=1e5, sigma1=300.0)
    t, u, _ = _records()
    v = fk.simulate(law, dt=float(t[1]), plant=fk.Mass(1.0), force=u).v
    fit_output_error({"t": t, "F": u, "v": v}, law, free=("sigma0", "sigma1"), inertia=1.0, jacobian="sensitivity")
    _fit_motion(law)


JOBS = {name: globals()[f"job_{name}"] for name in WEIGHTS}


#: job -> the job that must run before it in the same process (it calls that job's kernels, which
#: it would otherwise compile a second time beside it, before the cache has them)
AFTER = {"sens": "lugre", "axis": "machine"}


def split(jobs: list[str], n: int) -> list[list[str]]:
    """Longest-first greedy split of ``jobs`` over ``n`` processes by :data:`WEIGHTS`; a job of
    :data:`AFTER` goes right after its prerequisite (when that is in ``jobs``)."""
    units = [[j] + [d for d, a in AFTER.items() if a == j and d in jobs] for j in jobs
             if not (j in AFTER and AFTER[j] in jobs)]
    bins: list[list[str]] = [[] for _ in range(max(1, n))]
    load = [0.0] * len(bins)
    for u in sorted(units, key=lambda u: -sum(WEIGHTS[j] for j in u)):
        i = load.index(min(load))
        bins[i] += u
        load[i] += sum(WEIGHTS[j] for j in u)
    return [b for b in bins if b]


def main(argv: list[str]) -> int:
    if argv[:1] == ["--list"]:
        for name, w in WEIGHTS.items():
            print(f"{name}\t{w:g}\t{JOBS[name].__doc__.splitlines()[0]}")
        return 0
    for name in argv:
        t0 = time.process_time()
        try:
            JOBS[name]()
        except Exception:  # never decide a test's outcome: the tests compile what is missing
            last = traceback.format_exc().strip().splitlines()[-1]
            print(f"warm-up job {name!r} failed (tests will compile it): {last}", file=sys.stderr)
            continue
        print(f"warm-up {name}: {time.process_time() - t0:.1f} s CPU", file=sys.stderr)
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
