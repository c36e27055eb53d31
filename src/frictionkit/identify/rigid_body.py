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
"""

from __future__ import annotations

from collections.abc import Mapping

import numpy as np

from ..data.recording import Recording
from ..data.signals import decimate, derivative, lowpass
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
    if int(skip) != skip or skip < 0:
        raise ParameterError(f"skip = {skip!r}: must be a non-negative integer")
    if int(q) != q or q < 1:
        raise ParameterError(f"q = {q!r}: must be a positive integer")
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


def fit_rigid_body(
    recording: Recording,
    *,
    asymmetric: bool = False,
    cutoff: float = 100.0,
    order: int = 4,
    skip: int = 49,
    q: int = 10,
) -> IdentificationResult:
    """Identify mass, viscous and Coulomb friction (and offset) by IDIM-LS.

    Parameters
    ----------
    recording : Recording, or a list / dict of Recordings
        Position ``x`` [m] and actuator force ``F`` [N] (load side), uniformly sampled.
        Several records are fitted jointly: each is filtered, differentiated and
        decimated on its own, then their regressor rows are stacked.
    asymmetric : bool
        Fit ``[M, Fv_pos, Fc_pos, Fv_neg, Fc_neg]`` (no offset) instead of
        ``[M, Fv, Fc, offset]``.
    cutoff, order, skip, q
        Procedure settings, see :func:`rigid_body_regressors`.

    Returns
    -------
    IdentificationResult
        ``kind="rigid_body"``; ``model`` a :class:`RigidBody`; ``diagnostics`` holds
        ``condition_number`` (of X), ``error_norm`` [N] and ``error_std`` [N];
        ``data`` holds ``t``, ``y``, ``y_pred`` of the decimated fit.

    Raises
    ------
    DataError
        Missing position/force, irregular sampling, too few samples.
    IdentificationError
        Rank-deficient observation matrix (e.g. no motion in one direction).

    Examples
    --------
    >>> from frictionkit.data import load_recording
    >>> from frictionkit.identify import fit_rigid_body
    >>> rec = load_recording("DATA_EMPS.csv", time="t_s", position="qm_m", force="vir_V",
    ...                      scales={"force": 35.15065188248547})  # doctest: +SKIP
    >>> res = fit_rigid_body(rec)  # doctest: +SKIP
    >>> round(res["M"], 1), round(res.relative_error_percent, 2)  # doctest: +SKIP
    (95.1, 4.12)
    """
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
    Fu = recording.units["F"]
    xu = recording.units["x"]
    vu = recording.units["v"] if recording.units["v"] != "m/s" or xu == "m" else f"{xu}/s"
    unit = {"M": "kg" if xu == "m" else f"{Fu}·s²/{xu}", "offset": Fu}
    visc = f"{Fu}·s/{xu}"
    units = tuple(unit.get(nm, visc if nm.startswith("Fv") else Fu) for nm in names)
    prov = dict(recording.provenance)
    if len(recs) > 1:
        prov["records"] = [dict(r.provenance, name=r.name) for r in recs]
    prov.update({"recording": ", ".join(r.name for r in recs), "units": {"F": Fu, "x": xu, "v": vu},
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
                     "error_std": float(np.std(r, ddof=1)), "sigma2": s2},
        provenance=prov,
        data={"t": reg["t"], "y": y, "y_pred": X @ theta},
    )
