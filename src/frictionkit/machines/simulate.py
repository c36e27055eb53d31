"""Pack a :class:`Machine` for the compiled loop, run it, and return a :class:`MachineResult`."""

from __future__ import annotations

import dataclasses
import math
import warnings
from collections import OrderedDict
from dataclasses import dataclass

import numpy as np
from scipy.linalg import expm

from .. import _validate as val
from .._lru import remember
from ..errors import DataError, ParameterError, SimulationError, warn_renamed
from ..kernels import machine as _k
from ..models.static import Directional
from .elements import (FrictionFeedforward, HertzContact, PID, PiecewiseLinearSpring, Saturation, SineLoad,
                       StateSpace, Sum)
from .machine import Machine, memo_fingerprint
from typing import TYPE_CHECKING

if TYPE_CHECKING:
    from matplotlib.axes import Axes
    from numpy.typing import ArrayLike


def law_family(law, where: str = "law") -> str:
    """``"static"``, ``"lugre"`` or ``"gms"`` from the law registry; the error names ``where``."""
    from ..models.base import kernel_family

    try:
        return kernel_family(law)
    except ParameterError as exc:
        raise ParameterError(f"{where} = {type(law).__name__}: {exc}") from None


def _static_rows(law) -> np.ndarray:
    """The (2, 6) rows of a law's steady-state map ``Fss(v)``."""
    fam = law_family(law)
    if isinstance(law, Directional):
        return np.array([_static_rows(law.positive)[0], _static_rows(law.negative)[1]])
    if fam == "static":
        return np.asarray(law.static_rows(), dtype=float)
    rows = np.array(law.static.static_rows(), dtype=float)
    if fam == "gms":  # steady sliding: (sum xi) s(v) + sigma2 v
        rows[:, 0:2] *= float(np.sum(law.xi))
    return rows


def _static_par(rows9: np.ndarray) -> list[float]:
    """The kernel's static-law layout (``kernels.machine.N_STATIC_SITE`` floats) from ``(2, 9)``
    rows ``Fc0, Fc1, Fs0, Fs1, vs, delta, sigma2, shape, eps`` (``models.tdmssc.SCHEDULE_COLUMNS``):
    live rows ``Fc, Fs, vs, delta, sigma2, shape`` at schedule 0, eps+, eps-, then
    ``Fc0, Fc1, Fs0, Fs1`` of each direction."""
    r = np.asarray(rows9, dtype=float)
    live = [[x[0], x[2], x[4], x[5], x[6], x[7]] for x in r]
    par = [*live[0], *live[1], r[0, 8], r[1, 8], *r[0, :4], *r[1, :4]]
    return [float(x) for x in par]


def _ff_par(law) -> list[float]:
    """Static-law layout of a feed-forward block's map (the static map of a dynamic law)."""
    from ..models.tdmssc import schedule_rows

    if law_family(law) == "static":
        return _static_par(schedule_rows(law))
    r = _static_rows(law)
    z = np.zeros(2)
    return _static_par(np.column_stack([r[:, 0], z, r[:, 1], z, r[:, 2], r[:, 3], r[:, 4], r[:, 5], z]))


def _folded_viscous(machine: Machine) -> np.ndarray:
    """Per site, the viscous coefficient the core folds into the linear chain (else 0).

    Only for a machine whose sites are all flat static laws (``CoulombViscous``, or
    ``Stribeck`` with ``Fs = Fc``, and ``Directional`` of those with one ``sigma2``; no
    normal load, no schedule): ``sigma2 v`` is linear in the site velocity, so as a damper of
    the chain it is integrated exactly (matrix exponential) instead of held over a sub-step,
    and a sliding site is then exact at any sub-step — which lets :func:`_merge_maps` span
    whole samples. Any other machine keeps the viscous term in its sites (all zeros here).
    """
    from ..models.tdmssc import schedule_rows

    ns = len(machine.sites)
    fold = np.zeros(ns)
    for j, s in enumerate(machine.sites):
        if (s.role != "friction" or s.load is not None or s.schedule is not None
                or law_family(s.law) != "static"):
            return np.zeros(ns)
        r = schedule_rows(s.law)  # Fc0 Fc1 Fs0 Fs1 vs delta sigma2 shape eps
        flat = all(x[0] == x[2] > 0.0 and x[1] == x[3] == 0.0 and x[8] == 0.0 for x in r)
        if not flat or r[0, 6] != r[1, 6]:
            return np.zeros(ns)
        fold[j] = float(r[0, 6])
    return fold


def _all_flat(machine: Machine) -> bool:
    """Every site a flat static law without viscous term (then nothing is folded, but the
    machine still qualifies for the sample-spanning step)."""
    from ..models.tdmssc import schedule_rows

    for s in machine.sites:
        if (s.role != "friction" or s.load is not None or s.schedule is not None
                or law_family(s.law) != "static"):
            return False
        r = schedule_rows(s.law)
        if not all(x[0] == x[2] > 0.0 and x[1] == x[3] == 0.0 and x[8] == 0.0 and x[6] == 0.0 for x in r):
            return False
    return True


def _merge_maps(machine: Machine, par: list, po: list, kinds: list, fold: np.ndarray, has_loads: bool,
                Phi, G0, G1, Gf, Cq, Cm, n_sub: int):
    """The arguments of :func:`frictionkit.kernels.machine.merge_maps` that make the maps for a
    sample-spanning step (made lazily, by :func:`_general_kargs`), or ``None`` when the machine
    does not qualify.

    Qualifies: every site a static friction law with flat, non-negative levels (``Fc = Fs``,
    no ``eps``, no schedule: ``CoulombViscous``) whose viscous term is folded into the chain,
    no normal loads. While every site keeps sliding one way over a sample, its force is a
    constant ``+-Fc`` and the sub-step scheme is exact; the kernel then advances the whole
    sample with one map instead of ``n_sub`` sub-steps. The maps are the sub-step recursion
    itself (same results to round-off): ``R[i, j]`` gives site ``j``'s velocity at the end of
    sub-step ``i + 1`` and ``Mx`` the state at the end of the sample, each as a row over
    ``[X, w_start, w_end - w_start, F]`` (inputs affine over the sample, forces held). The
    kernel checks every site's direction at every sub-step end (as the sub-step scheme would
    decide) and falls back to the sub-steps when one stops or turns.
    """
    ns = len(kinds)
    if ns == 0 or n_sub < 2 or has_loads or not np.any(fold != 0.0) and not _all_flat(machine):
        return None
    for j in range(ns):  # the packed form agrees with _folded_viscous's reading of the laws
        o = po[j]
        if kinds[j] != _k.S_STATIC or par[o + 4] != 0.0 or par[o + _k.N_ROW + 4] != 0.0:
            return None
        for r in (0, _k.N_ROW):
            if par[o + r] != par[o + r + 1] or not par[o + r] > 0.0:
                return None
        if par[o + 12] != 0.0 or par[o + 13] != 0.0:
            return None
    nact = len(machine.actuators)
    nm = len(machine._motion_names)
    return (Phi, G0, G1, Gf, np.ascontiguousarray(Cq), np.ascontiguousarray(Cm), n_sub, nact + nm)


def _pack_law(law) -> tuple[int, list[float], list[float]]:
    """``(site kind, parameters, initial state)`` of a friction law for the kernel."""
    from ..models.pack import pack_gms, pack_lugre
    from ..models.tdmssc import schedule_rows

    fam = law_family(law)
    if fam == "static":
        return _k.S_STATIC, _static_par(schedule_rows(law)), []
    if fam == "lugre":
        p = pack_lugre(law)
        return _k.S_LUGRE, [*np.ravel(p.static), p.dyn[0, 0], p.dyn[0, 1], p.dyn[1, 0], p.dyn[1, 1]], [0.0]
    p = pack_gms(law)
    M = p.k.shape[1]
    par = [*np.ravel(p.static), float(M), *p.k[0], *p.xi[0], *p.k[1], *p.xi[1], p.C[0], p.C[1]]
    return _k.S_GMS, par, [0.0] * (2 * M)


