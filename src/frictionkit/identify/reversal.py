"""Compensator parameters from a reversal record (seed 001 Figs. 12-13, eqs. 5-6).

Seed 001 types its compensators' parameters in (sinc ``xs = 10 µm``, ``F0 = 2.431 N·m`` read
off Fig. 13; ``F0 = 2.65 N·m`` and sigmoid ``sigma = 2`` in §5.3). :func:`fit_reversal`
identifies them from the friction measured around velocity reversals, so that a
:class:`~frictionkit.control.compensators.RollingCompensator` can use identified values.

Each reversal is a turning point of the position (the extremum between two runs, confirmed
once the axis has moved ``min_travel`` away from it, so encoder noise makes no reversals).
Around it, with ``d`` the new direction and the samples split halfway in time between
turning points (as :meth:`RollingCompensator.signal` splits them; the samples before the
first turn are left out: there the axis starts from rest, not from a steady slide), the displacement is
``xi = sgn(t - t0) |x - x0|`` and the friction in the new direction is ``d (F - J a)``.
Fitted by least squares, one ``F0`` for both laws (seed 001 §5.3 uses one ``F0`` for all):

* sinc (eq. 6), ``F0`` and ``xs``: every sample with ``|xi| <= window`` — before the
  reversal the law is ``-F0`` (the previous direction's friction), after it the sinc rise;
* sigmoid (eq. 5), ``sigma`` with that ``F0`` held: the samples after the reversal
  (``0 <= xi <= window``) only. (A joint fit would let the sigmoid's misfit of the
  friction's shape pull ``F0``: measured 1.2 % on an exact sinc record.)
  The sigmoid falls to 0 *before* zero speed by design (it helps braking, seed 001 Fig. 11);
  the friction does not, so the samples before the reversal would only bias ``sigma``.

``xs`` and ``sigma`` are positive: their intervals come from the log scale (never across
zero); a parameter the record cannot pin (no sample inside the pre-sliding range, a reversal
too fast for the sampling) is flagged with the reason.
"""

from __future__ import annotations

import math
from collections.abc import Mapping

import numpy as np

from ..control.compensators import RollingCompensator
from ..data.recording import Recording
from ..data.signals import derivative
from ..errors import DataError, IdentificationError, ParameterError
from ..models.rolling import sigmoid_compensation, sinc_compensation
from .identifiability import analyse
from .result import IdentificationResult
from typing import TYPE_CHECKING

if TYPE_CHECKING:
    from collections.abc import Sequence

__all__ = ["MIN_TRAVEL_FRACTION", "fit_reversal", "reversal_samples", "turning_points"]

#: Default ``min_travel`` as a fraction of the record's position range (assumption: a
#: reversal record moves well beyond its pre-sliding range, so 5 % of the range is far above
#: the noise and far below any real stroke).
MIN_TRAVEL_FRACTION = 0.05

#: Start value of ``xs`` and ``sigma`` as a fraction of the window (or of the median stroke).
START_FRACTION = 0.1


def turning_points(x, *, min_travel: float) -> list[int]:
    """Indices of the position extrema between runs that travel at least ``min_travel``.

    A turn is confirmed once the position has moved ``min_travel`` back from the running
    extremum; the extremum itself is the turning point.

    Examples
    --------
    >>> import numpy as np
    >>> from frictionkit.identify.reversal import turning_points
    >>> x = np.r_[np.linspace(0, 1, 11), np.linspace(0.9, -1, 20), np.linspace(-0.9, 0, 10)]
    >>> turning_points(x, min_travel=0.5)
    [10, 30]
    """
    x = np.asarray(x, dtype=float)
    out: list[int] = []
    direction, lo, hi, ext = 0, 0, 0, 0
    for i in range(1, x.size):
        if direction == 0:  # until the first run of min_travel, track both extremes
            lo = i if x[i] < x[lo] else lo
            hi = i if x[i] > x[hi] else hi
            if x[hi] - x[lo] >= min_travel:
                direction, ext, first = (1, hi, lo) if hi > lo else (-1, lo, hi)
                if abs(x[first] - x[0]) >= min_travel:  # it went the other way first
                    out.append(int(first))
            continue
        if direction * (x[i] - x[ext]) > 0:
            ext = i
        elif direction * (x[ext] - x[i]) >= min_travel:  # moved back far enough: the extremum was a turn
            out.append(int(ext))
            direction, ext = -direction, i
    return out


