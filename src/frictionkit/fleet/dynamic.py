"""LuGre dynamics of one daily log, where the data allow: σ0 and σ1 from the brisk reversals.

The daily test motion is imposed (a stiff velocity loop), so the log gives position,
velocity and motor force but not the friction force itself. With the static map fitted
from the plateaus fixed:

1. **mass** — on the sliding samples (``|v| > 4 vs``), ``F - Fss(v) = m·a`` by least squares
   (``a`` a Savitzky–Golay derivative of the logged velocity): the staircase transitions
   carry it;
2. **friction through each reversal** — ``F_f = F - m·a`` in a window from the last sliding
   sample before the velocity changes sign to the first sliding sample after it (kept when
   shorter than 1 s: a reversal, not a stop at rest);
3. **σ0, σ1** — ``fk.simulate`` runs the LuGre law (fitted static map, σ0, σ1) *motion-driven*
   on the logged position of each window, starting in its sliding steady state
   (``z = s(v)/σ0``), and ``scipy.optimize.least_squares`` matches the simulated force to
   ``F_f`` over ``log σ0, log σ1`` (started from the best of a coarse σ0 grid). Standard errors from the Jacobian (``s² (JᵀJ)⁻¹`` on the
   log scale, delta method), 95 % intervals from Student's t on the log scale.

A log without brisk reversals (or without position) gives no dynamic fit and says why.
"""

from __future__ import annotations

import math

import numpy as np

#: Speed above which a sample counts as sliding, in multiples of the largest Stribeck velocity.
SLIDING_VS = 4.0
#: Longest reversal window used [s] (a longer one is a stop at rest, not a reversal).
MAX_WINDOW = 1.0
#: Bounds of σ0 [N/m] and σ1 [N·s/m] in the fit.
SIGMA0_BOUNDS = (1e3, 1e10)
SIGMA1_BOUNDS = (1e-3, 1e7)


def _g(law, v: np.ndarray) -> np.ndarray:
    """Stribeck level ``s(v) >= 0`` without the viscous term, per direction."""
    parts = (law.positive, law.negative) if hasattr(law, "positive") else (law, law)
    out = np.empty_like(v)
    for part, sel in zip(parts, (v >= 0, v < 0)):
        r = np.abs(v[sel]) / part.vs
        phi = np.exp(-(r**part.delta)) if part.shape == "exponential" else 1.0 / (1.0 + r * r)
        out[sel] = part.Fc + (part.Fs - part.Fc) * phi
    return out


def _sigma2(law, v: float) -> float:
    part = (law.positive if v >= 0 else law.negative) if hasattr(law, "positive") else law
    return float(part.sigma2)