class TraceAccess:
    """Named access to machine traces (``q``, ``v``, ``site_forces`` and the name tuples), shared by
    :class:`MachineResult` and the twin's result."""

    @property
    def F(self) -> np.ndarray:
        """Deprecated old name of ``site_forces`` (kept for one release)."""
        warn_renamed(type(self).__name__, "F", "site_forces")
        return self.site_forces

    def _index(self, names, name, what):
        if name not in names:
            raise DataError(f"no {what} named {name!r}; available: {list(names)}")
        return names.index(name)

    def position(self, at) -> np.ndarray:
        """Position of a DOF (by name) or of any coordinate (motions excluded) [m or rad]."""
        if isinstance(at, str):
            return self.q[:, self._index(self.dof_names, at, "degree of freedom")]
        c, _ = self.machine.row(at)
        return self.q @ c

    def velocity(self, at) -> np.ndarray:
        """Velocity of a DOF (by name) or of any coordinate [m/s or rad/s]."""
        if isinstance(at, str):
            return self.v[:, self._index(self.dof_names, at, "degree of freedom")]
        c, _ = self.machine.row(at)
        return self.v @ c

    def force(self, site: str) -> np.ndarray:
        """Force of a friction site, compliance or load [N or N·m]."""
        return self.site_forces[:, self._index(self.site_names, site, "site")]

    def _dof_lines(self) -> list[str]:
        """One summary line per degree of freedom: final position and largest speed."""
        return [f"  {d.name:>12s}: final x = {self.q[-1, i]:.6g} {d.unit}, "
                f"max |v| = {np.nanmax(np.abs(self.v[:, i])):.4g} {d.unit}/s" for i, d in enumerate(self.machine.dofs)]


@dataclass(frozen=True, eq=False)
class MachineResult(TraceAccess):
    """Time series of one machine run (SI units). ``status`` 0 = ok; else ``message`` says why.

    Attributes
    ----------
    t : ndarray (N,) — sample times [s].
    q, v : ndarray (N, n) — positions and velocities of the degrees of freedom at the samples.
    site_forces : ndarray (N, n_sites) — site forces at the samples (friction, compliance or load;
        ``F`` is the deprecated old name): from the state for dynamic laws and
        compliances; for a static law (no state) the mean over the last sub-step before the sample
        (at t = 0, for a site at rest, its force over the first sample: the holding force).
    signals : ndarray (N, n_signals) — every controller signal after the sample's update.
    u : ndarray (N, n_actuators) — applied actuator commands (after saturation and delay).
    dof_names, site_names, signal_names, actuator_names : tuple of str.
    """

    machine: Machine
    t: np.ndarray
    q: np.ndarray
    v: np.ndarray
    site_forces: np.ndarray
    signals: np.ndarray
    u: np.ndarray
    dof_names: tuple
    site_names: tuple
    signal_names: tuple
    actuator_names: tuple
    substeps: int
    status: int
    message: str
    #: Which kernel ran and, for the general loop, why the one-DOF fast paths were not taken
    #: (a debug note: ``"axis: ..."``, ``"single-axis: ..."`` or ``"general loop ..."``).
    path: str = "general loop"
    #: General loop: samples advanced in one step of ``dt`` (a kept coarse step or a
    #: sample-spanning step, ``kernels.machine.run``); the others ran in ``substeps`` sub-steps.
    #: 0 on the fast paths.
    one_step_samples: int = 0

    @property
    def success(self) -> bool:
        return self.status == 0

    def signal(self, name: str) -> np.ndarray:
        return self.signals[:, self._index(self.signal_names, name, "signal")]

    def summary(self) -> str:
        # the fast paths choose their own steps (substeps is 0 there): "0 sub-steps/sample" misread
        steps = f"{self.substeps} sub-steps/sample" if self.substeps else "steps chosen by its error control"
        lines = [f"{self.machine.name}: {self.t.size} samples over {self.t[-1]:.6g} s, "
                 f"{steps}, status {self.status} ({self.message})", f"  kernel: {self.path}"]
        lines += self._dof_lines()
        for j, s in enumerate(self.site_names):
            lines.append(f"  {s:>12s}: max |F| = {np.nanmax(np.abs(self.site_forces[:, j])) if self.site_forces.shape[0] else 0:.4g}"
                         f" {self.machine.sites[j].unit}")
        return "\n".join(lines)

    def plot(self, ax: Axes | None=None) -> Axes | np.ndarray:
        """Positions, velocities and site forces over time, one panel per quantity and unit (m, rad;
        m/s, rad/s; N, N·m) on a shared time axis; returns the array of Axes. On a given ``ax``: the
        positions of the first DOF's unit, returning ``ax`` (:func:`frictionkit.plotting.simulation.plot_machine`).
        """
        from ..plotting.simulation import plot_machine

        return plot_machine(self, ax=ax)


_EXPM_CACHE: "OrderedDict[bytes, np.ndarray]" = OrderedDict()
_EXPM_CACHE_SIZE = 64


def _expm_cached(Z: np.ndarray) -> np.ndarray:
    """``scipy.linalg.expm(Z)``, remembered for the last 64 distinct ``Z`` (bit for bit).

    Repeated runs of one machine at one step (identification loops, studies, benchmarks)
    then skip the exponential: on a loaded 2-core machine scipy's expm of a small matrix was
    measured at up to 13 ms (OpenBLAS threads waiting on each other), more than the whole
    compiled run of the EMPS axis. The result is the same array values either way.
    """
    return remember(_EXPM_CACHE, Z.tobytes() + repr(Z.shape).encode(), lambda: expm(Z), _EXPM_CACHE_SIZE)


def discretise(machine: Machine, h: float, *, site_damping: ArrayLike | None=None) -> tuple:
    """Exact discretisation of the linear chain over a sub-step ``h``.

    Returns ``(Phi, G0, G1, Gf, parts)``: ``X+ = Phi X + G0 w0 + G1 (w1 - w0) + Gf Fbar`` for
    inputs ``w`` affine over the sub-step (actuators, motions, motion rates) and site
    forces ``Fbar`` held over it; ``parts`` holds ``M, D, K, Bw, Cq, Cm``.

    ``site_damping`` (one value per site, optional) adds a linear damper on each site's
    coordinate to the chain: the machine core folds a static law's viscous term
    ``sigma2 v`` in here, where it is integrated exactly, and leaves the site only its
    level ``s(v)``.
    """
    n = machine.n
    nm = len(machine._motion_names)
    Mm = machine.mass_matrix()
    w, V = np.linalg.eigh(Mm)
    if n == 0:
        raise ParameterError(f"Machine {machine.name!r} has no degree of freedom")
    if w.min() <= 1e-12 * max(w.max(), 1e-300):
        bad = [machine.dofs[i].name for i in np.flatnonzero(np.abs(V[:, np.argmin(w)]) > 1e-6)]
        raise ParameterError(f"Machine {machine.name!r}: the mass matrix is singular — {bad} carry no "
                             "inertia (give them inertia or attach a mass)")
    K = np.zeros((n, n))
    D = np.zeros((n, n))
    nact = len(machine.actuators)
    Bw = np.zeros((n, nact + 2 * nm))
    for sp in machine.springs:
        c, cm = machine.row(sp.at)
        K += sp.k * np.outer(c, c)
        D += sp.c * np.outer(c, c)
        Bw[:, nact:nact + nm] -= sp.k * np.outer(c, cm)
        Bw[:, nact + nm:] -= sp.c * np.outer(c, cm)
    ns = len(machine.sites)
    Cq = np.zeros((ns, n))
    Cm = np.zeros((ns, nm))
    for j, s in enumerate(machine.sites):
        Cq[j], Cm[j] = machine.row(s.at)
        kl = getattr(s.law, "linear_stiffness", 0.0) if s.role != "friction" else 0.0
        if kl:
            K += kl * np.outer(Cq[j], Cq[j])
            Bw[:, nact:nact + nm] -= kl * np.outer(Cq[j], Cm[j])
        cs = 0.0 if site_damping is None else float(site_damping[j])
        if cs:
            D += cs * np.outer(Cq[j], Cq[j])
            Bw[:, nact + nm:] -= cs * np.outer(Cq[j], Cm[j])
    for i, a in enumerate(machine.actuators):
        c, cm = machine.row(a.at)
        Bw[:, i] = a.gain * c
    Bf = -Cq.T
    Minv = np.linalg.inv(Mm)
    A = np.zeros((2 * n, 2 * n))
    A[:n, n:] = np.eye(n)
    A[n:, :n] = -Minv @ K
    A[n:, n:] = -Minv @ D
    B = np.zeros((2 * n, Bw.shape[1] + ns))
    B[n:, :Bw.shape[1]] = Minv @ Bw
    B[n:, Bw.shape[1]:] = Minv @ Bf
    m = B.shape[1]
    Z = np.zeros((2 * n + 2 * m, 2 * n + 2 * m))
    Z[:2 * n, :2 * n] = A * h
    Z[:2 * n, 2 * n:2 * n + m] = B * h
    Z[2 * n:2 * n + m, 2 * n + m:] = np.eye(m)
    E = _expm_cached(Z)
    Phi = E[:2 * n, :2 * n]
    G0 = E[:2 * n, 2 * n:2 * n + m]
    G1 = E[:2 * n, 2 * n + m:]
    nw = Bw.shape[1]
    parts = {"M": Mm, "D": D, "K": K, "Bw": Bw, "Cq": Cq, "Cm": Cm}
    # copies: E may be the cached array, which must never reach a caller
    return (np.array(Phi, order="C"), np.array(G0[:, :nw], order="C"), np.array(G1[:, :nw], order="C"),
            np.array(G0[:, nw:], order="C"), parts)


