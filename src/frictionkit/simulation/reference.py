"""Slow, obviously-correct ``scipy.integrate.solve_ivp`` twins of the simulation kernels.

These functions exist for parity tests and benchmarks. They trade speed for
transparency: every right-hand side is written out in NumPy, every switching of
the GMS model is an explicit ``solve_ivp`` event, and the integration restarts
after each event with the new stick/slip flags, so that the dynamics inside each
piece are smooth.

Model conventions (SPEC §1, seed 000 eqs. 1-3, 6, 9; seed 002 eqs. 5-8)
-----------------------------------------------------------------------
Parameters are taken from the packed arrays of :mod:`frictionkit.models.pack`:
row 0 for ``v >= 0``, row 1 for ``v < 0``.

* LuGre / Dahl: ``dz/dt = v - sigma0 |v| z / |s(v)|``,
  ``F = sigma0 z + sigma1 dz/dt + sigma2 v``.
* GMS: a sticking element obeys ``dF_i/dt = k_i v`` and breaks away when
  ``sgn(v) F_i`` reaches ``xi_i |s(v)|`` while ``v != 0``; a slipping element obeys
  ``dF_i/dt = sgn(v) C (xi_i - F_i / s(v))`` (``s`` signed), i.e.
  ``C (d xi_i - F_i / |s|)`` with ``d`` the direction of slip, and sticks again when
  the velocity reverses. ``F = sum F_i + sigma2 v``.

  Velocity reversal is a terminal event only while some element slips: when every
  element sticks, the right-hand side is continuous through ``v = 0`` and only the
  breakaway thresholds change side (a breakaway that becomes due exactly at
  ``v = 0`` is still caught, because the event function jumps through zero there).
  In the motion-driven twin, where ``v`` is constant over each sample interval, a
  slipping element sticks at the start of any interval whose velocity is not in
  its direction of slip (reversed *or zero*).

``|s(v)|`` is floored at ``1e-9 max(Fc, Fs)`` so that a law with ``Fs = 0`` does not
divide by zero at rest (such a GMS is very stiff near ``v = 0``: use LSODA, not RK45),
nor one with ``Fc = 0`` at speed; the kernels floor the levels at the same fraction
(``kernels._stribeck.G_FLOOR``). Near that floor the LuGre relaxation rate reaches
1e13 /s: give ``atol`` below the bristle scale ``|s| / sigma0`` and a stiff method
(LSODA force-driven; Radau motion-driven, where LSODA's restarts fail).

Accuracy of the switching (force-driven GMS)
--------------------------------------------
``solve_ivp`` locates an event on the method's dense output, which for RK45 is one
order lower than the step itself; over a long step that error (~1e-6 s in event
time) would be carried into the next piece. The step holding an event is therefore
redone from its start with steps 64 times shorter before the event is accepted.
Events are detected from the sign of the event function at step ends, so a grazing
reversal (``v`` dipping below zero and back within one step) can be missed by a
method taking long steps; tighten ``rtol``/``max_step`` when that matters. Element
forces at a switching are continuous; only the reversal sets ``v`` to exactly 0
(the value the root finder located to within round-off).
"""

from __future__ import annotations

import math
import time
import warnings
from typing import Any

import numpy as np
from scipy.integrate import solve_ivp

from .. import _validate as val
from ..errors import FrictionKitDeprecationWarning, ParameterError, SimulationError
from ..models.pack import PackedGMS, kind_of, pack_gms, pack_lugre

__all__ = ["reference_force_driven", "reference_motion_driven"]

_METHODS = ("LSODA", "RK45", "RK23", "DOP853", "Radau", "BDF")

#: Default cap on the number of GMS switching events in one run.
MAX_EVENTS = 200_000

#: Consecutive (near) zero-length pieces tolerated before giving up (chattering).
_MAX_STALLS = 64


# --------------------------------------------------------------------------- helpers
class _TwinOutput(dict):
    """The twins' output dict; the old key ``"F"`` still reads ``"friction"`` for one release, with a
    :class:`~frictionkit.errors.FrictionKitDeprecationWarning`."""

    def __getitem__(self, key):
        if key == "F" and not dict.__contains__(self, "F"):
            warnings.warn('the twin\'s output key "F" is deprecated: use "friction" (the old key goes in the '
                          "next release)", FrictionKitDeprecationWarning, stacklevel=2)
            key = "friction"
        return dict.__getitem__(self, key)


