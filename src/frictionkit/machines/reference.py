"""A slow, obviously-correct ``scipy.integrate.solve_ivp`` twin of :func:`simulate_machine`.

It exists for parity tests and for checking a machine you built: the same
:class:`~frictionkit.machines.Machine`, integrated by a general-purpose ODE solver at tight
tolerances, with every friction state written out as an ODE state and every GMS switching
located as a ``solve_ivp`` event. It is open-loop only (input arrays drive actuators and
prescribed motions; no controller blocks) and costs seconds where the compiled loop costs
milliseconds.

Equations
---------
The linear chain comes from :func:`~frictionkit.machines.discretise`'s ``parts``
(``M, D, K, Bw, Cq, Cm``), the same matrices the compiled loop discretises exactly::

    q' = v
    M v' = Bw w(t) - K q - D v - Cq^T F(t)
    w(t) = [actuator commands u_i(t), motion positions p_m(t), motion rates p_m'(t)]

Actuator commands and motion positions are the input arrays interpolated linearly between
samples (commands clipped to the actuator limit, delayed by the actuator's whole-sample
``delay``); a motion rate is constant over each sample interval. Site ``j`` sits at
``s_j = Cq[j] q + Cm[j] p`` and slides at ``s_j' = Cq[j] v + Cm[j] p'``; its force ``F_j``
opposes it. Site laws (parameters from :mod:`frictionkit.models.pack`, row 0 for
``s' >= 0``, row 1 for ``s' < 0``):

* LuGre / Dahl — one state ``z``: ``z' = s' - sigma0 |s'| z / |s(s')|``,
  ``F = sigma0 z + sigma1 z' + sigma2 s'``.
* GMS — one state ``F_i`` per element. Sticking: ``F_i' = k_i s'``; it breaks away when
  ``d F_i`` reaches ``xi_i |s(s')|`` (``d`` the direction of motion). Slipping (all the
  site's slipping elements share the direction ``d``): ``F_i' = C (d xi_i - F_i / |s(s')|)``
  until ``s'`` reverses, when every element of the site sticks again.
  ``F = sum F_i + sigma2 s'``. Breakaway and reversal are terminal ``solve_ivp`` events;
  the integration restarts after each with the new stick/slip flags (as in
  :func:`frictionkit.simulation.reference.reference_force_driven`).
* Static laws (``Stribeck``, ``CoulombViscous`` and their ``Directional``; one static site per
  machine) — stick and slip as events: a sticking site does not move and carries the force
  that holds it still (``F = c M^-1 f / (c M^-1 c^T)``, ``f`` every other force, ``c`` its
  row) until that force reaches ``+Fs`` or ``-Fs``; a site slipping in direction ``d`` carries
  ``F = s(s') + sigma2 s'`` on ``d``'s row until ``s'`` comes to zero, where it sticks again
  if the holding force it then needs lies inside ``[-Fs-, Fs+]`` (Karnopp's model, exact).
  While it sticks the state may stand still, so the solver's step is unbounded: the holding
  force is also checked at every sample, and an interval where it left the band unseen is
  integrated again alone (inputs are linear inside a sample, so its event is found). A force
  that only reaches a level and rests there holds (``STICK_ROUNDOFF``). Slipping slower than
  ``SLOW_ZONE vs`` (steep part of the Stribeck curve) the step is capped (``SLOW_STEPS``).
* Compliances and loads (:class:`HertzContact`, :class:`PiecewiseLinearSpring`,
  :class:`SineLoad`) — memoryless: ``F = law.force(s) - law.linear_stiffness * s`` (the
  linear part is already in ``K``).

``|s(v)|`` is floored at ``1e-9 max(Fc, Fs)``. The record is integrated piece by piece: a
new piece starts at every GMS event and at every sample where a prescribed motion changes
its rate by more than round-off (the right-hand side jumps there); inside a piece the right-hand side is smooth or
has kinks only (actuator commands).

Not supported (a clear error): controller blocks and actuators that follow anything but an
input array (closed loop), more than one static site, state-dependent normal loads
(:class:`NormalLoad`). Sensors do not
act on an open-loop plant and are ignored. An actuator's ``delay`` shifts its input array by
whole samples (zeros before).

Outputs at the samples ``t_k = k dt``: ``q, v`` of the degrees of freedom and the site
forces ``site_forces`` at ``t_k`` from the state there, with the motion rate of the interval that
arrives at ``t_k`` (the first interval's at ``t_0``), as the compiled loop records them.
"""

from __future__ import annotations

import math
import time
from dataclasses import dataclass

import numpy as np
from scipy.integrate import solve_ivp

from .. import _validate as val
from ..errors import DataError, ParameterError, SimulationError
from ..models.pack import pack_gms, pack_lugre
from .elements import HertzContact, PiecewiseLinearSpring, SineLoad
from .machine import Machine
from .simulate import MachineResult, TraceAccess, discretise, law_family

__all__ = ["ReferenceResult", "reference_machine"]

_METHODS = ("LSODA", "Radau", "BDF", "RK45", "DOP853", "RK23")

#: Default cap on the number of GMS switching events in one run.
MAX_EVENTS = 200_000

#: Relative round-off allowance on a static site's levels: a holding force within it of a level holds.
STICK_ROUNDOFF = 1e-12