def _fast_path(machine: Machine, dt: float, inputs: dict, N: int, raise_on_failure: bool):
    """Run a one-mass, one-site, open-loop machine on the single-axis kernels, else None."""
    if (machine.n != 1 or machine.springs or machine._motion_names or machine.blocks or machine.sensors
            or len(machine.sites) != 1 or len(machine.actuators) != 1):
        return None
    site, act = machine.sites[0], machine.actuators[0]
    if (site.role != "friction" or site.load is not None or law_family(site.law) == "static"
            or site.at.dofs != {0: 1.0} or act.at.dofs != {0: 1.0} or act.delay
            or act.command not in inputs or len(inputs) != 1):
        return None
    from ..plants.mass import Mass
    from ..simulation.core import simulate

    u = np.clip(inputs[act.command], -act.limit, act.limit)
    d = machine.dofs[0]
    r = simulate(site.law, plant=Mass(float(machine.mass_matrix()[0, 0])), force=act.gain * u, dt=dt,
                 x0=d.x0, v0=d.v0)
    if r.status != 0 and raise_on_failure:
        raise SimulationError(r.message)
    names = (act.command, f"{act.name}.applied")
    return MachineResult(machine=machine, t=r.t, q=r.x[:, None], v=r.v[:, None], site_forces=r.friction[:, None],
                         signals=np.column_stack([inputs[act.command], u]), u=u[:, None],
                         dof_names=(d.name,), site_names=(site.name,), signal_names=names,
                         actuator_names=(act.name,), substeps=0, status=int(r.status),
                         message=f"{r.message} (one-DOF fast path: adaptive single-axis kernel)",
                         path="single-axis: the adaptive kernel of frictionkit.simulate (one dynamic-law site, open loop)")


def _axis_plan(machine: Machine, p: dict) -> tuple:
    """``(plan, why_not)``: the one-DOF axis kernel's plant arguments
    (:func:`frictionkit.kernels.machine_axis.run_axis`) when the machine qualifies, else
    ``(None, reason)``. Qualifies: one degree of freedom, no springs or prescribed motions, one
    friction site on it holding a static law with constant levels (``CoulombViscous``,
    ``Stribeck``, ``Directional`` of those; levels > 0, viscous >= 0, no normal load, schedule
    or ``eps``); any actuators (a controller signal held over the sample, or an input array
    linear over it — flat levels only), sensors and controller blocks. The loop screen is
    applied by the caller (:func:`_axis_screen`). ``p``: the machine's pack (:func:`_packed`)."""
    from ..models.tdmssc import schedule_rows

    if machine.n != 1:
        return None, f"{machine.n} degrees of freedom"
    if machine.springs or machine._motion_names:
        return None, "springs or prescribed motions"
    if len(machine.sites) != 1:
        return None, f"{len(machine.sites)} sites (the axis kernel takes one friction site)"
    site = machine.sites[0]
    if site.role != "friction" or site.load is not None or getattr(site, "schedule", None) is not None:
        return None, f"site {site.name!r} is not a plain friction site (compliance, load, normal load or schedule)"
    law = site.law
    if law_family(law) != "static":
        return None, f"{type(law).__name__} is a dynamic law (no exact step of the axis kernel)"
    r = np.asarray(schedule_rows(law), dtype=float)  # Fc0 Fc1 Fs0 Fs1 vs delta sigma2 shape eps
    for x in r:
        if not (x[0] > 0.0 and x[2] > 0.0 and x[1] == x[3] == 0.0 and x[8] == 0.0 and x[6] >= 0.0):
            return None, (f"{type(law).__name__} levels are not constant and positive (a schedule, eps, a level "
                          "<= 0 or sigma2 < 0)")
    flat = bool(np.all(r[:, 0] == r[:, 2]))
    ka = p["kargs"]
    if not flat and np.any(ka["act_foh"]):
        return None, ("Stribeck levels (Fs != Fc) with an input-array actuator (the axis kernel's Stribeck step "
                      "holds the force over the sample)")
    c = float(ka["Cq"][0, 0])
    if c == 0.0 or not math.isfinite(c):
        return None, f"site {site.name!r} does not move with the degree of freedom"
    M = float(machine.mass_matrix()[0, 0])
    a = abs(c)
    pos, neg = (r[0], r[1]) if c > 0.0 else (r[1], r[0])  # the site's row for the DOF's direction
    gain = np.array([act.gain * float(machine.row(act.at)[0][0]) for act in machine.actuators], dtype=float)
    Vp, Vn = c * c * float(pos[6]), c * c * float(neg[6])
    stribeck = np.zeros(0)
    if not flat:
        # Runge-Kutta steps per sample: 20 per shortest time scale of the slide (assumption: RK4's
        # local error ~ (h / tau)^5 ~ 3e-7 then): the Stribeck drop's M vs / |Fs - Fc| and the
        # viscous M / sigma2, at least 2, at most 256
        taus = [M / V for V in (Vp, Vn) if V > 0.0]
        taus += [M * (x[4] / a) / abs(a * (x[2] - x[0])) for x in (pos, neg) if x[2] != x[0]]
        n_rk = int(min(max(math.ceil(20.0 * float(p["kargs"]["dt"]) / min(taus)), 2), 256)) if taus else 2
        stribeck = np.array([a * pos[2], pos[4] / a, pos[5], pos[7], a * neg[2], neg[4] / a, neg[5], neg[7], n_rk],
                            dtype=float)
    plan = dict(Minv=1.0 / M, Lp=a * float(pos[0]), Ln=a * float(neg[0]), Vp=Vp, Vn=Vn, c_site=c, act_gain=gain,
                stribeck=stribeck)
    return plan, ""


def _axis_screen(machine: Machine, dt: float, p: dict) -> tuple:
    """``(unstable, note)``: the loop screen (:func:`_loop_check`'s eigenproblem) of a machine
    that qualifies for the axis kernel, remembered with its pack. An unstable loop goes to the
    general loop, whose sub-step convergence check then decides its status (the fast path would
    only drop that check); ``note`` is the screen's own note when it was skipped."""
    from .stability import screen

    if "loop_stability" not in p:
        stab, note = screen(machine, dt)
        p["loop_stability"] = ((False, note) if stab is None
                               else (bool(stab.unstable), stab.describe(dt) if stab.unstable else ""))
    return p["loop_stability"]


def _length(inputs: dict, n_samples):
    lens = {k: v.size for k, v in inputs.items()}
    if n_samples is None:
        if not lens:
            raise DataError("simulate_machine: give n_samples (or duration) when there are no input arrays")
        n_samples = next(iter(lens.values()))
    for k, L in lens.items():
        if L != n_samples:
            raise DataError(f"simulate_machine: input {k!r} has {L} samples, expected {n_samples} "
                            "(all inputs share the sample grid)")
    return n_samples


#: ``MachineResult.status`` when ``atol`` could not be met within ``max_substeps``, or when the
#: sub-step check (:func:`site_coupling`) finds the sub-step too coarse for a site.
STATUS_TOLERANCE = 2


