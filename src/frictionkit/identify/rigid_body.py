"""Rigid-body inverse-dynamics identification by least squares (IDIM-LS).

The procedure is the one of the EMPS benchmark (A. Janot, M. Gautier, M. Brunot,
"Data Set and Reference Models of EMPS", Nonlinear System Identification Benchmarks
2019, §3, ``Script_IDIM_LS.m``):

1. force ``y = F`` (for EMPS ``gtau * vir``);
2. position low-passed by a 4th-order Butterworth at 100 Hz, forward and backward;
3. velocity and acceleration by central differences of the filtered position;
4. the first 49 samples dropped (MATLAB ``n_border = 50``);
5. every regressor column and ``y`` decimated by 10 (Chebyshev I, zero phase);
6. ordinary least squares; relative error ``100 ||y - X theta|| / ||y||``,
   covariance ``sigma^2 (X^T X)^-1`` with ``sigma^2 = ||y - X theta||^2 / (n - p)``.

Symmetric model (description eq. 1): ``F = M a + Fv v + Fc sgn(v) + offset``.
Asymmetric model (description eq. 12, no offset):
``F = M a + (Fv+ v + Fc+) [v > 0] + (Fv- v - Fc-) [v < 0]``.
The identified model is a :class:`frictionkit.plants.RigidBody` (re-exported here).

``fit_rigid_body(..., law="stribeck" | "lorentzian")`` replaces the Coulomb–viscous map by
a Stribeck map (per direction with ``asymmetric``), fitted by nonlinear least squares on the
same signals and started from IDIM-LS (:mod:`frictionkit.identify.rigid_body_stribeck`).
"""

from __future__ import annotations

import math
from collections.abc import Mapping

import numpy as np

from ..data.recording import Recording
from ..data.signals import decimate, derivative, lowpass
from .. import _validate as val
from ..errors import DataError, IdentificationError, ParameterError
from ..models.static import CoulombViscous, Directional
from ..plants.rigid_body import RigidBody
from .result import IdentificationResult, parameter_statistics


def _regressor(a: np.ndarray, v: np.ndarray, asymmetric: bool) -> tuple[np.ndarray, tuple[str, ...]]:
    s = np.sign(v)
    if not asymmetric:
        return np.column_stack([a, v, s, np.ones_like(v)]), ("M", "Fv", "Fc", "offset")
    op, on = (1.0 + s) / 2.0, (1.0 - s) / 2.0
    X = np.column_stack([a, v * op, s * op, v * on, s * on])
    return X, ("M", "Fv_pos", "Fc_pos", "Fv_neg", "Fc_neg")


def rigid_body_regressors(
    recording: Recording,
    *,
    asymmetric: bool = False,
    cutoff: float = 100.0,
    order: int = 4,
    skip: int = 49,
    q: int = 10,
) -> dict[str, np.ndarray | tuple[str, ...]]:
    """Observation matrix ``X`` and force ``y`` of the IDIM-LS procedure (steps 1-5).

    Parameters
    ----------
    recording : Recording
        Uniformly sampled, with position ``x`` [m] and force ``F`` [N] (or current
        with gain).
    asymmetric : bool
        Direction-dependent friction columns instead of ``[a, v, sgn v, 1]``.
    cutoff : float
        Butterworth cut-off [Hz] (default 100, as in the EMPS scripts).
    order : int
        Butterworth order (default 4).
    skip : int
        Samples dropped at the start after differentiation (default 49).
    q : int
        Decimation factor (default 10; 1 disables decimation).

    Returns
    -------
    dict
        ``X`` (n, p), ``y`` (n,), ``t`` (n,), ``names``.

    Examples
    --------
    >>> reg = rigid_body_regressors(rec)  # doctest: +SKIP
    >>> reg["X"].shape  # doctest: +SKIP
    (2480, 4)
    """
    if not isinstance(recording, Recording):
        raise DataError(f"rigid_body_regressors: expected a Recording, got {type(recording).__name__}")
    recording.require("x", "F")
    if not recording.is_regular:
        raise DataError(f"recording '{recording.name}': irregular sampling; call recording.resample() first")
    skip = val.integer("rigid_body_regressors", "skip", skip, minimum=0)
    q = val.integer("rigid_body_regressors", "q", q, minimum=1)
    need = int(skip) + 30 * int(q) + 20
    if recording.n < need:
        raise DataError(
            f"recording '{recording.name}' has {recording.n} samples; IDIM-LS with skip={skip}, q={q} "
            f"needs at least {need}"
        )
    dt, fs = recording.dt, recording.fs
    xf = lowpass(recording.x, fs, cutoff, order=order)
    v = derivative(xf, dt)
    a = derivative(v, dt)
    X, names = _regressor(a, v, asymmetric)
    y = recording.force()
    sl = slice(int(skip), None)
    X, y, t = X[sl], y[sl], recording.t[sl]
    if q > 1:
        X = np.column_stack([decimate(c, q) for c in X.T])
        y = decimate(y, q)
        t = t[::q]
    return {"X": X, "y": np.asarray(y, dtype=float), "t": t, "names": names}