def fit_lugre_reversals(rec, law) -> dict:
    """σ0, σ1 (and the moving mass) of a LuGre law with the static map ``law`` fixed.

    Parameters
    ----------
    rec : Recording
        Needs ``x``, ``v`` (or ``x``) and the force.
    law : Directional of Stribeck, or Stribeck
        The static map (from :func:`~frictionkit.identify.stribeck_model`).

    Returns
    -------
    dict
        ``ok`` (bool), ``message``; with ``ok``: ``mass``, ``mass_se``, ``sigma0``, ``sigma1``
        with ``_se``, ``_lo``, ``_hi``, ``rms`` [force unit], ``n_reversals``, ``n_samples``.
    """
    from scipy import stats
    from scipy.optimize import least_squares

    import frictionkit as fk

    from ..data.segmentation import find_reversals
    from ..data.signals import derivative

    if rec.x is None:
        return {"ok": False, "message": "no position signal: LuGre needs the displacement through reversals"}
    dt = rec.dt
    v = rec.v if rec.v is not None else derivative(rec.x, dt)
    F = rec.force()
    x = rec.x
    parts = (law.positive, law.negative) if hasattr(law, "positive") else (law,)
    vs_max = max(p.vs for p in parts)
    v_slide = SLIDING_VS * vs_max
    a = derivative(v, dt, method="savgol", window=21, polyorder=3)
    Fss = law.steady_state(v)
    slide = np.abs(v) > v_slide
    A = a[slide]
    # sums, not BLAS dot products: a multi-threaded BLAS sums in another order, and the
    # single-process path must give the same digits as the one-thread Dask workers
    AA = float(np.sum(A * A))
    if A.size < 10 or AA == 0.0:
        return {"ok": False, "message": "too few sliding samples with acceleration to estimate the mass"}
    y = F[slide] - Fss[slide]
    mass = float(np.sum(A * y) / AA)
    res_m = y - mass * A
    mass_se = float(np.sqrt(np.sum(res_m * res_m) / max(A.size - 1, 1) / AA))
    Ff = F - mass * a

    windows = []
    for r in find_reversals(v, deadband=0.5 * v_slide):
        before = np.flatnonzero(slide[:r])
        after = np.flatnonzero(slide[r:])
        if not before.size or not after.size:
            continue
        s0, e = int(before[-1]), int(r + after[0])
        if (e - s0) * dt <= MAX_WINDOW and e - s0 >= 5:
            windows.append((s0, min(e + 20, rec.n)))
    if not windows:
        return {"ok": False, "message": f"no brisk reversal through |v| > {v_slide:.3g} (4 vs) on both sides"}
    n_obs = sum(e - s for s, e in windows)

    def simulate(p: np.ndarray) -> np.ndarray:
        s0_, s1_ = math.exp(p[0]), math.exp(p[1])
        model = fk.LuGre(law, sigma0=s0_, sigma1=s1_)
        out = []
        for s, e in windows:
            v0 = float(v[s])
            z0 = math.copysign(float(_g(law, np.array([v0]))[0]), v0) / s0_
            sim = fk.simulate(model, position=x[s:e] - x[s], dt=dt, state0=z0)
            out.append(sim.friction)
        return np.concatenate(out)

    target = np.concatenate([Ff[s:e] for s, e in windows])

    def resid(p):
        with np.errstate(all="ignore"):
            r = simulate(p) - target
        return np.where(np.isfinite(r), r, 1e6)

    lo = np.log([SIGMA0_BOUNDS[0], SIGMA1_BOUNDS[0]])
    hi = np.log([SIGMA0_BOUNDS[1], SIGMA1_BOUNDS[1]])
    # start: the best of a coarse σ0 grid (σ1 at critical damping of the bristles with the mass)
    grid = [np.log([s0, math.sqrt(s0 * max(mass, 1e-3))]) for s0 in np.geomspace(1e4, 1e9, 11)]
    p0 = min(grid, key=lambda q: float(np.sum(resid(q) ** 2)))
    best = least_squares(resid, p0, bounds=(lo, hi), x_scale=1.0, diff_step=1e-4, max_nfev=50)
    p = best.x
    dof = max(n_obs - 2, 1)
    s2 = 2.0 * best.cost / dof
    try:
        cov = s2 * np.linalg.pinv(best.jac.T @ best.jac)
        se_log = np.sqrt(np.clip(np.diag(cov), 0.0, None))
    except np.linalg.LinAlgError:  # pragma: no cover
        se_log = np.full(2, np.nan)
    tq = float(stats.t.ppf(0.975, dof))
    out = {"ok": True, "message": str(best.message), "mass": mass, "mass_se": mass_se,
           "rms": float(np.sqrt(2.0 * best.cost / n_obs)), "n_reversals": len(windows), "n_samples": int(n_obs)}
    notes = []
    for i, name in enumerate(("sigma0", "sigma1")):
        val = math.exp(p[i])
        out[name] = val
        out[f"{name}_se"] = val * float(se_log[i])
        out[f"{name}_lo"] = math.exp(p[i] - tq * se_log[i])
        out[f"{name}_hi"] = math.exp(p[i] + tq * se_log[i])
        if best.active_mask[i] != 0 or not np.isfinite(se_log[i]) or se_log[i] > 1.0:
            notes.append(f"LuGre: {name} not identifiable from the reversals (at a bound or standard error "
                         f"above 100 %)")
    out["warnings"] = notes
    return out


__all__ = ["fit_lugre_reversals"]