#: Sub-step check (issue 13): a site whose force feeds back on its own motion within one
#: sub-step by more than this (:func:`site_coupling`) makes the run suspect, and it is checked
#: against a run at ``SUBSTEP_CHECK_FACTOR`` times the sub-steps. Below it the held-force
#: scheme is in its accurate regime and nothing extra runs (the presets are at <= 0.23: the
#: hertz-nut ball screw; the parity cases and the other presets at <= 0.04).
COUPLING_CHECK = 1.0
#: The same bound for a GMS site. Its sticking elements are undamped springs, and the
#: presliding oscillation they make with the mass must be resolved: a GMS-3 slider of 1e-4 kg
#: was 9 / 3.4 % of its stroke off at coupling 0.92 / 0.067 (80 / 320 sub-steps), right at 0.017;
#: 1e-3 kg was right at 0.36 and 1e-2 kg at 0.56 (measured against the adaptive single-axis
#: kernel). Not a function of the coupling alone, so the bound sits below the worst case seen;
#: a 0.1 kg GMS slider at 10 sub-steps (0.056) is then checked too (17x its cost).
GMS_COUPLING_CHECK = 0.03
SUBSTEP_CHECK_FACTOR = 16
#: Flag bounds of that check, as fractions of each trace's range in the finer run: positions
#: 1 %, velocities and site forces 10 %.
CHECK_TOL_POSITION = 0.01
CHECK_TOL_RATE = 0.1


def _site_stiffness_damping(site, folded: float = 0.0) -> tuple[float, float]:
    """``(k, c)`` a site's force can take against its own motion: the stiffness of a sticking
    law (LuGre/Dahl ``sigma0``, GMS ``sum k_i``) or of a compliance beyond its linear part, and
    its damping (``sigma1 + |sigma2|``; a static law: ``|sigma2|`` unless folded into the chain,
    plus its steepest Stribeck slope bound ``|Fs - Fc| / vs``). Normal loads are taken at their
    reference (``lam = 1``; assumption: the check then sees the nominal law)."""
    law = site.law
    if site.role != "friction":
        if isinstance(law, HertzContact):
            return float(law.stiffness), 0.0
        if isinstance(law, PiecewiseLinearSpring):
            k = np.asarray(law.stiffness, dtype=float)
            return float(np.max(np.abs(k - k[0]))), 0.0
        if isinstance(law, SineLoad):
            return float(abs(getattr(law, "amplitude", 0.0))), 0.0
        return 0.0, 0.0
    fam = law_family(law)
    if fam == "static":
        from ..models.tdmssc import schedule_rows

        r = np.asarray(schedule_rows(law), dtype=float)  # Fc0 Fc1 Fs0 Fs1 vs delta sigma2 shape eps
        with np.errstate(divide="ignore", invalid="ignore"):
            slope = np.where(r[:, 4] > 0.0, np.abs(r[:, 2] - r[:, 0]) / r[:, 4], 0.0)
        c = float(np.max(slope)) + (0.0 if folded else float(np.max(np.abs(r[:, 6]))))
        return 0.0, c if math.isfinite(c) else 0.0
    from ..models.pack import pack_gms, pack_lugre

    if fam == "lugre":
        p = pack_lugre(law)
        return float(np.max(np.abs(p.dyn[:, 0]))), float(np.max(np.abs(p.dyn[:, 1])) + np.max(np.abs(p.static[:, 4])))
    p = pack_gms(law)
    return float(np.max(np.sum(np.abs(p.k), axis=1))), float(np.max(np.abs(p.static[:, 4])))


def site_coupling(machine: Machine, dt: float, substeps: int) -> np.ndarray:
    """Per site, how strongly its held force feeds back on its own motion within one sub-step:
    ``r_j = k_j G_jj + c_j H_jj`` (``G``, ``H``: the sub-step displacement and end-velocity
    compliances of the discretised chain; ``k_j, c_j``: :func:`_site_stiffness_damping`).

    For a site on a free mass ``m`` this is ``k h^2 / (2 m) + c h / m``. Well below 1 the site's
    own time scales span many sub-steps; far above it they are shorter than a sub-step, and the
    held-force scheme (which, like the trapezoidal rule, damps such a mode by a factor
    ``~ -(r - 1) / (r + 1)`` per sub-step only) can leave an undamped sub-step ringing in the
    velocities and forces after a breakaway or reversal. The positions stay close; the forces
    can be wrong by orders of magnitude (a LuGre slider of 1e-7 kg at 10 sub-steps: 99 N for 2 N).
    """
    n = machine.n
    ns = len(machine.sites)
    if ns == 0:
        return np.zeros(0)
    fold = _folded_viscous(machine)
    kc = np.array([_site_stiffness_damping(s, fold[j]) for j, s in enumerate(machine.sites)])
    if not np.any(kc):
        return np.zeros(ns)
    _, _, _, Gf, parts = discretise(machine, dt / int(substeps), site_damping=fold)
    Cq = parts["Cq"]
    G = np.abs(np.einsum("jn,nj->j", Cq, Gf[:n]))
    H = np.abs(np.einsum("jn,nj->j", Cq, Gf[n:]))
    return kc[:, 0] * G + kc[:, 1] * H


def site_force_spans(machine: Machine, fine) -> list:
    """The range each site force of a run is judged against by the convergence checks (the sub-step
    check here, the loop check in :mod:`.stability`), from the finer run ``fine``; ``None`` for a static
    friction site, whose force is the mean over the last sub-step (no state): at a stick/slip switch it
    legitimately depends on the sub-step, so only its motion is compared. A force is judged against the
    largest force range acting on the same degrees of freedom (its own, or a neighbour's): a 0.04 N error of
    a 0.26 N ball-load friction beside a 100 N screw support (seed 000's TDMS at 2 sub-steps) moves nothing,
    a light slider's only force does."""
    # every site's coordinate is one of this machine's (Machine._coord checks its owner), so its row exists;
    # a site on motions only acts on no degree of freedom and is judged on its own range
    dofs_of = {st.name: set(np.flatnonzero(machine.row(st.at)[0]).tolist()) for st in machine.sites}
    spans = {name: float(np.ptp(fine.site_forces[:, i])) for i, name in enumerate(fine.site_names)}
    out = []
    for st, name in zip(machine.sites, fine.site_names):
        if st.role == "friction" and law_family(st.law) == "static":
            out.append(None)
            continue
        mine = dofs_of.get(name)
        own = spans[name]
        out.append(own if not mine else max([own] + [spans[o] for o, od in dofs_of.items() if o in spans and od & mine]))
    return out


def _substep_check(machine, res, dt, inputs, N, substeps, seed, raise_on_failure, *,
                   atol_given: bool = False) -> MachineResult:
    """Flag a run whose sub-step is too coarse for a site (status 2), by a run at
    ``SUBSTEP_CHECK_FACTOR`` x the sub-steps; only when :func:`site_coupling` exceeds
    ``COUPLING_CHECK`` (otherwise ``res`` is returned untouched and nothing extra runs)."""
    if res.status != 0:
        return res
    p = _packed(machine, dt, tuple(inputs), int(substeps))
    if "coupling" not in p:  # remembered with the pack (same machine, dt and sub-steps)
        p["coupling"] = site_coupling(machine, dt, substeps)
    r = p["coupling"]
    if r.size == 0:
        return res
    limit = np.array([GMS_COUPLING_CHECK if s.role == "friction" and law_family(s.law) == "gms" else COUPLING_CHECK
                      for s in machine.sites])
    if not np.any(r > limit):
        return res
    j = int(np.argmax(r / limit))
    why = (f"site {machine.sites[j].name!r} couples to its own motion by {r[j]:.3g} per sub-step "
           f"(> {limit[j]:g}: its time scales are shorter than the sub-step dt/{substeps})")
    fine_n = SUBSTEP_CHECK_FACTOR * int(substeps)
    fine = _run_machine(machine, dt, inputs, N, fine_n, seed, False)
    if fine.status != 0:
        worst, est = f"the check run at {fine_n} sub-steps failed ({fine.message})", math.inf
    else:
        est, worst = 0.0, ""
        fspan = site_force_spans(machine, fine)
        for arr, ref, names, what, tol in ((res.q, fine.q, res.dof_names, "position", CHECK_TOL_POSITION),
                                           (res.v, fine.v, res.dof_names, "velocity", CHECK_TOL_RATE),
                                           (res.site_forces, fine.site_forces, res.site_names, "force", CHECK_TOL_RATE)):
            for i, name in enumerate(names):
                if what == "force" and fspan[i] is None:
                    continue
                d = float(np.max(np.abs(arr[:, i] - ref[:, i])))
                span = fspan[i] if what == "force" else float(np.ptp(ref[:, i]))
                floor = 1e-9 * float(np.max(np.abs(ref[:, i]))) + 1e-15
                frac = d / (tol * span + floor)  # > 1: beyond the bound
                if frac > est:
                    est = frac
                    worst = (f"{what} of {name!r} moves by {d:.3g} ({100 * d / span if span else math.inf:.3g} % "
                             f"of its range{' (the largest force range on its bodies)' if what == 'force' else ''}; "
                             f"bound {100 * tol:g} %)")
    if est <= 1.0:
        return dataclasses.replace(res, message=f"{res.message}; sub-step check passed ({why}; at {fine_n} "
                                                f"sub-steps every trace within its bound)")
    todo = ("raise substeps (the atol= control bounds the positions only)" if atol_given else
            "raise substeps until this check passes, or pass atol= for error-controlled positions")
    message = f"sub-steps too coarse: {why}; at {fine_n} sub-steps the {worst}. {todo[0].upper()}{todo[1:]}"
    return dataclasses.replace(res, status=STATUS_TOLERANCE, message=message)


