"""Which parameters the data pin down, why not, and intervals that respect the sign.

A least-squares fit always returns numbers; this module says which of them the data
actually determine. Three tests, each giving a reason in words:

* **interval** — the 95 % interval spans more than a decade (``hi / lo > 10``).
  Parameters that must be positive (stiffnesses, damping, levels, inertia) get their
  interval on a log scale, ``theta · exp(±t·se(log theta))``, or from the profile
  below, so it never crosses zero: drive 3's Stribeck exponent is reported as
  [0.42, 43], not as [−5.9, 14.3].
* **correlation** — ``|corr| > 0.99`` with another parameter: only a combination
  of the two is determined.
* **profile** — the cost, minimised over the other parameters with this one held
  fixed, stays within the 95 % likelihood-ratio region (``ΔSSE / s² < χ²₁(0.95) =
  3.84``) from ``theta / 1000`` or up to ``theta · 1000``: the data cannot tell
  the values apart.

The caller supplies the Jacobian at the optimum (columns with respect to ``log theta``
for log-scale parameters, ``theta`` otherwise), the residuals, and optionally a
profile function and the physics that turns a reason into the experiment that would
pin the parameter (:mod:`.motion_error` knows the sampling time and the bristle time
constant; this module does not).
"""

from __future__ import annotations

import math
from collections.abc import Callable, Sequence
from dataclasses import dataclass, field

import numpy as np
from scipy import stats

__all__ = ["CORRELATION_LIMIT", "DECADE", "PROFILE_DECADES", "Identifiability", "analyse", "log_interval"]

#: |correlation| above which two parameters are reported as confounded.
CORRELATION_LIMIT = 0.99
#: Ratio hi / lo of a 95 % interval above which a parameter is not identifiable.
DECADE = 10.0
#: log10 offsets at which each log-scale parameter's profile is evaluated (both sides).
PROFILE_DECADES = (0.25, 0.5, 1.0, 2.0, 3.0)


def log_interval(value: float, se_log: float, dof: int, *, level: float = 0.95) -> tuple[float, float]:
    """``value · exp(±t·se_log)``: the interval of a positive parameter from the error of its log.

    Examples
    --------
    >>> from frictionkit.identify.identifiability import log_interval
    >>> lo, hi = log_interval(4.22, 4.81 / 4.22, dof=37)   # drive 3's delta, se 4.81
    >>> round(lo, 2), round(hi, 1)
    (0.42, 42.5)
    """
    tq = float(stats.t.ppf(0.5 + level / 2.0, max(int(dof), 1)))
    if not (math.isfinite(se_log) and value > 0):
        return (0.0, math.inf)
    w = min(tq * se_log, 700.0)
    return (value * math.exp(-w), value * math.exp(w))


@dataclass(frozen=True)
class Identifiability:
    """Uncertainty of a fit and its verdict per parameter.

    Attributes
    ----------
    stderr : ndarray
        Standard errors in natural units (``theta · se(log theta)`` on log scale).
    ci95 : ndarray, shape (p, 2)
        95 % intervals: profile intervals where a profile was computed, else Wald
        intervals (on the log scale for positive parameters).
    correlation : ndarray
        Correlation matrix (pseudo-inverse where the Jacobian is singular, so a pair
        that only acts through its combination shows ±1).
    reasons : dict
        ``{name: [reason, ...]}`` for every parameter the data do not pin.
    warnings : tuple of str
        One sentence per unidentifiable parameter: which, why, and (with ``advice``)
        what experiment would pin it.
    details : dict
        JSON-ready numbers: Wald intervals, profiles, correlations above the limit.
    """

    stderr: np.ndarray
    ci95: np.ndarray
    correlation: np.ndarray
    reasons: dict = field(default_factory=dict)
    warnings: tuple = ()
    details: dict = field(default_factory=dict)

    @property
    def flagged(self) -> tuple[str, ...]:
        return tuple(self.reasons)