def _as_list(recording) -> list[Recording]:
    """One Recording, or several (a list, or a dict as from ``load_groups``) fitted jointly."""
    if isinstance(recording, Recording):
        return [recording]
    items = list(recording.values()) if isinstance(recording, Mapping) else list(recording) \
        if isinstance(recording, (list, tuple)) else None
    if not items or not all(isinstance(r, Recording) for r in items):
        raise DataError(f"fit_rigid_body: expected a Recording or a list/dict of Recordings, "
                        f"got {type(recording).__name__}")
    return items


@val.typed_arguments  # argument types named at the boundary (issue 13 round 11)
def fit_rigid_body(
    recording: Recording,
    *,
    law: str = "coulomb_viscous",
    asymmetric: bool = False,
    delta: float | None = None,
    cutoff: float = 100.0,
    order: int = 4,
    skip: int = 49,
    q: int = 10,
    profile: bool = True,
) -> IdentificationResult:
    """Identify mass, friction map (and offset) of a rigid axis by inverse dynamics.

    Parameters
    ----------
    recording : Recording, or a list / dict of Recordings
        Position ``x`` [m] and actuator force ``F`` [N] (load side), uniformly sampled.
        Several records are fitted jointly: each is filtered, differentiated and
        decimated on its own, then their regressor rows are stacked.
    law : {"coulomb_viscous", "stribeck", "lorentzian"}
        Static friction map. ``coulomb_viscous`` (default): linear IDIM-LS of
        ``F = M a + Fv v + Fc sgn(v) + offset``. ``stribeck`` / ``lorentzian``: a
        :class:`~frictionkit.Stribeck` map (exponential or Lorentzian shape) fitted by
        nonlinear least squares on the same signals, started from IDIM-LS
        (:mod:`frictionkit.identify.rigid_body_stribeck`); parameters ``M, Fc, Fs, vs,
        sigma2, offset`` (per direction ``Fc_pos ... sigma2_neg`` with ``asymmetric``).
    asymmetric : bool
        Direction-dependent friction, no offset: ``[M, Fv_pos, Fc_pos, Fv_neg, Fc_neg]``
        instead of ``[M, Fv, Fc, offset]`` (Coulomb–viscous), one Stribeck map per
        direction otherwise.
    delta : float, optional
        Stribeck exponent, fixed (default :data:`~frictionkit.identify.rigid_body_stribeck.DELTA_DEFAULT`
        = 2, seed 002 eq. 9b); only with ``law="stribeck"``.
    cutoff, order, skip, q
        Procedure settings, see :func:`rigid_body_regressors`.
    profile : bool
        Stribeck laws: interval of ``vs`` from its likelihood profile (about ten re-fits
        per direction) instead of the log-scale Wald interval.

    Returns
    -------
    IdentificationResult
        ``kind="rigid_body"``; ``model`` a :class:`RigidBody`; ``diagnostics`` holds
        ``condition_number`` (of X), ``error_norm`` [N] and ``error_std`` [N];
        ``data`` holds ``t``, ``y``, ``y_pred`` of the decimated fit. Stribeck laws add
        ``identifiability``, ``linear`` (the IDIM-LS start: parameters and relative
        error), ``starts``, ``nfev``; ``warnings`` name every parameter the data do not
        pin (``result.flagged``).

    Raises
    ------
    DataError
        Missing position/force, irregular sampling, too few samples.
    IdentificationError
        Rank-deficient observation matrix (e.g. no motion in one direction).
    ParameterError
        Unknown ``law``; ``delta`` with a law that has none.

    Examples
    --------
    >>> from frictionkit.data import load_recording
    >>> from frictionkit.identify import fit_rigid_body
    >>> rec = load_recording("DATA_EMPS.csv", time="t_s", position="qm_m", force="vir_V",
    ...                      scales={"force": 35.15065188248547})  # doctest: +SKIP
    >>> res = fit_rigid_body(rec)  # doctest: +SKIP
    >>> round(res["M"], 1), round(res.relative_error_percent, 2)  # doctest: +SKIP
    (95.1, 4.04)
    """
    from .rigid_body_stribeck import DELTA_DEFAULT, RIGID_BODY_LAWS

    if law not in RIGID_BODY_LAWS:
        raise ParameterError(f"fit_rigid_body.law = {law!r}: must be one of {list(RIGID_BODY_LAWS)}")
    if delta is not None and law != "stribeck":
        raise ParameterError(f"fit_rigid_body.delta = {delta!r}: only the 'stribeck' law has an exponent")
    if delta is not None and (val.is_bool(delta) or not (math.isfinite(float(delta)) and float(delta) > 0)):
        raise ParameterError(f"fit_rigid_body.delta = {delta!r}: must be finite and > 0")
    linear = _fit_linear(recording, asymmetric=asymmetric, cutoff=cutoff, order=order, skip=skip, q=q)
    if law == "coulomb_viscous":
        return linear
    return _fit_stribeck(recording, linear, law=law, asymmetric=asymmetric,
                         delta=float(delta) if delta is not None else DELTA_DEFAULT,
                         cutoff=cutoff, order=order, skip=skip, q=q, profile=profile)