@val.typed_arguments  # argument types named at the boundary (issue 13 round 11)
def simulate_machine(machine: Machine, *, dt: float, inputs: dict | None = None,
                     n_samples: int | None = None, duration: float | None = None,
                     substeps: int = 10, seed: int | None = 0, fast_path: bool = True,
                     raise_on_failure: bool = False, atol: float | None = None,
                     max_substeps: int = 640) -> MachineResult:
    """Run a machine in its compiled closed loop.

    Parameters
    ----------
    machine : Machine
    dt : float — sample period of inputs, sensors and controller [s].
    inputs : dict name -> array, optional — one value per sample: actuator commands for
        open-loop runs (interpolated linearly between samples), references and feed-forwards
        read by controller blocks, prescribed motions (:meth:`Machine.motion`, linear between
        samples).
    n_samples, duration : int / float, optional — run length when no input gives it.
    substeps : int — plant sub-steps per sample (the site forces are held over a sub-step;
        the linear chain is exact). Raise it until the result stops changing; the parity
        tests against the solve_ivp twin show the error at the default. A site whose time
        scales are shorter than the sub-step (:func:`site_coupling`: a very light mass on a
        stiff or damped contact) makes the run check itself against 16x the sub-steps and
        return status 2 (``STATUS_TOLERANCE``) with what to do when they disagree; other
        runs cost nothing extra. A closed loop that is linearly unstable at the sample period
        (:func:`frictionkit.machines.stability.loop_stability`) is checked the same way: status 2
        when its traces do not converge, else a note in ``message``.
    seed : int — seed of the sensor noise.
    fast_path : bool — one-DOF fast paths of the core (``MachineResult.path`` says which kernel
        ran and, for the general loop, why no fast path was taken):

        * a machine that is one mass, one dynamic friction site (LuGre, Dahl, GMS) and one
          open-loop force input, with nothing else, runs on the single-axis adaptive kernels
          of :func:`frictionkit.simulate` (error-controlled, breakaways located inside the
          step; ``substeps`` does not apply);
        * a rigid axis (one DOF, no springs or motions) with one friction site holding a
          static law with constant levels (``CoulombViscous``, ``Stribeck``, ``Directional``
          of those) whose closed loop the stability screen passes — the EMPS preset — runs on
          :mod:`frictionkit.kernels.machine_axis`: the same controller, a plant step per
          sample with stops located inside the sample (exact for Coulomb-viscous levels,
          converged Runge-Kutta for Stribeck ones: the limit of the general loop's
          sub-steps; ``substeps``, ``atol`` and the sub-step check do not apply, ``substeps``
          of the result is 0).

        ``False`` forces the general loop.
    raise_on_failure : bool — raise :class:`SimulationError` instead of returning status 1.
    atol : float, optional — error control: a tolerance on the positions of the degrees of
        freedom [m or rad]. The run is repeated with ``substeps``, ``2 substeps``, ... and stops
        at the first doubling that moves no position by more than ``atol`` at any sample (the
        scheme is first order, so that change estimates the finer run's error); the result is
        that finer run (``substeps`` says which count was chosen, ``message`` the estimate).
        If ``max_substeps`` is reached first, ``status`` is 2 (``STATUS_TOLERANCE``) and the
        message says by how much the tolerance was missed. A machine on the one-DOF fast path
        is error-controlled already and ignores ``atol``.
    max_substeps : int — cap of the error control's doubling.

    Returns
    -------
    MachineResult

    Examples
    --------
    >>> import numpy as np, frictionkit as fk
    >>> m = fk.Machine("slider")
    >>> x = m.dof("x", inertia=1.0)
    >>> m.friction("contact", x, law=fk.CoulombViscous(Fc=1.0))
    >>> m.actuator("u", x)
    >>> res = fk.simulate_machine(m, dt=1e-3, inputs={"u": np.full(1001, 0.5)})
    >>> float(np.abs(res.position("x")).max())   # 0.5 N < Fc: it sticks
    0.0
    """
    if not isinstance(machine, Machine):
        raise ParameterError(f"simulate_machine: machine = {type(machine).__name__}: must be a frictionkit Machine")
    dt = val.positive("simulate_machine", "dt", dt)
    if isinstance(substeps, bool) or not isinstance(substeps, (int, np.integer)) or substeps < 1:
        raise ParameterError(f"simulate_machine substeps = {substeps!r}: must be an integer >= 1")
    # its type checked even without atol (True, 2.5 or -1 were silently ignored there); the bound
    # max_substeps >= substeps matters only to the error control (atol) and is checked there
    if isinstance(max_substeps, bool) or not isinstance(max_substeps, (int, np.integer)) or max_substeps < 1:
        raise ParameterError(f"simulate_machine max_substeps = {max_substeps!r}: must be an integer >= 1")
    inputs = {} if inputs is None else dict(inputs)
    for k in list(inputs):
        if not isinstance(k, str):
            raise DataError(f"simulate_machine: input name {k!r} must be a string")
        inputs[k] = val.signal(f"inputs[{k!r}]", inputs[k], min_len=1)
    if duration is not None:
        dur = val.positive("simulate_machine", "duration", duration)
        if n_samples is not None:
            raise DataError("simulate_machine: give n_samples or duration, not both")
        n_samples = int(round(dur / dt)) + 1
    if n_samples is not None and (isinstance(n_samples, bool) or int(n_samples) != n_samples or n_samples < 2):
        raise DataError(f"simulate_machine n_samples = {n_samples!r}: must be an integer >= 2")
    N = _length(inputs, None if n_samples is None else int(n_samples))
    if N < 2:
        raise DataError(f"simulate_machine: {N} samples; need at least 2")
    # an input nothing reads is refused (issue 13, round 10: inputs={"zz": ...} ran as if not given,
    # so a misspelt reference or command went unnoticed)
    needed = machine.input_names()
    unread = [k for k in inputs if k not in needed]
    if unread:
        raise DataError(f"simulate_machine: input(s) {unread} are read by nothing in machine {machine.name!r} "
                        f"(a misspelt name?); it reads {needed or 'no inputs'}")
    # a delay line as long as the run only ever outputs its initial value, and its memory and the
    # loop screen's matrix grow with it (issue 13 round 5: delay 10000 spent 648 s in the screen,
    # 10**9 grew to 7.6 GB): refused, naming the part
    for kind, parts in (("actuator", machine.actuators), ("sensor", machine.sensors)):
        for p in parts:
            if p.delay >= N:
                raise ParameterError(f"simulate_machine: {kind} {p.name!r} delay = {p.delay} samples: must be shorter "
                                     f"than the run ({N} samples); nothing it delays would ever arrive")

    if fast_path:
        fast = _fast_path(machine, dt, inputs, N, raise_on_failure)
        if fast is not None:
            return fast
    key = id(machine)
    fp = _CALL_FP.get(key)
    if fp is None:  # not inside a running call on this machine: fingerprint it once for the call
        fp = _fingerprint(machine)
        if fp is not None:
            _CALL_FP[key] = fp
    try:
        why = "fast_path=False"
        if fast_path:
            p = _packed(machine, dt, tuple(inputs), int(substeps))
            if "axis" not in p:  # remembered with the pack (same machine, dt and input names)
                p["axis"] = _axis_plan(machine, p)
            why = p["axis"][1]
            if p["axis"][0] is not None:
                unstable, note = _axis_screen(machine, dt, p)
                if unstable:
                    why = f"{note}; the general loop checks such a run's convergence"
                else:  # exact already: atol and the sub-step check do not apply
                    res = _run_machine(machine, dt, inputs, N, int(substeps), seed, raise_on_failure, axis=True)
                    if note and res.status == 0:
                        res = dataclasses.replace(res, message=f"{res.message}; {note}")
                    return res
        if atol is not None:
            res = _error_controlled(machine, dt, inputs, N, int(substeps), seed, raise_on_failure,
                                    val.positive("simulate_machine", "atol", atol), max_substeps)
        else:
            res = _run_machine(machine, dt, inputs, N, int(substeps), seed, raise_on_failure)
            res = _substep_check(machine, res, dt, inputs, N, int(substeps), seed, raise_on_failure)
            res = _loop_check(machine, res, dt, inputs, N, seed)
        return dataclasses.replace(res, path=f"general loop (one-DOF axis kernel not taken: {why})")
    finally:
        if _CALL_FP.get(key) is fp:
            _CALL_FP.pop(key, None)


