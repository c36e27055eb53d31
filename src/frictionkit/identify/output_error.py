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
* the Jacobian of the LuGre family is exact: forward sensitivities
  (:mod:`frictionkit.kernels.sensitivity`, glue in ``_jacobian``) give ``d v / d theta``
  of every parameter in one augmented run that takes the simulation's own steps (about
  2.6 plain simulations' cost for six parameters) instead of ``p`` simulations. Every
  evaluation is then one augmented run, handed to ``least_squares`` as the ``(p + 1)``-row
  problem with the same cost, gradient and ``J^T J`` (``_jacobian.ReducedProblem``), so the
  trust-region steps do not factor a 25,000-row Jacobian; ``jacobian="fd"`` and GMS use
  differences;
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

Several records, and rests inside a record (the drive disabled: force logged exactly
zero over ``min_rest`` samples, or a mask), are cut into **segments** the same way as
the motion-driven fit does (:func:`.motion_data.segment_bounds`): each run between
rests is simulated from rest (``x = v = 0``, unloaded bristles or elements) starting at
the last rest sample, and the rest samples are not fitted.

Start values belong to the library: ``fit_output_error(data, "lugre", static=...)``
with ``initial="auto"`` (the default) computes the ones not given
(:mod:`.start_values`); how the search runs is one :class:`.fit_options.FitOptions`.
A fit that does not converge (or cannot pin its parameters) is a result with
``success=False`` and a message; ``raise_on_failure=True`` raises instead.

Layout: this module holds the fit itself; the parameters and the model they rebuild are
in ``_oe_params``, the LuGre sub-breakaway guess in ``initial_guess``, the start model
and the static map in ``start_values``, residuals, Jacobian, start screening and bounds
in ``_oe_problem`` (with the one-BLAS-thread guard), the search settings in
``fit_options``. The motion-driven direction (measured motion in, force compared) is
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
from ..errors import DataError, IdentificationError, ParameterError
from ..simulation.core import SimOptions
from . import _jacobian
from ._oe_params import _Template, _unit
from ._oe_problem import _batch_costs, _blas_limit, _bounds_tr, _Problem, _start_points
from .fit_options import OUTPUT_ERROR_FIT, FitOptions, fit_settings
from .initial_guess import initial_guess_lugre
from .motion_data import _as_records, _describe_rests, _rest_masks, irregular, no_motion_cause, segment_bounds
from .result import IdentificationResult, parameter_statistics
from .start_values import FORCE_DRIVE_FREE, output_error_start, static_law
from typing import TYPE_CHECKING

if TYPE_CHECKING:
    from ..models.base import FrictionLaw
    from numpy.typing import ArrayLike
    from typing import Any

__all__ = ["evaluate_output_error", "fit_output_error", "initial_guess_lugre", "OUTPUT_ERROR_OPTIONS"]

#: Integrator tolerances used by default during identification. Measured on the
#: 25,000-sample stick-slip run of ``benchmarks/identify.py``: max velocity error
#: 2.4e-6 m/s against a rtol = 1e-9 run (0.0006 % of the 0.39 m/s peak; the default
#: SimOptions give 4.5e-7) at 5 ms instead of 11.5 ms per simulation.
#: The accuracy check is off (``check=False``) in the fit's inner loop: the fit's error budget is
#: the data's noise, not the README's contract, and the check's reruns flag a lightly damped GMS
#: contact at every rtol (the error of such ringing falls more slowly than rtol): on the record of
#: tests/unit/test_identify_output_error.py::test_gms_stiffness_round_trip (sum k 1.1e6 N/m on
#: 1 kg, omega dt 1.05) an unchecked run is 5.3e-4 of the friction range off the twin at rtol 1e-5,
#: well below the fit's needs, but flagged runs (NaN after failed_at) drove the fit to sum k 8e7.
OUTPUT_ERROR_OPTIONS = SimOptions(rtol=1e-5, atol_v=1e-7, atol_F=1e-5, check=False)

#: Why ``jacobian="auto"`` differences a GMS force-drive fit (measured decision, issue 11; the
#: numbers: ``benchmarks/identify.py``'s GMS force section, README): the sensitivities along the
#: simulated trajectory (``jacobian="sensitivity"``) are as accurate, but the fits end no lower on
#: balance over random starts and each Jacobian costs more CPU than the differences'.
GMS_FORCE_AUTO = ("auto: differences for the GMS force drive — sensitivities measured no better over random "
                  "starts and dearer per Jacobian; jacobian='sensitivity' opts in")