#: A slipping static site slower than ``SLOW_ZONE vs`` is in the steep part of its Stribeck
#: curve; the solver's step is then capped so that it crosses that zone in at least
#: ``SLOW_STEPS`` steps (an unbounded step can jump the whole rise of the level toward ``Fs``:
#: DOP853, and LSODA inside the twin, put a stop 0.24 ms late that way).
SLOW_ZONE = 4.0
SLOW_STEPS = 20

#: Consecutive (near) zero-length pieces tolerated before giving up (chattering).
_MAX_STALLS = 64


# --------------------------------------------------------------------------- helpers
def _level(row: np.ndarray, v: float, floor: float) -> float:
    """``|s(v)|`` of one packed static row ``Fc, Fs, vs, delta, sigma2, shape``."""
    Fc, Fs, vs, delta, _s2, shape = row
    r = abs(v) / vs
    if shape == 0.0:
        e = r**delta
        phi = math.exp(-e) if e < 700.0 else 0.0
    else:
        phi = 1.0 / (1.0 + r * r)
    return max(abs(Fc + (Fs - Fc) * phi), floor)


def _sgn(x: float) -> int:
    return 1 if x > 0.0 else (-1 if x < 0.0 else 0)


class _LuGreSite:
    """LuGre / Dahl site: state ``z``."""

    nstate = 1

    def __init__(self, law):
        p = pack_lugre(law)
        self.static = np.asarray(p.static, dtype=float)
        self.dyn = np.asarray(p.dyn, dtype=float)
        self.floor = 1e-9 * float(np.max(self.static[:, :2]))

    def force_and_rates(self, sv: float, z: float) -> tuple[float, float]:
        r = 0 if sv >= 0.0 else 1
        s0, s1 = self.dyn[r]
        zd = sv - s0 * abs(sv) * z / _level(self.static[r], sv, self.floor)
        return s0 * z + s1 * zd + self.static[r, 4] * sv, zd


class _GMSSite:
    """GMS site: states ``F_i``; its stick/slip flags and slip direction live in the mode."""

    def __init__(self, law):
        p = pack_gms(law)
        self.static = np.asarray(p.static, dtype=float)
        self.k = np.asarray(p.k, dtype=float)
        self.xi = np.asarray(p.xi, dtype=float)
        self.C = np.asarray(p.C, dtype=float)
        self.M = self.k.shape[1]
        self.nstate = self.M
        self.floor = 1e-9 * float(np.max(self.static[:, :2]))
        self.tol = 1e-10 * float(np.max(self.static[:, :2]))

    def force_and_rates(self, sv: float, Fi: np.ndarray, slip: np.ndarray, d: int):
        rv = 0 if sv >= 0.0 else 1
        if not d:  # every element sticks
            return float(Fi.sum()) + self.static[rv, 4] * sv, self.k[rv] * sv
        r = 0 if d > 0 else 1
        S = _level(self.static[r], sv, self.floor)
        dF = np.where(slip, self.C[r] * (d * self.xi[r] - Fi / S), self.k[r] * sv)
        return float(Fi.sum()) + self.static[rv, 4] * sv, dF

    def margin(self, i: int, direction: int, sv: float, Fi: float) -> float:
        """Breakaway margin ``xi_i |s(s')| - direction F_i`` (> 0: the element holds)."""
        if direction == 0:
            return 1.0 + abs(Fi)  # no motion, nothing breaks away
        r = 0 if direction > 0 else 1
        return self.xi[r, i] * _level(self.static[r], sv, self.floor) - direction * Fi


class _StaticSite:
    """Static law (Stribeck, CoulombViscous, TDMSSC, Directional of them): sticks or slips (mode ``d``).

    Levels are signed and, for a TDMSSC, affine in the schedule value ``s``:
    ``Fc = Fc0 + Fc1 s``, ``Fs = Fs0 + Fs1 s``; slipping, ``F = d L_d(|v|, s) + sigma2 v - eps v |v|``.
    """

    nstate = 0

    def __init__(self, law, schedule=None):
        from ..models.tdmssc import schedule_rows

        self.rows = np.asarray(schedule_rows(law), dtype=float)  # Fc0 Fc1 Fs0 Fs1 vs delta sigma2 shape eps
        self.schedule = schedule  # (quantity, dof row, motion row) or None

    def level(self, r: int, sv: float, s: float) -> float:
        """Signed level ``Fc + (Fs - Fc) phi(|v|/vs)`` of row ``r`` at schedule ``s``."""
        Fc0, Fc1, Fs0, Fs1, vs, delta, _s2, shape, _eps = self.rows[r]
        Fc = Fc0 + Fc1 * s
        Fs = Fs0 + Fs1 * s
        x = abs(sv) / vs
        if shape == 0.0:
            e = x**delta
            phi = math.exp(-e) if e < 700.0 else 0.0
        else:
            phi = 1.0 / (1.0 + x * x)
        return Fc + (Fs - Fc) * phi

    def Fs(self, d: int, s: float) -> float:
        """Static level of direction ``d`` (+1/-1) at schedule ``s`` (signed)."""
        return self.level(0 if d > 0 else 1, 0.0, s)

    def bump_speed(self, d: int) -> float | None:
        """``SLOW_ZONE vs`` of direction ``d``: below it the level rises steeply toward ``Fs``
        (None when ``Fs = Fc``, no rise)."""
        Fc0, Fc1, Fs0, Fs1, vs = self.rows[0 if d > 0 else 1, :5]
        return None if (Fc0 == Fs0 and Fc1 == Fs1) else SLOW_ZONE * vs

    def slip_force(self, sv: float, d: int, s: float) -> float:
        """``d L_d(|v|, s) + sigma2 v - eps v |v|`` on the row of the direction of slip ``d``."""
        r = 0 if d > 0 else 1
        return d * self.level(r, sv, s) + self.rows[r, 6] * sv - self.rows[r, 8] * sv * abs(sv)