def _units(recording: Recording, names) -> tuple[tuple[str, ...], dict[str, str]]:
    """Unit of each parameter (from the recording's force and position units) and the signal units."""
    Fu = recording.units["F"]
    xu = recording.units["x"]
    vu = recording.units["v"] if recording.units["v"] != "m/s" or xu == "m" else f"{xu}/s"
    visc = f"{Fu}·s/{xu}"

    def one(nm: str) -> str:
        if nm == "M":
            return "kg" if xu == "m" else f"{Fu}·s²/{xu}"
        if nm.startswith(("Fv", "sigma2")):
            return visc
        if nm.startswith("vs"):
            return vu
        return Fu

    return tuple(one(nm) for nm in names), {"F": Fu, "x": xu, "v": vu}


def _fit_stribeck(recording, linear: IdentificationResult, *, law, asymmetric, delta, cutoff, order, skip, q,
                  profile) -> IdentificationResult:
    """The Stribeck rigid body (:mod:`.rigid_body_stribeck`) as an :class:`IdentificationResult`."""
    from .rigid_body_stribeck import VS_START_FRACTIONS, fit_rigid_body_stribeck

    recs = _as_list(recording)
    full = [rigid_body_regressors(r, asymmetric=asymmetric, cutoff=cutoff, order=order, skip=skip, q=1)
            for r in recs]
    fit = fit_rigid_body_stribeck(recs, full, linear, asymmetric=asymmetric, shape=law, delta=delta, q=q,
                                  profile=profile)
    ident = fit["ident"]
    names, values, r, y = fit["names"], fit["values"], fit["residual"], fit["y"]
    warns = list(ident.warnings)
    if fit["invalid"]:
        warns.append(f"estimates do not form a valid model ({fit['invalid']})")
    warns += [f"{n} sits at its bound 0 (the data push it below the physical range)" for n in fit["at_bound"]]
    for i, nm in enumerate(names):
        if nm in ident.reasons or nm.startswith("vs"):
            continue
        if abs(values[i]) < 2.0 * ident.stderr[i]:
            warns.append(f"{nm} = {values[i]:.6g} is not significantly different from 0 "
                         f"(standard error {ident.stderr[i]:.3g})")
    units, sig_units = _units(recs[0], names)
    scale = linear.diagnostics["data_scale"]
    warns += _scale_warnings(scale, dict(zip(names, np.asarray(values, dtype=float).tolist())),
                             sig_units["x"], sig_units["F"])
    prov = dict(linear.provenance)
    prov["procedure"] = dict(prov["procedure"], method="IDIM-NLS", law=law, delta=delta if law == "stribeck" else None,
                             evaluation="model at the full rate, then decimated like the IDIM-LS columns",
                             vs_start_fractions_of_v95=list(VS_START_FRACTIONS), profile=bool(profile))
    s2 = float(r @ r) / fit["dof"]
    t = linear.data["t"]
    return IdentificationResult(
        kind="rigid_body",
        model_name=f"rigid_body_{law}_{'asymmetric' if asymmetric else 'symmetric'}",
        model=fit["model"],
        names=names,
        values=values,
        stderr=ident.stderr,
        ci95=ident.ci95,
        units=units,
        correlation=ident.correlation,
        rms=float(np.sqrt(np.mean(r**2))),
        relative_error_percent=float(100.0 * np.linalg.norm(r) / np.linalg.norm(y)),
        n_obs=int(r.size),
        dof=int(fit["dof"]),
        success=fit["success"],
        message=f"nonlinear least squares (scipy trf): {fit['message']}",
        warnings=tuple(warns),
        diagnostics={"condition_number": fit["condition_number"], "error_norm": float(np.linalg.norm(r)),
                     "error_std": float(np.std(r, ddof=1)), "sigma2": s2, "nfev": fit["nfev"],
                     "starts": fit["starts"], "v95": fit["v95"], "identifiability": ident.details,
                     "data_scale": scale, "data_scale_text": linear.diagnostics["data_scale_text"],
                     "linear": {"parameters": linear.params,
                                "relative_error_percent": linear.relative_error_percent}},
        provenance=prov,
        data={"t": t, "y": y, "y_pred": fit["y_pred"]},
    )