def _smag(row: np.ndarray, v: float, floor: float) -> float:
    """``|s(v)|`` for one packed static row (magnitude, evaluated at ``|v|``)."""
    Fc, Fs, vs, delta, _sigma2, shape = row
    r = abs(v) / vs
    if shape == 0.0:
        phi = math.exp(-(r**delta)) if r < 1e3 else 0.0
    else:
        phi = 1.0 / (1.0 + r * r)
    return max(abs(Fc + (Fs - Fc) * phi), floor)


def _floor(static: np.ndarray) -> float:
    return 1e-9 * float(np.max(static[:, :2]))


def _row(v: float) -> int:
    return 0 if v >= 0.0 else 1


def _check_common(owner: str, dt, method, rtol, atol, max_step) -> tuple[float, float, float, float]:
    dt = val.positive(owner, "dt", dt)
    if method not in _METHODS:
        raise ParameterError(f"{owner}.method = {method!r}: must be one of {list(_METHODS)}")
    rtol = val.positive(owner, "rtol", rtol)
    atol = val.positive(owner, "atol", atol)
    max_step = math.inf if max_step is None else val.positive(owner, "max_step", max_step)
    return dt, rtol, atol, max_step


def _mass_value(owner: str, m) -> float:
    return val.positive(owner, "m", getattr(m, "m", m))


def _fail(owner: str, sol, t0: float) -> SimulationError:
    """The error for a failed ``solve_ivp`` piece that started at ``t0``.

    ``sol.t`` is a list, not an array, when the solver failed before reaching its
    first ``t_eval`` point, so the time reached is read through ``np.asarray``.
    """
    ts = np.asarray(sol.t, dtype=float).ravel()
    t_end = float(ts[-1]) if ts.size else t0
    return SimulationError(
        f"{owner}: solve_ivp failed after t = {max(t0, t_end):.6g} s: {sol.message}"
    )


# --------------------------------------------------------------------------- LuGre
def _lugre_zdot(static, dyn, floor, v, z):
    r = _row(v)
    S = _smag(static[r], v, floor)
    return v - dyn[r, 0] * abs(v) * z / S


def _lugre_force(static, dyn, floor, v, z):
    r = _row(v)
    zd = _lugre_zdot(static, dyn, floor, v, z)
    return dyn[r, 0] * z + dyn[r, 1] * zd + static[r, 4] * v


# --------------------------------------------------------------------------- GMS
class _GMSMode:
    """Right-hand side and event functions of the GMS model for one stick/slip mode.

    ``slip`` marks the slipping elements; ``d`` (+1/-1) is their common direction of
    slip and fixes the parameter row while any element slips. With no element
    slipping (``d = 0``) the row follows the sign of ``v``.
    """

    def __init__(self, p, floor: float, slip: np.ndarray, d: int):
        self.p = p
        self.floor = floor
        self.slip = slip.copy()
        self.stick = ~self.slip
        self.d = d if self.slip.any() else 0

    def row(self, v: float) -> int:
        if self.d:
            return 0 if self.d > 0 else 1
        return _row(v)

    def dF(self, v: float, F: np.ndarray) -> np.ndarray:
        """Element force rates at velocity ``v``."""
        p, r = self.p, self.row(v)
        out = p.k[r] * v
        if self.d:
            S = _smag(p.static[r], v, self.floor)
            out = np.where(self.slip, p.C[r] * (self.d * p.xi[r] - F / S), out)
        return out

    def margin(self, i: int, v: float, Fi: float) -> float:
        """Breakaway margin ``xi_i |s(v)| - sgn(v) F_i`` of a sticking element (> 0: holds)."""
        if self.d:
            sgn = self.d
        elif v == 0.0:
            return 1.0 + abs(Fi)  # at rest nothing breaks away
        else:
            sgn = 1 if v > 0.0 else -1
        r = 0 if sgn > 0 else 1
        return self.p.xi[r, i] * _smag(self.p.static[r], v, self.floor) - sgn * Fi


def _margin(p, floor: float, i: int, d: int, v: float, Fi: float) -> float:
    """Breakaway margin ``xi_i |s(v)| - d F_i`` of element ``i`` for motion in direction ``d``."""
    r = 0 if d > 0 else 1
    return p.xi[r, i] * _smag(p.static[r], v, floor) - d * Fi