class _ElasticSite:
    nstate = 0

    def __init__(self, law):
        self.law = law
        self.k_lin = float(getattr(law, "linear_stiffness", 0.0))

    def force(self, s: float) -> float:
        return float(self.law.force(s)) - self.k_lin * s


@dataclass(frozen=True, eq=False)
class ReferenceResult(TraceAccess):
    """Samples of a :func:`reference_machine` run, with the fields of :class:`MachineResult`.

    Attributes
    ----------
    t : ndarray (N,); q, v : ndarray (N, n); site_forces : ndarray (N, n_sites) — site forces at ``t_k``.
    u : ndarray (N, n_actuators) — applied actuator commands (clipped, delayed).
    states : ndarray (N, n_states) — friction states (LuGre ``z``, GMS element forces ``F_i``)
        in site order.
    nfev : int — right-hand-side evaluations; ``n_events`` GMS switchings (``event_log``:
        ``(t, kind, site, element)``: GMS ``"breakaway"`` / ``"reversal"`` (element -1), static
        site ``"slip"`` (element: direction) / ``"stop"``);
        ``n_pieces`` ``solve_ivp`` calls; ``wall_s`` wall time [s]; ``method``, ``rtol``.
    """

    machine: Machine
    t: np.ndarray
    q: np.ndarray
    v: np.ndarray
    site_forces: np.ndarray
    u: np.ndarray
    states: np.ndarray
    dof_names: tuple
    site_names: tuple
    actuator_names: tuple
    nfev: int
    n_events: int
    n_pieces: int
    event_log: list
    wall_s: float
    method: str
    rtol: float
    status: int = 0
    message: str = "ok"

    @property
    def success(self) -> bool:
        return self.status == 0

    def summary(self) -> str:
        lines = [f"{self.machine.name} (solve_ivp twin, {self.method}, rtol {self.rtol:g}): {self.t.size} samples "
                 f"over {self.t[-1]:.6g} s, {self.nfev} RHS evaluations, {self.n_events} switchings, "
                 f"{self.wall_s:.3g} s; status {self.status} ({self.message})"]
        return "\n".join(lines + self._dof_lines())

    #: Positions, velocities and site forces over time, drawn as for a :class:`MachineResult`; returns the
    #: array of Axes (the given Axes with ``ax=``: positions only).
    plot = MachineResult.plot