#: Kinematic limits beyond which a record is not a plausible axis in the given position
#: unit (assumption, issue 13). Linear: the longest machine-tool and gantry axes travel
#: some tens of metres, the fastest linear-motor stages reach ~10 m/s and ~20 g; rotary:
#: 2000 rad/s is ~19,000 rpm (spindle speed), 1e5 rad/s² far beyond any servo axis. The
#: limits are generous on purpose: they catch unit and scale slips (a factor of 1000),
#: not unusual machines.
PLAUSIBLE_LIMITS = {
    "m": {"travel": 50.0, "peak_speed": 20.0, "peak_acceleration": 500.0},
    "rad": {"travel": math.inf, "peak_speed": 2000.0, "peak_acceleration": 1e5},
}


def data_scale(recs, regs, asymmetric: bool) -> dict[str, float]:
    """Physical scale of the data a rigid-body fit saw: travel, peak speed and acceleration
    (filtered, decimated regressor columns) and the force range."""
    a = np.concatenate([np.asarray(g["X"])[:, 0] for g in regs])
    if asymmetric:
        v = np.concatenate([np.asarray(g["X"])[:, 1] + np.asarray(g["X"])[:, 3] for g in regs])
    else:
        v = np.concatenate([np.asarray(g["X"])[:, 1] for g in regs])
    F = np.concatenate([r.force() for r in recs])
    return {"travel": float(max(np.ptp(r.x) for r in recs)), "peak_speed": float(np.max(np.abs(v))),
            "peak_acceleration": float(np.max(np.abs(a))), "force_min": float(F.min()),
            "force_max": float(F.max())}


def _scale_warnings(scale: dict[str, float], vals: dict[str, float], xu: str, Fu: str) -> list[str]:
    """Flags for a record (and the fitted mass) implausible at the data's physical scale."""
    out = []
    lim = PLAUSIBLE_LIMITS.get(xu)
    units = {"travel": xu, "peak_speed": f"{xu}/s", "peak_acceleration": f"{xu}/s²"}
    over = [f"{key.replace('_', ' ')} {scale[key]:.4g} {units[key]} > {limit:.4g} {units[key]}"
            for key, limit in (lim or {}).items() if scale[key] > limit]
    if over:
        out.append(
            f"implausible physical scale of the data ({'; '.join(over)}), beyond any real axis: a position "
            f"scale or unit slip (mm read as m?) would make M = {vals.get('M', math.nan):.4g} and the "
            "viscous terms wrong by the same factor"
        )
    M = vals.get("M")
    span = scale["force_max"] - scale["force_min"]
    if M is not None and M > 0 and span > 0:
        share = M * scale["peak_acceleration"] / span
        if share < 1e-3:
            out.append(f"the inertial force M·a reaches {100 * share:.2g} % of the force range "
                       f"({span:.4g} {Fu}): the data barely see the mass")
    return out


def _scale_line(scale: dict[str, float], xu: str, Fu: str) -> str:
    return (f"travel {scale['travel']:.4g} {xu}, peak speed {scale['peak_speed']:.4g} {xu}/s, "
            f"peak acceleration {scale['peak_acceleration']:.4g} {xu}/s², "
            f"force {scale['force_min']:.4g} … {scale['force_max']:.4g} {Fu}")


