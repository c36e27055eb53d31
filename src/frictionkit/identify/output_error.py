"""Output-error identification of dynamic friction by simulation (seed 002 §3.1, eq. 12).

The measured input force drives the model (mass + friction law) and the
parameters minimise the squared difference between the simulated and the
measured velocity (or position)::

    min_theta  sum_k ( y_k - y_hat_k(theta) )^2          (seed 002 eq. 12)

Any subset of the parameters can be freed: LuGre ``sigma0``, ``sigma1``; GMS
``k1 .. kM``, ``xi1 .. xiM``, ``C``; the static map ``Fc``, ``Fs``, ``vs``,
``delta``, ``sigma2`` (both directions, or ``Fc_pos``, ``Fc_neg`` ... per
direction); the mass ``m``; a constant force ``offset`` (``m a = u - F - offset``).

How the simulations are organised (measured, see ``benchmarks/identify.py``):

* the residual vector of one parameter set comes from :func:`frictionkit.simulate`
  (numba kernel, about 10 ms for 25,000 samples);
* the finite-difference Jacobian needs the residual *vectors* of the ``p``
  perturbed parameter sets. :func:`frictionkit.simulate_batch` returns only
  weighted SSEs, so it cannot give a Jacobian; instead the ``p`` runs go to a
  thread pool — the kernels release the GIL (``nogil=True``), so this is the
  same parallelism as the batch kernel's ``prange`` without touching the kernels;
* the multi-start screening needs only the cost of each start, so all starts go
  to **one** :func:`~frictionkit.simulate_batch` call and the optimiser is run
  from the best ones;
* the optimiser is :func:`scipy.optimize.least_squares` (trust-region
  reflective, bounds) on transformed parameters: logarithms of the strictly
  positive ones (stiffnesses, ``C``, ``vs``, ``delta``, mass), the others scaled
  by their start value.

Standard errors come from ``s^2 (J^T J)^-1`` with the Jacobian at the optimum.

Layout: this module holds the fit itself; the parameters and the model they rebuild are
in ``_oe_params``, the data and the LuGre start values in ``initial_guess``, residuals,
Jacobian, start screening and bounds in ``_oe_problem``, the batched Levenberg–Marquardt
in ``_lm``. The motion-driven direction (measured motion in, force compared) is
:mod:`.motion_error`.
"""

from __future__ import annotations

import math
import os
import warnings
from collections.abc import Callable, Mapping, Sequence

import numpy as np
from scipy.optimize import least_squares

from .. import _validate as val
from ..data.recording import Recording
from ..errors import DataError, IdentificationError, ParameterError
from ..simulate.core import SimOptions
from ._lm import _blas_limit, _levenberg_marquardt
from ._oe_params import _Template, _unit
from ._oe_problem import _batch_costs, _bounds_tr, _Problem, _start_points
from .initial_guess import _arrays, initial_guess_lugre
from .result import IdentificationResult, parameter_statistics

__all__ = ["fit_output_error", "initial_guess_lugre", "OUTPUT_ERROR_OPTIONS"]

#: Integrator tolerances used by default during identification. Measured on the
#: 25,000-sample stick-slip run of ``benchmarks/identify.py``: max velocity error
#: 2.4e-6 m/s against a rtol = 1e-9 run (0.0006 % of the 0.39 m/s peak; the default
#: SimOptions give 4.5e-7) at 5 ms instead of 11.5 ms per simulation.
OUTPUT_ERROR_OPTIONS = SimOptions(rtol=1e-5, atol_v=1e-7, atol_F=1e-5)