# --------------------------------------------------------------------------- the twin
class _Twin:
    """Right-hand side, events and bookkeeping of one open-loop machine run."""

    def __init__(self, machine: Machine, dt: float, inputs: dict, N: int):
        self.machine = machine
        self.dt = dt
        self.N = N
        self.t = dt * np.arange(N)
        *_, parts = discretise(machine, dt)
        Minv = np.linalg.inv(parts["M"])
        self.Cq, self.Cm = parts["Cq"], parts["Cm"]
        # M v' = Bw w - K q - D v - Cq^T F, premultiplied by M^-1
        self.A_w = Minv @ parts["Bw"]
        self.A_q = Minv @ parts["K"]
        self.A_v = Minv @ parts["D"]
        self.A_F = Minv @ self.Cq.T
        self.n = machine.n
        self.nact = len(machine.actuators)
        self.nm = len(machine._motion_names)

        # actuator commands: input arrays, delayed by whole samples, clipped to the limit
        self.U = np.zeros((N, self.nact))
        self.lim = np.array([a.limit for a in machine.actuators], dtype=float)
        for i, a in enumerate(machine.actuators):
            if a.command not in inputs or a.command in machine._motion_names:
                raise DataError(f"reference_machine: actuator {a.name!r} follows {a.command!r}, which is not an "
                                f"input array (the twin is open-loop only); inputs given: {sorted(inputs)}")
            col = inputs[a.command]
            if a.delay:
                col = np.concatenate([np.zeros(min(a.delay, N)), col[:max(N - a.delay, 0)]])
            self.U[:, i] = col
        # prescribed motions: positions at the samples, a constant rate per interval
        self.P = np.zeros((N, self.nm))
        for m, name in enumerate(machine._motion_names):
            if name not in inputs:
                raise DataError(f"reference_machine: prescribed motion {name!r} needs an input array of that name")
            self.P[:, m] = inputs[name]
        self.R = np.diff(self.P, axis=0) / dt  # (N-1, nm)

        # sites and the layout of the state vector [q, v, site states...]
        self.sites, self.offsets = [], []
        off = 2 * self.n
        for s in machine.sites:
            if getattr(s, "load", None) is not None:
                raise ParameterError(f"reference_machine: site {s.name!r} has a state-dependent normal load; "
                                     "the solve_ivp twin does not model normal loads")
            if s.role == "friction":
                fam = law_family(s.law, f"site {s.name!r}")
                if fam == "static":
                    sc = getattr(s, "schedule", None)
                    site = _StaticSite(s.law, None if sc is None else (sc.quantity, *machine.row(sc.at)))
                else:
                    site = _LuGreSite(s.law) if fam == "lugre" else _GMSSite(s.law)
            elif isinstance(s.law, (HertzContact, PiecewiseLinearSpring, SineLoad)):
                site = _ElasticSite(s.law)
            else:  # pragma: no cover - Machine refuses anything else
                raise ParameterError(f"reference_machine: site {s.name!r} holds an unsupported {type(s.law).__name__}")
            self.sites.append(site)
            self.offsets.append(off)
            off += site.nstate
        self.ny = off
        self.has_elastic = any(isinstance(s, _ElasticSite) for s in self.sites)
        self._no_u = np.zeros(0)
        self.kinds = [1 if isinstance(s, _LuGreSite) else 2 if isinstance(s, _GMSSite) else
                      3 if isinstance(s, _StaticSite) else 0 for s in self.sites]
        self.gms = [j for j, s in enumerate(self.sites) if isinstance(s, _GMSSite)]
        statics = [j for j, s in enumerate(self.sites) if isinstance(s, _StaticSite)]
        if len(statics) > 1:
            raise ParameterError(
                f"reference_machine: sites {[machine.sites[j].name for j in statics]} hold static laws; the "
                "solve_ivp twin handles one static site (several sticking at once need a complementarity solve)")
        #: the static site (or None) and ``Cq_j M^-1 Cq_j^T``, its compliance to its own force
        self.static = statics[0] if statics else None
        if self.static is not None:
            self.static_gain = float(self.Cq[self.static] @ self.A_F[:, self.static])

    # ---- inputs
    def u_at(self, t: float) -> np.ndarray:
        if self.nact == 0:
            return self._no_u
        k = min(max(int(math.floor(t / self.dt)), 0), self.N - 2)
        f = t / self.dt - k
        u = self.U[k] + (self.U[k + 1] - self.U[k]) * f
        return np.minimum(np.maximum(u, -self.lim), self.lim)

    # ---- right-hand side; `seg` = (t_a, p_a, rate) of the current constant-rate piece
    def forces(self, t, y, mode, seg, dy=None):
        """Motion positions, site forces and (into ``dy``) the friction-state rates at ``(t, y)``."""
        n = self.n
        ta, pa, rate = seg
        p = pa + rate * (t - ta)
        sv = (self.Cq @ y[n:2 * n] + self.Cm @ rate).tolist()
        s = (self.Cq @ y[:n] + self.Cm @ p).tolist() if self.has_elastic else None
        F = np.zeros(len(self.sites))
        for j, site in enumerate(self.sites):
            o = self.offsets[j]
            kind = self.kinds[j]
            if kind == 1:
                F[j], zd = site.force_and_rates(sv[j], y[o])
                if dy is not None:
                    dy[o] = zd
            elif kind == 2:
                slip, d = mode[j]
                F[j], dF = site.force_and_rates(sv[j], y[o:o + site.M], slip, d)
                if dy is not None:
                    dy[o:o + site.M] = dF
            elif kind == 3:  # sticking (mode 0): the holding force, set by accel()
                F[j] = site.slip_force(sv[j], mode[j], self.schedule_value(y, p, rate)) if mode[j] else 0.0
            else:
                F[j] = site.force(s[j])
        return p, F

    def schedule_value(self, y, p, rate) -> float:
        """The static site's schedule input (0 without one) at state ``y``, motions ``p``, ``rate``."""
        sc = self.sites[self.static].schedule if self.static is not None else None
        if sc is None:
            return 0.0
        quantity, c, cm = sc
        n = self.n
        if quantity == "velocity":
            return float(c @ y[n:2 * n] + cm @ rate)
        return float(c @ y[:n] + cm @ p)

    def static_limits(self, t, y, seg) -> tuple[float, float]:
        """``(Fs+, Fs-)`` of the static site at ``(t, y)`` (signed; schedule read from the state),
        each widened by ``STICK_ROUNDOFF (|Fs+| + |Fs-|)``: Karnopp's site sticks while the
        holding force lies in ``[-Fs-, Fs+]``, so one that reaches a level and stays there (or
        sits on it up to round-off) holds; only one that goes past it slips. Without the
        allowance the slip event fired on a force resting at ``Fs`` and the twin chattered."""
        ta, pa, rate = seg
        s = self.schedule_value(y, pa + rate * (t - ta), rate)
        site = self.sites[self.static]
        pos, neg = site.Fs(1, s), site.Fs(-1, s)
        tol = STICK_ROUNDOFF * (abs(pos) + abs(neg))
        return pos + tol, neg + tol

    def accel(self, t, y, mode, seg, dy=None):
        """Accelerations and site forces at ``(t, y)``. A sticking static site holds its
        coordinate still: its force is the one that makes the site acceleration zero."""
        n = self.n
        p, F = self.forces(t, y, mode, seg, dy)
        w = np.concatenate([self.u_at(t), p, seg[2]]) if self.nm else self.u_at(t)
        acc = self.A_w @ w - self.A_q @ y[:n] - self.A_v @ y[n:2 * n] - self.A_F @ F
        j = self.static
        if j is not None and mode[j] == 0:
            F[j] = float(self.Cq[j] @ acc) / self.static_gain  # motion rates are constant in a piece
            acc = acc - self.A_F[:, j] * F[j]
        return acc, F

    def rhs(self, t, y, mode, seg):
        n = self.n
        dy = np.empty(self.ny)
        dy[n:2 * n], _F = self.accel(t, y, mode, seg, dy)
        dy[:n] = y[n:2 * n]
        return dy

    def site_motion(self, t, y, mode, seg):
        """Site velocities and accelerations at ``(t, y)``."""
        n = self.n
        dy = self.rhs(t, y, mode, seg)
        sv = self.Cq @ y[n:2 * n] + self.Cm @ seg[2]
        sa = self.Cq @ dy[n:2 * n]  # motion rates are constant inside a piece
        return sv, sa

    def direction(self, t, sv: float, sa: float) -> int:
        """Direction a sticking site is moving in (or about to move in) at a piece start.

        At rest it is the sign of the site acceleration; when the site velocity is a
        round-off residue of a located reversal (it would reach zero within ~1e-10 of a
        sample) and the acceleration opposes it, the site is reversing: the acceleration's.
        """
        if sv == 0.0:
            return _sgn(sa)
        if sa != 0.0 and _sgn(sa) != _sgn(sv) and abs(sv) <= 1e-10 * abs(sa) * max(self.dt, t):
            return _sgn(sa)
        return _sgn(sv)


