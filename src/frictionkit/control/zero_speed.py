"""Zero-speed region analysis after seed 001 §3 and Table 2.

* :func:`find_crossings` — zero-speed points of a reference (reverse or not).
* :func:`classify_crossings` — slow/fast: does the drive force on the table
  ``F_bn = M_t a + f_g + C_t v`` (eq. 2) change sign *before* zero speed? Fast deceleration
  -> deformation Pattern II at zero speed, slow -> Pattern I (§3.2, Figs. 8-9).
* :func:`deformation_ratio` — ``l_d = Δx_t / Δθ_m`` over a window ``T_p`` (eqs. 3-4).
* :func:`select_compensators` — Table 2: which compensation each crossing needs.
* :func:`reversal_lead` — how long before zero speed a signal (motor input, drive force)
  turned against the motion and stayed so (Fig. 5(b), Pattern II).
* :func:`pattern_i_stop_segments` — the redesigned deceleration Table 2 asks for in a fast
  non-reverse motion: the fastest stop whose drive force keeps the direction of motion.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from .. import _validate as val
from ..errors import DataError
from typing import TYPE_CHECKING

if TYPE_CHECKING:
    from ..control.trajectories import Reference
    from collections.abc import Sequence
    from numpy.typing import ArrayLike

#: Seed 001 Table 2: motion type -> (deformation patterns, compensation law).
#: Laws: ``sinc`` = compensation after the zero-speed point (eq. 6, refs. 8, 11-14),
#: ``sigmoid`` = compensation before the zero-speed point (eq. 5, this paper),
#: ``hold`` = after-zero compensation of a non-reverse motion (ref. 12: friction keeps
#: its direction), ``None`` = the reference must be redesigned.
TABLE2 = {
    "slow_reverse": ("Pattern I -> Pattern II", "sinc"),
    "fast_reverse": ("Pattern II -> Pattern II", "sigmoid"),
    "slow_non_reverse": ("Pattern I -> Pattern I", "hold"),
    "fast_non_reverse": ("Pattern II -> Pattern I", None),
}


@dataclass(frozen=True)
class Crossing:
    """One zero-speed point of a reference.

    Attributes
    ----------
    index : int — sample nearest to the zero-speed instant.
    t0 : float — zero-speed instant [s] (interpolated).
    x0 : float — reference position there [m].
    before, after : int — direction of motion (+1/-1) before and after.
    reverse : bool — ``after != before``.
    fast : bool or None — drive force reversed before zero speed (None until classified).
    drive_force : float — predicted ``F_bn`` just before zero speed [N] (nan until classified).
    """

    index: int
    t0: float
    x0: float
    before: int
    after: int
    fast: bool | None = None
    drive_force: float = float("nan")

    @property
    def reverse(self) -> bool:
        return self.after != self.before

    @property
    def kind(self) -> str:
        """``slow_reverse``, ``fast_reverse``, ``slow_non_reverse``, ``fast_non_reverse`` or ``unclassified``."""
        if self.fast is None:
            return "unclassified"
        return ("fast_" if self.fast else "slow_") + ("reverse" if self.reverse else "non_reverse")


def find_crossings(t: ArrayLike, v: ArrayLike, x: ArrayLike | None=None, *, v_tol: float = 1e-12) -> list[Crossing]:
    """Zero-speed points of a sampled velocity ``v`` [m/s] (starts and stops at rest excluded).

    A crossing is a sign change of ``v``, a run of samples with ``|v| <= v_tol`` between
    two moving samples, or a *touch*: a local minimum of ``|v|`` no larger than the velocity
    change of an adjacent sample step (zero speed reached between samples, same direction).

    Examples
    --------
    >>> import numpy as np
    >>> from frictionkit.control.zero_speed import find_crossings
    >>> t = np.linspace(0, 1, 11); v = np.array([0, 1, 1, .5, -.5, -1, -1, 0, -1, -1, 0.])
    >>> [(c.index, c.before, c.after) for c in find_crossings(t, v)]
    [(4, 1, -1), (7, -1, -1)]
    """
    t = val.signal("t", t)
    v = val.signal("v", v)
    if v.size != t.size:
        raise DataError(f"v has {v.size} samples: must match t ({t.size})")
    xa = None if x is None else val.signal("x", x)
    s = np.where(np.abs(v) <= v_tol, 0, np.sign(v)).astype(int)
    nz = np.flatnonzero(s != 0)
    out = []
    for i, j in zip(nz[:-1], nz[1:]):
        if j == i + 1 and s[i] == s[j]:
            continue
        if j == i + 1:  # sign change between two samples
            f = v[i] / (v[i] - v[j])
            t0 = t[i] + f * (t[j] - t[i])
            k = i if f < 0.5 else j
            x0 = np.nan if xa is None else xa[i] + f * (xa[j] - xa[i])
        else:
            k = (i + j) // 2
            t0 = t[k] if (j - i) % 2 == 0 else 0.5 * (t[k] + t[k + 1])
            x0 = np.nan if xa is None else xa[k]
        out.append(Crossing(index=int(k), t0=float(t0), x0=float(x0), before=int(s[i]), after=int(s[j])))
    # touches: |v| has a local minimum that is within one sample step of zero
    av = np.abs(v)
    step = np.abs(np.diff(v))
    k = np.arange(1, v.size - 1)
    touch = ((s[k - 1] == s[k]) & (s[k] == s[k + 1]) & (s[k] != 0) & (av[k] <= av[k - 1]) & (av[k] < av[k + 1])
             & (av[k] <= np.maximum(step[k - 1], step[k])))
    for kk in k[touch]:
        x0 = np.nan if xa is None else xa[kk]
        out.append(Crossing(index=int(kk), t0=float(t[kk]), x0=float(x0), before=int(s[kk]), after=int(s[kk])))
    out.sort(key=lambda c: c.index)
    return out


def classify_crossings(reference: Reference, *, table_mass: float, guide_friction: float,
                       guide_viscosity: float = 0.0, window: float = 10e-3) -> list[Crossing]:
    """Find and classify the zero-speed points of ``reference`` (seed 001 §3.2).

    The drive force needed on the table is predicted from eq. 2 with the reference motion,
    ``F_bn = M_t a + f_g sgn(v) + C_t v``; a crossing is *fast* if, within ``window`` [s]
    before zero speed, ``F_bn`` opposes the motion (the stage is braked by the screw before
    it stops: Pattern II), otherwise *slow* (Pattern I).

    Examples
    --------
    >>> from frictionkit.control.trajectories import cosine_reference
    >>> from frictionkit.control.zero_speed import classify_crossings
    >>> cs = classify_crossings(cosine_reference(duration=1.2), table_mass=273.0, guide_friction=100.0)
    >>> [(round(c.t0, 3), c.kind) for c in cs]
    [(0.5, 'fast_reverse'), (1.0, 'fast_reverse')]
    """
    M = val.positive("classify_crossings", "table_mass", table_mass)
    Fg = val.nonnegative("classify_crossings", "guide_friction", guide_friction)
    Ct = val.nonnegative("classify_crossings", "guide_viscosity", guide_viscosity)
    W = val.positive("classify_crossings", "window", window)
    t, v, a = reference.t, reference.v, reference.a
    out = []
    for c in find_crossings(t, v, reference.x):
        sel = (t >= c.t0 - W) & (t < c.t0) & (np.sign(v) == c.before)
        if not sel.any():
            sel = np.zeros(t.size, bool)
            sel[max(c.index - 1, 0)] = True
        F = M * a[sel] + Fg * c.before + Ct * v[sel]
        fast = bool(np.any(c.before * F < 0.0))
        out.append(Crossing(index=c.index, t0=c.t0, x0=c.x0, before=c.before, after=c.after,
                            fast=fast, drive_force=float(F[-1])))
    return out


@dataclass(frozen=True)
class Selection:
    """The Table 2 choice for one crossing: ``law`` (``sinc``/``sigmoid``/``hold``) and a flag."""

    crossing: Crossing
    law: str
    needs_new_reference: bool


def select_compensators(crossings: Sequence[Crossing], *, fallback: str = "hold") -> list[Selection]:
    """Seed 001 Table 2 as a rule: slow reverse -> ``sinc``, fast reverse -> ``sigmoid``,
    slow non-reverse -> ``hold``; fast non-reverse is flagged ``needs_new_reference`` and gets
    ``fallback``.
    """
    out = []
    for c in crossings:
        if c.fast is None:
            raise DataError(f"crossing at t0 = {c.t0!r} s is not classified: use classify_crossings first")
        law = TABLE2[c.kind][1]
        out.append(Selection(crossing=c, law=fallback if law is None else law, needs_new_reference=law is None))
    return out


@dataclass(frozen=True, eq=False)
class DeformationRatio:
    """``l_d`` (eq. 4) per window end ``t`` [s]; ``ld`` is NaN where ``|R Δθ_m| < min_displacement``."""

    t: np.ndarray
    ld: np.ndarray
    R: float
    Tp: float

    @property
    def ratio(self) -> np.ndarray:
        """``l_d / R`` (1 for a rigid drive)."""
        return self.ld / self.R


def deformation_ratio(t: ArrayLike, x_t: ArrayLike, theta_m: ArrayLike, *, R: float, Tp: float, min_displacement: float = 10e-6) -> DeformationRatio:
    """Seed 001 eqs. 3-4: ``l_d = Δx_t / Δθ_m`` over windows of length ``Tp`` [s].

    Parameters
    ----------
    t : array_like — uniform sample times [s].
    x_t : array_like — table position [m] (linear scale).
    theta_m : array_like — motor angle [rad] (encoder).
    R : float — screw ratio [m/rad]; ``l_d = R`` without deformation.
    Tp : float — window [s].
    min_displacement : float — windows whose motor displacement ``|R Δθ_m|`` is below this
        [m] are not evaluated (NaN): there ``l_d`` is dominated by the position resolution
        (seed 001 §3.3, slow cases).

    Examples
    --------
    >>> import numpy as np
    >>> from frictionkit.control.zero_speed import deformation_ratio
    >>> t = np.arange(0, 0.1, 1e-3); th = 10 * t; R = 2e-3
    >>> d = deformation_ratio(t, R * th, th, R=R, Tp=5e-3, min_displacement=1e-6)
    >>> bool(np.allclose(d.ratio[~np.isnan(d.ratio)], 1.0))
    True
    """
    t = val.signal("t", t)
    x_t = val.signal("x_t", x_t)
    th = val.signal("theta_m", theta_m)
    if not (t.size == x_t.size == th.size):
        raise DataError(f"t, x_t, theta_m have {t.size}, {x_t.size}, {th.size} samples: must match")
    R = val.positive("deformation_ratio", "R", R)
    Tp = val.positive("deformation_ratio", "Tp", Tp)
    dmin = val.nonnegative("deformation_ratio", "min_displacement", min_displacement)
    dt = np.diff(t)
    if np.any(dt <= 0):
        raise DataError("t: must be strictly increasing")
    m = max(int(round(Tp / np.median(dt))), 1)
    if m >= t.size:
        raise DataError(f"Tp = {Tp!r} s spans {m} samples: the record has only {t.size}")
    dx = x_t[m:] - x_t[:-m]
    dth = th[m:] - th[:-m]
    ok = np.abs(R * dth) >= max(dmin, 1e-300)
    ld = np.full(dx.size, np.nan)
    ld[ok] = dx[ok] / dth[ok]
    return DeformationRatio(t=t[m:], ld=ld, R=R, Tp=Tp)


def _decel_windows(d: DeformationRatio, t_start: float, t_zero: float) -> np.ndarray:
    sel = (d.t - d.Tp >= t_start - 1e-12) & (d.t <= t_zero + 1e-12) & ~np.isnan(d.ld)
    if not sel.any():
        raise DataError(f"no evaluable l_d window inside [{t_start!r}, {t_zero!r}] s")
    return d.ratio[sel]


def min_ratio_before_zero(d: DeformationRatio, *, t_start: float, t_zero: float) -> float:
    """``min(l_d)/R`` over windows lying inside the deceleration ``[t_start, t_zero]``
    (window start ``>= t_start``, window end ``<= t_zero``), NaN windows skipped."""
    return float(np.min(_decel_windows(d, t_start, t_zero)))


def max_ratio_before_zero(d: DeformationRatio, *, t_start: float, t_zero: float) -> float:
    """``max(l_d)/R`` over the same windows as :func:`min_ratio_before_zero`."""
    return float(np.max(_decel_windows(d, t_start, t_zero)))


def reversal_lead(t, u, crossing: Crossing, *, since: float | None = None) -> float | None:
    """How long before the zero-speed instant ``crossing.t0`` the signal ``u`` turned against
    the motion and stayed so until ``t0`` [s]; ``None`` if ``u`` still has the direction of
    motion at the last sample before ``t0``.

    ``u`` is e.g. the motor input (seed 001 Fig. 5(b): "the control input ... changed its
    direction before the velocity comes to zero-speed point") or the drive force ``F_bn``
    (eq. 2, Pattern II). The lead is ``t0 - t_k`` for the first sample ``t_k`` of the final run
    of samples before ``t0`` with ``sgn(u) = -crossing.before``; ``since`` [s] bounds the search
    from below (default: the start of the record).

    Examples
    --------
    >>> import numpy as np
    >>> from frictionkit.control.zero_speed import Crossing, reversal_lead
    >>> t = np.arange(10) * 1e-3; u = np.array([3, 2, 1, -1, 1, -1, -2, -3, -2, 1.])
    >>> c = Crossing(index=8, t0=8e-3, x0=0.0, before=1, after=-1)
    >>> round(reversal_lead(t, u, c) * 1e3, 6)
    3.0
    """
    t = val.signal("t", t)
    u = val.signal("u", u)
    if u.size != t.size:
        raise DataError(f"u has {u.size} samples: must match t ({t.size})")
    lo = -np.inf if since is None else float(since)
    idx = np.flatnonzero((t < crossing.t0) & (t >= lo))
    if idx.size == 0:
        raise DataError(f"no sample before the zero-speed instant t0 = {crossing.t0!r} s")
    against = crossing.before * u[idx] < 0.0
    if not against[-1]:
        return None
    keep = np.flatnonzero(~against)
    first = idx[keep[-1] + 1] if keep.size else idx[0]
    return float(crossing.t0 - t[first])


def pattern_i_stop_segments(*, speed: float, decel: float, table_mass: float, guide_friction: float,
                            guide_viscosity: float = 0.0, margin: float = 0.5) -> list[tuple[float, float]]:
    """Redesigned stop for a fast non-reverse motion (seed 001 Table 2: "redesign of trajectory
    reference is necessary"): the deceleration segments ``[(duration, -a), ...]`` from ``speed``
    to rest (positive direction) for which the drive force on the table predicted by eq. 2,
    ``F_bn = -M_t a + f_g + C_t v``, keeps the direction of motion until zero speed — the stop
    ends in Pattern I, so the following acceleration in the same direction is Pattern I ->
    Pattern I (the case the conventional compensation handles) instead of Pattern II -> I.

    The stop decelerates at ``decel`` down to the speed ``v1 = (M_t decel - f_g) / C_t`` below
    which ``decel`` would turn ``F_bn`` into braking, then at the constant rate
    ``a_s = (1 - margin) f_g / M_t`` to rest, where ``F_bn >= margin f_g > 0`` is left.
    Without guide viscosity the whole stop is at ``a_s``. If ``decel`` already keeps
    ``F_bn >= margin f_g`` at rest, the single segment ``[(speed / decel, -decel)]`` is returned.
    The price is time: the example's stop takes 126 ms instead of 51 ms.

    Examples
    --------
    >>> from frictionkit.control.zero_speed import pattern_i_stop_segments
    >>> segs = pattern_i_stop_segments(speed=50e-3, decel=0.987, table_mass=273.0, guide_friction=100.0,
    ...                                guide_viscosity=1e4)
    >>> [(round(d * 1e3, 1), round(a, 3)) for d, a in segs]
    [(33.5, -0.987), (92.5, -0.183)]
    """
    from .. import _validate as _v

    V = _v.positive("pattern_i_stop_segments", "speed", speed)
    a_f = _v.positive("pattern_i_stop_segments", "decel", decel)
    M = _v.positive("pattern_i_stop_segments", "table_mass", table_mass)
    Fg = _v.positive("pattern_i_stop_segments", "guide_friction", guide_friction)
    Ct = _v.nonnegative("pattern_i_stop_segments", "guide_viscosity", guide_viscosity)
    mg = _v.nonnegative("pattern_i_stop_segments", "margin", margin)
    if not mg < 1.0:
        raise DataError(f"pattern_i_stop_segments margin = {margin!r}: must be < 1")
    if M * a_f <= Fg * (1.0 - mg):  # already Pattern I at rest
        return [(V / a_f, -a_f)]
    a_s = (1.0 - mg) * Fg / M
    v1 = min(V, (M * a_f - Fg) / Ct) if Ct > 0.0 else V
    v1 = max(v1, 0.0)
    segs = []
    if V > v1:
        segs.append(((V - v1) / a_f, -a_f))
    if v1 > 0.0:
        segs.append((v1 / a_s, -a_s))
    return segs