def fit_output_error(
    data,
    model0,
    *,
    free: Sequence[str] = ("sigma0", "sigma1"),
    plant_mass: float,
    offset: float = 0.0,
    external_load=None,
    compare: str = "v",
    bounds: Mapping[str, tuple[float, float]] | None = None,
    starts: int = 1,
    refine: int = 1,
    seed: int = 0,
    weight=None,
    options: SimOptions | None = None,
    optimiser: str = "trf",
    max_nfev: int = 200,
    ftol: float = 1e-8,
    xtol: float = 1e-8,
    step_tol: float = 0.02,
    workers: int | None = None,
    diff_step: float = 1e-3,
    progress: Callable[[int, int, float], None] | None = None,
) -> IdentificationResult:
    """Fit dynamic-friction parameters by simulated-vs-measured output error (seed 002 eq. 12).

    The model ``m a = u - F(model) - offset`` is simulated from rest with the
    measured force ``u`` and the parameters named in ``free`` minimise
    ``sum_k w_k (y_k - y_hat_k)^2`` with ``y`` the velocity (``compare="v"``) or the
    position relative to its first sample (``compare="x"``).

    Parameters
    ----------
    data : Recording or mapping, or a list of them
        Uniformly sampled ``t`` [s], force ``F`` (or ``u``) [N] and the compared
        signal ``v`` [m/s] or ``x`` [m]. A list: the recordings (same sampling period)
        are fitted jointly, each simulated from rest on the single-axis kernel, the
        residuals stacked (``external_load`` is then a list with one array or None per
        recording; ``weight`` is not accepted).
    model0 : LuGre or GMS
        Structure and start values (the parameters not in ``free`` stay fixed).
    free : sequence of str
        Parameters to fit: ``sigma0``, ``sigma1`` (LuGre); ``k1..kM``, ``xi1..xiM``,
        ``C``, or ``k``/``xi`` for all elements (GMS); ``Fc``, ``Fs``, ``vs``,
        ``delta``, ``sigma2`` (both directions) or with ``_pos``/``_neg``; ``m``;
        ``offset``.
    plant_mass : float
        Moving mass [kg] (start value when ``"m"`` is free).
    offset : float
        Constant force [N] (start value when ``"offset"`` is free).
    external_load : array_like, optional
        A known load force [N] per sample, e.g. gravity evaluated on the measured
        position (seed 002 eq. 13: ``G2 = m g X sin(theta)``); it acts like friction,
        ``m a = u - F - offset - external_load``. It is taken as given (not fed back from
        the simulated position): the single-axis kernels stay usable, and the error
        this makes is the load's change over the simulated-vs-measured position
        difference, small wherever the fit is good.
    compare : {"v", "x"}
        Compared signal.
    bounds : mapping, optional
        ``{name: (low, high)}`` in natural units; default ``[0, inf)`` for
        non-negative parameters, ``(0, inf)`` for positive ones, unbounded ``offset``.
    starts : int
        Number of start points: the given values and ``starts - 1`` random
        perturbations (factor ``e^±1.5`` for log-parameters, ±50 % otherwise),
        screened by one :func:`~frictionkit.simulate_batch` call.
    refine : int
        How many of the best-screened starts are optimised to convergence.
    seed : int
        Random seed of the start perturbations.
    weight : array_like, optional
        Per-sample weights (default 1; sample 0 never counts).
    options : SimOptions, optional
        Integrator tolerances (default :data:`OUTPUT_ERROR_OPTIONS`).
    optimiser : {"trf", "lm"}
        ``"trf"`` (default): :func:`scipy.optimize.least_squares` trust-region
        reflective. ``"lm"``: Levenberg–Marquardt whose trial steps (three damping
        values) are judged in one :func:`~frictionkit.simulate_batch` call per
        iteration. Measured: on the 6-parameter LuGre benchmark ``"lm"`` needs
        ~190 simulations against ~260 for ``"trf"``, but on the GMS stiffness
        round trip it stalls on the non-smooth cost (4.7e-7 vs 2.6e-9), so
        ``"trf"`` is the default.
    max_nfev : int
        Iteration limit (``"lm"``) or evaluation limit (``"trf"``) per refined start.
    ftol, xtol
        Relative cost-reduction and (``"trf"`` only) step tolerances.
    step_tol : float
        ``"lm"`` stops when every step component is below ``step_tol`` times the
        parameter's standard error: further iterations cannot change the result
        by a statistically visible amount.
    workers : int, optional
        Threads for the Jacobian simulations (default: CPU count).
    diff_step : float
        Forward-difference step of the transformed parameters (relative for
        log-parameters). 1e-3 is large against the integrator noise (rtol 1e-6) yet
        small against the curvature; measured on GMS round trips, 1e-4 stalls in
        false minima and 1e-2 biases the result.
    progress : callable, optional
        Called after every residual evaluation as ``progress(nfev, simulations, cost)``
        (the CLI shows it as a live status line). Exceptions from it propagate.

    Returns
    -------
    IdentificationResult
        ``kind="output_error"``; ``model`` the fitted LuGre/GMS; ``diagnostics``
        holds ``nfev``, ``njev``, ``status``, ``cost_history``, ``start_costs``,
        ``mass``, ``offset``, ``condition_number``; ``data`` holds ``t``, ``y``, ``y_pred``.

    Raises
    ------
    ParameterError
        Unknown or repeated parameter names, bad settings.
    DataError
        Missing signals, irregular sampling.
    IdentificationError
        Every start fails to simulate, the optimiser stops without convergence
        (``max_nfev`` reached), or the Jacobian at the optimum is singular
        (a parameter has no effect on the output, or parameters are confounded).

    Examples
    --------
    >>> import numpy as np, frictionkit as fk
    >>> from frictionkit.identify.output_error import fit_output_error
    >>> true = fk.LuGre(fk.Stribeck(Fc=1.0, Fs=1.5, vs=1e-3, sigma2=0.4), sigma0=1e5, sigma1=63.2)
    >>> dt = 1e-3; t = np.arange(3001) * dt; u = 2.0 * np.sin(np.pi * t)
    >>> sim = fk.simulate(true, plant=fk.Mass(1.0), force=u, dt=dt)
    >>> start = fk.LuGre(true.static, sigma0=3e4, sigma1=100.0)
    >>> res = fit_output_error({"t": t, "F": u, "v": sim.v}, start, plant_mass=1.0)
    >>> round(res["sigma0"] / 1e5, 2)           # within 1 % of the truth
    1.0
    """
    owner = "fit_output_error"
    if optimiser not in ("lm", "trf"):
        raise ParameterError(f"{owner}: optimiser = {optimiser!r}: must be 'lm' or 'trf'")
    if compare not in ("v", "x"):
        raise ParameterError(f"{owner}: compare = {compare!r}: must be 'v' or 'x'")
    plant_mass = val.positive(owner, "plant_mass", plant_mass)
    offset = val.finite(owner, "offset", offset)
    if not isinstance(starts, (int, np.integer)) or starts < 1:
        raise ParameterError(f"{owner}: starts = {starts!r}: must be an integer >= 1")
    refine = max(1, min(int(refine), int(starts)))
    records = list(data) if isinstance(data, (list, tuple)) else [data]
    if not records:
        raise DataError(f"{owner}: data is an empty list; give a recording or a list of recordings")
    if len(records) == 1:
        loads = [external_load]
    else:
        loads = [None] * len(records) if external_load is None else list(external_load)
    if len(loads) != len(records):
        raise DataError(f"{owner}: {len(records)} recordings but {len(loads)} external_load arrays")
    if weight is not None and len(records) > 1:
        raise ParameterError(f"{owner}: weight= is for one recording; with {len(records)} recordings give none")
    ts, us, ys, ws, segments = [], [], [], [], []
    for k, (rec_k, load_k) in enumerate(zip(records, loads)):
        t, u, x, v, prov_k, name_k = _arrays(rec_k)
        if k == 0:
            prov, name = prov_k, name_k
        if load_k is not None:
            load = val.signal("external_load", load_k)
            if load.size != u.size:
                raise DataError(f"{owner}: external_load has {load.size} samples, the recording {u.size}")
            u = u - load
            prov["external_load"] = "given per sample (subtracted from the input force)"
        y = x if compare == "x" else v
        if y is None:
            raise DataError(f"recording '{name_k}': compare = {compare!r} needs the signal {compare!r}")
        y = np.asarray(y, float)
        if compare == "x":
            y = y - y[0]
        w = np.ones(u.size) if weight is None else val.signal("weight", weight)
        if w.size != u.size or (w < 0).any():
            raise DataError("weight must have one non-negative entry per sample")
        w = w.copy()
        w[0] = 0.0
        dt_k = float(np.median(np.diff(t)))
        if k == 0:
            dt = dt_k
        elif abs(dt_k - dt) > 1e-9 * dt:
            raise DataError(f"{owner}: recording {k} is sampled every {dt_k:.6g} s, recording 0 every {dt:.6g} s")
        n0 = sum(a.size for a in us)
        segments.append((n0, n0 + u.size))
        ts.append(t if not ts else t - t[0] + ts[-1][-1] + dt)  # records one after the other
        us.append(u)
        ys.append(y)
        ws.append(w)
    t, u, y, w = (np.concatenate(a) for a in (ts, us, ys, ws))
    if len(records) > 1:
        prov["records"] = len(records)
    sw = np.sqrt(w)
    tmpl = _Template.of(model0, plant_mass, offset)
    names = tmpl.expand(free)
    theta0 = np.array([tmpl.get(n) for n in names])
    options = options or OUTPUT_ERROR_OPTIONS
    workers = workers or os.cpu_count() or 1
    prob = _Problem(tmpl, names, u, dt, y, compare, sw, options, theta0, workers)
    prob.segments = segments
    prob.diff_step = val.positive(owner, "diff_step", diff_step)
    if progress is not None and not callable(progress):
        raise ParameterError(f"{owner}: progress = {progress!r}: must be callable(nfev, simulations, cost) or None")
    prob.progress = progress
    lo, hi = _bounds_tr(names, tmpl, bounds, prob)
    p0 = prob.to_tr(theta0)
    if np.any(p0 < lo) or np.any(p0 > hi):
        j = int(np.flatnonzero((p0 < lo) | (p0 > hi))[0])
        raise ParameterError(f"{owner}: start value {names[j]} = {theta0[j]:.6g} lies outside its bounds")
    rng = np.random.default_rng(seed)
    pts = _start_points(p0, lo, hi, prob.is_log, int(starts), rng)

    # --- screening: one batched simulation for all starts (SSE only)
    start_costs = np.full(len(pts), np.inf)
    if len(pts) > 1:
        start_costs = _batch_costs(prob, pts, w, options)
        order = [int(i) for i in np.argsort(start_costs) if np.isfinite(start_costs[i])]
        if not order:
            raise IdentificationError(f"{owner}: the simulation failed at every one of the {len(pts)} start points")
    else:
        order = [0]

    best = None
    runs = []
    for i in order[:refine]:
        prob.cost_history = []
        with warnings.catch_warnings(), _blas_limit():
            warnings.simplefilter("ignore", RuntimeWarning)
            if optimiser == "lm":
                sol = _levenberg_marquardt(prob, pts[i], lo, hi, w, options, max_iter=max_nfev, ftol=ftol,
                                           step_tol=step_tol)
            else:
                sol = least_squares(prob.fun, pts[i], jac=prob.jac, bounds=(lo, hi), method="trf",
                                    x_scale=1.0, max_nfev=max_nfev, ftol=ftol, xtol=xtol, gtol=1e-12)
        runs.append({"start": i, "cost": float(sol.cost), "status": int(sol.status), "nfev": int(sol.nfev),
                     "njev": int(sol.njev or 0), "message": sol.message, "history": list(prob.cost_history)})
        if best is None or sol.cost < best[0].cost:
            best = (sol, runs[-1])
    sol, run = best
    if not np.isfinite(sol.cost) or sol.cost >= 0.5 * prob.big**2:
        raise IdentificationError(f"{owner}: the simulation fails at the optimum; check the start values and bounds")
    if sol.status == 0:
        raise IdentificationError(
            f"{owner}: {optimiser} did not converge within max_nfev = {max_nfev} "
            f"{'iterations' if optimiser == 'lm' else 'evaluations'} "
            f"(cost {run['history'][0]:.4g} -> {sol.cost:.4g}); raise max_nfev or improve the start values"
        )

    theta = prob.to_nat(sol.x)
    r = prob.fun(sol.x)
    J = prob.jac(sol.x)
    # natural-parameter Jacobian: d r / d theta = d r / d p * d p / d theta
    dpdth = np.where(prob.is_log, 1.0 / theta, 1.0 / prob.scale)
    n_obs = int((w > 0).sum())
    dof = n_obs - len(names)
    if dof <= 0:
        raise IdentificationError(f"{owner}: {n_obs} samples for {len(names)} parameters")
    colnorm = np.linalg.norm(J, axis=0)
    dead = [names[j] for j in range(len(names)) if colnorm[j] <= 1e-10 * max(colnorm.max(), 1e-300)]
    if dead:
        raise IdentificationError(
            f"{owner}: unidentifiable — {', '.join(dead)} has no effect on the simulated {compare} "
            "for this data (zero Jacobian column); fix it or use data that excite it"
        )
    Js = J / colnorm
    sv = np.linalg.svd(Js, compute_uv=False)
    cond = float(sv[0] / sv[-1]) if sv[-1] > 0 else math.inf
    if not np.isfinite(cond) or cond > 1e8:
        raise IdentificationError(
            f"{owner}: unidentifiable — the Jacobian is singular (condition number {cond:.3g}); "
            f"the parameters {names} are confounded on this data"
        )
    s2 = float(r @ r) / dof
    # covariance in column-normalised transformed coordinates (well conditioned), then
    # mapped to natural units: cov_theta = D C D with D = d theta / d p
    Ci = np.linalg.inv(Js.T @ Js) / np.outer(colnorm, colnorm)
    dthdp = 1.0 / dpdth
    cov = s2 * Ci * np.outer(dthdp, dthdp)
    st = parameter_statistics(theta, cov, dof)
    model, m_fit, off_fit = tmpl.build(names, theta)
    res_sim = prob.simulate_nat(theta)
    y_pred = res_sim.x if compare == "x" else res_sim.v
    warns = []
    for j, nm in enumerate(names):
        if np.isfinite(st["stderr"][j]) and st["stderr"][j] > 0.5 * abs(theta[j]):
            warns.append(f"{nm} is poorly determined (standard error {st['stderr'][j]:.3g} > 50 % of {theta[j]:.6g})")
        if np.isfinite(lo[j]) and abs(sol.x[j] - lo[j]) < 1e-6 * max(1, abs(lo[j])) or \
                np.isfinite(hi[j]) and abs(sol.x[j] - hi[j]) < 1e-6 * max(1, abs(hi[j])):
            warns.append(f"{nm} = {theta[j]:.6g} sits on its bound")
    resid = (y_pred - y)[w > 0]
    units_map = {"F": "N", "x": "m"}
    if isinstance(data, Recording):
        units_map = {"F": data.units["F"], "x": data.units["x"]}
    prov.update({"recording": name, "units": {"F": units_map["F"], "x": units_map["x"],
                                               compare: f"{units_map['x']}/s" if compare == "v" else units_map["x"]},
                 "procedure": {"method": "output error (seed 002 eq. 12)", "compare": compare,
                               "optimiser": ("Levenberg-Marquardt, batched trial steps" if optimiser == "lm"
                                             else "scipy.optimize.least_squares trf")
                                            + ", forward-difference Jacobian (threaded nogil simulations)",
                               "starts": int(starts), "refine": refine, "seed": int(seed),
                               "rtol": options.rtol, "atol_v": options.atol_v, "atol_F": options.atol_F}})
    return IdentificationResult(
        kind="output_error",
        model_name=tmpl.kind,
        model=model,
        names=tuple(names),
        values=theta,
        stderr=st["stderr"],
        ci95=st["ci"],
        units=tuple(_unit(n, units_map["F"], units_map["x"]) for n in names),
        correlation=st["correlation"],
        rms=float(np.sqrt(np.mean(resid**2))),
        relative_error_percent=float(100.0 * np.linalg.norm(resid) / max(np.linalg.norm(y[w > 0]), 1e-300)),
        n_obs=n_obs,
        dof=dof,
        success=True,
        message=str(sol.message),
        warnings=tuple(warns),
        diagnostics={"nfev": run["nfev"], "njev": run["njev"], "status": run["status"],
                     "iterations": run["njev"], "cost_history": run["history"],
                     "start_costs": start_costs.tolist(), "runs": [{k: v for k, v in rr.items() if k != "history"}
                                                                   for rr in runs],
                     "mass": float(m_fit), "offset": float(off_fit), "condition_number": cond,
                     "simulations": int(prob.nsim)},
        provenance=prov,
        data={"t": t, "y": y, "y_pred": y_pred},
    )