def _force_segments(owner, data, compare, external_load, weight, rests, min_rest):
    """The records cut into runs between rests, each a dict of arrays the fit simulates from rest."""
    recs = _as_records(data)
    if len(recs) == 1:
        loads = [external_load]
    else:
        loads = [None] * len(recs) if external_load is None else list(external_load)
    if len(loads) != len(recs):
        raise DataError(f"{owner}: {len(recs)} recordings but {len(loads)} external_load arrays")
    if weight is not None and len(recs) > 1:
        raise ParameterError(f"{owner}: weight= is for one recording; with {len(recs)} recordings give none")
    for r in recs:
        r.require("F")
    masks = _rest_masks(rests, recs, min_rest)
    segs, summary = [], {}
    dt = None
    for k, (rec, load, rest) in enumerate(zip(recs, loads, masks)):
        if not rec.is_regular:
            raise irregular(rec)
        u = np.asarray(rec.force(), dtype=float)
        if load is not None:
            load = val.signal("external_load", load)
            if load.size != u.size:
                raise DataError(f"{owner}: external_load has {load.size} samples, the recording {u.size}")
            u = u - load
        y_all = rec.x if compare == "x" else rec.v
        if y_all is None:
            raise DataError(f"recording '{rec.name}': compare = {compare!r} needs the signal {compare!r}")
        y_all = np.asarray(y_all, float)
        w_all = np.ones(u.size) if weight is None else val.signal("weight", weight)
        if w_all.size != u.size or (w_all < 0).any():
            raise DataError("weight must have one non-negative entry per sample")
        dt_k = float(np.median(np.diff(rec.t)))  # each record simulated with its own sample period
        if dt is None:
            dt = dt_k
        bounds = segment_bounds(rest)
        for s0, _start, stop in bounds:
            sl = slice(s0, stop)
            y = y_all[sl] - y_all[s0] if compare == "x" else y_all[sl]
            w = w_all[sl].copy()
            w[0] = 0.0  # the initial state: from rest by assumption, never fitted
            x = None if rec.x is None else np.asarray(rec.x, float)[sl] - float(rec.x[s0])
            v = None if rec.v is None else np.asarray(rec.v, float)[sl]
            segs.append({"record": rec.name, "record_index": k, "t": rec.t[sl], "u": u[sl], "y": y, "w": w,
                         "x": x, "v": v, "dt": dt_k})
        summary[rec.name] = {"samples": rec.n, "rest_samples": int(rest.sum()),
                             "segments": [[int(a), int(b)] for _, a, b in bounds], "dt": dt_k}
    if not segs:
        raise DataError(f"{owner}: no motion to fit: {no_motion_cause(rests, min_rest)}")
    if not any(np.any(s["u"] != 0) for s in segs):  # from rest, a zero force moves nothing: sigma0 "unidentifiable"
        raise DataError(f"{owner}: the applied force is exactly 0 on every sample to fit; nothing drives the mass "
                        "(the wrong --force column, or a rest mask that marks the motion as rest?)")
    if not isinstance(rests, str) and rests is not None and not any(np.any(s["y"][s["w"] > 0] != 0) for s in segs):
        # a mask that is zero only where the axis stood (the inverted sense, or the wrong column) left
        # nothing but rest samples: the fit ran on them and reported 1e299 % relative error
        what = "position change" if compare == "x" else "velocity"
        raise DataError(f"{owner}: no motion to fit: the measured {what} is exactly 0 on every sample the rest "
                        f"mask leaves ({sum(int((s['w'] > 0).sum()) for s in segs)} samples); a mask is non-zero "
                        "where the drive is disabled")
    return recs, segs, summary, dt  # dt: the first record's period (each segment carries its own)


def _relative_percent(resid, y) -> float:
    """100 |resid| / |y|; NaN when the compared signal is zero on every fitted sample (no scale to relate
    to: a floor of 1e-300 reported 1e299 %)."""
    ny = float(np.linalg.norm(y))
    return float(100.0 * np.linalg.norm(resid) / ny) if ny > 0 else math.nan