def _gms_initial_breakaway(mode: _GMSMode, v: float, F: np.ndarray, tol: float) -> np.ndarray:
    """Sticking elements already at or past their threshold (only while moving)."""
    out = np.zeros(F.size, dtype=bool)
    if v == 0.0 and not mode.d:
        return out
    for i in np.flatnonzero(mode.stick):
        if mode.margin(i, v, F[i]) <= tol:
            out[i] = True
    return out


# --------------------------------------------------------------------------- public API
def reference_force_driven(
    model,
    m,
    u,
    dt: float,
    *,
    method: str = "LSODA",
    rtol: float = 1e-10,
    atol: float = 1e-12,
    max_step: float | None = None,
    max_events: int = MAX_EVENTS,
) -> dict[str, Any]:
    """Mass driven by a sampled force against dynamic friction, solved by ``solve_ivp``.

    Integrates ``dx/dt = v``, ``m dv/dt = u(t) - F`` together with the friction
    states, starting at rest (``x = v = 0``, ``z = 0`` / every ``F_i = 0``, every GMS
    element sticking). ``u`` is sampled at ``t_k = k dt`` and linearly interpolated.

    LuGre and Dahl are integrated over the whole record in one call (their
    right-hand side is continuous). GMS is integrated piecewise between switching
    events — breakaway of a sticking element and velocity reversal while some
    element slips — restarting after each event with the new stick/slip flags.

    Parameters
    ----------
    model : LuGre | Dahl | GMS | Directional
        Dynamic friction law (a ``Directional`` of one of them picks its parameter
        set by the sign of ``v``).
    m : float or Mass
        Moving mass [kg] (or inertia [kg·m²]), > 0.
    u : array_like, shape (N,)
        Driving force [N] at ``t_k = k dt``, ``N >= 2``, finite.
    dt : float
        Sample period [s], > 0.
    method : {"LSODA", "RK45", "RK23", "DOP853", "Radau", "BDF"}
        ``solve_ivp`` method.
    rtol, atol : float
        ``solve_ivp`` tolerances, > 0.
    max_step : float or None
        Largest step [s]; ``None`` for no limit.
    max_events : int
        Cap on GMS switching events; exceeding it raises :class:`SimulationError`.

    Returns
    -------
    dict
        ``t`` (N,) [s]; ``x`` (N,) [m]; ``v`` (N,) [m/s]; ``friction`` (N,) friction force [N] at
        the samples (``"F"``: deprecated old key) (LuGre ``sigma0 z + sigma1 dz/dt + sigma2 v``, GMS
        ``sum F_i + sigma2 v``); ``states`` (N, 1) ``z`` or (N, M) ``F_i``;
        ``nfev`` right-hand-side evaluations; ``wall_s`` wall time [s];
        ``n_events``, ``n_breakaway``, ``n_reversal`` (GMS switching events; 0 for LuGre);
        for GMS also ``event_log``, a list of ``(t, "breakaway" | "reversal", element)``
        (element ``-1`` for a reversal).

    Raises
    ------
    ParameterError
        Bad ``model``, ``m``, ``dt``, ``method`` or tolerances.
    DataError
        ``u`` not a finite 1-D signal of at least 2 samples.
    SimulationError
        ``solve_ivp`` fails, or the GMS event count exceeds ``max_events`` / the
        switching chatters without progress.

    Examples
    --------
    >>> import numpy as np, frictionkit as fk
    >>> from frictionkit.simulation.reference import reference_force_driven
    >>> law = fk.Stribeck(Fc=1.0, Fs=1.5, vs=1e-3, sigma2=0.4)
    >>> out = reference_force_driven(fk.LuGre(law, sigma0=1e5, sigma1=63.2), 1.0,
    ...                              np.full(201, 0.5), 1e-3)
    >>> bool(abs(out["x"]).max() < 1e-4)        # 0.5 N < Fs: stays in pre-sliding
    True
    """
    owner = "reference_force_driven"
    kind = kind_of(model)
    mval = _mass_value(owner, m)
    u = val.signal("u", u)
    dt, rtol, atol, max_step = _check_common(owner, dt, method, rtol, atol, max_step)
    max_events = int(max_events)
    if max_events < 0:
        raise ParameterError(f"{owner}.max_events = {max_events}: must be >= 0")

    N = u.size
    t = dt * np.arange(N)
    T = t[-1]
    du = np.diff(u)

    def u_at(tt: float) -> float:
        k = min(max(int(tt / dt), 0), N - 2)
        return u[k] + du[k] * (tt / dt - k)

    tic = time.perf_counter()
    if kind == "lugre":
        p = pack_lugre(model)
        static, dyn = p.static, p.dyn
        floor = _floor(static)

        def rhs(tt, y):
            v, z = y[1], y[2]
            zd = _lugre_zdot(static, dyn, floor, v, z)
            r = _row(v)
            F = dyn[r, 0] * z + dyn[r, 1] * zd + static[r, 4] * v
            return np.array([v, (u_at(tt) - F) / mval, zd])

        sol = solve_ivp(
            rhs, (0.0, T), np.zeros(3), method=method, t_eval=t, rtol=rtol, atol=atol,
            max_step=max_step,
        )
        if sol.status != 0:
            raise _fail(owner, sol, 0.0)
        x, v, z = sol.y
        F = np.array([_lugre_force(static, dyn, floor, vi, zi) for vi, zi in zip(v, z)])
        return _TwinOutput(
            t=t, x=x, v=v, friction=F, states=z[:, None], nfev=int(sol.nfev),
            wall_s=time.perf_counter() - tic, n_events=0, n_breakaway=0, n_reversal=0,
        )

    # ----------------------------------------------------------------- GMS
    p_full = pack_gms(model)
    # An element with zero weight in both directions carries no force at all (it slips as
    # soon as it is loaded and relaxes to 0): leave it out rather than chatter over it.
    keep = (p_full.xi > 0.0).any(axis=0)
    p = PackedGMS(p_full.static, p_full.k[:, keep], p_full.xi[:, keep], p_full.C)
    M = int(keep.sum())
    floor = _floor(p.static)
    S_ref = float(np.max(p.static[:, :2]))
    tol = 1e-10 * S_ref
    out = np.empty((N, 2 + M))
    out[0] = 0.0
    filled = 1
    y = np.zeros(2 + M)
    t0 = 0.0
    slip = np.zeros(M, dtype=bool)
    d = 0
    nfev = n_break = n_rev = stalls = 0
    log: list[tuple[float, str, int]] = []

    while t0 < T:
        mode = _GMSMode(p, floor, slip, d)
        # Elements already at (or past) their threshold in the direction of motion break
        # away before integrating. At rest, that direction is the sign of the acceleration
        # (or, if it is zero, of the force slope) about to set the mass moving.
        v0 = y[1]
        if mode.d:
            d_go = mode.d
        elif v0 != 0.0:
            d_go = 1 if v0 > 0.0 else -1
        else:
            a0 = u_at(t0) - y[2:].sum()
            if a0 == 0.0:
                a0 = du[min(max(int(t0 / dt), 0), N - 2)]
            d_go = 0 if a0 == 0.0 else (1 if a0 > 0.0 else -1)
        if d_go:
            due = np.array(
                [not slip[i] and _margin(p, floor, i, d_go, v0, y[2 + i]) <= tol for i in range(M)],
                dtype=bool,
            )
            if due.any():
                slip = slip | due
                d = d_go
                n_break += int(due.sum())
                log += [(t0, "breakaway", int(j)) for j in np.flatnonzero(due)]
                mode = _GMSMode(p, floor, slip, d)

        def rhs(tt, yy, mode=mode):
            v = yy[1]
            Fi = yy[2:]
            r = mode.row(v)
            Ft = Fi.sum() + p.static[r, 4] * v
            return np.concatenate(([v, (u_at(tt) - Ft) / mval], mode.dF(v, Fi)))

        # Event functions. At ta each returns its value at the exact initial state: the
        # dense output of some methods (LSODA) does not reproduce ya exactly at ta, and a
        # margin that jumps at v = 0 would otherwise confuse the root finder.
        stick_idx = np.flatnonzero(mode.stick)

        def make_events(ta, ya, mode=mode, stick_idx=stick_idx):
            evs = []
            for i in stick_idx:
                def ev(tt, yy, i=i, ta=ta, g0=mode.margin(i, ya[1], ya[2 + i])):
                    return g0 if tt == ta else mode.margin(i, yy[1], yy[2 + i])

                ev.terminal = True
                ev.direction = -1
                evs.append(ev)
            if mode.d:
                def ev_rev(tt, yy, dd=mode.d, ta=ta, g0=mode.d * ya[1]):
                    return g0 if tt == ta else dd * yy[1]

                ev_rev.terminal = True
                ev_rev.direction = -1
                evs.append(ev_rev)
            return evs

        def run(ta, ya, tb, k_first, step=None, rhs=rhs, make_events=make_events):
            """Integrate from (ta, ya) towards tb; samples k >= k_first up to tb are reported."""
            k_last = int(np.searchsorted(t, tb, side="right"))
            kw = {"max_step": max_step}
            if step is not None:
                kw = {"max_step": min(step, max_step), "first_step": step}
            args = (rhs, (ta, tb), ya)
            kw.update(method=method, t_eval=t[k_first:k_last], rtol=rtol, atol=atol)
            try:
                return solve_ivp(*args, events=make_events(ta, ya), dense_output=True, **kw)
            except ValueError as exc:
                # scipy cannot build the dense output when the event falls exactly on the
                # start of a step (repeated node); redo this piece without it (no refinement).
                if "strictly increasing" not in str(exc):
                    raise
                return solve_ivp(*args, events=make_events(ta, ya), dense_output=False, **kw)

        sol = run(t0, y, T, filled)
        nfev += int(sol.nfev)
        if sol.status == -1:
            raise _fail(owner, sol, t0)
        if sol.status == 1 and sol.sol is not None and len(sol.sol.ts) >= 2:
            # Refine: redo the last step, in which the event was found, with steps 64 times
            # shorter, so that the event time and the state there do not carry the error of
            # the method's (lower-order) dense output over one long step.
            t_ev = max(te[-1] for te in sol.t_events if te.size)
            t_old = float(sol.sol.ts[-2])
            h = t_ev - t_old
            if h > 1e-12 * max(1.0, t_ev):
                y_old = y if t_old == t0 else np.asarray(sol.sol(t_old), dtype=float)
                n_coarse = len(sol.t)
                k_old = max(int(np.searchsorted(t, t_old, side="right")), 1)
                filled_before, sol_coarse = filled, sol
                if n_coarse:
                    out[filled:filled + n_coarse] = np.asarray(sol.y).T
                filled = min(filled + n_coarse, k_old)
                t_end = min(t_ev + h, T)
                try:
                    sol = run(t_old, y_old, t_end, filled, step=h / 64.0)
                except ValueError as exc:
                    # scipy's event root finder can see no sign change on the refined
                    # step when the coarse event sat on a step boundary: keep the coarse piece.
                    if "different signs" not in str(exc):
                        raise
                    sol, filled, t_old = sol_coarse, filled_before, t0
                nfev += int(sol.nfev)
                if sol.status == -1:
                    raise _fail(owner, sol, t_old)
                t0 = t_old
                if sol.status == 0 and t_end < T:
                    # No event after all (the coarse dense output invented it): carry on.
                    n_new = len(sol.t)
                    if n_new:
                        out[filled:filled + n_new] = np.asarray(sol.y).T
                        filled += n_new
                    y = np.asarray(sol.sol(t_end), dtype=float)
                    t0 = t_end
                    continue
        n_new = len(sol.t)  # a list, not an array, when no t_eval point was reached
        if n_new:
            out[filled:filled + n_new] = np.asarray(sol.y).T
            filled += n_new
        if sol.status == 0:
            break

        # A terminal event ended the piece: find which one(s) and when.
        t_ev = [te[-1] if te.size else -math.inf for te in sol.t_events]
        j = int(np.argmax(t_ev))
        t_e = t_ev[j]
        y = np.array(sol.y_events[j][-1], dtype=float)
        if t_e - t0 <= 1e-14 * max(1.0, abs(t0)):
            stalls += 1
            if stalls > _MAX_STALLS + 4 * M:
                raise SimulationError(
                    f"{owner}: GMS switching chatters at t = {t_e:.9g} s "
                    f"({stalls} zero-length pieces in a row, v = {y[1]:.3g} m/s); "
                    "the stick/slip state cannot be resolved"
                )
        else:
            stalls = 0
        reversed_ = mode.d and sol.t_events[-1].size and sol.t_events[-1][-1] >= t_e
        if reversed_:
            # Velocity reversal: every slipping element sticks again.
            y[1] = 0.0
            slip = np.zeros(M, dtype=bool)
            d = 0
            n_rev += 1
            log.append((t_e, "reversal", -1))
        else:
            broke = np.zeros(M, dtype=bool)
            for n_i, i in enumerate(stick_idx):
                te = sol.t_events[n_i]
                if (te.size and te[-1] >= t_e) or mode.margin(i, y[1], y[2 + i]) <= tol:
                    broke[i] = True
            if not mode.d:
                v_e = y[1]
                if v_e != 0.0:
                    d = 1 if v_e > 0.0 else -1
                else:
                    a = u_at(t_e) - y[2:].sum()
                    d = 1 if a >= 0.0 else -1
            slip = slip | broke
            n_break += int(broke.sum())
            log += [(t_e, "breakaway", int(j)) for j in np.flatnonzero(broke)]
        t0 = t_e
        if n_break + n_rev > max_events:
            raise SimulationError(
                f"{owner}: more than max_events = {max_events} GMS switching events "
                f"(reached t = {t0:.6g} s of {T:.6g} s); raise max_events or check the input"
            )

    if filled < N:  # the last event fell exactly on the final sample
        out[filled:] = y
    x, v = out[:, 0], out[:, 1]
    Fi = np.zeros((N, keep.size))
    Fi[:, keep] = out[:, 2:]
    sig2 = np.where(v < 0.0, p.static[1, 4], p.static[0, 4])
    F = Fi.sum(axis=1) + sig2 * v
    return _TwinOutput(
        t=t, x=x, v=v, friction=F, states=Fi, nfev=nfev, wall_s=time.perf_counter() - tic,
        n_events=n_break + n_rev, n_breakaway=n_break, n_reversal=n_rev,
        event_log=[(te, kind_, int(np.flatnonzero(keep)[j]) if j >= 0 else -1) for te, kind_, j in log],
    )