def _loop_check(machine, res, dt, inputs, N, seed):
    """Unstable closed loops (issue 13): see :func:`frictionkit.machines.stability.loop_check`."""
    from .stability import loop_check

    return loop_check(machine, res, dt, lambda n: _run_machine(machine, dt, inputs, N, n, seed, False))


def _error_controlled(machine, dt, inputs, N, substeps, seed, raise_on_failure, atol, max_substeps):
    """Double the sub-steps until the positions move by at most ``atol`` (see simulate_machine)."""
    if isinstance(max_substeps, bool) or not isinstance(max_substeps, (int, np.integer)) or max_substeps < substeps:
        raise ParameterError(f"simulate_machine max_substeps = {max_substeps!r}: must be an integer >= substeps "
                             f"({substeps})")
    prev = _run_machine(machine, dt, inputs, N, substeps, seed, raise_on_failure)
    n = substeps
    err = None
    while True:
        if prev.status != 0:
            return prev
        if 2 * n > max_substeps:
            est = ("no estimate (one run)" if err is None else
                   f"the error estimate {n // 2} -> {n} sub-steps is {err:.3g} m or rad")
            return dataclasses.replace(prev, status=STATUS_TOLERANCE,
                                       message=f"atol = {atol:.3g} not met within max_substeps = {max_substeps}: {est}")
        nxt = _run_machine(machine, dt, inputs, N, 2 * n, seed, raise_on_failure)
        if nxt.status != 0:
            return nxt
        with np.errstate(invalid="ignore"):
            err = float(np.nanmax(np.abs(nxt.q - prev.q))) if nxt.q.size else 0.0
        n *= 2
        if err <= atol:
            ok = dataclasses.replace(nxt, message=f"{nxt.message}; error estimate {err:.3g} <= atol = {atol:.3g} "
                                                  f"(positions, {n // 2} -> {n} sub-steps)")
            # atol bounds the positions only: a light mass's forces and velocities can ring while
            # its positions agree (LuGre 1e-9 kg, atol 1e-3: status 0 with a peak friction of 193 N
            # for 2 N), so the accepted run gets the same sub-step check as a plain one
            ok = _substep_check(machine, ok, dt, inputs, N, n, seed, raise_on_failure, atol_given=True)
            return _loop_check(machine, ok, dt, inputs, N, seed)
        prev = nxt


