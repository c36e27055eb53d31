"""The error of a fitted model on another record — what an engineer checks before trusting a fit.

:func:`validate` takes any :class:`~frictionkit.identify.IdentificationResult` and a
record it was not fitted on, predicts that record the way the fit predicted its
training data, and returns the error beside the training error:

=================  ===========================================================  ===========
result kind        prediction on the validation record                          compared
=================  ===========================================================  ===========
``static_map``     steady-state map at the record's (or records') mean speeds   mean force
``rigid_body``     ``M a + friction(v) + offset`` on the IDIM-LS signals        force
``output_error``   motion-driven: the law driven by the recorded motion          force
                   (with ``J a + offset``, resets at rests), beside the static
                   map; force-driven: the mass driven by the recorded force     v or x
                   (each run between rests from rest)
``presliding``     the GMS driven by the recorded position                      force
``reversal``       the sinc law around the record's reversals                  friction
=================  ===========================================================  ===========
"""

from __future__ import annotations

import dataclasses
from collections.abc import Mapping

import numpy as np

from ..data.recording import Recording
from ..errors import DataError
from .result import IdentificationResult

__all__ = ["validate", "with_validation"]


def _records(data) -> list[Recording]:
    if isinstance(data, Recording):
        return [data]
    if isinstance(data, Mapping) and data and all(isinstance(r, Recording) for r in data.values()):
        return list(data.values())
    if isinstance(data, (list, tuple)) and data and all(isinstance(r, Recording) for r in data):
        return list(data)
    raise DataError(f"validate: data = {type(data).__name__}: give a Recording or a list/dict of Recordings")


def _stats(y: np.ndarray, y_pred: np.ndarray) -> dict:
    r = y_pred - y
    return {"rms": float(np.sqrt(np.mean(r**2))),
            "relative_error_percent": float(100 * np.linalg.norm(r) / max(float(np.linalg.norm(y)), 1e-300)),
            "n": int(y.size)}