def reference_machine(machine: Machine, *, dt: float, inputs: dict | None = None, n_samples: int | None = None,
                      duration: float | None = None, method: str = "LSODA", rtol: float = 1e-10, atol=None,
                      max_step: float | None = None, max_events: int = MAX_EVENTS) -> ReferenceResult:
    """Integrate an open-loop machine with ``solve_ivp``: the twin of :func:`simulate_machine`.

    Parameters
    ----------
    machine : Machine — degrees of freedom, springs, LuGre/Dahl/GMS friction sites (and at
        most one static-law site), compliances, loads, actuators, prescribed motions (no
        controller blocks).
    dt : float — sample period of the inputs and outputs [s].
    inputs : dict name -> array — actuator commands and prescribed motions, one value per
        sample (as for :func:`simulate_machine`).
    n_samples, duration : run length when no input gives it.
    method : {"LSODA", "Radau", "BDF", "RK45", "DOP853", "RK23"} — ``solve_ivp`` method
        (the machine is stiff: LSODA or Radau).
    rtol : float — relative tolerance.
    atol : float or array (n_states,), optional — absolute tolerance; default ``1e-3 rtol``
        in SI units for ``q, v``, ``1e-3 rtol Fs / sigma0`` for a LuGre ``z`` and
        ``1e-3 rtol Fs`` for a GMS element force.
    max_step : float, optional — largest ``solve_ivp`` step [s].
    max_events : int — cap on GMS switching events.

    Returns
    -------
    ReferenceResult — ``t, q, v, F`` at the samples, ``position()``, ``force()``, ...

    Raises
    ------
    ParameterError — closed-loop parts, two static sites, normal loads, bad options.
    DataError — missing or inconsistent inputs.
    SimulationError — ``solve_ivp`` fails, too many events, or the switching chatters.

    Examples
    --------
    >>> import numpy as np, frictionkit as fk
    >>> from frictionkit.machines.reference import reference_machine
    >>> m = fk.Machine("slider")
    >>> x = m.dof("x", inertia=1.0)
    >>> m.friction("contact", x, law=fk.LuGre(fk.Stribeck(Fc=1.0, Fs=1.5, vs=1e-3, sigma2=0.4),
    ...                                          sigma0=1e5, sigma1=316.2))
    >>> m.actuator("u", x)
    >>> ref = reference_machine(m, dt=1e-3, inputs={"u": np.full(201, 0.5)})
    >>> bool(np.abs(ref.position("x")).max() < 1e-5)   # 0.5 N < Fs: pre-sliding only
    True
    """
    owner = "reference_machine"
    tic = time.perf_counter()
    if not isinstance(machine, Machine):
        raise ParameterError(f"{owner}: machine = {type(machine).__name__}: must be a frictionkit Machine")
    if machine.blocks:
        raise ParameterError(f"{owner}: machine {machine.name!r} has {len(machine.blocks)} controller blocks; "
                             "the solve_ivp twin runs open-loop machines only (drive actuators with input arrays)")
    dt = val.positive(owner, "dt", dt)
    if method not in _METHODS:
        raise ParameterError(f"{owner}.method = {method!r}: must be one of {list(_METHODS)}")
    rtol = val.positive(owner, "rtol", rtol)
    max_step = math.inf if max_step is None else val.positive(owner, "max_step", max_step)
    inputs = {} if inputs is None else dict(inputs)
    for k in list(inputs):
        inputs[k] = val.signal(f"inputs[{k!r}]", inputs[k], min_len=2)
    if duration is not None:
        if n_samples is not None:
            raise DataError(f"{owner}: give n_samples or duration, not both")
        n_samples = int(round(val.positive(owner, "duration", duration) / dt)) + 1
    lens = {k: a.size for k, a in inputs.items()}
    if n_samples is None:
        if not lens:
            raise DataError(f"{owner}: give n_samples (or duration) when there are no input arrays")
        n_samples = next(iter(lens.values()))
    N = int(n_samples)
    if N < 2:
        raise DataError(f"{owner}: {N} samples; need at least 2")
    for k, L in lens.items():
        if L != N:
            raise DataError(f"{owner}: input {k!r} has {L} samples, expected {N}")

    tw = _Twin(machine, dt, inputs, N)
    n, ny, t = tw.n, tw.ny, tw.t
    if atol is None:
        atol_v = np.full(ny, 1e-3 * rtol)
        for j, site in enumerate(tw.sites):
            o = tw.offsets[j]
            if isinstance(site, _LuGreSite):
                atol_v[o] = 1e-3 * rtol * float(np.max(site.static[:, :2]) / np.min(site.dyn[:, 0]))
            elif isinstance(site, _GMSSite):
                atol_v[o:o + site.M] = 1e-3 * rtol * float(np.max(site.static[:, :2]))
    else:
        atol_v = np.broadcast_to(np.asarray(atol, dtype=float), (ny,)).copy()
        if not np.all(atol_v > 0):
            raise ParameterError(f"{owner}.atol = {atol!r}: must be > 0")

    y = np.zeros(ny)
    y[:n] = [d.x0 for d in machine.dofs]
    y[n:2 * n] = [d.v0 for d in machine.dofs]
    # mode: per GMS site (slipping flags, common slip direction d, 0 when all stick)
    mode = {j: (np.zeros(tw.sites[j].M, dtype=bool), 0) for j in tw.gms}
    # the static site: 0 sticking, +1/-1 slipping in that direction (decided at the first piece)
    if tw.static is not None:
        mode[tw.static] = 0
    static_mode = np.zeros(N, dtype=int)  # at the samples
    out = np.empty((N, ny))
    out[0] = y
    filled = 1
    nfev = n_pieces = stalls = 0
    log: list = []

    # pieces of constant motion rate: breaks where any rate changes (by more than round-off)
    if tw.nm:
        scale = np.abs(tw.R).max(axis=0) + 1e-300
        change = np.flatnonzero(np.any(np.abs(np.diff(tw.R, axis=0)) > 1e-9 * scale, axis=1)) + 1
    else:
        change = np.zeros(0, dtype=int)
    bounds = [0, *change.tolist(), N - 1]

    prev_rate = None  # motion rates of the previous piece
    bound_next = False  # the next piece ends at the next sample (a crossing of +-Fs was stepped over)
    for ka, kb in zip(bounds[:-1], bounds[1:]):
        ta, tb = t[ka], t[kb]
        # the motions are exactly linear over the piece: through the samples at its ends
        seg = (ta, tw.P[ka].copy(), (tw.P[kb] - tw.P[ka]) / (tb - ta))
        t0 = ta
        while t0 < tb:
            if tw.static is not None:
                y = _static_start(tw, mode, seg, t0, y, log, prev_rate)
                if t0 == 0.0:
                    static_mode[0] = mode[tw.static]
            prev_rate = seg[2]
            # elements already at their threshold in the direction of motion break away first
            go = {}
            if tw.gms:
                sv0, sa0 = tw.site_motion(t0, y, mode, seg)
                for j in tw.gms:
                    site = tw.sites[j]
                    slip, d = mode[j]
                    d_go = d if d else tw.direction(t0, sv0[j], sa0[j])
                    go[j] = d_go
                    o = tw.offsets[j]
                    due = [i for i in range(site.M)
                           if not slip[i] and site.margin(i, d_go, sv0[j], y[o + i]) <= site.tol]
                    if due:
                        slip = slip.copy()
                        slip[due] = True
                        mode[j] = (slip, d_go)
                        log += [(t0, "breakaway", j, i) for i in due]
            events, kinds = _events(tw, mode, seg, t0, y, go)

            def fun(tt, yy, mode=dict(mode), seg=seg):
                return tw.rhs(tt, yy, mode, seg)

            # A sticking static site holds its DOFs still: the state may stand still while the
            # holding force follows the inputs, so the solver's steps grow without bound and can
            # step over a crossing of +-Fs and back (solve_ivp sees an event only as a sign change
            # between step ends). So the holding force is checked at every sample of a sticking
            # piece; at the first sample where it lies outside [-Fs-, Fs+] the samples before it
            # are kept and the interval that holds the crossing is integrated alone (its inputs
            # are linear, so its event is found).
            sticking = tw.static is not None and mode[tw.static] == 0
            t_end = tb
            if bound_next:
                t_end = min(tb, float(t[int(np.searchsorted(t, t0 + 1e-9 * dt, side="right"))]))
            k_last = int(np.searchsorted(t, t_end, side="right"))
            sol = solve_ivp(fun, (t0, t_end), y, method=method, t_eval=t[filled:k_last], events=events or None,
                            rtol=rtol, atol=atol_v, max_step=min(max_step, _slow_cap(tw, mode, seg, t0, y)))
            nfev += int(sol.nfev)
            n_pieces += 1
            if sol.status == -1:
                raise SimulationError(f"{owner}: solve_ivp ({method}) failed after t = {t0:.6g} s: {sol.message}")
            m_new = len(sol.t)
            if sticking and m_new and not bound_next:
                miss = _first_outside_band(tw, mode, seg, sol.t, np.asarray(sol.y))
                if miss is not None:
                    if miss:
                        out[filled:filled + miss] = np.asarray(sol.y)[:, :miss].T
                        static_mode[filled:filled + miss] = 0
                        filled += miss
                        t0, y = float(t[filled - 1]), out[filled - 1].copy()
                    bound_next = True
                    continue
            bound_next = False
            if m_new:
                out[filled:filled + m_new] = np.asarray(sol.y).T
                if tw.static is not None:
                    static_mode[filled:filled + m_new] = mode[tw.static]
                filled += m_new
            if sol.status == 0:
                y = np.asarray(sol.y)[:, -1].copy() if m_new else y
                if t_end < tb:
                    t0 = t_end
                    continue
                break
            # a terminal event ended the piece
            t_ev = [te[-1] if te.size else -math.inf for te in sol.t_events]
            e = int(np.argmax(t_ev))
            t_e = float(t_ev[e])
            y = np.array(sol.y_events[e][-1], dtype=float)
            if t_e - t0 <= 1e-14 * max(1.0, abs(t0)):
                stalls += 1
                if stalls > _MAX_STALLS:
                    raise SimulationError(f"{owner}: GMS switching chatters at t = {t_e:.9g} s ({stalls} zero-length "
                                          "pieces in a row); the stick/slip state cannot be resolved")
            else:
                stalls = 0
            fired = [kinds[q] for q in range(len(kinds)) if sol.t_events[q].size and sol.t_events[q][-1] >= t_e]
            sv_e, sa_e = tw.site_motion(t_e, y, mode, seg)
            for kind, j, i in fired:
                if kind == "stop":  # a slipping static site comes to rest: decided at the next start
                    mode[j] = 0
                    log.append((t_e, "stop", j, -1))
                elif kind == "slip":
                    mode[j] = i
                    log.append((t_e, "slip", j, i))
                # kind "slow": the restart caps the step (_slow_cap); nothing switches
            for kind, j, i in fired:
                if kind not in ("breakaway", "reversal"):
                    continue
                slip, d = mode[j]
                if kind == "reversal":
                    mode[j] = (np.zeros_like(slip), 0)
                    log.append((t_e, "reversal", j, -1))
            for kind, j, i in fired:
                if kind == "breakaway":
                    slip, d = mode[j]
                    if slip[i]:
                        continue
                    slip = slip.copy()
                    slip[i] = True
                    mode[j] = (slip, d if d else tw.direction(t_e, sv_e[j], sa_e[j]))
                    log.append((t_e, "breakaway", j, i))
            if len(log) > max_events:
                raise SimulationError(f"{owner}: more than max_events = {max_events} GMS switching events "
                                      f"(reached t = {t_e:.6g} s)")
            t0 = t_e
    if filled < N:  # the last event fell exactly on the final sample
        out[filled:] = y

    # outputs at the samples
    q, v = out[:, :n].copy(), out[:, n:2 * n].copy()
    F = np.zeros((N, len(tw.sites)))
    u = np.zeros((N, tw.nact))
    out_mode = {j: (np.zeros(tw.sites[j].M, dtype=bool), 0) for j in tw.gms}
    for k in range(N):
        rate = tw.R[max(k - 1, 0)] if tw.nm else np.zeros(0)  # the arriving rate (the first at t_0)
        if tw.static is not None:
            out_mode[tw.static] = int(static_mode[k])
        _acc, F[k] = tw.accel(t[k], out[k], out_mode, (t[k], tw.P[k], rate))
        u[k] = tw.u_at(t[k])
    return ReferenceResult(
        machine=machine, t=t, q=q, v=v, site_forces=F, u=u, states=out[:, 2 * n:].copy(),
        dof_names=tuple(machine._dof_names), site_names=tuple(s.name for s in machine.sites),
        actuator_names=tuple(a.name for a in machine.actuators), nfev=nfev, n_events=len(log),
        n_pieces=n_pieces, event_log=log, wall_s=time.perf_counter() - tic, method=method, rtol=rtol)