def reference_motion_driven(
    model,
    x,
    dt: float,
    *,
    method: str = "LSODA",
    rtol: float = 1e-10,
    atol: float = 1e-12,
    max_step: float | None = None,
) -> dict[str, Any]:
    """Friction along a prescribed, sampled position, solved interval by interval.

    The position is linearly interpolated between samples, so the velocity on
    ``[t_k, t_{k+1}]`` is the constant ``(x_{k+1} - x_k) / dt``. Each interval is
    integrated with ``solve_ivp``; for GMS the breakaways inside an interval are
    events, and at the start of an interval whose velocity is not in the direction
    of slip (reversed or zero) every slipping element sticks.

    Parameters
    ----------
    model : LuGre | Dahl | GMS | Directional
        Dynamic friction law.
    x : array_like, shape (N,)
        Position [m] at ``t_k = k dt``, ``N >= 2``, finite.
    dt : float
        Sample period [s], > 0.
    method, rtol, atol, max_step
        As in :func:`reference_force_driven`.

    Returns
    -------
    dict
        ``t`` (N,) [s]; ``friction`` (N,) friction force [N] (``"F"``: deprecated old key) from the state at ``t_k`` and the
        velocity of the interval ending at ``t_k`` (the first interval's for
        ``k = 0``); ``v`` (N,) that velocity; ``states`` (N, 1) ``z`` or (N, M)
        ``F_i``; for GMS also ``slipping`` (N, M) flags at ``t_k`` and
        ``n_breakaway``; ``nfev``; ``wall_s``.

    Raises
    ------
    ParameterError
        Bad ``model``, ``dt``, ``method`` or tolerances.
    DataError
        ``x`` not a finite 1-D signal of at least 2 samples.
    SimulationError
        ``solve_ivp`` fails.

    Examples
    --------
    >>> import numpy as np, frictionkit as fk
    >>> from frictionkit.simulation.reference import reference_motion_driven
    >>> law = fk.Stribeck(Fc=1.0, Fs=1.5, vs=1e-3, sigma2=0.4)
    >>> gms = fk.GMS(law, k=[1e4, 1e5, 1e6], xi=[0.5, 0.3, 0.2], C=20.0)
    >>> out = reference_motion_driven(gms, np.array([0.0, 1e-7]), 1e-3)
    >>> round(float(out["friction"][1]), 6)          # all sticking: (sum k) * x + sigma2 * v
    0.11104
    """
    owner = "reference_motion_driven"
    kind = kind_of(model)
    x = val.signal("x", x)
    dt, rtol, atol, max_step = _check_common(owner, dt, method, rtol, atol, max_step)
    N = x.size
    t = dt * np.arange(N)
    vi = np.diff(x) / dt  # velocity of interval k = [t_k, t_{k+1}]
    vs_ = np.concatenate(([vi[0]], vi))  # velocity of the interval ending at t_k
    tic = time.perf_counter()
    nfev = 0

    if kind == "lugre":
        p = pack_lugre(model)
        static, dyn = p.static, p.dyn
        floor = _floor(static)
        z = np.zeros(N)
        for k in range(N - 1):
            v = vi[k]
            if v == 0.0:
                z[k + 1] = z[k]
                continue

            def rhs(tt, y, v=v):
                return [_lugre_zdot(static, dyn, floor, v, y[0])]

            sol = solve_ivp(
                rhs, (t[k], t[k + 1]), [z[k]], method=method, rtol=rtol, atol=atol,
                max_step=max_step,
            )
            nfev += int(sol.nfev)
            if sol.status != 0:
                raise _fail(owner, sol, t[k])
            z[k + 1] = sol.y[0, -1]
        F = np.array([_lugre_force(static, dyn, floor, v, zk) for v, zk in zip(vs_, z)])
        return _TwinOutput(t=t, friction=F, v=vs_, states=z[:, None], nfev=nfev, wall_s=time.perf_counter() - tic)

    p = pack_gms(model)
    M = p.k.shape[1]
    floor = _floor(p.static)
    tol = 1e-10 * float(np.max(p.static[:, :2]))
    Fi = np.zeros((N, M))
    flags = np.zeros((N, M), dtype=bool)
    slip = np.zeros(M, dtype=bool)
    d = 0
    n_break = 0
    for k in range(N - 1):
        v = vi[k]
        dv = 0 if v == 0.0 else (1 if v > 0.0 else -1)
        if slip.any() and dv != d:
            slip[:] = False  # reversal (or stop): every slipping element sticks
        F = Fi[k].copy()
        if dv == 0:
            Fi[k + 1] = F
            flags[k + 1] = slip
            continue
        d = dv
        ta, tb = t[k], t[k + 1]
        while True:
            mode = _GMSMode(p, floor, slip, d)
            due = _gms_initial_breakaway(mode, v, F, tol)
            if due.any():
                slip |= due
                n_break += int(due.sum())
                mode = _GMSMode(p, floor, slip, d)
            stick_idx = np.flatnonzero(mode.stick)
            events = []
            for i in stick_idx:
                def ev(tt, yy, i=i, mode=mode, v=v):
                    return mode.margin(i, v, yy[i])

                ev.terminal = True
                ev.direction = -1
                events.append(ev)

            def rhs(tt, yy, mode=mode, v=v):
                return mode.dF(v, yy)

            sol = solve_ivp(
                rhs, (ta, tb), F, method=method, events=events or None, rtol=rtol,
                atol=atol, max_step=max_step,
            )
            nfev += int(sol.nfev)
            if sol.status == -1:
                raise _fail(owner, sol, ta)
            if sol.status == 0:
                F = sol.y[:, -1]
                break
            t_ev = [te[-1] if te.size else -math.inf for te in sol.t_events]
            j = int(np.argmax(t_ev))
            ta = t_ev[j]
            F = np.array(sol.y_events[j][-1], dtype=float)
            for n_i, i in enumerate(stick_idx):
                te = sol.t_events[n_i]
                if (te.size and te[-1] >= ta) or mode.margin(i, v, F[i]) <= tol:
                    slip[i] = True
                    n_break += 1
            if ta >= tb:
                break
        Fi[k + 1] = F
        flags[k + 1] = slip

    sig2 = np.where(vs_ < 0.0, p.static[1, 4], p.static[0, 4])
    Ftot = Fi.sum(axis=1) + sig2 * vs_
    return _TwinOutput(
        t=t, friction=Ftot, v=vs_, states=Fi, slipping=flags, n_breakaway=n_break, nfev=nfev,
        wall_s=time.perf_counter() - tic,
    )