def _wald(J: np.ndarray, r: np.ndarray, dof: int):
    """Variances (inf along singular directions) and a pseudo-inverse correlation."""
    p = J.shape[1]
    s2 = float(r @ r) / max(dof, 1)
    colnorm = np.linalg.norm(J, axis=0)
    live = colnorm > 1e-12 * max(float(colnorm.max(initial=0.0)), 1e-300)
    var = np.full(p, np.inf)
    corr = np.full((p, p), np.nan)
    np.fill_diagonal(corr, 1.0)
    cond = math.inf
    if live.any():
        Js = J[:, live] / colnorm[live]
        _, S, Vt = np.linalg.svd(Js, full_matrices=False)
        cond = float(S[0] / S[-1]) if S[-1] > 0 else math.inf
        tiny = S <= 1e-12 * S[0]  # directions the data do not pin at all
        with np.errstate(divide="ignore", over="ignore", invalid="ignore"):
            inv2 = np.where(tiny, 0.0, 1.0 / S**2)
            var_live = (Vt.T**2 @ inv2) * s2 / colnorm[live] ** 2
            var_live[(Vt.T**2 @ tiny.astype(float)) > 1e-8] = np.inf
            pc = (Vt[~tiny].T / S[~tiny]) @ (Vt[~tiny].T / S[~tiny]).T
            d = np.sqrt(np.diag(pc))
            cl = pc / np.outer(d, d)
        var[live] = var_live
        idx = np.flatnonzero(live)
        corr[np.ix_(idx, idx)] = cl
        np.fill_diagonal(corr, 1.0)
    return var, corr, s2, cond