@val.typed_arguments  # argument types named at the boundary (issue 13 round 11)
def fit_output_error(
    data: Any,
    model0: str | FrictionLaw="lugre",
    *,
    static: Any=None,
    initial: Any="auto",
    free: Sequence[str] | None = None,
    inertia: float,
    offset: float = 0.0,
    external_load: Any=None,
    compare: str = "v",
    bounds: Mapping[str, tuple[float, float]] | None = None,
    weight: ArrayLike | None=None,
    rests: Any="auto",
    min_rest: int = 3,
    elements: int = 3,
    options: SimOptions | None = None,
    fit: FitOptions | None = None,
    progress: Callable[[int, int, float], None] | None = None,
    **settings: Any,
) -> IdentificationResult:
    """Fit dynamic-friction parameters by simulated-vs-measured output error (seed 002 eq. 12).

    The model ``m a = u - F(model) - offset`` is simulated from rest with the
    measured force ``u`` and the parameters named in ``free`` minimise
    ``sum_k w_k (y_k - y_hat_k)^2`` with ``y`` the velocity (``compare="v"``) or the
    position relative to the segment's first sample (``compare="x"``).

    Parameters
    ----------
    data : Recording or mapping, or a list / dict of them
        Uniformly sampled ``t`` [s], force ``F`` (or ``u``) [N] and the compared
        signal ``v`` [m/s] or ``x`` [m]. Several records (each uniformly sampled, the
        periods may differ) are fitted jointly; every record is cut at its rests (``rests``) and every run
        between rests is simulated from rest, starting at the last rest sample.
    model0 : "lugre", "gms", "dahl", or a LuGre / GMS / Dahl law
        A name: the structure, with ``static`` the map and ``initial`` the start
        values (Dahl: the map's Coulomb level ``Fc`` and ``sigma2``, per direction).
        Dahl may be a ``Directional`` of two Dahl laws sharing ``sigma0``. A law: structure and start values as given (``static`` and an
        ``initial`` mapping are then refused).
    static : law, static-map result, or path, optional
        With a model name: the static map — a ``Stribeck``/``Directional`` law, the
        result of :func:`~frictionkit.identify.fit_static_map`, or the JSON file
        ``identify static --json`` wrote.
    initial : "auto" or mapping
        ``"auto"`` (default): start values not given are computed from the data
        (:func:`.start_values.output_error_start`: LuGre ``sigma0`` from the
        sub-breakaway branches, ``sigma1`` from critical damping; GMS stiffnesses
        sharing that total). A mapping gives some of them (LuGre ``sigma0``,
        ``sigma1``; GMS ``k``, ``xi``, ``C``; Dahl ``sigma0``), the rest are computed.
    free : sequence of str, optional
        Parameters to fit (default LuGre ``sigma0, sigma1``; GMS ``k``; Dahl ``sigma0``;
        Dahl has ``sigma0``, ``Fc``, ``sigma2``, ``m``, ``offset``):
        ``sigma0``, ``sigma1`` (LuGre); ``k1..kM``, ``xi1..xiM``, ``C``, or
        ``k``/``xi`` for all elements (GMS); ``Fc``, ``Fs``, ``vs``, ``delta``,
        ``sigma2`` (both directions) or with ``_pos``/``_neg``; ``m``; ``offset``.
    inertia : float
        The plant's inertia: moving mass [kg], or [kg·m²] for a rotary axis (the package's one
        word for a generalised mass; start value when ``"m"`` is free).
    offset : float
        Constant force [N] (start value when ``"offset"`` is free).
    external_load : array_like, or a list of them
        A known load force [N] per sample, e.g. gravity evaluated on the measured
        position (seed 002 eq. 13: ``G2 = m g X sin(theta)``); it acts like friction,
        ``m a = u - F - offset - external_load``. It is taken as given (not fed back from
        the simulated position): the single-axis kernels stay usable, and the error
        this makes is the load's change over the simulated-vs-measured position
        difference, small wherever the fit is good. One array (or None) per record.
    compare : {"v", "x"}
        Compared signal.
    bounds : mapping, optional
        ``{name: (low, high)}`` in natural units; default ``[0, inf)`` for
        non-negative parameters, ``(0, inf)`` for positive ones, unbounded ``offset``.
    weight : array_like, optional
        Per-sample weights of one record (default 1; a segment's first sample never counts).
    rests : "auto", None, array of bool, or one per record
        Where the drive is disabled (state reset, not fitted): ``"auto"`` finds runs of
        force logged exactly 0 over ``min_rest`` samples
        (:func:`frictionkit.data.find_rests`); a mask gives them (True = rest); None:
        no rests.
    min_rest : int
        Shortest run of zero force taken as a rest with ``rests="auto"``.
    elements : int
        GMS elements when ``model0="gms"`` and ``k``, ``xi`` are not given.
    options : SimOptions, optional
        Integrator tolerances (default :data:`OUTPUT_ERROR_OPTIONS`).
    fit : FitOptions, optional
        How the search runs (default :data:`.fit_options.OUTPUT_ERROR_FIT`: one start,
        ``"trf"``, ``max_nfev=200``, ``ftol = xtol = 1e-8``, ``diff_step=1e-3``,
        ``raise_on_failure=False``).
    progress : callable, optional
        Called after every residual evaluation as ``progress(nfev, simulations, cost)``
        (the CLI shows it as a live status line). Exceptions from it propagate.
    **settings
        Single :class:`~.fit_options.FitOptions` fields replacing those of ``fit``:
        ``starts``, ``refine``, ``seed``, ``max_nfev``, ``ftol``, ``xtol``, ``workers``,
        ``diff_step``, ``jacobian``, ``raise_on_failure``.
        ``diff_step`` 1e-3 is large against the integrator noise yet small against the
        curvature (measured on GMS round trips: 1e-4 stalls in false minima, 1e-2 biases).

    Returns
    -------
    IdentificationResult
        ``kind="output_error"``; ``model`` the fitted LuGre/GMS (None when no
        simulation succeeded); ``success`` False when the optimiser did not converge or
        the parameters are not identifiable on this data (``message`` says which,
        ``diagnostics["status"]`` is the optimiser's status, 0 = evaluation limit);
        ``diagnostics`` holds ``nfev``, ``njev``, ``status``, ``cost_history``,
        ``start_costs``, ``mass``, ``offset``, ``condition_number``, ``jacobian``
        (``"sensitivities"`` or ``"differences"``, ``" (auto: GMS force drive)"`` added where
        ``jacobian="auto"`` chose differences for GMS: :data:`GMS_FORCE_AUTO`), ``segments`` (per
        record: samples, rest samples, runs), ``initial`` (computed start values);
        ``data`` holds ``t``, ``y``, ``y_pred`` (fitted runs, records one after another).

    Raises
    ------
    ParameterError
        Unknown or repeated parameter names, bad settings, a start value outside its bounds.
    DataError
        Missing signals, irregular sampling, no motion, no pre-sliding branch for an
        ``"auto"`` start value.
    IdentificationError
        Only with ``raise_on_failure=True``: every start fails to simulate, the
        optimiser stops without convergence, or the Jacobian at the optimum is singular
        (a parameter has no effect on the output, or parameters are confounded).

    Examples
    --------
    >>> import numpy as np, frictionkit as fk
    >>> from frictionkit.identify.output_error import fit_output_error
    >>> true = fk.LuGre(fk.Stribeck(Fc=1.0, Fs=1.5, vs=1e-3, sigma2=0.4), sigma0=1e5, sigma1=63.2)
    >>> dt = 1e-3; t = np.arange(3001) * dt; u = 2.0 * np.sin(np.pi * t)
    >>> sim = fk.simulate(true, plant=fk.Mass(1.0), force=u, dt=dt)
    >>> start = fk.LuGre(true.static, sigma0=3e4, sigma1=100.0)
    >>> res = fit_output_error({"t": t, "F": u, "v": sim.v}, start, inertia=1.0)
    >>> round(res["sigma0"] / 1e5, 2), res.success           # within 1 % of the truth
    (1.0, True)
    """
    owner = "fit_output_error"
    cfg = fit_settings(owner, OUTPUT_ERROR_FIT, fit, settings,
                       unused={"profile": "the force-driven fit has no likelihood profiles"})
    if cfg.starts == "auto":
        raise ParameterError(f"{owner}: starts = 'auto' is the motion-driven start grid; give an integer >= 1")
    if compare not in ("v", "x"):
        raise ParameterError(f"{owner}: compare = {compare!r}: must be 'v' or 'x'")
    inertia = val.positive(owner, "inertia", inertia)
    offset = val.finite(owner, "offset", offset)
    if progress is not None and not callable(progress):
        raise ParameterError(f"{owner}: progress = {progress!r}: must be callable(nfev, simulations, cost) or None")
    if isinstance(data, (list, tuple)) and not data:
        raise DataError(f"{owner}: data is an empty list; give a recording or a list of recordings")
    recs, segs, seg_summary, dt = _force_segments(owner, data, compare, external_load, weight, rests, min_rest)

    # --- the start model: given, or computed from the data (initial="auto")
    computed: dict = {}
    start_from = "given"
    if isinstance(model0, str):
        start_from = "auto" if initial == "auto" else "auto, some given"
        kind = model0.lower()
        if not (initial == "auto" or isinstance(initial, Mapping)):
            raise ParameterError(f"{owner}: initial = {initial!r}: must be 'auto' or a mapping of start values")
        law = static_law(static, owner)
        model0, computed = output_error_start(
            kind, law, [{"t": s["t"], "F": s["u"], "x": s["x"], "v": s["v"]} for s in segs],
            inertia=inertia, given=initial if isinstance(initial, Mapping) else None, elements=elements,
            owner=owner)
    else:
        if static is not None:
            raise ParameterError(f"{owner}: static= is for a model name (model0='lugre' or 'gms'); "
                                 f"the {type(model0).__name__} given carries its own static map")
        if initial != "auto":
            raise ParameterError(f"{owner}: initial = {initial!r} with a {type(model0).__name__} given: its values "
                                 "are the start; give model0='lugre'/'gms' to compute some of them")
    tmpl = _Template.of(model0, inertia, offset)
    names = tmpl.expand(free if free is not None else FORCE_DRIVE_FREE[tmpl.kind])

    shift, ts, last = {}, [], None  # records one after the other on the time axis
    for s in segs:
        k = s["record_index"]
        if k not in shift:
            shift[k] = 0.0 if last is None else last + s["dt"] - float(s["t"][0])
        ts.append(s["t"] + shift[k])
        last = float(ts[-1][-1])
    t = np.concatenate(ts)
    u, y, w = (np.concatenate([s[k] for s in segs]) for k in ("u", "y", "w"))
    edges = np.cumsum([0] + [s["u"].size for s in segs])
    segments = [(int(a), int(b)) for a, b in zip(edges[:-1], edges[1:])]
    sw = np.sqrt(w)
    theta0 = np.array([tmpl.get(n) for n in names])
    options = options or OUTPUT_ERROR_OPTIONS
    workers = cfg.workers or os.cpu_count() or 1
    prob = _Problem(tmpl, names, u, dt, y, compare, sw, options, theta0, workers)
    prob.segments = segments
    prob.dts = [s["dt"] for s in segs]
    prob.diff_step = cfg.diff_step
    prob.progress = progress
    # forward sensitivities (kernels.sensitivity; GMS: kernels.sensitivity_gms along the simulated trajectory)
    prob.exact = (cfg.jacobian in ("auto", "sensitivity") and tmpl.kind in ("lugre", "dahl")
                  or cfg.jacobian == "sensitivity" and tmpl.kind == "gms")
    auto_gms = cfg.jacobian == "auto" and tmpl.kind == "gms"  # differences, by the measured decision
    lo, hi = _bounds_tr(names, tmpl, bounds, prob)
    p0 = prob.to_tr(theta0)
    if np.any(p0 < lo) or np.any(p0 > hi):
        j = int(np.flatnonzero((p0 < lo) | (p0 > hi))[0])
        raise ParameterError(f"{owner}: start value {names[j]} = {theta0[j]:.6g} lies outside its bounds")
    n_obs = int((w > 0).sum())
    dof = n_obs - len(names)
    if dof <= 0:
        raise DataError(f"{owner}: {n_obs} fitted samples for {len(names)} parameters")
    rng = np.random.default_rng(cfg.seed)
    pts = _start_points(p0, lo, hi, prob.is_log, int(cfg.starts), rng)
    refine = min(cfg.refine, len(pts))

    units_map = {"F": recs[0].units["F"], "x": recs[0].units["x"]}
    prov = dict(recs[0].provenance)
    if len(recs) > 1:
        prov["records"] = len(recs)
    prov.update({"recording": recs[0].name if len(recs) == 1 else [r.name for r in recs],
                 "units": {"F": units_map["F"], "x": units_map["x"],
                           compare: f"{units_map['x']}/s" if compare == "v" else units_map["x"]},
                 "procedure": {"method": "output error (seed 002 eq. 12)", "drive": "force", "compare": compare,
                               "rests": _describe_rests(rests, min_rest), "min_rest": int(min_rest),
                               "initial": start_from,
                               "free": list(names),
                               "optimiser": "scipy.optimize.least_squares trf"
                                            + ((", exact Jacobian (forward sensitivities)" if tmpl.kind != "gms" else
                                                ", Jacobian from forward sensitivities along the simulated "
                                                "trajectory") if prob.exact else
                                               ", forward-difference Jacobian (threaded nogil simulations)"
                                               + (f" ({GMS_FORCE_AUTO})" if auto_gms else "")),
                               "starts": int(cfg.starts), "refine": refine, "seed": int(cfg.seed),
                               "rtol": options.rtol, "atol_v": options.atol_v, "atol_F": options.atol_F}})
    units = tuple(_unit(n, units_map["F"], units_map["x"]) for n in names)

    def failed(message: str, theta, sol=None, run=None, start_costs=None) -> IdentificationResult:
        if cfg.raise_on_failure:
            raise IdentificationError(f"{owner}: {message}")
        try:
            model, m_fit, off_fit = tmpl.build(names, theta)
            sim = prob.simulate_nat(theta)
        except ParameterError:
            model, sim, (m_fit, off_fit) = None, None, (inertia, offset)
        y_pred = None if sim is None else (sim.x if compare == "x" else sim.v)
        ok = y_pred is not None and bool(np.all(np.isfinite(y_pred)))
        resid = (y_pred - y)[w > 0] if ok else np.full(n_obs, np.nan)
        nan = np.full(len(names), np.nan)
        return IdentificationResult(
            kind="output_error", model_name=tmpl.kind, model=model if ok else None, names=tuple(names),
            values=theta, stderr=nan, ci95=np.column_stack([nan, nan]), units=units,
            correlation=np.full((len(names), len(names)), np.nan),
            rms=float(np.sqrt(np.mean(resid**2))),
            relative_error_percent=_relative_percent(resid, y[w > 0]),
            n_obs=n_obs, dof=dof, success=False, message=message, warnings=(f"not identified: {message}",),
            diagnostics={"nfev": run["nfev"] if run else 0, "njev": run["njev"] if run else 0,
                         "status": int(sol.status) if sol is not None else -1,
                         "cost_history": run["history"] if run else [],
                         "start_costs": [] if start_costs is None else start_costs.tolist(),
                         "mass": float(m_fit), "offset": float(off_fit), "condition_number": math.inf,
                         "simulations": int(prob.nsim), "segments": seg_summary, "initial": computed},
            provenance=prov,
            data={"t": t, "y": y, "y_pred": y_pred} if ok else {"t": t, "y": y},
        )

    def start_note() -> str:
        """Why a fit that ended unidentifiable may never have started: the start values do not simulate
        (e.g. sigma0 = 1e16 on 1 kg: the fit then wanders off to sigma0 ~ 1e-96). Run only on failure."""
        try:
            sim0 = prob.simulate_nat(prob.to_nat(pts[order[0]] if order else pts[0]))
        except Exception as exc:  # noqa: BLE001 - any failure of the start is the point of the note
            return f"; the start values do not simulate ({type(exc).__name__}: {exc})"
        if getattr(sim0, "status", 0) != 0:
            msg = " ".join(str(sim0.message).split())
            msg = msg[msg.find("sigma0 ="):] if "sigma0 =" in msg else msg  # the kernel's reason, if it gives one
            return f"; the start values do not simulate ({msg[:400]})"
        return ""

    # --- screening: one batched simulation for all starts (SSE only)
    start_costs = np.full(len(pts), np.inf)
    if len(pts) > 1:
        start_costs = _batch_costs(prob, pts, w, options)
        order = [int(i) for i in np.argsort(start_costs) if np.isfinite(start_costs[i])]
        if not order:
            return failed(f"the simulation failed at every one of the {len(pts)} start points; check the start "
                          "values and bounds", theta0, start_costs=start_costs)
    else:
        order = [0]

    def search():
        best, runs = None, []
        for i in order[:refine]:
            prob.cost_history = []
            with warnings.catch_warnings(), _blas_limit():
                warnings.simplefilter("ignore", RuntimeWarning)
                # exact Jacobians: every evaluation is one augmented run, handed to trf as the (p + 1)-row
                # problem with the same cost, gradient and Gauss-Newton matrix (_jacobian.ReducedProblem)
                red = _jacobian.ReducedProblem(prob) if prob.exact else prob
                sol = least_squares(red.fun, pts[i], jac=red.jac, bounds=(lo, hi), method="trf",
                                    x_scale=1.0, max_nfev=cfg.max_nfev, ftol=cfg.ftol, xtol=cfg.xtol, gtol=1e-12)
                sol.full = red.full(sol.x) if prob.exact else None  # (r, J) at the optimum, if at hand
            runs.append({"start": i, "cost": float(sol.cost), "status": int(sol.status), "nfev": int(sol.nfev),
                         "njev": int(sol.njev or 0), "message": sol.message, "history": list(prob.cost_history)})
            if best is None or sol.cost < best[0].cost:
                best = (sol, runs[-1])
        sol, run = best
        theta = prob.to_nat(sol.x)
        # the simulation itself at the optimum (a cost as large as the data's is no failure: a mass of
        # 1e300 kg that barely moves gave "the simulation fails" although every run succeeded)
        sim_opt = prob.simulate_nat(theta) if np.isfinite(sol.cost) else None
        y_opt = None if sim_opt is None else (sim_opt.x if compare == "x" else sim_opt.v)
        ok = y_opt is not None and bool(np.all(np.isfinite(y_opt))) and getattr(sim_opt, "status", 0) == 0
        return sol, run, runs, theta, sim_opt, y_opt, ok

    sol, run, runs, theta, sim_opt, y_opt, ok = search()
    if not ok:
        # a run the kernel stopped or flagged (e.g. sigma0 = 1e300: ringing far faster than the samples)
        # is no optimum, even where its truncated trace is finite
        why = ""
        if sim_opt is not None and getattr(sim_opt, "message", "ok") != "ok":
            why = f" ({sim_opt.message})"  # simulate's own message
        elif sim_opt is None and np.isfinite(sol.cost):
            why = f" ({prob.last_failure})" if prob.last_failure else ""
        elif sim_opt is None:
            why = " (the cost is not finite)"
        elif y_opt is not None:
            bad = np.flatnonzero(~np.isfinite(y_opt))
            if bad.size:
                why = f" (the simulated {compare} is not finite from sample {int(bad[0])})"
        return failed(f"the simulation fails at the optimum{why}; check the start values and bounds", theta, sol,
                      run, start_costs)
    converged = sol.status != 0
    message = str(sol.message) if converged else (
        f"least_squares did not converge within max_nfev = {cfg.max_nfev} evaluations "
        f"(cost {run['history'][0]:.4g} -> {sol.cost:.4g}); raise max_nfev or improve the start values")
    if not converged and cfg.raise_on_failure:
        raise IdentificationError(f"{owner}: {message}")

    if sol.full is not None:  # the augmented run at the optimum (the reduced problem's last Jacobian)
        r, J = sol.full
    else:
        r = prob.fun(sol.x)
        J = prob.jac(sol.x)
    # natural-parameter Jacobian: d r / d theta = d r / d p * d p / d theta
    dpdth = np.where(prob.is_log, 1.0 / theta, 1.0 / prob.scale)
    colnorm = np.linalg.norm(J, axis=0)
    dead = [names[j] for j in range(len(names)) if colnorm[j] <= 1e-10 * max(colnorm.max(), 1e-300)]
    if dead:
        return failed(f"unidentifiable — {', '.join(dead)} has no effect on the simulated {compare} for this data "
                      f"(zero Jacobian column); fix it or use data that excite it{start_note()}", theta, sol, run,
                      start_costs)
    Js = J / colnorm
    sv = np.linalg.svd(Js, compute_uv=False)
    cond = float(sv[0] / sv[-1]) if sv[-1] > 0 else math.inf
    if not np.isfinite(cond) or cond > 1e8:
        return failed(f"unidentifiable — the Jacobian is singular (condition number {cond:.3g}); the parameters "
                      f"{names} are confounded on this data{start_note()}", theta, sol, run, start_costs)
    s2 = float(r @ r) / dof
    # covariance in column-normalised transformed coordinates (well conditioned), then
    # mapped to natural units: cov_theta = D C D with D = d theta / d p
    Ci = np.linalg.inv(Js.T @ Js) / np.outer(colnorm, colnorm)
    dthdp = 1.0 / dpdth
    cov = s2 * Ci * np.outer(dthdp, dthdp)
    st = parameter_statistics(theta, cov, dof)
    model, m_fit, off_fit = tmpl.build(names, theta)
    y_pred = y_opt  # the simulation at the optimum, above
    warns = []
    for j, nm in enumerate(names):
        if np.isfinite(st["stderr"][j]) and st["stderr"][j] > 0.5 * abs(theta[j]):
            warns.append(f"{nm} is poorly determined (standard error {st['stderr'][j]:.3g} > 50 % of {theta[j]:.6g})")
        if np.isfinite(lo[j]) and abs(sol.x[j] - lo[j]) < 1e-6 * max(1, abs(lo[j])) or \
                np.isfinite(hi[j]) and abs(sol.x[j] - hi[j]) < 1e-6 * max(1, abs(hi[j])):
            warns.append(f"{nm} = {theta[j]:.6g} sits on its bound")
    if not converged:
        warns.append(f"not converged: {message}")
    resid = (y_pred - y)[w > 0]
    return IdentificationResult(
        kind="output_error",
        model_name=tmpl.kind,
        model=model,
        names=tuple(names),
        values=theta,
        stderr=st["stderr"],
        ci95=st["ci"],
        units=units,
        correlation=st["correlation"],
        rms=float(np.sqrt(np.mean(resid**2))),
        relative_error_percent=_relative_percent(resid, y[w > 0]),
        n_obs=n_obs,
        dof=dof,
        success=bool(converged),
        message=message,
        warnings=tuple(warns),
        diagnostics={"nfev": run["nfev"], "njev": run["njev"], "status": run["status"],
                     "iterations": run["njev"], "cost_history": run["history"],
                     "start_costs": start_costs.tolist(), "runs": [{k: v for k, v in rr.items() if k != "history"}
                                                                   for rr in runs],
                     "mass": float(m_fit), "offset": float(off_fit), "condition_number": cond,
                     "simulations": int(prob.nsim), "sensitivity_runs": int(prob.nsens),
                     "jacobian": ("sensitivities" if prob.exact else "differences")
                                 + (" (auto: GMS force drive)" if auto_gms else ""),
                     "segments": seg_summary, "initial": computed},
        provenance=prov,
        data={"t": t, "y": y, "y_pred": y_pred},
    )