def _events(tw: _Twin, mode: dict, seg, ta: float, ya: np.ndarray, go: dict):
    """Terminal events of one piece: breakaway of each sticking GMS element, reversal of each
    slipping GMS site. At ``ta`` each returns its value at the start state in the direction
    the site was found to move in (``go``), so a round-off velocity residue of a located
    reversal cannot fake a crossing."""
    n = tw.n
    events, kinds = [], []
    sv_a = tw.Cq @ ya[n:2 * n] + tw.Cm @ seg[2]
    for j in tw.gms:
        site = tw.sites[j]
        slip, d = mode[j]
        o = tw.offsets[j]
        for i in np.flatnonzero(~slip):
            g0 = site.margin(int(i), go[j], sv_a[j], ya[o + i])

            def ev(tt, yy, j=j, i=int(i), o=o, d=d, site=site, g0=g0):
                if tt == ta:
                    return g0
                sv = float(tw.Cq[j] @ yy[n:2 * n] + tw.Cm[j] @ seg[2])
                return site.margin(i, d if d else _sgn(sv), sv, yy[o + i])

            ev.terminal = True
            ev.direction = -1
            events.append(ev)
            kinds.append(("breakaway", j, int(i)))
        if d:
            g0r = d * sv_a[j]

            def ev_rev(tt, yy, j=j, d=d, g0=g0r):
                if tt == ta:
                    return g0
                return d * float(tw.Cq[j] @ yy[n:2 * n] + tw.Cm[j] @ seg[2])

            ev_rev.terminal = True
            ev_rev.direction = -1
            events.append(ev_rev)
            kinds.append(("reversal", j, -1))
    j = tw.static
    if j is not None:
        d = mode[j]
        if d == 0:  # sticking: the holding force reaches +Fs or -Fs
            for sgn in (1, -1):
                def ev_hold(tt, yy, sgn=sgn):
                    lim = tw.static_limits(tt, yy, seg)[0 if sgn > 0 else 1]
                    return lim - sgn * tw.accel(tt, yy, mode, seg)[1][j]

                ev_hold.terminal = True
                ev_hold.direction = -1
                events.append(ev_hold)
                kinds.append(("slip", j, sgn))
        else:  # slipping: the site velocity comes to zero
            def ev_stop(tt, yy, d=d):
                return d * float(tw.Cq[j] @ yy[n:2 * n] + tw.Cm[j] @ seg[2])

            ev_stop.terminal = True
            ev_stop.direction = -1
            events.append(ev_stop)
            kinds.append(("stop", j, 0))
            vb = tw.sites[j].bump_speed(d)
            if vb is not None:  # it enters the slow zone (at vb), or leaves it (at 2 vb): a new piece
                inside = d * float(tw.Cq[j] @ ya[n:2 * n] + tw.Cm[j] @ seg[2]) < 1.5 * vb
                edge = 2.0 * vb if inside else vb

                def ev_slow(tt, yy, d=d, edge=edge):
                    return d * float(tw.Cq[j] @ yy[n:2 * n] + tw.Cm[j] @ seg[2]) - edge

                ev_slow.terminal = True
                ev_slow.direction = 1 if inside else -1
                events.append(ev_slow)
                kinds.append(("slow", j, 0))
    return events, kinds


