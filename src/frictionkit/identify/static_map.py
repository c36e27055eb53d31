"""Static friction map from steady-state (constant-velocity) data.

Procedure (seed 002 §3.1 eq. 10, seed 000 §5.2.1 eq. 18): average force over
constant-velocity segments, then, for each direction separately, minimise
``sum_i [F_i - Fss(v_i)]^2`` over ``Fc, Fs, vs, delta, sigma2`` with bounded
nonlinear least squares (``scipy.optimize.least_squares``), where

    Fss(v) = sgn(v) [Fc + (Fs - Fc) phi(|v| / vs)] + sigma2 v,
    phi = exp(-r**delta)  (exponential, seed 000 eq. 4 / seed 002 eq. 9b with delta = 2)
    phi = 1 / (1 + r**2)  (Lorentzian, seed 002 eq. 9a).

Standard errors come from the Jacobian at the solution, ``s^2 (J^T J)^-1`` with
``s^2 = RSS / (n - p)``; 95 % intervals use Student's t with ``n - p`` degrees of
freedom. ``covariance="run_robust"`` takes per parameter the larger of that variance and the
HC3 sandwich (each run's own residual, leverage-corrected; see :data:`COVARIANCES`), for
campaigns where each run mean carries its own error. The model structure (Coulomb-viscous, exponential or Lorentzian Stribeck)
is chosen per direction by AIC or BIC unless given.
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass

import numpy as np
from scipy.optimize import least_squares

from .. import _validate as val
from ..data.recording import Recording
from ..data.segmentation import SteadyStatePoints, steady_state_points
from ..errors import DataError, IdentificationError, ParameterError
from ..models.static import CoulombViscous, Directional, Stribeck
from .result import IdentificationResult, parameter_statistics
from typing import TYPE_CHECKING

if TYPE_CHECKING:
    from collections.abc import Mapping
    from numpy.typing import ArrayLike
    from typing import Any

#: Model structures :func:`fit_static_map` can fit.
MODELS = ("coulomb_viscous", "exponential", "lorentzian")

#: Relative standard error above which a parameter is flagged as not identifiable.
UNIDENTIFIABLE_RSE = 1.0

#: Ratio of smallest to largest singular value of the Jacobian below which it is rank deficient.
RANK_TOL = 1e-8

_LOSSES = ("linear", "soft_l1", "huber", "cauchy", "arctan")

#: How :func:`fit_static_map` computes the parameter covariance:
#:
#: * ``"residual"`` — ``s² (JᵀJ)⁻¹``, ``s² = RSS / (n − p)``: every point carries one common
#:   error variance;
#: * ``"run_robust"`` — per parameter the larger of that variance and the HC3 sandwich
#:   ``(JᵀJ)⁻¹ Jᵀ diag(e_i² / (1 − h_ii)²) J (JᵀJ)⁻¹`` (``h`` the leverages ``diag(J (JᵀJ)⁻¹ Jᵀ)``;
#:   MacKinnon & White 1985, recommended for small samples by Long & Ervin 2000; the
#:   linearised delete-one-run jackknife), the correlation kept from the residual form. For
#:   constant-velocity campaigns: the unit of independent information is the run, each run mean
#:   carries its own error (averaging noise, velocity jitter through the map's curvature, a small
#:   limit cycle), and with ~12 runs for 4 parameters per direction the few runs inside the
#:   Stribeck transition have high leverage — the fit bends to their error, their residual is
#:   small and the error hides in the parameters, which ``"residual"`` cannot see. HC3 can itself
#:   fall below ``"residual"`` when the errors are exchangeable (it is noisy in small samples), hence
#:   the larger of the two. A run with ``h_ii → 1`` (it alone fixes a parameter) gives an unbounded
#:   variance: the parameter is then flagged. Neither form carries an error common to every run.
COVARIANCES = ("residual", "run_robust")


@dataclass(frozen=True)
class _Structure:
    name: str
    params: tuple[str, ...]


def _structure(model: str, delta: float | None) -> _Structure:
    if model == "coulomb_viscous":
        return _Structure(model, ("Fc", "sigma2"))
    if model == "lorentzian":
        return _Structure(model, ("Fc", "Fs", "vs", "sigma2"))
    if model == "exponential":
        if delta is None:
            return _Structure(model, ("Fc", "Fs", "vs", "delta", "sigma2"))
        return _Structure(model, ("Fc", "Fs", "vs", "sigma2"))
    raise ParameterError(f"fit_static_map.model = {model!r}: must be 'auto' or one of {list(MODELS)}")


def _curve(st: _Structure, p: np.ndarray, u: np.ndarray, delta: float | None) -> np.ndarray:
    """Friction magnitude for speeds ``u >= 0`` (scaled units)."""
    if st.name == "coulomb_viscous":
        return p[0] + p[1] * u
    Fc, Fs, vs = p[0], p[1], p[2]
    r = u / vs
    if st.name == "lorentzian":
        phi = 1.0 / (1.0 + r * r)
    else:
        d = p[3] if delta is None else delta
        with np.errstate(over="ignore", under="ignore"):
            phi = np.exp(-(r**d))
    return Fc + (Fs - Fc) * phi + p[-1] * u


def _jacobian(st: _Structure, p: np.ndarray, u: np.ndarray, delta: float | None) -> np.ndarray:
    """Analytic derivatives of :func:`_curve` with respect to the parameters (columns)."""
    if st.name == "coulomb_viscous":
        return np.column_stack([np.ones_like(u), u])
    Fc, Fs, vs = p[0], p[1], p[2]
    r = u / vs
    cols = {}
    if st.name == "lorentzian":
        phi = 1.0 / (1.0 + r * r)
        dphi_dvs = 2.0 * r * r / (vs * (1.0 + r * r) ** 2)
    else:
        d = p[3] if delta is None else delta
        with np.errstate(over="ignore", under="ignore", divide="ignore", invalid="ignore"):
            rd = r**d
            phi = np.exp(-rd)
            dphi_dvs = phi * d * rd / vs
            cols["delta"] = np.nan_to_num(-(Fs - Fc) * phi * rd * np.log(r))
    cols["Fc"] = 1.0 - phi
    cols["Fs"] = phi
    cols["vs"] = (Fs - Fc) * dphi_dvs
    cols["sigma2"] = u
    return np.column_stack([cols[n] for n in st.params])


#: Largest fixed ``delta`` (issue 13 round 9: ``--delta 1e9`` ended in scipy's "array must not contain
#: infs or NaNs"; 100 ran, 300 did not). Why 50: the fit scales speeds by the top speed and bounds vs
#: below by 1e-6 of it (:func:`_bounds`), so ``|v|/vs`` reaches 1e6 and ``(1e6)**delta`` stays below the
#: double's 1.8e308 for ``delta <= 51``; at delta = 50 ``phi`` falls from 0.99 to 0.01 within 10 % of vs.
MAX_FIXED_DELTA = 50.0


def _bounds(st: _Structure) -> tuple[np.ndarray, np.ndarray]:
    lo = {"Fc": 0.0, "Fs": 0.0, "vs": 1e-6, "delta": 0.1, "sigma2": 0.0}
    hi = {"Fc": np.inf, "Fs": np.inf, "vs": 1e3, "delta": 10.0, "sigma2": np.inf}
    return np.array([lo[n] for n in st.params]), np.array([hi[n] for n in st.params])


def _starts(st: _Structure, u: np.ndarray, y: np.ndarray) -> list[np.ndarray]:
    order = np.argsort(u)
    upper = order[len(order) // 2:] if len(order) >= 4 else order
    if np.ptp(u[upper]) > 0:
        slope, icpt = np.polyfit(u[upper], y[upper], 1)
    else:
        slope, icpt = 0.0, float(np.mean(y))
    Fc0 = max(float(icpt), 1e-3)
    s0 = max(float(slope), 0.0)
    if st.name == "coulomb_viscous":
        return [np.array([Fc0, s0])]
    Fs0 = max(float(np.mean(y[order[:2]])), 1e-3)
    out = []
    for vs0 in (0.02, 0.1, 0.3):
        vs0 = max(vs0, 1.5e-6)
        for d0 in ((1.0, 2.0) if "delta" in st.params else (None,)):
            p = [Fc0, Fs0, vs0] + ([d0] if d0 is not None else []) + [s0]
            out.append(np.array(p))
    return out


def _unit_of(name: str, Fu: str, vu: str) -> str:
    if name in ("Fc", "Fs"):
        return Fu
    if name == "vs":
        return vu
    if name == "delta":
        from ._advice import DIMENSIONLESS

        return DIMENSIONLESS
    if vu.endswith("/s"):
        return f"{Fu}·s/{vu[:-2]}"
    return f"{Fu}/({vu})"


def _hc3(J: np.ndarray, e: np.ndarray) -> tuple[np.ndarray, float]:
    """HC3 sandwich covariance of least-squares parameters (scaled units) and the largest leverage."""
    A = np.linalg.pinv(J.T @ J)
    h = np.einsum("ij,jk,ik->i", J, A, J)
    alone = h > 1.0 - 1e-9  # the fit passes through such a run: its own error cannot be seen
    den = np.where(alone, 1.0, 1.0 - h)
    meat = J.T @ (J * ((np.where(alone, 0.0, e) / den) ** 2)[:, None])
    cov = A @ meat @ A
    if alone.any():  # unbounded variance for the parameters such a run moves
        infl = np.abs(A @ J.T)
        moved = (infl[:, alone] > 1e-9 * np.max(infl, axis=1, keepdims=True)).any(axis=1)
        cov[moved, :] = np.inf
        cov[:, moved] = np.inf
    return cov, float(np.max(h)) if h.size else 0.0


#: Component along a right singular vector of the Jacobian whose singular value is below
#: :data:`RANK_TOL` of the largest, above which a parameter counts as moved by that unseen direction
#: (singular vectors are unit vectors; rounding leaves components ~1e-16 x the condition number).
UNSEEN_COMPONENT = 1e-4


def _unseen(sv: np.ndarray, vt: np.ndarray) -> np.ndarray:
    """Parameters (boolean mask) that move along a direction the data do not determine, from the
    singular values ``sv`` and the full right singular vectors ``vt`` (p x p) of the Jacobian."""
    p = vt.shape[1]
    if sv.size == 0 or not (np.all(np.isfinite(sv)) and np.all(np.isfinite(vt))):
        return np.zeros(p, dtype=bool)
    sv = np.r_[sv, np.zeros(p - sv.size)] if sv.size < p else sv
    if sv[0] <= 0:
        return np.ones(p, dtype=bool)
    weak = vt[sv < RANK_TOL * sv[0]]
    return (np.abs(weak) > UNSEEN_COMPONENT).any(axis=0) if weak.size else np.zeros(p, dtype=bool)


def _fit_direction(
    u: np.ndarray, y: np.ndarray, w: np.ndarray, st: _Structure, *, delta: float | None,
    loss: str, f_scale: float | None, covariance: str = "residual",
) -> dict:
    """Fit one structure to speeds ``u`` and friction magnitudes ``y`` (unscaled)."""
    Fsc = float(np.max(np.abs(y))) or 1.0
    vsc = float(np.max(u))
    us, ys = u / vsc, y / Fsc
    lo, hi = _bounds(st)

    def resid(p):
        return (_curve(st, p, us, delta) - ys) * w

    def jac(p):
        return _jacobian(st, p, us, delta) * w[:, None]

    fs = 1.0 if f_scale is None else float(f_scale) / Fsc
    best = None
    for p0 in _starts(st, us, ys):
        p0 = np.clip(p0, lo, np.where(np.isfinite(hi), hi * (1 - 1e-9), hi))
        r = least_squares(resid, p0, jac=jac, bounds=(lo, hi), loss=loss, f_scale=fs, x_scale="jac",
                          method="trf", max_nfev=200 * len(p0))
        if best is None or r.cost < best.cost:
            best = r
    # scale factors back to physical units
    scale = np.array([{"Fc": Fsc, "Fs": Fsc, "vs": vsc, "delta": 1.0, "sigma2": Fsc / vsc}[n] for n in st.params])
    n, p = u.size, len(st.params)
    dof = n - p
    raw = (_curve(st, best.x, us, delta) - ys) * Fsc  # unweighted residuals, physical units
    J = best.jac
    if loss == "linear":
        s2 = float(np.sum(best.fun**2)) / dof
    else:
        s2 = 2.0 * float(best.cost) / dof
    # one decomposition for the rank ratio and the unseen directions (was two SVDs of J)
    # full V (p x p) is needed only with fewer points than parameters; full U would be n x n (a 1e6-point fit asked
    # for 1.8 TiB, 20,000 points per direction took 3.2 GB: issue 13 round 11, family O)
    _, sv, vt = np.linalg.svd(J, full_matrices=J.shape[0] < J.shape[1])
    rank_ratio = float(sv[-1] / sv[0]) if sv[0] > 0 else 0.0
    cov_s = s2 * np.linalg.pinv(J.T @ J)
    max_leverage = None
    if covariance == "run_robust":
        cov_h, max_leverage = _hc3(J, best.fun)
        var_r = np.clip(np.diag(cov_s), 0.0, None)
        var_h = np.diag(cov_h)
        var_h = np.where(np.isfinite(var_h), np.clip(var_h, 0.0, None), np.inf)
        sd = np.sqrt(np.maximum(var_r, var_h))
        sd_r = np.sqrt(var_r)
        with np.errstate(invalid="ignore", divide="ignore"):
            corr = cov_s / np.outer(sd_r, sd_r)
        corr = np.where(np.isfinite(corr), corr, 0.0)
        np.fill_diagonal(corr, 1.0)
        with np.errstate(invalid="ignore"):
            cov_s = corr * np.outer(sd, sd)
        cov_s[np.diag_indices_from(cov_s)] = sd**2
    # pinv drops the directions the data cannot see, which leaves their parameters a small, finite
    # variance: a rank-deficient negative staircase (one plateau inside the Stribeck range) printed
    # delta 4.008 with a 95 % interval 4e-5 wide around a true 2 (issue 13, round 9). A parameter
    # that moves along such a direction has an unbounded variance instead.
    unseen = _unseen(sv, vt)
    if unseen.any():
        cov_s = cov_s.copy()
        cov_s[unseen, :] = np.inf
        cov_s[:, unseen] = np.inf
    # J and s2 are both in scaled residual units, so cov_s is the covariance of the
    # scaled parameters; each physical parameter is scaled parameter * scale.
    cov = cov_s * np.outer(scale, scale)
    values = best.x * scale
    rss = float(np.sum(raw**2))
    k = p
    # Residuals below 1e-9 of the force scale are rounding noise: floor them, so that
    # exact fits tie and the penalty picks the simplest structure.
    rss_eff = max(rss, n * (1e-9 * Fsc) ** 2)
    aic = n * np.log(rss_eff / n) + 2 * k
    bic = n * np.log(rss_eff / n) + k * np.log(n)
    return {"res": best, "values": values, "cov": cov, "dof": dof, "raw": raw, "rss": rss,
            "aic": float(aic), "bic": float(bic), "rank_ratio": rank_ratio, "jac": J,
            "max_leverage": max_leverage, "unseen": unseen}


def _phi(st: _Structure, vals: np.ndarray, u: np.ndarray, delta: float | None) -> np.ndarray:
    """Stribeck shape function at speeds ``u`` for physical parameter values."""
    r = u / vals[2]
    if st.name == "lorentzian":
        return 1.0 / (1.0 + r * r)
    d = vals[3] if delta is None else delta
    with np.errstate(over="ignore", under="ignore"):
        return np.exp(-(r**d))


def _flags(st: _Structure, fit: dict, u: np.ndarray, label: str, delta: float | None) -> list[str]:
    out = []
    vals, se = fit["values"], np.sqrt(np.clip(np.diag(fit["cov"]), 0, None))
    lo, hi = _bounds(st)
    x = fit["res"].x
    weak = []
    if fit["rank_ratio"] < RANK_TOL:
        weak = [n for n, u in zip(st.params, fit["unseen"]) if u]
        out.append(f"{label}: Jacobian is rank deficient (singular value ratio {fit['rank_ratio']:.2g}); "
                   f"{', '.join(weak)} not identifiable from these data (unbounded intervals)")
    if st.name != "coulomb_viscous":
        phi = _phi(st, vals, u, delta)
        k = int(np.sum((phi > 0.05) & (phi < 0.95)))
        span = float(np.ptp(phi)) if phi.size else 0.0
        if k < 2 or span < 0.5:
            out.append(f"{label}: vs not identifiable: the data cover {100 * span:.0f} % of the Stribeck "
                       f"transition and {k} point(s) lie inside it (0.05 < phi < 0.95) for the fitted "
                       f"vs = {vals[2]:.4g}; add plateaus near vs or fit coulomb_viscous")
    for i, n in enumerate(st.params):
        near = fit["res"].active_mask[i] != 0 or abs(x[i] - lo[i]) <= 1e-6 * max(1.0, abs(lo[i])) or (
            np.isfinite(hi[i]) and abs(hi[i] - x[i]) <= 1e-6 * abs(hi[i]))
        if near:
            out.append(f"{label}: {n} = {vals[i]:.6g} is at its bound; its standard error is not meaningful")
            continue
        if n in weak:  # named above
            continue
        rse = se[i] / abs(vals[i]) if vals[i] != 0 else np.inf
        if not np.isfinite(rse) or rse > UNIDENTIFIABLE_RSE:
            hint = ""
            if n == "vs":
                slow = int(np.sum(u < 2.0 * vals[i]))
                hint = f" ({slow} point(s) below 2·vs; add low-speed plateaus)"
            out.append(f"{label}: {n} not identifiable: standard error {se[i]:.3g} is "
                       f"{100 * rse:.0f} % of its value {vals[i]:.6g}{hint}")
    if not fit["res"].success:
        out.append(f"{label}: optimiser did not converge ({fit['res'].message})")
    return out


def _sign_respecting(params, values, stats, dof) -> np.ndarray:
    """Intervals that stay where the parameter may live (issue 11, part 4).

    ``vs`` and ``delta`` must be > 0: their interval comes from the standard error of
    their logarithm, ``theta · exp(±t·se/theta)`` (drive 3's delta: [0.38, 46], not
    [−5.9, 14.3]). The levels ``Fc``, ``Fs``, ``sigma2`` may be 0: their Wald interval is
    cut at 0.
    """
    from .identifiability import log_interval

    ci = np.array(stats["ci"], dtype=float)
    for i, n in enumerate(params):
        v, se = float(values[i]), float(stats["stderr"][i])
        if n in ("vs", "delta") and v > 0 and np.isfinite(se):
            ci[i] = log_interval(v, se / v, dof)
        elif n in ("vs", "delta"):  # unbounded: anywhere it may live
            ci[i] = (0.0, np.inf)
        elif n in ("Fc", "Fs", "sigma2"):
            ci[i, 0] = max(ci[i, 0], 0.0)
    return ci


def _law(st: _Structure, vals: dict, delta: float | None):
    if st.name == "coulomb_viscous":
        return CoulombViscous(Fc=vals["Fc"], sigma2=vals["sigma2"])
    return Stribeck(Fc=vals["Fc"], Fs=vals["Fs"], vs=vals["vs"],
                    delta=vals.get("delta", 2.0 if delta is None else delta),
                    sigma2=vals["sigma2"], shape=st.name)


def _as_points(v, F, sigma) -> tuple[np.ndarray, np.ndarray, np.ndarray | None, SteadyStatePoints | None]:
    if isinstance(v, Recording):
        v = steady_state_points(v)
    if isinstance(v, SteadyStatePoints):
        if F is not None:
            raise DataError("fit_static_map: pass either SteadyStatePoints or (v, F) arrays, not both")
        return v.v, v.F, sigma, v
    if F is None:
        raise DataError("fit_static_map: F (mean force/torque per segment) is required with a velocity array")
    va = val.real_array("fit_static_map: v", v).ravel()
    Fa = val.real_array("fit_static_map: F", F).ravel()
    if va.size != Fa.size:
        raise DataError(f"fit_static_map: v has {va.size} points, F has {Fa.size}")
    for nm, a in (("v", va), ("F", Fa)):
        bad = ~np.isfinite(a)
        if bad.any():
            i = int(np.flatnonzero(bad)[0])
            raise DataError(f"fit_static_map: {nm}[{i}] = {float(a[i])!r}: must be finite")
    return va, Fa, sigma, None


def _check_magnitudes(va: np.ndarray, Fa: np.ndarray) -> None:
    """Refuse points whose squares overflow (a 1e300 sample in a plateau mean): name the point."""
    for nm, a in (("v", va), ("F", Fa)):
        big = np.abs(a) > val.HUGE
        if big.any():
            i = int(np.flatnonzero(big)[0])
            raise DataError(
                f"fit_static_map: {nm}[{i}] = {float(a[i]):.6g} is beyond {val.HUGE:.0e}: a corrupt "
                "sample or a unit/scale slip in that segment; remove or repair it"
            )


@val.typed_arguments  # argument types named at the boundary (issue 13 round 11)
def fit_static_map(
    v: ArrayLike | Recording,
    F: ArrayLike | None=None,
    *,
    model: str = "auto",
    direction: str = "both",
    delta: float | None = None,
    loss: str = "linear",
    f_scale: float | None = None,
    sigma: ArrayLike | None=None,
    criterion: str = "aic",
    units: dict | None = None,
    covariance: str = "residual",
) -> IdentificationResult:
    """Fit a static friction map per direction to steady-state points.

    Parameters
    ----------
    v : array_like, SteadyStatePoints or Recording
        Mean velocity of each constant-velocity segment [m/s or rad/s]; or the points
        from :func:`~frictionkit.data.steady_state_points`; or a recording, whose
        plateaus are then found and averaged automatically.
    F : array_like, optional
        Mean friction force/torque of each segment [N or N·m] (signed, as measured).
    model : {"auto", "coulomb_viscous", "exponential", "lorentzian"}
        Structure; ``"auto"`` picks, per direction, the lowest ``criterion`` among the
        structures that leave at least one residual degree of freedom.
    direction : {"both", "positive", "negative"}
        Which direction(s) to fit; each is fitted independently (seed 002 §3.1).
    delta : float, optional
        Fix the exponent of the exponential shape (2 gives seed 002 eq. 9b); default free.
    loss : {"linear", "soft_l1", "huber", "cauchy", "arctan"}
        Loss of ``scipy.optimize.least_squares``; robust losses down-weight outliers.
    f_scale : float, optional
        Residual scale of the robust loss [N or N·m]; default ``max |F|`` of the
        direction (the internal force unit).
    sigma : array_like, optional
        Standard deviation of each mean force (weights ``1/sigma``); default equal weights.
    criterion : {"aic", "bic"}
        Model-choice criterion for ``model="auto"``.
    units : dict, optional
        ``{"v": ..., "F": ...}`` unit strings used for the parameter units; default
        taken from the points, else ``m/s`` and ``N``.
    covariance : {"residual", "run_robust"}
        How the standard errors and intervals are computed (:data:`COVARIANCES`):
        ``"run_robust"`` for points that are run means of a constant-velocity campaign, each
        with its own error (needs ``loss="linear"``).

    Returns
    -------
    IdentificationResult
        Parameters ``Fc_pos, Fs_pos, vs_pos, delta_pos, sigma2_pos`` and/or the ``_neg``
        set (only those of the chosen structures), ``parts["positive"]`` /
        ``parts["negative"]`` with the per-direction results, and ``model`` a
        ``Directional`` law (or the single-direction law). ``warnings`` flags
        parameters that are not identifiable (relative standard error above
        :data:`UNIDENTIFIABLE_RSE`, at a bound, or a rank-deficient Jacobian).

    Raises
    ------
    DataError
        Non-finite or mismatched inputs.
    IdentificationError
        Too few points in a direction for the requested structure.

    Examples
    --------
    >>> import numpy as np
    >>> from frictionkit import Stribeck
    >>> from frictionkit.identify import fit_static_map
    >>> law = Stribeck(Fc=1.0, Fs=1.5, vs=0.01, delta=2.0, sigma2=5.0)
    >>> v = np.geomspace(1e-3, 0.2, 20)
    >>> res = fit_static_map(v, law.steady_state(v), model="exponential", direction="positive")
    >>> round(res["Fs_pos"], 4), round(res["vs_pos"], 4)
    (1.5, 0.01)
    """
    va, Fa, sig, pts = _as_points(v, F, sigma)
    _check_magnitudes(va, Fa)
    if direction not in ("both", "positive", "negative"):
        raise ParameterError(f"fit_static_map.direction = {direction!r}: must be 'both', 'positive' or 'negative'")
    if loss not in _LOSSES:
        raise ParameterError(f"fit_static_map.loss = {loss!r}: must be one of {list(_LOSSES)}")
    if criterion not in ("aic", "bic"):
        raise ParameterError(f"fit_static_map.criterion = {criterion!r}: must be 'aic' or 'bic'")
    if covariance not in COVARIANCES:
        raise ParameterError(f"fit_static_map.covariance = {covariance!r}: must be one of {list(COVARIANCES)}")
    if covariance == "run_robust" and loss != "linear":
        raise ParameterError(f"fit_static_map.covariance = 'run_robust' needs loss='linear' (got {loss!r}): "
                             "the sandwich is that of ordinary least squares")
    if model != "auto":
        _structure(model, delta)
    if delta is not None and (val.is_bool(delta) or not (np.isfinite(delta) and delta > 0)):
        raise ParameterError(f"fit_static_map.delta = {delta!r}: must be finite and > 0")
    if delta is not None and delta > MAX_FIXED_DELTA:
        raise ParameterError(f"fit_static_map.delta = {delta!r}: a fixed Stribeck exponent must be <= "
                             f"{MAX_FIXED_DELTA:g} (above it (|v|/vs)**delta overflows within the fit's vs range; "
                             f"the drop is then a step anyway)")
    if sig is not None:
        sig = val.real_array("fit_static_map.sigma", sig).ravel()  # "abc" was float()'s ValueError (round 11)
        if sig.size != va.size or not np.all(np.isfinite(sig) & (sig > 0)):
            raise DataError("fit_static_map.sigma: need one finite, positive standard deviation per point")
    un = dict(pts.units) if pts is not None else {"v": "m/s", "F": "N"}
    un.update(units or {})
    Fu, vu = un["F"], un["v"]

    dirs = {"both": (1, -1), "positive": (1,), "negative": (-1,)}[direction]
    parts: dict[str, IdentificationResult] = {}
    laws = {}
    for sgn in dirs:
        label = "positive" if sgn == 1 else "negative"
        sel = np.sign(va) == sgn
        u = np.abs(va[sel])
        y = sgn * Fa[sel]
        w = np.ones(u.size) if sig is None else 1.0 / sig[sel]
        w = w / np.mean(w) if w.size else w
        cands = list(MODELS) if model == "auto" else [model]
        fits = {}
        for m in cands:
            st = _structure(m, delta)
            if u.size < len(st.params) + 1:
                continue
            fits[m] = (st, _fit_direction(u, y, w, st, delta=delta, loss=loss, f_scale=f_scale,
                                          covariance=covariance))
        if not fits:
            need = len(_structure(cands[0], delta).params) + 1
            raise IdentificationError(
                f"{label} direction: {u.size} steady-state point(s); a {cands[0]} fit needs at least {need}"
            )
        chosen = min(fits, key=lambda m: fits[m][1][criterion])
        st, fit = fits[chosen]
        st_vals = dict(zip(st.params, fit["values"].tolist()))
        flags = _flags(st, fit, u, label, delta)
        try:
            law = _law(st, st_vals, delta)
        except ParameterError as exc:
            law = None
            flags.append(f"{label}: estimates do not form a valid model ({exc})")
        laws[label] = law
        stats = parameter_statistics(fit["values"], fit["cov"], fit["dof"])
        stats["ci"] = _sign_respecting(st.params, fit["values"], stats, fit["dof"])
        pred = sgn * (y + fit["raw"])  # raw = predicted - measured magnitude
        parts[label] = IdentificationResult(
            kind="static_map",
            model_name=chosen,
            model=law,
            names=st.params,
            values=fit["values"],
            stderr=stats["stderr"],
            ci95=stats["ci"],
            units=tuple(_unit_of(n, Fu, vu) for n in st.params),
            correlation=stats["correlation"],
            rms=float(np.sqrt(np.mean(fit["raw"] ** 2))),
            relative_error_percent=float(100 * np.linalg.norm(fit["raw"]) / np.linalg.norm(y)),
            n_obs=int(u.size),
            dof=int(fit["dof"]),
            success=bool(fit["res"].success),
            message=str(fit["res"].message),
            warnings=tuple(flags),
            diagnostics={
                "criterion": criterion,
                "candidates": {m: {"aic": f["aic"], "bic": f["bic"], "rss": f["rss"], "n_params": len(s.params)}
                               for m, (s, f) in fits.items()},
                "singular_value_ratio": fit["rank_ratio"],
                "nfev": int(fit["res"].nfev),
                "loss": loss,
                "delta_fixed": delta,
                "covariance": covariance,
                **({"max_leverage": fit["max_leverage"]} if fit["max_leverage"] is not None else {}),
            },
            provenance={"units": {"v": vu, "F": Fu}},
            data={"v": va[sel], "F": Fa[sel], "F_pred": pred,
                  **({"F_std": pts.F_std[sel]} if pts is not None else {})},
        )
    return _combine(parts, laws, un, pts, direction)


def _combine(parts, laws, un, pts, direction) -> IdentificationResult:
    sfx = {"positive": "_pos", "negative": "_neg"}
    names, units, vals, se, ci, warns, blocks = [], [], [], [], [], [], []
    for label, r in parts.items():
        names += [n + sfx[label] for n in r.names]
        units += list(r.units)
        vals.append(r.values)
        se.append(r.stderr)
        ci.append(r.ci95)
        warns += list(r.warnings)
        blocks.append(r.correlation)
    if pts is not None:
        warns += list(pts.dropped)  # what the segmentation left out, and why
    p = len(names)
    corr = np.full((p, p), 0.0)
    i = 0
    for b in blocks:
        k = b.shape[0]
        corr[i:i + k, i:i + k] = b
        i += k
    if len(laws) == 2:
        lp, ln = laws["positive"], laws["negative"]
        if lp is None or ln is None:
            model = None
        elif type(lp) is not type(ln):
            model = Directional(positive=_as_stribeck(lp), negative=_as_stribeck(ln))
        else:
            model = Directional(positive=lp, negative=ln)
        model_name = "directional(" + ", ".join(r.model_name for r in parts.values()) + ")"
    else:
        model = next(iter(laws.values()))
        model_name = next(iter(parts.values())).model_name
    raw = np.concatenate([r.data["F_pred"] - r.data["F"] for r in parts.values()])
    Fall = np.concatenate([r.data["F"] for r in parts.values()])
    data = {k: np.concatenate([r.data[k] for r in parts.values()]) for k in next(iter(parts.values())).data}
    prov = {"units": {"v": un["v"], "F": un["F"]}, "direction": direction}
    if pts is not None:
        prov["labels"] = list(pts.labels)
    return IdentificationResult(
        kind="static_map",
        model_name=model_name,
        model=model,
        names=tuple(names),
        values=np.concatenate(vals),
        stderr=np.concatenate(se),
        ci95=np.vstack(ci),
        units=tuple(units),
        correlation=corr,
        rms=float(np.sqrt(np.mean(raw**2))),
        relative_error_percent=float(100 * np.linalg.norm(raw) / np.linalg.norm(Fall)),
        n_obs=int(raw.size),
        dof=int(sum(r.dof for r in parts.values())),
        success=all(r.success for r in parts.values()),
        message="; ".join(f"{k}: {r.message}" for k, r in parts.items()),
        warnings=tuple(warns),
        diagnostics={k: dict(r.diagnostics) for k, r in parts.items()},
        provenance=prov,
        data=data,
        parts=parts,
    )


def _as_stribeck(law):
    if isinstance(law, Stribeck):
        return law
    # A flat Stribeck curve (Fs = Fc) is Coulomb + viscous; vs is then irrelevant.
    return Stribeck(Fc=law.Fc, Fs=law.Fc, vs=1.0, sigma2=law.sigma2)


def stribeck_model(result: IdentificationResult) -> Directional:
    """``Directional(positive=Stribeck(...), negative=Stribeck(...))`` from a two-direction fit.

    Coulomb-viscous parts become flat Stribeck curves (``Fs = Fc``), so the result
    can feed any model that needs a Stribeck static map (LuGre, GMS).

    Examples
    --------
    >>> import numpy as np
    >>> from frictionkit.identify import fit_static_map, stribeck_model
    >>> v = np.r_[np.linspace(0.01, 0.2, 8), -np.linspace(0.01, 0.2, 8)]
    >>> law = stribeck_model(fit_static_map(v, np.sign(v) + 2 * v, model="coulomb_viscous"))
    >>> round(law.positive.Fs, 6), round(law.negative.sigma2, 6)
    (1.0, 2.0)
    """
    if set(result.parts) != {"positive", "negative"}:
        raise IdentificationError("stribeck_model: needs a fit with direction='both'")
    laws = [result.parts[k].model for k in ("positive", "negative")]
    if any(m is None for m in laws):
        raise IdentificationError("stribeck_model: a direction has no valid model; see result.warnings")
    return Directional(positive=_as_stribeck(laws[0]), negative=_as_stribeck(laws[1]))


@val.typed_arguments  # argument types named at the boundary (issue 13 round 11)
def fit_static_records(records: Recording | Mapping[str, Recording], *, trim: float = 0.0, **kwargs: Any) -> IdentificationResult:
    """Average each record whole (one steady-state point per record) and fit the map.

    Parameters
    ----------
    records : mapping of str to Recording
        E.g. from :func:`~frictionkit.data.load_groups` (one record per speed).
    trim : float
        Fraction dropped at both ends of each record before averaging (default 0).
    **kwargs
        Passed to :func:`fit_static_map`.

    Returns
    -------
    IdentificationResult

    Examples
    --------
    >>> recs = load_groups("steady_state_records.csv", group="source_file", time="t_s",
    ...                    velocity="motor_velocity_rad_per_s", force="motor_torque_N_m",
    ...                    where={"drive_id": 1})  # doctest: +SKIP
    >>> fit_static_records(recs).summary()  # doctest: +SKIP
    """
    return fit_static_map(steady_state_points(records, trim=trim), **kwargs)


__all__: Sequence[str] = ("MODELS", "COVARIANCES", "fit_static_map", "fit_static_records", "stribeck_model")