def _pack(machine: Machine, dt: float, in_keys: tuple, substeps: int) -> dict:
    """Everything the kernel needs that depends only on the machine, ``dt``, the sub-steps and
    the input names (not on the input values, the run length or the seed): the discretised
    chain, packed sites, loads, schedules, signals, actuators, sensors and blocks. Checks the
    machine against the input names (missing motion input, unread signal, actuator command).
    Cached across runs by :func:`_packed`."""
    n = machine.n
    h = dt / int(substeps)
    fold = _folded_viscous(machine)
    Phi, G0, G1, Gf, parts = discretise(machine, h, site_damping=fold)
    Cq, Cm = parts["Cq"], parts["Cm"]
    ns = len(machine.sites)
    Gss = -(Cq @ Gf[:n]) if ns else np.zeros((0, 0))  # sub-step displacement compliance
    Hss = -(Cq @ Gf[n:]) if ns else np.zeros((0, 0))  # end-velocity compliance

    # motions
    mnames = machine._motion_names
    for mname in mnames:
        if mname not in in_keys:
            raise DataError(f"simulate_machine: prescribed motion {mname!r} needs an input array of that name")

    # sites
    kinds, po, so, par, st, xtol = [], [], [], [], [], []
    for j, s in enumerate(machine.sites):
        if s.role == "friction":
            kind, p, s0 = _pack_law(s.law)
            if fold[j]:  # its viscous term lives in the chain (see _folded_viscous)
                p[4] = p[_k.N_ROW + 4] = 0.0
        else:
            kind = {HertzContact: _k.S_HERTZ, PiecewiseLinearSpring: _k.S_PWL, SineLoad: _k.S_SINE}[type(s.law)]
            p, s0 = s.law.pack(), []
        kinds.append(kind)
        po.append(len(par))
        so.append(len(st))
        par += p
        st += s0
        xtol.append(_k.SITE_XTOL)

    # normal loads
    nmo = len(mnames)
    ld_mode = np.zeros(ns, dtype=np.int64)
    ld_row = np.zeros((ns, 2 * n))
    ld_mrow = np.zeros((ns, nmo))
    ld_site = np.full(ns, -1, dtype=np.int64)
    ld_par = np.ones((ns, 4))
    springs = {sp.name: sp for sp in machine.springs}
    site_names = [s.name for s in machine.sites]
    for j, s in enumerate(machine.sites):
        L = s.load
        if L is None:
            continue
        where = f"friction site {s.name!r}: NormalLoad.on = {L.on!r}"
        if L.on in springs:
            if L.hertz_set:
                raise ParameterError(f"{where} is a linear spring; hertz_set needs a HertzContact compliance")
            sp = springs[L.on]
            c, cm = machine.row(sp.at)
            ld_row[j, :n] = sp.k * c
            ld_row[j, n:] = sp.c * c
            ld_mrow[j] = sp.k * cm
        elif L.on in site_names and machine.sites[site_names.index(L.on)].role == "compliance":
            ci = site_names.index(L.on)
            comp = machine.sites[ci]
            if L.hertz_set and not isinstance(comp.law, HertzContact):
                raise ParameterError(f"{where}: hertz_set needs a HertzContact, not {type(comp.law).__name__}")
            ld_site[j] = ci
            if not L.hertz_set:
                c, cm = machine.row(comp.at)
                ld_row[j, :n] = comp.law.linear_stiffness * c
                ld_mrow[j] = comp.law.linear_stiffness * cm
                dmp = springs.get(f"{L.on}.damper")
                if dmp is not None:
                    ld_row[j, n:] = dmp.c * c
        else:
            raise ParameterError(f"{where}: no spring or compliance of that name in machine {machine.name!r}")
        ld_mode[j] = 2 if L.hertz_set else 1
        ld_par[j] = [L.preload, float(L.hertz_set) if L.hertz_set else L.gain, L.floor_gain, L.reference]

    # schedule inputs (a TDMSSC's base speed): a coordinate's position or velocity
    sch_mode = np.zeros(ns, dtype=np.int64)
    sch_row = np.zeros((ns, n))
    sch_mrow = np.zeros((ns, nmo))
    for j, s in enumerate(machine.sites):
        sc = getattr(s, "schedule", None)
        if sc is None:
            continue
        sch_mode[j] = 2 if sc.quantity == "velocity" else 1
        sch_row[j], sch_mrow[j] = machine.row(sc.at)

    # signals: inputs, sensors, block outputs, actuator applied values
    sig_names: list[str] = []

    def sig_index(name: str) -> int:
        if name not in sig_names:
            sig_names.append(name)
        return sig_names.index(name)

    in_names = [k for k in in_keys if k not in mnames]
    produced = set(in_names) | {s.name for s in machine.sensors} | {f"{a.name}.applied" for a in machine.actuators}
    for b in machine.blocks:
        produced |= set(b.outputs)
    for b in machine.blocks:
        for s in b.inputs:
            if s not in produced:
                raise DataError(f"controller block {type(b).__name__}({b.outputs[0]!r}) reads signal {s!r}, "
                                f"which nothing produces; known signals: {sorted(produced)}")
    in_sig = np.array([sig_index(k) for k in in_names], dtype=np.int64)

    # actuators
    nact = len(machine.actuators)
    block_out = set()
    for b in machine.blocks:
        block_out |= set(b.outputs)
    act_sig = np.zeros(nact, dtype=np.int64)
    act_foh = np.zeros(nact, dtype=np.bool_)
    act_col = np.full(nact, -1, dtype=np.int64)
    for i, a in enumerate(machine.actuators):
        if a.command in block_out or a.command in {s.name for s in machine.sensors}:
            act_sig[i] = sig_index(a.command)
        elif a.command in in_names:
            act_foh[i] = True
            act_col[i] = in_names.index(a.command)
            act_sig[i] = sig_index(a.command)
        else:
            raise DataError(f"actuator {a.name!r} follows signal {a.command!r}, which is neither an input array "
                            f"nor a controller output; inputs given: {sorted(in_keys)}")
    act_applied = np.array([sig_index(f"{a.name}.applied") for a in machine.actuators], dtype=np.int64)
    act_lim = np.array([a.limit for a in machine.actuators], dtype=float)
    act_delay = np.array([a.delay for a in machine.actuators], dtype=np.int64)

    # sensors
    nsen = len(machine.sensors)
    sen_row = np.zeros((nsen, n))
    sen_mrow = np.zeros((nsen, len(mnames)))
    for i, s in enumerate(machine.sensors):
        sen_row[i], sen_mrow[i] = machine.row(s.at)
    sen_qty = np.array([1 if s.quantity == "velocity" else 0 for s in machine.sensors], dtype=np.int64)
    sen_res = np.array([s.resolution for s in machine.sensors], dtype=float)
    sen_delay = np.array([s.delay for s in machine.sensors], dtype=np.int64)
    sen_sig = np.array([sig_index(s.name) for s in machine.sensors], dtype=np.int64)
    sen_noise = [float(s.noise) for s in machine.sensors]

    # blocks
    act_names = [a.name for a in machine.actuators]
    code, iptr, idx, fptr, bpar, sptr, bst = [], [0], [], [0], [], [0], []
    for b in machine.blocks:
        if isinstance(b, Sum):
            code.append(_k.B_LINEAR)
            idx += [sig_index(b.out), len(b.terms), *[sig_index(s) for s in b.terms]]
            bpar += [b.bias, *b.terms.values()]
        elif isinstance(b, PID):
            code.append(_k.B_PID)
            aw = -1
            if b.antiwindup is not None:
                if b.antiwindup not in act_names:
                    raise DataError(f"PID({b.out!r}).antiwindup = {b.antiwindup!r}: no such actuator; "
                                    f"actuators: {act_names}")
                aw = act_names.index(b.antiwindup)
            idx += [sig_index(b.out), sig_index(b.error), sig_index(b.derivative_error or b.error), aw]
            bpar += [b.Kp, b.Ki, b.Kd, b.tau_d, dt]
            bst += [0.0, 0.0, 0.0, 0.0]
        elif isinstance(b, StateSpace):
            code.append(_k.B_SS)
            nx = b.A.shape[0]
            idx += [len(b.inputs), len(b.outputs), *[sig_index(s) for s in b.inputs],
                    *[sig_index(s) for s in b.outputs]]
            bpar += [float(nx), *b.A.ravel(), *b.B.ravel(), *b.C.ravel(), *b.D.ravel()]
            bst += [*b.x0, *([0.0] * nx)]
        elif isinstance(b, Saturation):
            code.append(_k.B_SAT)
            idx += [sig_index(b.out), sig_index(b.inp)]
            bpar += [b.lo, b.hi]
        elif isinstance(b, FrictionFeedforward):
            code.append(_k.B_FFF)
            idx += [sig_index(b.out), sig_index(b.velocity), -1 if b.schedule is None else sig_index(b.schedule)]
            bpar += [b.scale, *_ff_par(b.law)]
        iptr.append(len(idx))
        fptr.append(len(bpar))
        sptr.append(len(bst))

    X = np.array([d.x0 for d in machine.dofs] + [d.v0 for d in machine.dofs], dtype=float)
    I64 = np.int64
    # the sample-spanning step's maps are made on the general loop's first run of this pack
    # (:func:`_general_kargs`): the one-DOF axis kernel never uses them, and making them compiles
    # kernels.machine.merge_maps (~1.1 s CPU on a cold numba cache)
    mg_args = _merge_maps(machine, par, po, kinds, fold, bool(np.any(ld_mode)), Phi, G0, G1, Gf, Cq, Cm,
                          int(substeps))
    # the kernel's arguments by name (kernels.machine.run), except what a run supplies (the
    # motions, inputs, noise and outputs); the arrays the kernel updates in place are copied for
    # every run (_KARGS_MUTABLE: a kernel that writes to another argument must add it there)
    kargs = dict(
        n_sub=int(substeps), dt=dt, Phi=Phi, G0=G0, G1=G1, Gf=Gf, Gss=np.ascontiguousarray(Gss, dtype=float),
        Hss=np.ascontiguousarray(Hss, dtype=float), Cq=np.ascontiguousarray(Cq), Cm=np.ascontiguousarray(Cm),
        s_off=np.zeros(ns), s_visc=fold,
        site_kind=np.array(kinds, dtype=I64), site_po=np.array(po, dtype=I64), site_so=np.array(so, dtype=I64),
        par=np.array(par, dtype=float), st=np.array(st, dtype=float), xtol=np.array(xtol, dtype=float),
        ld_mode=ld_mode, ld_row=ld_row, ld_mrow=ld_mrow, ld_site=ld_site, ld_par=ld_par,
        sch_mode=sch_mode, sch_row=sch_row, sch_mrow=sch_mrow, X=X,
        act_sig=act_sig, act_lim=act_lim, act_delay=act_delay, act_foh=act_foh, act_applied_sig=act_applied,
        act_col=act_col, in_sig=in_sig,
        sen_row=sen_row, sen_mrow=sen_mrow, sen_qty=sen_qty, sen_res=sen_res, sen_delay=sen_delay, sen_sig=sen_sig,
        blk_code=np.array(code, dtype=I64), blk_iptr=np.array(iptr, dtype=I64), blk_idx=np.array(idx, dtype=I64),
        blk_fptr=np.array(fptr, dtype=I64), blk_par=np.array(bpar, dtype=float), blk_sptr=np.array(sptr, dtype=I64),
        blk_st=np.array(bst, dtype=float), sig=np.zeros(len(sig_names)))
    return {"kargs": kargs, "mg_args": mg_args, "mnames": list(mnames), "in_names": in_names, "sen_noise": sen_noise,
            "sig_names": tuple(sig_names), "act_names": tuple(act_names), "n": n, "ns": ns, "nact": nact}


#: Packed machines of recent runs (:func:`_packed`), oldest first.
_PACK_CACHE: "OrderedDict[tuple, dict]" = OrderedDict()
_PACK_CACHE_SIZE = 16
#: Kernel arguments the kernel writes to (copied from the cached pack for every run).
_KARGS_MUTABLE = ("par", "st", "X", "blk_par", "blk_st", "sig")  # blk_par: a scheduled feed-forward's levels


def _signature_names(f) -> tuple[tuple, tuple]:
    """Names of ``f``'s parameters without a default (in order) and with one."""
    import inspect

    ps = inspect.signature(getattr(f, "py_func", f)).parameters.values()
    return (tuple(p.name for p in ps if p.default is inspect.Parameter.empty),
            tuple(p.name for p in ps if p.default is not inspect.Parameter.empty))


#: Parameter names of ``kernels.machine.run``: required ones in order, then those with a default
#: (passed by keyword when the pack gives them); read at import, before any wrapper such as the
#: benchmark's kernel clock replaces the module attribute.
_RUN_PARAMS, _RUN_OPTIONAL = _signature_names(_k.run)


def _fingerprint(machine: Machine):
    """The machine's content as a hashable key — its JSON form (:meth:`Machine.to_dict`, which
    is complete: :meth:`Machine.from_dict` rebuilds the machine from it) — or None when it has
    no JSON form (such a machine is packed anew for every run). An edited machine (a part
    added, a law or parameter replaced, even in place in its lists) has another key, so it can
    never meet a stale pack; two equal machines share one. Remembered on the machine object
    until a part of it changes (:func:`~frictionkit.machines.machine.memo_fingerprint`): a
    study's many runs of one machine pay the JSON form once."""
    fp = _CALL_FP.get(id(machine))
    if fp is not None:
        return fp
    return memo_fingerprint(machine, _json_form)


