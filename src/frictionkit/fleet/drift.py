"""Drift monitoring: per axis, the trend of each friction parameter over time, with its uncertainty.

Per axis and tracked parameter ``y`` (``Fc_pos`` ... with standard error ``s`` from the daily
static-map fits), on the log scale by default (``log y``, standard error ``s / y``: changes
are relative, and a viscosity law ``exp(-k T)`` is linear):

**Which days.** Only days fitted with the axis's usual structure (``model_pos`` /
``model_neg``) enter a parameter's series: ``Fc`` of a Coulomb–viscous fit is not ``Fc`` of a
Stribeck fit. The daily standard errors come from ~5 residual degrees of freedom each and
are too noisy to weight by, so each series uses one variance level, the median ``s²`` of
the axis (``weights="pooled"``; ``weights="se"`` weights by ``1 / max(s_d, se_floor·median)²``).

**Trend, with temperature regressed out (reported).** Least squares over all days,

    y_d = b0 + Σ_j c_j (u_jd - mean u_j) + w · (t_d - t_0) + e_d,    e_d ~ N(0, φ s²),

``t`` in days, ``u_j`` the logged scheduling variables (temperature, ...). ``w`` is the wear
drift (per day) beyond what temperature explains, ``c_j`` the temperature effect (per
unit), each with its standard error; ``φ = max(1, χ²/(n - k))`` widens them when the days
scatter beyond what the intervals say (lubrication state, unmodelled effects).

**Alarm (``method="cusum"``, default): CUSUM on standardised recursive residuals.** Each
day is predicted from the days before it by the model without the time term
(``b0 + Σ c_j u_j``, refitted every day); the prediction error is standardised by its
standard error (interval + parameter uncertainty) and by the scatter of the earlier
errors when that is larger than the intervals, and turned into a normal score. Two-sided
CUSUMs ``S+ = max(0, S+ + z - k)``, ``S- = max(0, S- - z - k)`` (``k = 0.5``) of all tracked
parameters run from ``min_periods`` on; the axis alarms on the first day one exceeds
``h``. Under no drift the recursive residuals of a linear model are independent and
identically distributed whatever the temperatures and days (Brown, Durbin & Evans 1975),
so ``h`` depends only on the number of days and parameters: it is the ``1 - alpha``
quantile of the largest CUSUM of that many simulated series, so that a drift-free axis is
flagged with probability ``alpha`` over its whole history (family-wise over days and
parameters; the floor at the intervals only lowers the scores, so it errs on the safe
side). Computed once per (days, parameters) and cached.

**Alarm (``method="slope"``).** The ``w`` t-test repeated every day from ``min_periods``
on, the threshold on the smallest p-value simulated per axis under the fitted null
(parametric bootstrap over days and parameters). Weaker against wear that starts
mid-history (a line through flat-then-rising data) and, in our simulations, above the
nominal rate (1.7–2.7 % at ``alpha = 1 %``), so it is not the default.

Columns added (per row; axis-level values repeated on each row of the axis):
``drift_flag`` (the axis has alarmed at or before this period), ``drift_alarm_period``,
``drift_detail`` (one line), ``drift_method``, ``drift_scale``, ``drift_threshold`` (``h`` or the p-value
threshold), ``drift_statistic`` (largest CUSUM or smallest p); per tracked parameter ``P``:
``drift_P_wear_per_day`` and ``_se`` (relative per day on the log scale), ``drift_P_p_value``
(of ``w``, descriptive), ``drift_P_cusum`` (largest), ``drift_P_<u>_coef`` and ``_se`` per
scheduling variable (relative per unit), ``drift_P_<u>_part`` and ``drift_P_wear_part``
(that row's temperature-explained and wear-explained deviation), ``drift_P_trend`` (the
fitted value in the parameter's unit) and ``drift_P_phi``.
"""

from __future__ import annotations