def validate(result: IdentificationResult, data, *, name: str | None = None, **how) -> dict:
    """Error of ``result.model`` on a record it was not fitted on.

    Parameters
    ----------
    result : IdentificationResult
        Any fit (static map, rigid body, output error, pre-sliding).
    data : Recording, or a list / dict of Recordings
        The validation record(s), loaded with the same columns and scales.
    name : str, optional
        Label of the validation data (default: the record names).
    **how
        Output error: ``rests``, ``min_rest`` (and, motion-driven, ``drive``,
        ``integration``) overriding those of the fit (e.g. a rest mask of this record).

    Returns
    -------
    dict
        ``rms``, ``relative_error_percent``, ``n`` on the validation data, beside
        ``training_rms`` and ``training_relative_error_percent``; motion-driven fits
        add ``static_rms`` (the static map, same ``J a + offset``) and
        ``training_static_rms``.

    Examples
    --------
    >>> import numpy as np
    >>> from frictionkit.data import Recording
    >>> from frictionkit.identify import fit_static_map
    >>> from frictionkit.identify.validation import validate
    >>> v = np.r_[np.linspace(0.01, 0.2, 8), -np.linspace(0.01, 0.2, 8)]
    >>> res = fit_static_map(v, np.sign(v) + 2 * v, model="coulomb_viscous")
    >>> rec = Recording(t=np.arange(50) * 0.01, v=np.full(50, 0.1), F=np.full(50, 1.25))
    >>> round(validate(res, rec)["rms"], 6)
    0.05
    """
    if result.model is None:
        raise DataError("validate: the result holds no model (see its warnings)")
    recs = _records(data)
    label = name or ", ".join(r.name for r in recs)
    out = {"data": label, "training_rms": float(result.rms),
           "training_relative_error_percent": float(result.relative_error_percent)}
    kind = result.kind
    proc = dict(result.provenance.get("procedure", {}))
    if kind == "static_map":
        from ..data.segmentation import steady_state_points

        pts = steady_state_points(recs[0] if len(recs) == 1 else {r.name: r for r in recs})
        out.update(_stats(np.asarray(pts.F), np.asarray(result.model.steady_state(pts.v), float)))
        out["points"] = len(pts)
    elif kind == "rigid_body":
        from ..data.signals import decimate
        from .rigid_body import rigid_body_regressors

        # the model at the full rate, then decimated like the fit's columns (any friction law;
        # for Coulomb-viscous this equals the decimated regressors times the parameters)
        q = int(proc.get("decimation", 10))
        ys, ps = [], []
        for r in recs:
            reg = rigid_body_regressors(r, asymmetric=False, cutoff=proc.get("cutoff_hz", 100.0),
                                        order=proc.get("butterworth_order", 4), skip=proc.get("skip", 49), q=1)
            pred = result.model.force(reg["X"][:, 0], reg["X"][:, 1])
            ys.append(decimate(reg["y"], q))
            ps.append(decimate(pred, q))
        out.update(_stats(np.concatenate(ys), np.concatenate(ps)))
    elif kind == "output_error" and proc.get("drive") in ("position", "velocity", "mixed"):
        from .motion_data import evaluate_motion

        kw = {"drive": proc.get("drive") if proc.get("drive") != "mixed" else "auto",
              "integration": proc.get("integration", "held"), "rests": "auto", "min_rest": 3}
        rest_desc = str(proc.get("rests", "auto"))
        if rest_desc == "none":
            kw["rests"] = None
        kw.update(how)
        J = float(result.diagnostics.get("J", 0.0))
        off = float(result.diagnostics.get("offset", 0.0))
        ev = evaluate_motion(result.model, recs[0] if len(recs) == 1 else {r.name: r for r in recs},
                             inertia=J, offset=off, **kw)
        out.update({"rms": ev["rms"], "relative_error_percent": ev["relative_error_percent"], "n": ev["n"],
                    "static_rms": ev["static_rms"],
                    "static_relative_error_percent": ev["static_relative_error_percent"],
                    "training_static_rms": float(result.diagnostics.get("static_rms", np.nan))})
    elif kind == "output_error":
        from ..simulation.core import SimOptions
        from .output_error import evaluate_output_error

        opts = SimOptions(**{k: proc[k] for k in ("rtol", "atol_v", "atol_F") if proc.get(k) is not None})
        kw = {"rests": None if str(proc.get("rests", "none")) == "none" else "auto",
              "min_rest": int(proc.get("min_rest", 3))}  # files written before rests existed: none
        kw.update(how)  # a rest mask of this record, or min_rest
        ev = evaluate_output_error(result.model, recs[0] if len(recs) == 1 else {r.name: r for r in recs},
                                   inertia=float(result.diagnostics["mass"]),
                                   offset=float(result.diagnostics.get("offset", 0.0)),
                                   compare=proc.get("compare", "v"), options=opts, **kw)
        out.update({"rms": ev["rms"], "relative_error_percent": ev["relative_error_percent"], "n": ev["n"]})
    elif kind == "reversal":
        from ..models.rolling import sinc_compensation
        from .reversal import reversal_samples

        xi, f, n_rev, _ = reversal_samples(recs, min_travel=proc.get("min_travel"), inertia=proc.get("inertia", 0.0),
                                           offset=proc.get("offset", 0.0))
        w = proc.get("window")
        use = np.abs(xi) <= (w if w is not None else np.inf)
        c = result.model
        out.update(_stats(f[use], sinc_compensation(xi[use], F0=c.F0, xs=c.xs)))
        out["reversals"] = n_rev
    elif kind == "presliding":
        from .motion_data import evaluate_motion

        rest_desc = str(proc.get("rests", "none"))  # files written before rests existed: whole records
        kw = {"rests": None if rest_desc == "none" else "auto", "min_rest": int(proc.get("min_rest", 3))}
        kw.update(how)
        ev = evaluate_motion(result.model, recs[0] if len(recs) == 1 else {r.name: r for r in recs},
                             drive="position", **kw)
        out.update({"rms": ev["rms"], "relative_error_percent": ev["relative_error_percent"], "n": ev["n"]})
    else:
        raise DataError(f"validate: results of kind {kind!r} cannot be validated")
    return out


def with_validation(result: IdentificationResult, report: dict) -> IdentificationResult:
    """``result`` with ``diagnostics["validation"] = report`` (a new, frozen result)."""
    diag = dict(result.diagnostics)
    diag["validation"] = report
    return dataclasses.replace(result, diagnostics=diag)