def _json_form(machine: Machine):
    import json

    try:
        return json.dumps(machine.to_dict(), allow_nan=True)
    except Exception:  # a part without a JSON form: no caching, never a wrong pack
        return None


#: Fingerprints of the machines whose :func:`simulate_machine` call is running (by ``id``): the
#: machine cannot change during the call, so its runs, checks and reruns share one fingerprint.
_CALL_FP: dict = {}


def _packed(machine: Machine, dt: float, in_keys: tuple, substeps: int) -> dict:
    """:func:`_pack`, remembered for the last 16 (machine content, ``dt``, input names,
    sub-steps). Repeated runs of one machine (identification loops, studies, benchmarks, the
    sub-step and loop checks' reruns) then skip the packing and the exact discretisation —
    about 1 ms of Python per run, a tenth of a whole EMPS run. The pack's in-place arrays are
    copied for every run by the caller."""
    fp = _fingerprint(machine)
    key = None if fp is None else (fp, float(dt), tuple(in_keys), int(substeps))
    return remember(_PACK_CACHE, key, lambda: _pack(machine, dt, in_keys, substeps), _PACK_CACHE_SIZE)


def _general_kargs(p: dict) -> dict:
    """The pack's kernel arguments with the sample-spanning step's maps (``mg_on``, ``mg_R``,
    ``mg_M``; :func:`_merge_maps`), made on the first general-loop run of the pack and kept in it
    (a pack's arrays are never written: the kernel's in-place arguments are copied per run)."""
    ka = p["kargs"]
    if "mg_on" not in ka:
        mg = p["mg_args"]
        mg_R, mg_M = _k.merge_maps(*mg) if mg is not None else (np.zeros((0, 0, 0)), np.zeros((0, 0)))
        ka.update(mg_on=mg is not None, mg_R=mg_R, mg_M=mg_M)
    return ka


def _run_machine(machine, dt, inputs, N, substeps, seed, raise_on_failure, axis: bool = False) -> MachineResult:
    if seed is not None and (isinstance(seed, bool) or not isinstance(seed, (int, np.integer)) or seed < 0):
        raise ParameterError(f"simulate_machine seed = {seed!r}: must be a non-negative integer or None")
    p = _packed(machine, dt, tuple(inputs), int(substeps))
    n, ns, nact = p["n"], p["ns"], p["nact"]
    mnames, in_names, sig_names, act_names = p["mnames"], p["in_names"], p["sig_names"], p["act_names"]
    mot = np.zeros((N, len(mnames)))
    for i, mname in enumerate(mnames):
        mot[:, i] = inputs[mname]
    in_arr = np.zeros((N, len(in_names)))
    for i, k in enumerate(in_names):
        in_arr[:, i] = inputs[k]
    noise = np.zeros((N, len(p["sen_noise"])))
    rng = None  # made only when a sensor draws (~30-80 us a run otherwise)
    for i, sn in enumerate(p["sen_noise"]):
        if sn > 0:
            if rng is None:
                rng = np.random.default_rng(seed)
            noise[:, i] = rng.standard_normal(N) * sn
    # every sample before the kernel's k_end is written by it; the rest is set to NaN below
    q_out = np.empty((N, n))
    v_out = np.empty((N, n))
    F_out = np.empty((N, ns))
    sig_out = np.empty((N, len(sig_names)))
    u_out = np.empty((N, nact))
    kw = dict(p["kargs"] if axis else _general_kargs(p), mot=mot, inputs=in_arr, noise=noise, q_out=q_out, v_out=v_out, F_out=F_out,
              sig_out=sig_out, u_out=u_out)
    for name in _KARGS_MUTABLE:
        kw[name] = kw[name].copy()
    if axis:  # the one-DOF fast path (_axis_plan), same controller code and outputs
        from ..kernels import machine_axis as _ka

        a = p["axis"][0]
        status, k_end, n_bad = _ka.run_axis(
            dt, kw["X"], a["Minv"], a["Lp"], a["Ln"], a["Vp"], a["Vn"], a["c_site"], a["act_gain"], a["stribeck"],
            in_arr, kw["in_sig"], kw["sen_row"], kw["sen_qty"], kw["sen_res"], kw["sen_delay"], kw["sen_sig"], noise,
            kw["blk_code"], kw["blk_iptr"], kw["blk_idx"], kw["blk_fptr"], kw["blk_par"], kw["blk_sptr"], kw["blk_st"],
            kw["act_sig"], kw["act_lim"], kw["act_delay"], kw["act_foh"], kw["act_applied_sig"], kw["act_col"], kw["sig"],
            q_out, v_out, F_out, sig_out, u_out)
        n_one = 0
    else:
        # always given, as a bool: an omitted default is another numba signature, so a caller passing
        # coarse=False (the tests) would compile the whole kernel a second time (~19 s CPU)
        kw.setdefault("coarse", True)
        status, k_end, n_bad, n_one, _ = _k.run(*[kw[name] for name in _RUN_PARAMS],
                                         **{name: kw[name] for name in _RUN_OPTIONAL if name in kw})
    if k_end > (1 if axis else 2):
        _initial_static_forces(p["kargs"], v_out, mot, F_out, dt, axis)
    if k_end < N:
        for arr in (q_out, v_out, F_out, sig_out, u_out):
            arr[k_end:] = np.nan
    message = "ok"
    if status == _k.STATUS_NONFINITE:
        message = (f"non-finite state after sample {k_end - 1} (t = {(k_end - 1) * dt:.6g} s): the run was "
                   "stopped and later samples are NaN; check the parameters or raise substeps")
        if raise_on_failure:
            raise SimulationError(message)
        warnings.warn(message, RuntimeWarning, stacklevel=2)
    elif n_bad:
        message = (f"ok, but the coupled site forces did not converge in {n_bad} sub-steps "
                   "(Gauss-Seidel over sites); raise substeps")
    t = np.arange(N, dtype=float)  # the same values as np.arange(N) * dt, without the int -> float pass
    t *= dt
    return MachineResult(machine=machine, t=t, q=q_out, v=v_out, site_forces=F_out, signals=sig_out, u=u_out,
                         dof_names=tuple(machine._dof_names), site_names=tuple(s.name for s in machine.sites),
                         signal_names=tuple(sig_names), actuator_names=tuple(act_names),
                         substeps=0 if axis else int(substeps), status=int(status), message=message,
                         path=_AXIS_PATH if axis else "general loop", one_step_samples=int(n_one))


def _initial_static_forces(ka: dict, v_out: np.ndarray, mot: np.ndarray, F_out: np.ndarray, dt: float,
                           axis: bool) -> None:
    """Set the t = 0 force of each static-law site at rest at t = 0 from the next samples.

    A static law's force at rest is set-valued (anything up to the breakaway level that balances
    the other forces); both kernels only learn it by stepping the first sample, so they recorded 0
    at t = 0 (the EMPS axis held against its 3.1648 N offset read 0, then 3.1648 N from t = dt on).
    The axis kernel holds the forces over a sample, so its force at t = dt is the one at t = 0 (the
    holding force, or the sliding force when the site broke away in the first sample). The general
    loop records a sub-step mean, and springs or motions may change the holding force within the
    sample: a site still at rest at t = dt gets the linear extrapolation ``2 F(dt) - F(2 dt)`` (its
    error falls with the sub-step, as the twin parity asks), one that broke away ``F(dt)``. Sites
    moving at t = 0 keep the kernel's value."""
    kinds = ka["site_kind"]
    if kinds.size == 0:
        return
    rate = np.diff(mot[:3], axis=0) / dt if mot.shape[1] else np.zeros((2, 0))
    v0 = ka["Cq"] @ v_out[0] + ka["Cm"] @ rate[0]
    at_rest = (kinds == _k.S_STATIC) & (v0 == 0.0)
    F_out[0, at_rest] = F_out[1, at_rest]
    if not axis:
        v1 = ka["Cq"] @ v_out[1] + ka["Cm"] @ rate[1]
        held = at_rest & (v1 == 0.0)
        F_out[0, held] = 2.0 * F_out[1, held] - F_out[2, held]


#: ``MachineResult.path`` of a run on the one-DOF axis kernel.
_AXIS_PATH = ("axis: the one-DOF kernel kernels.machine_axis (exact step per sample, stops located inside "
              "the sample; substeps do not apply)")