def _records(data) -> list[Recording]:
    if isinstance(data, Recording):
        return [data]
    items = list(data.values()) if isinstance(data, Mapping) else list(data) if isinstance(data, (list, tuple)) else None
    if not items or not all(isinstance(r, Recording) for r in items):
        raise DataError(f"fit_reversal: expected a Recording or a list/dict of Recordings, got {type(data).__name__}")
    return items


def reversal_samples(recordings, *, min_travel: float | None = None, inertia: float = 0.0,
                     offset: float = 0.0) -> tuple[np.ndarray, np.ndarray, int, float]:
    """Displacement ``xi`` and friction in the new direction ``d (F - J a - offset)`` around every reversal.

    Returns ``(xi, f, n_reversals, median_stroke)``; see the module docstring for the split
    of the samples between reversals.
    """
    xi_all, f_all, n_rev, strokes = [], [], 0, []
    for r in _records(recordings):
        r.require("x", "F")
        x, t = np.asarray(r.x, float), np.asarray(r.t, float)
        F = np.asarray(r.force(), float) - offset
        if inertia > 0:
            F = F - inertia * derivative(derivative(x, r.dt), r.dt)
        span = float(x.max() - x.min())
        h = min_travel if min_travel is not None else MIN_TRAVEL_FRACTION * span
        if not span > 0:
            raise DataError(f"recording '{r.name}': the position does not change; a reversal record must move")
        tp = turning_points(x, min_travel=h)
        if not tp:
            continue
        t0 = t[tp]
        edges = np.concatenate(([-np.inf], 0.5 * (t0[1:] + t0[:-1]), [np.inf]))
        seg = np.searchsorted(edges, t, side="right") - 1
        for j, k in enumerate(tp):
            sel = seg == j
            if j == 0:  # before the first turn the axis starts from rest (a virgin branch), not a steady slide
                sel &= t >= t[k]
            # the new direction: away from the extremum (a maximum turns the axis negative)
            after = -1.0 if x[k] >= np.max(x[sel]) else 1.0
            xi = np.sign(t[sel] - t[k]) * np.abs(x[sel] - x[k])
            xi_all.append(xi)
            f_all.append(after * F[sel])
            n_rev += 1
        strokes.append(float(np.median(np.abs(np.diff(x[tp])))) if len(tp) > 1 else span)
    if n_rev == 0:
        recs = _records(recordings)
        raise DataError(f"recording '{recs[0].name}': no reversal found (no turn of at least {h:.3g} in position); "
                        "give min_travel or a record with back-and-forth motion")
    return np.concatenate(xi_all), np.concatenate(f_all), n_rev, float(np.median(strokes))


