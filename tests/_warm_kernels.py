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
#: one job per process in an empty NUMBA_CACHE_DIR (machine load ~12): 2 processes take 69 / 73 s.
#: Kernels compiled by one xdist group only (kernels.batch's parallel kernel: tests/kernels/test_batch.py)
#: are left out: they compile once anyway.
WEIGHTS = {
    "machine": 51.0,  # kernels.machine.run (multi-DOF loop)
    "lugre": 38.0,  # kernels.lugre.lugre_force (+ lugre_motion)
    "gms": 35.0,  # kernels.gms.gms_force (+ gms_motion)
    "axis": 18.0,  # kernels.machine_axis.run_axis (one-DOF fast path, static law)
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
    """Force- and motion-driven LuGre (kernels.lugre.lugre_force, lugre_motion)."""
    import frictionkit as fk

    law = fk.LuGre(fk.Stribeck(Fc=1.0, Fs=1.5, vs=1e-3, sigma2=0.4), sigma0=1e5, sigma1=300.0)
    dt = 1e-3
    t = _t(0.05, dt)
    fk.simulate(law, dt=dt, plant=fk.Mass(1.0), force=2.0 * np.sin(np.pi * t))
    fk.simulate(law, dt=dt, position=1e-4 * np.sin(np.pi * t))


def job_gms() -> None:
    """Force- and motion-driven GMS (kernels.gms.gms_force, gms_motion)."""
    import frictionkit as fk

    law = fk.GMS(fk.Stribeck(Fc=1.0, Fs=1.5, vs=1e-3, sigma2=0.4), k=[1e4, 1e5], xi=[0.5, 0.5], C=20.0)
    dt = 1e-3
    t = _t(0.05, dt)
    fk.simulate(law, dt=dt, plant=fk.Mass(1.0), force=2.0 * np.sin(np.pi * t))
    fk.simulate(law, dt=dt, position=1e-4 * np.sin(np.pi * t))


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


JOBS = {name: globals()[f"job_{name}"] for name in WEIGHTS}


def split(jobs: list[str], n: int) -> list[list[str]]:
    """Longest-first greedy split of ``jobs`` over ``n`` processes by :data:`WEIGHTS`."""
    bins: list[list[str]] = [[] for _ in range(max(1, n))]
    load = [0.0] * len(bins)
    for j in sorted(jobs, key=lambda j: -WEIGHTS[j]):
        i = load.index(min(load))
        bins[i].append(j)
        load[i] += WEIGHTS[j]
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