def _slow_cap(tw: _Twin, mode: dict, seg, t0: float, y: np.ndarray) -> float:
    """Largest step of a piece: a static site slipping below ``SLOW_ZONE vs`` at ``t0`` crosses
    that zone in no fewer than ``SLOW_STEPS`` steps at its acceleration there (inf otherwise)."""
    j = tw.static
    if j is None or mode[j] == 0:
        return math.inf
    d = mode[j]
    vb = tw.sites[j].bump_speed(d)
    if vb is None:
        return math.inf
    sv, sa = tw.site_motion(t0, y, mode, seg)
    if d * sv[j] >= 1.5 * vb or sa[j] == 0.0:  # outside (the zone is left at 2 vb, entered at vb)
        return math.inf
    return vb / abs(sa[j]) / SLOW_STEPS


def _first_outside_band(tw: _Twin, mode: dict, seg, ts, ys) -> int | None:
    """Index of the first output sample of a sticking piece whose holding force lies outside
    ``[-Fs-, Fs+]`` (None if none does)."""
    j = tw.static
    for i in range(len(ts)):
        F_hold = tw.accel(ts[i], ys[:, i], mode, seg)[1][j]
        Fs_pos, Fs_neg = tw.static_limits(ts[i], ys[:, i], seg)
        if F_hold > Fs_pos or F_hold < -Fs_neg:
            return i
    return None