import functools
import math
import zlib
from collections import Counter
from collections.abc import Sequence
from typing import Any

import numpy as np

from ..errors import DataError, ParameterError
from typing import TYPE_CHECKING

if TYPE_CHECKING:
    from pathlib import Path
    import pandas as pd

#: Parameters tracked by default.
TRACKED = ("Fc_pos", "Fc_neg", "Fs_pos", "Fs_neg", "sigma2_pos", "sigma2_neg")


def _base_columns() -> set[str]:
    from .config import FleetConfig
    from .task import result_schema

    cfg = FleetConfig(columns={"time": "t", "velocity": "v", "force": "F"})
    return set(result_schema(cfg).names)


def infer_schedule(df) -> tuple[str, ...]:
    """Scheduling columns of a results table: numeric columns beyond the fixed schema (not ``drift_*``)."""
    base = _base_columns()
    return tuple(c for c in df.columns if c not in base and not str(c).startswith("drift_")
                 and df[c].dtype.kind == "f")


def _when(periods) -> np.ndarray:
    """Periods as datetime64[ns] (NaT where not a date)."""
    import pandas as pd

    return pd.to_datetime(pd.Series(np.asarray(periods, dtype=object)), errors="coerce").to_numpy("datetime64[ns]")


def _days(periods: np.ndarray, when: np.ndarray | None = None) -> np.ndarray:
    """Days since the first period (``when``: the periods already parsed by :func:`_when`); the
    period's index when any period is not a date."""
    when = _when(periods) if when is None else when
    if not np.isnat(when).any() and when.size:
        return (when - when[0]) / np.timedelta64(1, "D")
    return np.arange(len(periods), dtype=float)


def _t_sf2(t: np.ndarray, dof: np.ndarray) -> np.ndarray:
    """Two-sided p-value of a t statistic."""
    from scipy import special

    return 2.0 * special.stdtr(dof, -np.abs(t))