def fit_reversal(
    recording: Recording | Sequence[Recording] | Mapping[str, Recording],
    *,
    window: float | None = None,
    min_travel: float | None = None,
    inertia: float = 0.0,
    offset: float = 0.0,
) -> IdentificationResult:
    """Fit ``F0``, the sinc ``xs`` and the sigmoid ``sigma`` to the friction around reversals.

    Parameters
    ----------
    recording : Recording, or a list / dict of Recordings
        Position ``x`` [m or rad] and force ``F`` [N or N·m] (the drive force; at the slow
        reversals of such a record it is the friction), uniformly sampled.
    window : float, optional
        Largest ``|xi|`` used [m or rad]; default: every sample of each reversal's share of
        the record (halfway to the neighbouring reversals).
    min_travel : float, optional
        Travel that confirms a turning point [m or rad]; default :data:`MIN_TRAVEL_FRACTION`
        of the position range.
    inertia : float
        ``J`` [kg or kg·m²] of an inertia term removed from the force, ``F - J a`` (default 0).
    offset : float
        Constant force removed from the force [N or N·m] (default 0).

    Returns
    -------
    IdentificationResult
        ``kind="reversal"``; ``model`` a :class:`~frictionkit.control.compensators.RollingCompensator`
        (``F0``, ``xs``, ``sigma``); ``data`` holds ``xi``, ``F`` (friction in the new
        direction), ``F_sinc``, ``F_sigmoid``; ``diagnostics`` the number of reversals,
        the RMS of each law and the identifiability details.

    Raises
    ------
    DataError
        Missing position/force, fewer than one reversal.
    ParameterError
        Non-positive ``window`` or ``min_travel``, negative ``inertia``.

    Examples
    --------
    >>> import numpy as np, frictionkit as fk
    >>> from frictionkit.data import Recording
    >>> from frictionkit.identify.reversal import fit_reversal
    >>> t = np.arange(4000) * 1e-3
    >>> x = 50e-6 * np.sin(2 * np.pi * t)                       # ±50 µm, two cycles
    >>> law = fk.Dahl(Fc=2.4, sigma0=2.4 / 2e-6)               # pre-sliding ~ a few µm
    >>> F = fk.simulate(law, position=x, dt=1e-3).friction
    >>> res = fit_reversal(Recording(t=t, x=x, F=F))
    >>> round(res["F0"], 1), res.model.xs > 2e-6
    (2.4, True)
    """
    from scipy.optimize import least_squares

    recs = _records(recording)
    if window is not None and not (math.isfinite(window) and window > 0):
        raise ParameterError(f"fit_reversal.window = {window!r}: must be finite and > 0")
    if min_travel is not None and not (math.isfinite(min_travel) and min_travel > 0):
        raise ParameterError(f"fit_reversal.min_travel = {min_travel!r}: must be finite and > 0")
    if not (math.isfinite(inertia) and inertia >= 0):
        raise ParameterError(f"fit_reversal.inertia = {inertia!r}: must be finite and >= 0")
    if not math.isfinite(offset):
        raise ParameterError(f"fit_reversal.offset = {offset!r}: must be finite")
    xi, f, n_rev, stroke = reversal_samples(recs, min_travel=min_travel, inertia=inertia, offset=offset)
    w = window if window is not None else math.inf
    use = np.abs(xi) <= w
    post = use & (xi >= 0)
    if post.sum() < 3 or (use & (xi < 0)).sum() < 1:
        raise DataError(f"fit_reversal: {int(post.sum())} sample(s) after and {int((use & (xi < 0)).sum())} before the "
                        f"reversals within window = {window!r}; need at least 3 after and 1 before")
    scale0 = START_FRACTION * (window if window is not None else stroke)
    F0_0 = float(np.median(np.abs(f[use])))

    def sinc_res(p):
        return sinc_compensation(xi[use], F0=max(p[0], 0.0), xs=math.exp(p[1])) - f[use]

    best = None
    for fac in (0.1, 1.0, 10.0):  # the xs valley is not convex: three starts, keep the best
        sol = least_squares(sinc_res, np.array([F0_0, math.log(scale0 * fac)]), method="trf",
                            x_scale=np.array([max(F0_0, 1e-12), 1.0]), bounds=([0.0, -np.inf], np.inf))
        if best is None or sol.cost < best.cost:
            best = sol
    F0 = float(best.x[0])

    def sig_res(p):
        return sigmoid_compensation(xi[post], F0=F0, sigma=math.exp(p[0])) - f[post]

    best_s = None
    for fac in (0.1, 1.0, 10.0):
        sol = least_squares(sig_res, np.array([math.log(scale0 * fac)]), method="trf")
        if best_s is None or sol.cost < best_s.cost:
            best_s = sol
    p_sinc, p_sig = best.x, best_s.x
    r_sinc, r_sig = sinc_res(p_sinc), sig_res(p_sig)
    xs, sg = math.exp(p_sinc[1]), math.exp(p_sig[0])

    def jac(fun, p):  # central differences (the sinc law is smooth enough: its kink is in the 2nd derivative)
        J = np.empty((fun(p).size, p.size))
        for j in range(p.size):
            e = np.zeros(p.size)
            e[j] = 1e-6 * max(abs(p[j]), 1.0)
            J[:, j] = (fun(p + e) - fun(p - e)) / (2 * e[j])
        return J

    if r_sinc.size < 3 or r_sig.size < 2:
        raise IdentificationError(f"fit_reversal: {r_sinc.size} / {r_sig.size} samples for the sinc / sigmoid law")
    with np.errstate(over="ignore", divide="ignore"):  # an unpinned length gives an interval [~0, ~inf]
        id_sinc = analyse(("F0", "xs"), [F0, xs], jac(sinc_res, p_sinc), r_sinc, r_sinc.size - 2,
                          log_scale=[False, True])
        id_sig = analyse(("sigma",), [sg], jac(sig_res, p_sig), r_sig, r_sig.size - 1, log_scale=[True])
    names = ("F0", "xs", "sigma")
    values = np.array([F0, xs, sg])
    corr = np.full((3, 3), np.nan)  # sigma is fitted after F0 and xs, not jointly with them
    corr[:2, :2] = id_sinc.correlation
    corr[2, 2] = 1.0
    dof = r_sinc.size - 2
    rec0 = recs[0]
    Fu, xu = rec0.units["F"], rec0.units["x"]
    warns = list(id_sinc.warnings) + list(id_sig.warnings)
    inside = int(np.sum((xi[post] > 0) & (xi[post] < xs)))
    if inside < 3:
        warns.append(f"only {inside} sample(s) lie inside the fitted pre-sliding range (0, xs = {xs:.3g} {xu}): "
                     "record slower reversals or sample faster")
    try:
        model = RollingCompensator(F0=F0, xs=xs, sigma=sg)
    except ParameterError as exc:
        model = None
        warns.append(f"estimates do not form a valid compensator ({exc})")
    order = np.argsort(xi[use], kind="stable")
    prov = dict(rec0.provenance)
    if len(recs) > 1:
        prov["records"] = [dict(rr.provenance, name=rr.name) for rr in recs]
    prov.update({"recording": ", ".join(rr.name for rr in recs), "units": {"F": Fu, "x": xu, "v": rec0.units["v"]},
                 "procedure": {"method": "reversal least squares (seed 001 eqs. 5-6)", "window": window,
                               "min_travel": min_travel, "inertia": inertia, "offset": offset}})
    return IdentificationResult(
        kind="reversal",
        model_name="rolling_compensation",
        model=model,
        names=names,
        values=values,
        stderr=np.r_[id_sinc.stderr, id_sig.stderr],
        ci95=np.vstack([id_sinc.ci95, id_sig.ci95]),
        units=(Fu, xu, xu),
        correlation=corr,
        rms=float(np.sqrt(np.mean(r_sinc**2))),
        relative_error_percent=float(100 * np.linalg.norm(r_sinc) / max(float(np.linalg.norm(f[use])), 1e-300)),
        n_obs=int(r_sinc.size),
        dof=int(dof),
        success=bool(best.success and best_s.success),
        message=f"nonlinear least squares (scipy trf): sinc {best.message}; sigmoid {best_s.message}",
        warnings=tuple(warns),
        diagnostics={"reversals": n_rev, "sinc_rms": float(np.sqrt(np.mean(r_sinc**2))),
                     "sigmoid_rms": float(np.sqrt(np.mean(r_sig**2))), "samples_inside_xs": inside,
                     "identifiability": {"sinc": id_sinc.details, "sigmoid": id_sig.details}},
        provenance=prov,
        data={"xi": xi[use][order], "F": f[use][order], "F_sinc": (r_sinc + f[use])[order]},
    )