def analyse(
    names: Sequence[str],
    values,
    J,
    r,
    dof: int,
    *,
    log_scale: Sequence[bool],
    profile: Callable[[int, float], float] | None = None,
    advice: Callable[[str, dict], str | None] | None = None,
    level: float = 0.95,
) -> Identifiability:
    """Standard errors, sign-respecting intervals and the identifiability verdict.

    Parameters
    ----------
    names, values
        Parameters and estimates (natural units).
    J : ndarray (n, p)
        Jacobian of the residuals at the optimum, column j with respect to
        ``log theta_j`` where ``log_scale[j]``, else to ``theta_j``.
    r : ndarray (n,)
        Residuals at the optimum.
    dof : int
        ``n - p``.
    log_scale : sequence of bool
        Which parameters are positive (log-scale intervals and profiles).
    profile : callable, optional
        ``profile(j, value) -> SSE`` minimised over the other parameters with
        parameter ``j`` held at ``value`` (``inf`` if the model cannot be evaluated).
        Evaluated at ``theta_j · 10^±d`` for ``d`` in :data:`PROFILE_DECADES`.
    advice : callable, optional
        ``advice(name, info) -> str``: the experiment that would pin ``name``;
        ``info`` holds ``reasons``, ``ci95``, ``value``, ``partner`` (most correlated parameter).
    level : float
        Confidence level (0.95).

    Returns
    -------
    Identifiability
    """
    names = list(names)
    theta = np.asarray(values, dtype=float)
    J = np.asarray(J, dtype=float)
    r = np.asarray(r, dtype=float)
    logs = np.asarray(log_scale, dtype=bool)
    p = len(names)
    var, corr, s2, cond = _wald(J, r, dof)
    se_tr = np.sqrt(var)
    tq = float(stats.t.ppf(0.5 + level / 2.0, max(int(dof), 1)))
    # on the log scale a standard error beyond 5 (a factor e^10 at one sigma) is no number
    stderr = np.where(logs, np.where(se_tr > 5.0, np.inf, np.abs(theta) * se_tr), se_tr)
    wald = np.empty((p, 2))
    for j in range(p):
        if logs[j]:
            wald[j] = log_interval(theta[j], se_tr[j], dof, level=level)
        else:
            wald[j] = (theta[j] - tq * se_tr[j], theta[j] + tq * se_tr[j])
    ci = wald.copy()
    sse0 = float(r @ r)
    limit = float(stats.chi2.ppf(level, 1))
    profiles: dict[str, dict] = {}
    flat: dict[int, list[str]] = {}
    if profile is not None and s2 > 0:
        for j in np.flatnonzero(logs):
            side_bounds = []
            prof = {"log10_offset": [], "delta_chi2": []}
            for sign in (-1.0, 1.0):
                prev_d, prev_q = 0.0, 0.0
                bound = None
                for d in PROFILE_DECADES:
                    sse = profile(int(j), float(theta[j] * 10.0 ** (sign * d)))
                    q = (sse - sse0) / s2 if math.isfinite(sse) else math.inf
                    prof["log10_offset"].append(sign * d)
                    prof["delta_chi2"].append(q if math.isfinite(q) else None)
                    if q >= limit:
                        # interpolate the crossing in log10 between the last two points, on sqrt(delta):
                        # near the optimum sqrt(delta chi2) grows linearly with the offset
                        frac = ((math.sqrt(limit) - math.sqrt(prev_q)) / (math.sqrt(q) - math.sqrt(prev_q))
                                if math.isfinite(q) and q > prev_q else 0.0)
                        bound = prev_d + frac * (d - prev_d)
                        break
                    prev_d, prev_q = d, max(q, 0.0)
                if bound is None:
                    flat.setdefault(int(j), []).append("below" if sign < 0 else "above")
                    side_bounds.append(0.0 if sign < 0 else math.inf)
                else:
                    side_bounds.append(float(theta[j] * 10.0 ** (sign * bound)))
            order = np.argsort(prof["log10_offset"])
            prof = {k: [prof[k][i] for i in order] for k in prof}
            prof["ci95"] = side_bounds
            profiles[names[j]] = prof
            ci[j] = side_bounds
    reasons: dict[str, list[str]] = {}
    notes: dict[str, dict] = {}
    for j, n in enumerate(names):
        why = []
        lo, hi = ci[j]
        if logs[j]:
            span = hi / lo if lo > 0 else math.inf
            if not span <= DECADE:
                why.append(f"its 95 % interval [{_g(lo)}, {_g(hi)}] spans "
                           + ("more than a decade" if not math.isfinite(span) else f"{math.log10(span):.1f} decades"))
        elif not np.isfinite(se_tr[j]):
            why.append("its standard error is infinite (no effect on the fitted signal)")
        others = [(abs(corr[j, k]), k) for k in range(p) if k != j and np.isfinite(corr[j, k])]
        partner = max(others)[1] if others else None
        if partner is not None and abs(corr[j, partner]) > CORRELATION_LIMIT:
            why.append(f"it is confounded with {names[partner]} (correlation {corr[j, partner]:+.3f}): "
                       "only a combination of the two is determined")
        if j in flat:
            sides = " and ".join(flat[j])
            why.append(f"the profile is flat {sides} it: from {_g(theta[j])} to "
                       + " and to ".join(f"{_g(theta[j] * 10.0 ** (-3 if s == 'below' else 3))}" for s in flat[j])
                       + " the cost stays within the 95 % region")
        if why:
            reasons[n] = why
            notes[n] = {"reasons": why, "ci95": [float(lo), float(hi)], "value": float(theta[j]),
                        "partner": names[partner] if partner is not None else None,
                        "flat": flat.get(j, [])}
    warns = []
    for n, info in notes.items():
        tip = advice(n, info) if advice is not None else None
        warns.append(f"{n} is not identifiable from these data: " + "; ".join(info["reasons"])
                     + (f". To pin it: {tip}" if tip else ""))
    big = [[names[a], names[b], float(corr[a, b])] for a in range(p) for b in range(a + 1, p)
           if np.isfinite(corr[a, b]) and abs(corr[a, b]) > CORRELATION_LIMIT]
    details = {"wald_ci95": wald.tolist(), "profiles": profiles, "confounded_pairs": big,
               "condition_number": cond, "chi2_limit": limit,
               "not_identifiable": {n: info["reasons"] for n, info in notes.items()}}
    return Identifiability(stderr=stderr, ci95=ci, correlation=corr, reasons=reasons, warnings=tuple(warns),
                           details=details)


def _g(x: float) -> str:
    if x == 0:
        return "0"
    if not math.isfinite(x):
        return "inf"
    return f"{x:.3g}"