def _fit_linear(recording, *, asymmetric: bool, cutoff: float, order: int, skip: int, q: int) -> IdentificationResult:
    """Coulomb–viscous IDIM-LS (the benchmark's procedure)."""
    recs = _as_list(recording)
    regs = [rigid_body_regressors(r, asymmetric=asymmetric, cutoff=cutoff, order=order, skip=skip, q=q)
            for r in recs]
    if len(recs) > 1:  # several records: their regressor rows stacked, times one after another
        t_all, shift = [], 0.0
        for g in regs:
            t_all.append(g["t"] - g["t"][0] + shift)
            shift = t_all[-1][-1] + 2 * (g["t"][1] - g["t"][0])
        reg = {"X": np.vstack([g["X"] for g in regs]), "y": np.concatenate([g["y"] for g in regs]),
               "t": np.concatenate(t_all), "names": regs[0]["names"]}
        recording = recs[0]
    else:
        reg = regs[0]
        recording = recs[0]
    X, y, names = reg["X"], reg["y"], reg["names"]
    n, p = X.shape
    if np.linalg.matrix_rank(X) < p:
        raise IdentificationError(
            f"recording '{recording.name}': observation matrix has rank {np.linalg.matrix_rank(X)} < {p}; "
            "the motion does not excite every parameter (e.g. no motion in one direction)"
        )
    theta, *_ = np.linalg.lstsq(X, y, rcond=None)
    r = y - X @ theta
    dof = n - p
    s2 = float(r @ r) / dof
    cov = s2 * np.linalg.inv(X.T @ X)
    st = parameter_statistics(theta, cov, dof)
    vals = dict(zip(names, theta.tolist()))
    warns = []
    try:
        if asymmetric:
            fr = Directional(positive=CoulombViscous(Fc=vals["Fc_pos"], sigma2=vals["Fv_pos"]),
                             negative=CoulombViscous(Fc=vals["Fc_neg"], sigma2=vals["Fv_neg"]))
            model = RigidBody(M=vals["M"], friction=fr, offset=0.0)
        else:
            model = RigidBody(M=vals["M"], friction=CoulombViscous(Fc=vals["Fc"], sigma2=vals["Fv"]),
                              offset=vals["offset"])
    except ParameterError as exc:
        model = None
        warns.append(f"estimates do not form a valid model ({exc})")
    for i, nm in enumerate(names):
        if abs(theta[i]) < 2.0 * st["stderr"][i]:
            warns.append(f"{nm} = {theta[i]:.6g} is not significantly different from 0 "
                         f"(standard error {st['stderr'][i]:.3g})")
    units, sig_units = _units(recording, names)
    scale = data_scale(recs, regs, asymmetric)
    warns += _scale_warnings(scale, vals, sig_units["x"], sig_units["F"])
    prov = dict(recording.provenance)
    if len(recs) > 1:
        prov["records"] = [dict(r.provenance, name=r.name) for r in recs]
    prov.update({"recording": ", ".join(r.name for r in recs), "units": sig_units,
                 "procedure": {"method": "IDIM-LS", "butterworth_order": order, "cutoff_hz": cutoff,
                               "derivative": "central differences", "skip": skip, "decimation": q,
                               "decimation_filter": "scipy.signal.decimate(ftype='iir', zero_phase=True)"}})
    return IdentificationResult(
        kind="rigid_body",
        model_name="rigid_body_asymmetric" if asymmetric else "rigid_body_symmetric",
        model=model,
        names=names,
        values=theta,
        stderr=st["stderr"],
        ci95=st["ci"],
        units=units,
        correlation=st["correlation"],
        rms=float(np.sqrt(np.mean(r**2))),
        relative_error_percent=float(100.0 * np.linalg.norm(r) / np.linalg.norm(y)),
        n_obs=int(n),
        dof=int(dof),
        success=True,
        message="ordinary least squares",
        warnings=tuple(warns),
        diagnostics={"condition_number": float(np.linalg.cond(X)), "error_norm": float(np.linalg.norm(r)),
                     "error_std": float(np.std(r, ddof=1)), "sigma2": s2, "data_scale": scale,
                     "data_scale_text": _scale_line(scale, sig_units["x"], sig_units["F"])},
        provenance=prov,
        data={"t": reg["t"], "y": y, "y_pred": X @ theta},
    )