def evaluate_output_error(model, data, *, inertia: float, offset: float = 0.0, compare: str = "v",
                          rests="auto", min_rest: int = 3, external_load=None,
                          options: SimOptions | None = None) -> dict:
    """Error of a force-driven model on records: each run between rests simulated from rest.

    The same cut as :func:`fit_output_error` (``rests``, ``min_rest``); used to validate
    a fit on another record.

    Returns
    -------
    dict
        ``rms``, ``relative_error_percent``, ``n`` (fitted samples), ``t``, ``y``, ``y_pred``.
    """
    from ..plants.mass import Mass
    from ..simulation.core import simulate

    owner = "evaluate_output_error"
    if compare not in ("v", "x"):
        raise ParameterError(f"{owner}: compare = {compare!r}: must be 'v' or 'x'")
    inertia = val.positive(owner, "inertia", inertia)
    _, segs, _, _ = _force_segments(owner, data, compare, external_load, None, rests, min_rest)
    options = options or OUTPUT_ERROR_OPTIONS
    ys, ps, ts = [], [], []
    for s in segs:
        with warnings.catch_warnings():
            warnings.simplefilter("ignore", RuntimeWarning)
            sim = simulate(model, plant=Mass(inertia), force=s["u"] - offset, dt=s["dt"], options=options)
        k = s["w"] > 0
        ys.append(s["y"][k])
        ps.append((sim.x if compare == "x" else sim.v)[k])
        ts.append(s["t"][k])
    y, yp = np.concatenate(ys), np.concatenate(ps)
    r = yp - y
    return {"rms": float(np.sqrt(np.mean(r**2))),
            "relative_error_percent": _relative_percent(r, y),
            "n": int(y.size), "t": np.concatenate(ts), "y": y, "y_pred": yp}