def _static_start(tw: _Twin, mode: dict, seg, t0: float, y: np.ndarray, log: list, prev_rate) -> np.ndarray:
    """Stick or slip of the static site at the start of a piece; returns the (projected) state.

    A slipping site keeps slipping. A sticking one is moving only if it starts with a velocity
    (``prev_rate`` None: the initial state) or a prescribed motion it rides on changed its rate
    at this sample; then it slips that way. Otherwise its velocity is zero up to round-off
    (projected away along ``M^-1 c^T``) and it sticks if the holding force lies inside
    ``[-Fs-, Fs+]``, else it slips in the direction of the force it could not supply.
    """
    j = tw.static
    if mode[j] != 0:
        return y
    n = tw.n
    c, cm, rate = tw.Cq[j], tw.Cm[j], seg[2]
    sv = float(c @ y[n:2 * n] + cm @ rate)
    if prev_rate is None:
        moving = sv != 0.0
    else:
        jump = float(cm @ (rate - prev_rate))
        moving = abs(jump) > 1e-9 * float(np.abs(cm) @ (np.abs(rate) + np.abs(prev_rate))) and sv != 0.0
    if moving:
        mode[j] = _sgn(sv)
        log.append((t0, "slip", j, mode[j]))
        return y
    if sv != 0.0:
        y = y.copy()
        y[n:2 * n] -= tw.A_F[:, j] * (sv / tw.static_gain)
    F_hold = tw.accel(t0, y, mode, seg)[1][j]
    Fs_pos, Fs_neg = tw.static_limits(t0, y, seg)
    up, dn = F_hold > Fs_pos, F_hold < -Fs_neg
    if up and dn:  # empty stick band (negative levels): the way the holding force points
        up, dn = F_hold > 0.0, F_hold < 0.0
    if up:
        mode[j] = 1
    elif dn:
        mode[j] = -1
    if mode[j]:
        log.append((t0, "slip", j, mode[j]))
    return y