class _Design:
    """Cumulative WLS over the looks for one parameter of one axis."""

    def __init__(self, X: np.ndarray, s: np.ndarray, min_periods: int) -> None:
        self.X = X
        self.w = 1.0 / (s * s)
        n, k = X.shape
        self.k = k
        Sxx = np.cumsum(self.w[:, None, None] * X[:, :, None] * X[:, None, :], axis=0)
        looks = np.arange(n)[(np.arange(n) + 1 >= max(min_periods, k + 2))]
        inv = np.full((n, k, k), np.nan)
        if looks.size:
            with np.errstate(all="ignore"):
                cond = np.linalg.cond(Sxx[looks])
            good = looks[np.isfinite(cond) & (cond < 1e12)]
            if good.size:
                inv[good] = np.linalg.inv(Sxx[good])
            looks = good
        self.looks = looks
        self.inv = inv
        self.dof = (np.arange(n) + 1 - k).astype(float)

    def _operators(self) -> tuple[np.ndarray, np.ndarray]:
        """``C`` (n × looks·k): ``Y @ C`` gives X'Wy of every look; ``B``: ``Y @ B`` its coefficients."""
        if not hasattr(self, "_ops"):
            L, (n, k) = self.looks, self.X.shape
            mask = (np.arange(n)[:, None] <= L[None, :]).astype(float)  # n × looks
            C = (self.w[:, None, None] * self.X[:, None, :]) * mask[:, :, None]  # n × looks × k
            B = np.einsum("lij,dlj->dli", self.inv[L], C)
            self._ops = (C.reshape(n, -1), B.reshape(n, -1))
        return self._ops

    def tstats(self, Y: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """Slope, its standard error and φ at every look, for each row of ``Y`` (m × n)."""
        L, k = self.looks, self.k
        C, B = self._operators()
        Sxy = (Y @ C).reshape(Y.shape[0], L.size, k)
        beta = (Y @ B).reshape(Y.shape[0], L.size, k)
        Syy = np.cumsum(self.w[None, :] * Y * Y, axis=1)[:, L]
        chi2 = np.maximum(Syy - np.sum(beta * Sxy, axis=-1), 0.0)
        phi = np.maximum(1.0, chi2 / self.dof[L])
        se = np.sqrt(phi * self.inv[L][:, -1, -1][None, :])
        return beta[:, :, -1], se, phi

    def pvalues(self, Y: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
        """Slope, its SE, two-sided p-value and φ at every look, for each row of ``Y`` (m × n)."""
        slope, se, phi = self.tstats(Y)
        dof = np.broadcast_to(self.dof[self.looks], slope.shape)
        return slope, se, _t_sf2(slope / se, dof), phi


def _threshold(null_t: list[tuple[np.ndarray, np.ndarray]], alpha: float) -> float:
    """Largest p-value threshold whose family-wise rate over the null draws is at most ``alpha``.

    ``null_t``: per parameter, |t| of the null draws (m × looks) and the dof of each look. An
    alarm at threshold ``a`` is ``|t| >= t_crit(a, dof)`` at any look of any parameter; the
    rate falls monotonically with ``a``, so bisection on ``log a`` finds it without a
    p-value per draw.
    """
    from scipy import special

    tabs = np.concatenate([t for t, _ in null_t], axis=1)  # m × (looks of every parameter)
    dof = np.concatenate([d for _, d in null_t])

    def rate(a: float) -> float:
        return float((tabs >= special.stdtrit(dof, 1.0 - a / 2.0)[None, :]).any(axis=1).mean())

    lo, hi = -15.0, math.log10(0.5)
    if rate(10.0**hi) <= alpha:
        return 10.0**hi
    for _ in range(30):  # 15 decades / 2**30: far below the Monte-Carlo error
        mid = 0.5 * (lo + hi)
        if rate(10.0**mid) <= alpha:
            lo = mid
        else:
            hi = mid
    return 10.0**lo


#: CUSUM reference value (half the shift, in standard deviations, it is tuned to).
CUSUM_K = 0.5


def _series(sub, p: str, sched: Sequence[str], days: np.ndarray, *, log: bool, weights: str,
            se_floor: float) -> dict | None:
    """The usable days of one parameter of one axis: indices, y, s, scheduling values, days."""
    if p not in sub or f"{p}_se" not in sub:
        return None
    n = len(sub)
    y = sub[p].to_numpy(float)
    s = sub[f"{p}_se"].to_numpy(float)
    U = np.column_stack([sub[u].to_numpy(float) for u in sched]) if sched else np.zeros((n, 0))
    keep = np.isfinite(y) & np.isfinite(s) & (s > 0) & np.isfinite(U).all(axis=1)
    if log:  # relative changes: log y with standard error s / y (first order)
        keep &= y > 0
        with np.errstate(all="ignore"):
            s = s / np.abs(y)
            y = np.log(np.where(y > 0, y, 1.0))
    mcol = "model_" + p.rsplit("_", 1)[-1]
    if mcol in sub:  # a parameter means the same only within one structure: keep the axis's usual one
        models = sub[mcol].to_numpy(object)
        counts = Counter(m for m in models[keep] if isinstance(m, str))
        if counts:  # the most frequent; among equals the first in sorted order (as pandas' mode)
            top = max(counts.values())
            keep &= models == min(m for m, c in counts.items() if c == top)
    idx = np.flatnonzero(keep)
    if idx.size == 0:
        return None
    sk = s[idx]
    sk = np.full(sk.size, np.median(sk)) if weights == "pooled" else np.maximum(sk, se_floor * np.median(sk))
    Uk = U[idx]
    return {"idx": idx, "y": y[idx], "s": sk, "U": Uk - Uk.mean(axis=0), "t": days[idx] - days[idx][0]}


def _trend(ser: dict) -> dict | None:
    """Least squares over all days: coefficients [b0, c_j..., w], standard errors, φ, fitted values."""
    X = np.column_stack([np.ones(ser["y"].size), ser["U"], ser["t"]])
    n, k = X.shape
    if n < k + 2:
        return None
    W = 1.0 / ser["s"] ** 2
    A = X.T @ (W[:, None] * X)
    if not np.isfinite(np.linalg.cond(A)) or np.linalg.cond(A) > 1e12:
        return None
    inv = np.linalg.inv(A)
    beta = inv @ (X.T @ (W * ser["y"]))
    res = ser["y"] - X @ beta
    phi = max(1.0, float(np.sum(W * res**2)) / (n - k))
    se = np.sqrt(phi * np.diag(inv))
    return {"beta": beta, "se": se, "phi": phi, "X": X, "fit": X @ beta,
            "p_value": float(_t_sf2(np.array(beta[-1] / se[-1]), np.array(float(n - k))))}


def _recursive_scores(ser: dict) -> np.ndarray:
    """Normal scores of the standardised recursive residuals (NaN where none): day L predicted
    from days < L by ``b0 + Σ c_j u_j``."""
    from scipy import special

    y, s = ser["y"], ser["s"]
    X = np.column_stack([np.ones(y.size), ser["U"]])
    n, k = X.shape
    w = 1.0 / s**2
    Sxx = np.cumsum(w[:, None, None] * X[:, :, None] * X[:, None, :], axis=0)
    Sxy = np.cumsum((w * y)[:, None] * X, axis=0)
    r = np.full(n, np.nan)
    if n > k:  # every day L >= k at once: the fit on days < L predicts day L
        A = Sxx[k - 1:n - 1]
        with np.errstate(all="ignore"):
            c = np.linalg.cond(A)
        good = np.flatnonzero(np.isfinite(c) & (c <= 1e12))
        if good.size:
            inv = np.linalg.inv(A[good])
            L = good + k
            x = X[L]
            pred = np.einsum("li,lij,lj->l", x, inv, Sxy[L - 1])
            var = s[L] ** 2 + np.einsum("li,lij,lj->l", x, inv, x)
            r[L] = (y[L] - pred) / np.sqrt(var)
    z = np.full(n, np.nan)
    fin = np.isfinite(r)
    prev = np.cumsum(np.where(fin, r * r, 0.0))
    nu = np.cumsum(fin) - 1  # earlier residuals
    use = fin & (nu >= 2)
    if use.any():
        scale = np.maximum(1.0, (prev[use] - r[use] ** 2) / nu[use])  # never tighter than the intervals
        z[use] = special.ndtri(special.stdtr(nu[use].astype(float), r[use] / np.sqrt(scale)))
    return np.clip(z, -8.0, 8.0)


def _cusum(z: np.ndarray, start: int) -> np.ndarray:
    """max(S+, S-) after each day (NaN scores skipped; 0 before ``start``)."""
    up = dn = 0.0
    out = np.zeros(z.size)
    for i, zi in enumerate(z):
        if i >= start and np.isfinite(zi):
            up = max(0.0, up + zi - CUSUM_K)
            dn = max(0.0, dn - zi - CUSUM_K)
        out[i] = max(up, dn)
    return out


@functools.lru_cache(maxsize=64)
def cusum_threshold(n_days: int, n_params: int, alpha: float, min_periods: int, n_null: int = 20_000,
                    seed: int = 0, n_coef: int = 2) -> float:
    """CUSUM alarm level ``h``: a drift-free axis with ``n_params`` series of ``n_days`` days alarms
    with probability ``alpha`` (simulated: independent normal recursive residuals, studentised
    by the earlier ones as in the monitor; the first ``n_coef`` days have none: intercept and
    scheduling coefficients)."""
    from scipy import special

    rng = np.random.default_rng([seed, n_days, n_params])
    best = np.zeros(n_null)
    k0 = int(n_coef)
    for _ in range(n_params):
        r = rng.standard_normal((n_null, n_days))
        r[:, :k0] = np.nan
        prev = np.nancumsum(r * r, axis=1) - np.nan_to_num(r * r)
        cnt = np.cumsum(np.isfinite(r), axis=1) - 1
        with np.errstate(all="ignore"):
            z = special.ndtri(special.stdtr(cnt, r / np.sqrt(prev / cnt)))
        z[:, cnt[0] < 2] = np.nan
        z = np.clip(z, -8.0, 8.0)
        up = np.zeros(n_null)
        dn = np.zeros(n_null)
        for i in range(n_days):
            if i < min_periods - 1 or not np.isfinite(z[0, i]):
                continue
            up = np.maximum(0.0, up + z[:, i] - CUSUM_K)
            dn = np.maximum(0.0, dn - z[:, i] - CUSUM_K)
            best = np.maximum(best, np.maximum(up, dn))
    return float(np.quantile(best, 1.0 - alpha))


def _axis(sub, params: Sequence[str], schedule: Sequence[str], *, alpha: float, min_periods: int, n_null: int,
          se_floor: float, seed: int, weights: str, log: bool, method: str,
          when: np.ndarray | None = None) -> dict[str, Any]:
    """Monitor one axis (rows with ``ok`` only, sorted by period; ``when``: their periods parsed)."""
    periods = sub["period"].to_numpy()
    days = _days(periods, when)
    n = len(sub)
    sched = [u for u in schedule if u in sub and np.isfinite(sub[u].to_numpy(float)).sum() >= max(3, n // 2)]
    need = max(min_periods, 3 + len(sched))
    out: dict[str, Any] = {"per_param": {}, "schedule": sched, "n_periods": n, "alarm_index": None,
                           "threshold": float("nan"), "statistic": float("nan"), "method": method}
    series = {}
    for p in params:
        ser = _series(sub, p, sched, days, log=log, weights=weights, se_floor=se_floor)
        if ser is None or ser["idx"].size < need:
            continue
        tr = _trend(ser)
        if tr is None:
            continue
        series[p] = {**ser, **tr, "log": log, "sched": list(sched)}
    if not series:
        out["detail"] = f"not monitored: {n} period(s) with a fit; needs at least {need}"
        return out
    if method == "cusum":
        longest = max(ser["idx"].size for ser in series.values())
        h = cusum_threshold(int(longest), len(series), float(alpha), int(min_periods), int(n_null), int(seed),
                            1 + len(sched))
        stat_at = np.zeros(n)
        for ser in series.values():
            c = _cusum(_recursive_scores(ser), start=min_periods - 1)
            ser["stat"] = np.full(n, np.nan)
            ser["stat"][ser["idx"]] = c
            ser["cusum"] = float(c.max())
            filled = np.maximum.accumulate(np.nan_to_num(ser["stat"], nan=0.0))
            ser["stat_filled"] = filled
            stat_at = np.maximum(stat_at, filled)
        hit = np.flatnonzero(stat_at >= h)
        out.update(threshold=h, statistic=float(stat_at.max()))
        if hit.size:
            a = int(hit[0])
            out["alarm_index"] = a
            for ser in series.values():
                ser["alarmed"] = bool(ser["stat_filled"][a] >= h)
    else:
        _slope_alarm(series, out, alpha=alpha, min_periods=min_periods, n_null=n_null, seed=seed,
                     axis=str(sub["axis"].iloc[0]))
    out["per_param"] = series
    return out


def _slope_alarm(series: dict, out: dict, *, alpha: float, min_periods: int, n_null: int, seed: int,
                 axis: str) -> None:
    """``method="slope"``: the wear t-test at every day, threshold by parametric bootstrap."""
    rng = np.random.default_rng([seed, zlib.crc32(axis.encode())])
    null_t = []
    n = max(int(ser["idx"].max()) + 1 for ser in series.values())
    minp_at = np.full(n, np.inf)
    for ser in series.values():
        d = _Design(ser["X"], ser["s"], min_periods)
        ser["pv_looks"] = np.zeros(0)
        if d.looks.size == 0:
            continue
        _, _, pv, _ = d.pvalues(ser["y"][None, :] - ser["y"].mean())
        ser["pv_looks"], ser["look_idx"] = pv[0], ser["idx"][d.looks]
        minp_at[ser["look_idx"]] = np.minimum(minp_at[ser["look_idx"]], pv[0])
        Z = rng.standard_normal((n_null, ser["y"].size)) * (math.sqrt(ser["phi"]) * ser["s"])[None, :]
        sl0, se0, _ = d.tstats(Z)
        null_t.append((np.abs(sl0 / se0), d.dof[d.looks]))
    if not null_t:
        return
    thr = _threshold(null_t, alpha)
    alarms = np.flatnonzero(minp_at <= thr)
    out.update(threshold=thr, statistic=float(np.min(minp_at)))
    if alarms.size:
        a = int(alarms[0])
        out["alarm_index"] = a
        for ser in series.values():
            at = np.flatnonzero(ser.get("look_idx", np.zeros(0, int)) <= a)
            ser["alarmed"] = bool(at.size and np.min(ser["pv_looks"][at]) <= thr)


def _detail(res: dict, periods: np.ndarray) -> str | None:
    if not res["per_param"]:
        return res.get("detail")
    a = res["alarm_index"]
    thr = res["threshold"]
    if a is None:
        if res["method"] == "cusum":
            return f"no drift beyond the intervals (largest CUSUM {res['statistic']:.2f} < {thr:.2f})"
        return f"no drift beyond the intervals (smallest p = {res['statistic']:.2g}, threshold {thr:.2g})"
    parts = []
    for p, ser in res["per_param"].items():
        if not ser.get("alarmed"):
            continue
        base = 1.0 if ser["log"] else ser["beta"][0]
        if not base:
            continue
        rel, rel_se = 100.0 * ser["beta"][-1] / base, 100.0 * ser["se"][-1] / abs(base)
        txt = f"{p} wear {rel:+.2f} ± {rel_se:.2f} %/day"
        for j, u in enumerate(ser["sched"]):
            c, cse = ser["beta"][1 + j], ser["se"][1 + j]
            # the table keeps no unit of a scheduling column ('%/unit' read as a unit called 'unit')
            txt += f", {u} {100 * c / base:+.2f} ± {100 * cse / abs(base):.2f} % per unit of {u}"
        parts.append(txt)
    how = f"CUSUM >= {thr:.2f}" if res["method"] == "cusum" else f"p <= {thr:.2g}"
    return f"drift from {periods[a]} ({how}): " + "; ".join(parts)


def monitor_drift(
    results: pd.DataFrame | str | Path,
    *,
    alpha: float = 0.01,
    min_periods: int = 5,
    parameters: Sequence[str] = TRACKED,
    schedule: Sequence[str] | None = None,
    method: str = "cusum",
    n_null: int = 20_000,
    se_floor: float = 1.0,
    weights: str = "pooled",
    scale: str = "log",
    seed: int = 0,
) -> pd.DataFrame:
    """Trend of each friction parameter per axis; flag axes whose change the intervals do not explain.

    Parameters
    ----------
    results : pandas.DataFrame or str or Path
        The results table of :func:`~frictionkit.fleet.identify_fleet` (or its Parquet file):
        ``axis``, ``period``, ``ok`` and the parameter columns with ``_se``.
    alpha : float
        Probability that a drift-free axis is ever flagged over the history in the table
        (default 0.01), in (0, 0.5).
    min_periods : int
        Periods with a fit before the first test (default 5; at least the number of
        regression coefficients + 2).
    parameters : sequence of str
        Columns tracked (default :data:`TRACKED`); those missing or all-NaN are skipped.
    schedule : sequence of str, optional
        Scheduling columns regressed out (default: every numeric column beyond the fixed
        result schema, e.g. ``temperature``).
    method : {"cusum", "slope"}
        Alarm statistic (see the module docstring); default CUSUM on standardised
        recursive residuals.
    n_null : int
        Null simulations for the alarm threshold (default 20,000; with ``"slope"`` per axis,
        so use ~2,000 there).
    se_floor : float
        With ``weights="se"``: standard errors below this fraction of the axis's median are
        raised to it (default 1).
    weights : {"pooled", "se"}
        One variance level per series (default) or the daily standard errors.
    scale : {"log", "linear"}
        Monitor ``log y`` (relative changes; default) or ``y``.
    seed : int
        Seed of the null simulations.

    Returns
    -------
    pandas.DataFrame
        The table with the ``drift_*`` columns described in the module docstring
        (replacing any from an earlier run).

    Examples
    --------
    >>> from frictionkit.fleet import monitor_drift
    >>> df = monitor_drift("results.parquet")  # doctest: +SKIP
    >>> df.loc[df["drift_flag"], "axis"].unique()  # doctest: +SKIP
    """
    import pandas as pd

    if not isinstance(results, pd.DataFrame):
        results = pd.read_parquet(results)
    if not 0.0 < float(alpha) < 0.5:
        raise ParameterError(f"monitor_drift.alpha = {alpha!r}: must be in (0, 0.5)")
    if isinstance(min_periods, bool) or int(min_periods) != min_periods or min_periods < 3:
        raise ParameterError(f"monitor_drift.min_periods = {min_periods!r}: must be an integer >= 3")
    if isinstance(n_null, bool) or int(n_null) != n_null or n_null < 100:
        raise ParameterError(f"monitor_drift.n_null = {n_null!r}: must be an integer >= 100")
    if method not in ("cusum", "slope"):
        raise ParameterError(f"monitor_drift.method = {method!r}: must be 'cusum' or 'slope'")
    if scale not in ("log", "linear"):
        raise ParameterError(f"monitor_drift.scale = {scale!r}: must be 'log' or 'linear'")
    if weights not in ("pooled", "se"):
        raise ParameterError(f"monitor_drift.weights = {weights!r}: must be 'pooled' or 'se'")
    if not 0.0 <= float(se_floor) <= 1.0:
        raise ParameterError(f"monitor_drift.se_floor = {se_floor!r}: must be in [0, 1]")
    parameters = [parameters] if isinstance(parameters, str) else list(parameters)
    for col in ("axis", "period", "ok"):
        if col not in results:
            raise DataError(f"monitor_drift: the results table has no column '{col}'")
    df = results.drop(columns=[c for c in results.columns if str(c).startswith("drift_")]).copy()
    df = df.reset_index(drop=True)
    sched = infer_schedule(df) if schedule is None else tuple(schedule)
    for u in sched:
        if u not in df:
            raise DataError(f"monitor_drift: scheduling column '{u}' not in the results table")
    params = [p for p in parameters if p in df and f"{p}_se" in df and df[p].notna().any()]

    cols: dict[str, np.ndarray] = {
        "drift_flag": np.zeros(len(df), bool),
        "drift_alarm_period": np.full(len(df), None, object),
        "drift_detail": np.full(len(df), None, object),
        "drift_method": np.full(len(df), method, object),
        "drift_scale": np.full(len(df), scale, object),
        "drift_threshold": np.full(len(df), np.nan),
        "drift_statistic": np.full(len(df), np.nan),
    }
    for p in params:
        for name in ("wear_per_day", "wear_per_day_se", "p_value", "cusum", "trend", "wear_part", "phi"):
            cols[f"drift_{p}_{name}"] = np.full(len(df), np.nan)
        for u in sched:
            for name in ("coef", "coef_se", "part"):
                cols[f"drift_{p}_{u}_{name}"] = np.full(len(df), np.nan)

    ok = df["ok"].fillna(False).astype(bool)
    when_all = _when(df["period"].to_numpy())
    for axis, sub_all in df.groupby("axis", sort=True):
        rows_all = sub_all.index.to_numpy()
        sub = sub_all[ok.loc[rows_all].to_numpy()].sort_values("period", kind="stable")
        if sub.empty:
            cols["drift_detail"][rows_all] = "not monitored: no period with a fit"
            continue
        res = _axis(sub, params, sched, alpha=float(alpha), min_periods=int(min_periods), n_null=int(n_null),
                    se_floor=float(se_floor), seed=int(seed), weights=weights, log=scale == "log", method=method,
                    when=when_all[sub.index.to_numpy()])
        periods = sub["period"].to_numpy()
        detail = _detail(res, periods)
        alarm = periods[res["alarm_index"]] if res.get("alarm_index") is not None else None
        cols["drift_detail"][rows_all] = detail
        cols["drift_threshold"][rows_all] = res["threshold"]
        cols["drift_statistic"][rows_all] = res["statistic"]
        if alarm is not None:
            cols["drift_alarm_period"][rows_all] = alarm
            cols["drift_flag"][rows_all] = sub_all["period"].to_numpy() >= alarm
        for p, info in res["per_param"].items():
            rix = sub.index.to_numpy()[info["idx"]]
            cols[f"drift_{p}_wear_per_day"][rows_all] = info["beta"][-1]
            cols[f"drift_{p}_wear_per_day_se"][rows_all] = info["se"][-1]
            cols[f"drift_{p}_p_value"][rows_all] = info["p_value"]
            cols[f"drift_{p}_cusum"][rows_all] = info.get("cusum", np.nan)
            cols[f"drift_{p}_phi"][rows_all] = info["phi"]
            cols[f"drift_{p}_wear_part"][rix] = info["beta"][-1] * info["X"][:, -1]
            cols[f"drift_{p}_trend"][rix] = np.exp(info["fit"]) if info["log"] else info["fit"]
            for j, u in enumerate(info["sched"]):
                cols[f"drift_{p}_{u}_coef"][rows_all] = info["beta"][1 + j]
                cols[f"drift_{p}_{u}_coef_se"][rows_all] = info["se"][1 + j]
                cols[f"drift_{p}_{u}_part"][rix] = info["beta"][1 + j] * info["X"][:, 1 + j]
    new = pd.DataFrame(cols, index=df.index)
    return pd.concat([df, new], axis=1)


def drift_summary(results: pd.DataFrame | str | Path) -> pd.DataFrame:
    """One row per axis: flag, alarm period, detail, and per tracked parameter the wear slope
    (per day and relative, with standard errors), the scheduling coefficients and the p-value.

    Parameters
    ----------
    results : pandas.DataFrame or str or Path
        A table with the ``drift_*`` columns (from :func:`monitor_drift`).

    Returns
    -------
    pandas.DataFrame
    """
    import pandas as pd

    if not isinstance(results, pd.DataFrame):
        results = pd.read_parquet(results)
    if "drift_flag" not in results:
        raise DataError("drift_summary: no drift_* columns; run monitor_drift first")
    per_row = {"drift_flag"} | {c for c in results.columns if c.endswith("_part")}
    axis_cols = [c for c in results.columns if c.startswith("drift_") and c not in per_row]
    g = results.groupby("axis", sort=True)
    out = g[axis_cols].first()
    out.insert(0, "drift_flag", g["drift_flag"].any())
    out.insert(1, "periods", g["period"].count())
    out.insert(2, "ok_periods", g["ok"].sum())
    return out.reset_index()


__all__ = ["TRACKED", "cusum_threshold", "drift_summary", "infer_schedule", "monitor_drift"]
