"""The result object returned by every identification procedure.

An :class:`IdentificationResult` carries the identified model object, a table of
parameters (value, standard error, 95 % confidence interval, unit), their
correlation matrix, residual statistics, warnings about unidentifiable parameters,
and the provenance of the data. It plots itself (``.plot(ax=None)``) and round-trips
through JSON with units and provenance (``save_json`` / ``load_json``).
"""

from __future__ import annotations

import dataclasses
import json
import math
from collections.abc import Mapping
from dataclasses import dataclass, field
from pathlib import Path
from types import MappingProxyType
from typing import Any

import numpy as np
from scipy import stats

from ..errors import DataError, FrictionKitError, ParameterError
from ..models.base import law_from_dict, law_to_dict, registered_laws
from ..control.compensators import RollingCompensator
from ..plants.rigid_body import RigidBody
from typing import TYPE_CHECKING

if TYPE_CHECKING:
    from matplotlib.axes import Axes
    from numpy.typing import ArrayLike

#: Version of the JSON layout written by :meth:`IdentificationResult.save_json`.
JSON_FORMAT = "frictionkit.identification/1"


# --------------------------------------------------------------------------- statistics
def parameter_statistics(values: ArrayLike, cov: ArrayLike, dof: int, *, level: float = 0.95) -> dict[str, np.ndarray]:
    """Standard errors, t-distribution confidence intervals and correlations from a covariance.

    Parameters
    ----------
    values : array_like
        Parameter estimates.
    cov : array_like
        Their covariance matrix (``sigma^2 (J^T J)^-1`` for least squares).
    dof : int
        Residual degrees of freedom ``n - p`` (> 0).
    level : float
        Confidence level of the intervals (default 0.95).

    Returns
    -------
    dict
        ``stderr`` (p,), ``ci`` (p, 2), ``correlation`` (p, p). Entries are NaN where
        the covariance is not finite.

    Examples
    --------
    >>> from frictionkit.identify.result import parameter_statistics
    >>> s = parameter_statistics([1.0], [[0.04]], dof=10)
    >>> round(float(s["stderr"][0]), 3), s["ci"].round(3).tolist()
    (0.2, [[0.554, 1.446]])
    """
    values = np.asarray(values, dtype=float)
    cov = np.asarray(cov, dtype=float)
    var = np.diag(cov).copy()
    var[var < 0] = np.nan
    se = np.sqrt(var)
    tq = float(stats.t.ppf(0.5 + level / 2.0, max(int(dof), 1)))
    ci = np.column_stack([values - tq * se, values + tq * se])
    with np.errstate(invalid="ignore", divide="ignore"):
        corr = cov / np.outer(se, se)
    np.fill_diagonal(corr, np.where(np.isfinite(se), 1.0, np.nan))
    return {"stderr": se, "ci": ci, "correlation": corr}


# --------------------------------------------------------------------------- model (de)serialisation
# A result's model is a friction law (its JSON form comes from the law registry,
# ``models.base``, contract point 6) or a plant (``RigidBody``, below). In the files of
# format JSON_FORMAT the discriminator is spelled "type", at every level of nesting:
# the layout predates the registry and files written before it must stay loadable
# (``{"type": "LuGre", "static": {"type": "Stribeck", ...}, ...}``). Reading also
# accepts the registry's spelling, "law".

#: Plants a result may hold, by name; their fields are plain values and laws. Also the
#: compensator parameters of ``identify reversal`` (plain values), so they load back.
_PLANTS: dict[str, type] = {"RigidBody": RigidBody, "RollingCompensator": RollingCompensator}


def _respell(node: Any, old: str, new: str) -> Any:
    """``node`` with the discriminator key ``old`` renamed ``new`` in every nested mapping."""
    if not isinstance(node, Mapping):
        return node
    return {(new if k == old else k): _respell(v, old, new) for k, v in node.items()}


def model_to_dict(model: Any) -> dict[str, Any] | None:
    """A JSON-ready description ``{"type": <name>, <fields>}`` of a law or plant.

    For a friction law this is the registry's JSON form (:func:`frictionkit.models.law_to_dict`)
    with ``"law"`` spelled ``"type"``.
    """
    if model is None:
        return None
    name = type(model).__name__
    if _PLANTS.get(name) is type(model):
        out: dict[str, Any] = {"type": name}
        for f in dataclasses.fields(model):
            val = getattr(model, f.name)
            out[f.name] = model_to_dict(val) if dataclasses.is_dataclass(val) else _jsonable(val)
        return out
    try:
        law = law_to_dict(model)
    except ParameterError:
        raise DataError(
            f"cannot serialise model of type {name}: not a registered friction law "
            f"({sorted(registered_laws())}) nor a plant ({sorted(_PLANTS)})"
        ) from None
    return _respell(law, "law", "type")


def model_from_dict(data: Mapping[str, Any] | None) -> Any:
    """Rebuild a model written by :func:`model_to_dict` (or a law in the registry's JSON form)."""
    if data is None:
        return None
    if not isinstance(data, Mapping):
        raise DataError(f"a model is a JSON object {{\"type\": ..., ...}}, got {type(data).__name__}")
    kind = data.get("type", data.get("law"))
    if isinstance(kind, str) and kind in _PLANTS:
        return _plant_from_dict(kind, data)
    if not isinstance(kind, str) or kind not in registered_laws():
        raise DataError(f"model type {kind!r} unknown; known: {sorted([*registered_laws(), *_PLANTS])}")
    return law_from_dict(_respell(data, "type", "law"))


def _plant_from_dict(kind: str, data: Mapping[str, Any]) -> Any:
    fields = [f for f in dataclasses.fields(_PLANTS[kind]) if f.init]
    names = [f.name for f in fields]
    kw = {}
    for k, v in data.items():
        if k in ("type", "law"):
            continue
        if k not in names:
            raise DataError(f"model {kind!r}: unknown field {k!r}; {kind} takes {names}")
        kw[k] = model_from_dict(v) if isinstance(v, Mapping) else v
    for f in fields:
        if f.name not in kw and f.default is dataclasses.MISSING and f.default_factory is dataclasses.MISSING:
            raise DataError(f"model {kind!r}: field {f.name!r} missing; {kind} takes {names}")
    return _PLANTS[kind](**kw)


def _jsonable(x: Any) -> Any:
    if isinstance(x, np.ndarray):
        return [_jsonable(v) for v in x.tolist()]
    if isinstance(x, (np.floating, float)):
        x = float(x)
        return x if math.isfinite(x) else None
    if isinstance(x, np.integer):
        return int(x)
    if isinstance(x, np.bool_):
        return bool(x)
    if isinstance(x, Mapping):
        return {str(k): _jsonable(v) for k, v in x.items()}
    if isinstance(x, (list, tuple)):
        return [_jsonable(v) for v in x]
    return x


def check_model_numbers(node: Any, at: str) -> None:
    """Model fields in a JSON file must be JSON numbers: ``true`` or ``"1.0"`` are not taken as 1.

    Raises :class:`DataError` naming the field by its path (``parts.positive.model.Fc``).
    """
    if not isinstance(node, Mapping):
        return
    for key, val in node.items():
        if key in ("type", "law", "shape"):
            continue
        if isinstance(val, Mapping):
            check_model_numbers(val, f"{at}.{key}")
            continue
        items = val if isinstance(val, list) else [val]
        for x in items:
            if isinstance(x, Mapping):
                check_model_numbers(x, f"{at}.{key}")
            elif isinstance(x, bool) or not isinstance(x, (int, float)):
                raise DataError(f"{at}.{key} is {json.dumps(val)}, expected a number"
                                + (" or a list of numbers" if isinstance(val, list) else ""))


def read_json_object(path: str | Path, where: str | None = None) -> dict[str, Any]:
    """The JSON object in a file, or one :class:`DataError` saying why not (prefixed by ``where``).

    Not UTF-8 text, not JSON, nested too deeply, or not an object at the top level.
    Missing files and folders raise the usual ``OSError``.
    """
    from .._io import check_regular_input

    p = Path(path)
    where = where or f"file '{p}'"
    check_regular_input(p, where)  # a FIFO blocked for ever, /dev/zero filled the memory (round 11)
    raw = p.read_bytes()
    try:
        text = raw.decode("utf-8")
    except UnicodeDecodeError as exc:
        raise DataError(f"{where}: not UTF-8 text (byte {exc.start})") from None
    from .._io import DuplicateKeyError, json_loads

    try:
        doc = json_loads(text)
    except json.JSONDecodeError as exc:
        raise DataError(f"{where}: not valid JSON ({exc.msg} at line {exc.lineno}, column {exc.colno})") from None
    except DuplicateKeyError as exc:
        raise DataError(f"{where}: {exc}") from None
    except RecursionError:
        raise DataError(f"{where}: JSON nested too deeply") from None
    if not isinstance(doc, dict):
        raise DataError(f"{where}: the top level is a JSON {type(doc).__name__}, expected an object")
    return doc


def _floats(x: Any) -> np.ndarray:
    if any(isinstance(v, bool) for v in np.ravel(np.array(x, dtype=object))):
        raise TypeError(f"{json.dumps(x)[:60]}: true/false where a number belongs")
    return np.array([np.nan if v is None else v for v in np.ravel(np.array(x, dtype=object))],
                    dtype=float).reshape(np.shape(x))


def _table_problems(d: Mapping[str, Any], params: Mapping[str, Any], names: tuple[str, ...]) -> list[str]:
    """Every hand edit of the numeric table that would be read as something else, each naming its field.

    A JSON string (``"1"``) is not a number (numpy would read it as 1.0); ``null`` is a value only
    where the writer puts one (a non-finite number: standard errors, intervals, correlations, RMS of
    a failed fit), never for a parameter value of a successful fit; standard errors, RMS and counts
    are >= 0, a correlation lies in [-1, 1], an interval's low end is not above its high end
    (issue 13 round 7: ``"1"``, ``null`` and a stderr of -1 were accepted).
    """
    bad: list[str] = []
    success = d.get("success", True) is not False

    def num(x: Any) -> bool:
        return x is None or (isinstance(x, (int, float)) and not isinstance(x, bool))

    def show(x: Any) -> str:
        return json.dumps(x)[:60]

    for n in names:
        p, at = params[n], f"parameters.{n}"
        for key in ("value", "stderr", "ci95"):
            if key not in p:
                bad.append(f"{at}.{key} is missing")
        v = p.get("value")
        if "value" in p and (not num(v) or (v is None and success) or (v is not None and not math.isfinite(v))):
            bad.append(f"{at}.value is {show(v)}, expected a finite number"
                       + (" (null only in a failed fit's result)" if v is None else ""))
        se = p.get("stderr")
        if "stderr" in p and (not num(se) or (se is not None and not se >= 0)):
            bad.append(f"{at}.stderr is {show(se)}, expected a number >= 0 or null")
        ci = p.get("ci95")
        if "ci95" in p:
            if not (isinstance(ci, list) and len(ci) == 2 and all(num(x) for x in ci)):
                bad.append(f"{at}.ci95 is {show(ci)}, expected [low, high] (numbers or null)")
            elif None not in ci and ci[0] > ci[1]:
                bad.append(f"{at}.ci95 is {show(ci)}: the low end is above the high end")
    corr = d.get("correlation")
    rows = corr if isinstance(corr, list) else None
    if rows is None or len(rows) != len(names) or not all(isinstance(r, list) and len(r) == len(names) for r in rows):
        bad.append(f"correlation is {show(corr)}, expected a {len(names)} x {len(names)} list of lists")
    else:
        for i, r in enumerate(rows):
            for j, x in enumerate(r):
                if not num(x) or (x is not None and not abs(x) <= 1.0 + 1e-6):
                    bad.append(f"correlation[{i}][{j}] is {show(x)}, expected a number in [-1, 1] or null")
    for key in ("rms", "relative_error_percent"):
        x = d.get(key)
        if key in d and (not num(x) or (x is not None and not x >= 0)):
            bad.append(f"{key} is {show(x)}, expected a number >= 0 or null")
    n_obs, dof = d.get("n_obs"), d.get("dof")
    if isinstance(n_obs, int) and not isinstance(n_obs, bool) and n_obs < 0:
        bad.append(f"n_obs is {n_obs}, expected >= 0")
    if isinstance(dof, int) and not isinstance(dof, bool) and isinstance(n_obs, int) and not 0 <= dof <= max(n_obs, 0):
        bad.append(f"dof is {dof}, expected 0 ... n_obs = {n_obs}")
    return bad


def _flat_numbers(node: Any, at: str = "") -> dict[str, float]:
    """Every number in a law's JSON form by its dotted path (``positive.Fc``, ``static.sigma2``)."""
    flat: dict[str, float] = {}
    if isinstance(node, Mapping):
        for k, v in node.items():
            if k not in ("type", "law", "shape"):
                flat.update(_flat_numbers(v, f"{at}.{k}" if at else str(k)))
    elif isinstance(node, (int, float)) and not isinstance(node, bool):
        flat[at] = float(node)
    return flat


def _agree(a: float, b: float) -> bool:
    return a == b or (math.isfinite(a) and math.isfinite(b) and abs(a - b) <= 1e-12 * max(abs(a), abs(b)))


def _table_model_disagreement(model: Any, params: Mapping[str, Any], names: tuple[str, ...],
                              parts: Any = None) -> list[str]:
    """A number the document states twice must agree (to 1e-12 relative): a parameter whose value the
    ``model`` also holds (``Fc_pos`` is ``model.positive.Fc``, ``sigma0`` is ``model.sigma0``, ``Fc`` of a
    dynamic law is ``model.static.Fc``), and a field of the top-level model's direction with the same field
    of ``parts.<side>.model`` (or, without a top-level model, ``Fc_pos`` with ``parts.positive.model.Fc``).
    Was (issue 13 round 7): ``report`` of a result whose top-level model was edited in one place only
    (positive.Fc 1 -> 5) showed the table's 1 beside the model's 5. The one check of every reader
    (``load_static_law`` had its own copy of the parts half)."""
    flat = _flat_numbers(model)
    sides = {side: _flat_numbers(part.get("model")) for side, part in (parts or {}).items()
             if side in ("positive", "negative") and isinstance(part, Mapping)}
    bad = []
    for n in names:
        v = params[n].get("value")
        if not isinstance(v, (int, float)) or isinstance(v, bool) or not math.isfinite(v):
            continue
        base, side = (n[:-4], "positive") if n.endswith("_pos") else (n[:-4], "negative") if n.endswith("_neg") \
            else (n, "")
        pre = f"{side}." if side else ""
        for path in (f"{pre}{base}", f"{pre}static.{base}"):
            if path in flat:
                if not _agree(flat[path], v):
                    bad.append(f"parameters.{n}.value = {v:g} disagrees with model.{path} = {flat[path]:g}; the "
                               "file was edited in one place only — make them agree")
                break
        else:
            part = sides.get(side, {})
            for path in (base, f"static.{base}"):
                if path in part:
                    if not _agree(part[path], v):
                        bad.append(f"parameters.{n}.value = {v:g} disagrees with parts.{side}.model ({path} = "
                                   f"{part[path]:g}); the file was edited in one place only — make them agree")
                    break
    for side, part in sides.items():
        for path, w in part.items():
            top = flat.get(f"{side}.{path}")
            if top is not None and not _agree(top, w):
                bad.append(f"the top-level \"model\" ({side}.{path} = {top:g}) disagrees with parts.{side}.model "
                           f"({path} = {w:g}); the file was edited in one place only — make them agree")
    return bad


# --------------------------------------------------------------------------- result
@dataclass(frozen=True, kw_only=True, eq=False)
class IdentificationResult:
    """Parameters identified from data, with their uncertainty and diagnostics.

    Parameters
    ----------
    kind : str
        Procedure: ``"static_map"`` or ``"rigid_body"``.
    model_name : str
        Model structure, e.g. ``"exponential"``, ``"rigid_body_symmetric"``.
    model : object or None
        The identified model object (``Stribeck``, ``Directional``, ``RigidBody`` ...);
        None when the estimates do not make a valid model (see ``warnings``).
    names : tuple of str
        Parameter names.
    values, stderr : ndarray
        Estimates and standard errors, in the units of ``units``.
    ci95 : ndarray, shape (p, 2)
        95 % confidence intervals (Student t with ``dof`` degrees of freedom).
    units : tuple of str
        Unit of each parameter.
    correlation : ndarray, shape (p, p)
        Parameter correlation matrix.
    rms : float
        Root-mean-square residual [unit of the fitted signal].
    relative_error_percent : float
        ``100 * ||y - y_hat|| / ||y||``.
    n_obs, dof : int
        Observations used, and residual degrees of freedom.
    success : bool
        False when the optimiser did not converge (``status`` 2; 1 = converged with warnings).
    message : str
        Optimiser or procedure message.
    warnings : tuple of str
        Identifiability and quality flags (empty when nothing is suspicious).
    diagnostics : mapping
        Procedure-specific numbers (AIC, BIC, condition number, candidates ...).
    provenance : mapping
        Where the data came from (file, columns, scales, hash) and the settings used.
    data : mapping of str to ndarray
        What the fit saw, for plots: static maps ``v``, ``F``, ``F_pred``; rigid body
        ``t``, ``y``, ``y_pred``; pre-sliding also ``x``.
    parts : mapping of str to IdentificationResult
        Per-direction results (``"positive"``, ``"negative"``) of a static-map fit.

    Examples
    --------
    >>> import numpy as np
    >>> from frictionkit.identify import fit_static_map
    >>> v = np.r_[np.linspace(0.01, 0.2, 12), -np.linspace(0.01, 0.2, 12)]
    >>> F = np.sign(v) * 2.0 + 10.0 * v
    >>> res = fit_static_map(v, F, model="coulomb_viscous")
    >>> round(res["Fc_pos"], 6), round(res["sigma2_neg"], 6)
    (2.0, 10.0)
    """

    kind: str
    model_name: str
    model: Any
    names: tuple[str, ...]
    values: np.ndarray
    stderr: np.ndarray
    ci95: np.ndarray
    units: tuple[str, ...]
    correlation: np.ndarray
    rms: float
    relative_error_percent: float
    n_obs: int
    dof: int
    success: bool = True
    message: str = ""
    warnings: tuple[str, ...] = ()
    diagnostics: Mapping[str, Any] = field(default_factory=dict)
    provenance: Mapping[str, Any] = field(default_factory=dict)
    data: Mapping[str, np.ndarray] = field(default_factory=dict)
    parts: Mapping[str, IdentificationResult] = field(default_factory=dict)

    def __post_init__(self) -> None:
        p = len(self.names)
        for name in ("values", "stderr"):
            arr = np.asarray(getattr(self, name), dtype=float).reshape(p)
            arr.setflags(write=False)
            object.__setattr__(self, name, arr)
        ci = np.asarray(self.ci95, dtype=float).reshape(p, 2)
        corr = np.asarray(self.correlation, dtype=float).reshape(p, p)
        for a in (ci, corr):
            a.setflags(write=False)
        object.__setattr__(self, "ci95", ci)
        object.__setattr__(self, "correlation", corr)
        object.__setattr__(self, "names", tuple(self.names))
        object.__setattr__(self, "units", tuple(self.units))
        object.__setattr__(self, "warnings", tuple(self.warnings))
        object.__setattr__(self, "diagnostics", MappingProxyType(dict(self.diagnostics)))
        object.__setattr__(self, "provenance", MappingProxyType(dict(self.provenance)))
        object.__setattr__(self, "data", MappingProxyType({k: np.asarray(v, dtype=float) for k, v in self.data.items()}))
        object.__setattr__(self, "parts", MappingProxyType(dict(self.parts)))
        if len(self.units) != p:
            raise DataError(f"IdentificationResult: {p} names but {len(self.units)} units")

    # ------------------------------------------------------------------ access
    @property
    def params(self) -> dict[str, float]:
        """``{name: value}``."""
        return dict(zip(self.names, self.values.tolist()))

    def __getitem__(self, name: str) -> float:
        try:
            return float(self.values[self.names.index(name)])
        except ValueError:
            raise KeyError(f"{name!r}: not a parameter of this result; parameters are {list(self.names)}") from None

    def parameter(self, name: str) -> dict[str, Any]:
        """Value, standard error, 95 % interval and unit of one parameter."""
        i = self.names.index(name) if name in self.names else None
        if i is None:
            raise KeyError(f"{name!r}: not a parameter of this result; parameters are {list(self.names)}")
        return {"value": float(self.values[i]), "stderr": float(self.stderr[i]),
                "ci95": [float(self.ci95[i, 0]), float(self.ci95[i, 1])], "unit": self.units[i]}

    @property
    def flagged(self) -> bool:
        """True when the fit carries warnings or did not converge."""
        return bool(self.warnings) or not self.success

    @property
    def status(self) -> int:
        """0 converged without warnings, 1 converged with warnings (:attr:`warnings`), 2 did not
        converge (:attr:`message` says why) — the package's one result convention."""
        return 2 if not self.success else (1 if self.warnings else 0)

    def summary(self) -> str:
        """Plain-text parameter table with intervals, residuals and warnings."""
        lines = [f"{self.kind}: {self.model_name}  (n = {self.n_obs}, dof = {self.dof})",
                 f"{'parameter':<12}{'value':>14}{'stderr':>12}{'95 % CI':>30}  unit"]
        for i, n in enumerate(self.names):
            ci = f"[{self.ci95[i, 0]:.6g}, {self.ci95[i, 1]:.6g}]"
            lines.append(f"{n:<12}{self.values[i]:>14.6g}{self.stderr[i]:>12.3g}{ci:>30}  {self.units[i]}")
        lines.append(f"RMS residual {self.rms:.6g}, relative error {self.relative_error_percent:.4g} %")
        if self.diagnostics.get("jacobian"):  # how the fit's Jacobian was formed (output error)
            lines.append(f"Jacobian: {self.diagnostics['jacobian']}")
        if self.diagnostics.get("data_scale_text"):
            lines.append(f"data scale: {self.diagnostics['data_scale_text']}")
        for k, part in self.parts.items():
            lines.append(f"  {k}: {part.model_name}, n = {part.n_obs}, RMS residual {part.rms:.6g}, "
                         f"relative error {part.relative_error_percent:.4g} %")
        lines.extend(f"warning: {w}" for w in self.warnings)
        return "\n".join(lines)

    def __repr__(self) -> str:
        vals = ", ".join(f"{n}={v:.6g}" for n, v in zip(self.names, self.values))
        return f"IdentificationResult({self.kind}, {self.model_name}: {vals})"

    # ------------------------------------------------------------------ presentation
    def plot(self, ax: Axes | None=None) -> Axes | np.ndarray:
        """Fitted curve over the data points (static map) or measured vs predicted (rigid body).

        Parameters
        ----------
        ax : matplotlib Axes, optional
            Axes to draw on; default a new figure.

        Returns
        -------
        matplotlib Axes
        """
        from ..plotting.identify import plot_identification

        return plot_identification(self, ax=ax)

    # ------------------------------------------------------------------ JSON
    def to_dict(self, *, include_data: bool = True) -> dict[str, Any]:
        """JSON-ready dict; see :meth:`save_json` for the layout."""
        out = {
            "format": JSON_FORMAT,
            "kind": self.kind,
            "model_name": self.model_name,
            "model": model_to_dict(self.model),
            "parameters": {n: self.parameter(n) for n in self.names},
            "correlation": self.correlation,
            "rms": self.rms,
            "relative_error_percent": self.relative_error_percent,
            "n_obs": self.n_obs,
            "dof": self.dof,
            "success": self.success,
            "message": self.message,
            "warnings": list(self.warnings),
            "diagnostics": dict(self.diagnostics),
            "provenance": dict(self.provenance),
            "parts": {k: v.to_dict(include_data=include_data) for k, v in self.parts.items()},
        }
        if include_data:
            out["data"] = dict(self.data)
        return _jsonable(out)

    @classmethod
    def from_dict(cls, d: Mapping[str, Any]) -> IdentificationResult:
        """Inverse of :meth:`to_dict`, validated: every way a document can be wrong ends in
        one :class:`DataError` saying what is wrong (missing key, a value of the wrong type,
        a model field that is not a number or breaks its rule, malformed content)."""
        if not isinstance(d, Mapping):
            raise DataError(f"the top level is a JSON {type(d).__name__}, expected an object")
        if d.get("format") != JSON_FORMAT:
            raise DataError(f"not a frictionkit identification result "
                            f"(\"format\" is {d.get('format')!r}, expected {JSON_FORMAT!r})")
        try:
            check_model_numbers(d.get("model"), "model")
            parts = d.get("parts")
            for side, part in (parts.items() if isinstance(parts, Mapping) else ()):
                if isinstance(part, Mapping):
                    check_model_numbers(part.get("model"), f"parts.{side}.model")
            return cls._from_dict(d)
        except KeyError as exc:
            raise DataError(f"missing key {exc.args[0]!r}") from None
        except RecursionError:
            raise DataError("JSON nested too deeply") from None
        except FrictionKitError as exc:
            if isinstance(exc, DataError):
                raise
            raise DataError(" ".join(str(exc).split())) from None
        except (TypeError, ValueError, AttributeError, IndexError, OverflowError) as exc:
            raise DataError(f"malformed content ({type(exc).__name__}: {' '.join(str(exc).split())})") from None

    @classmethod
    def _from_dict(cls, d: Mapping[str, Any]) -> IdentificationResult:
        parts = d.get("parts") or {}
        for k, v in (parts.items() if isinstance(parts, Mapping) else ()):
            if not isinstance(v, Mapping):
                raise TypeError(f"parts.{k} is a JSON {type(v).__name__}, expected an object")
        params = d["parameters"]
        if not isinstance(params, Mapping) or not all(isinstance(v, Mapping) for v in params.values()):
            raise TypeError("\"parameters\" must map each name to {\"value\", \"stderr\", \"ci95\", \"unit\"}")
        names = tuple(params)

        def typed(key, kinds, what, default=dataclasses.MISSING):
            x = d[key] if default is dataclasses.MISSING else d.get(key, default)
            kinds = kinds if isinstance(kinds, tuple) else (kinds,)
            if (isinstance(x, bool) and bool not in kinds) or not isinstance(x, kinds):
                raise TypeError(f"\"{key}\" is {json.dumps(x)[:60]}, expected {what}")
            return x

        typed("kind", str, "a string")
        typed("model_name", str, "a string")
        typed("n_obs", int, "an integer")
        typed("dof", int, "an integer")
        typed("success", bool, "true or false", True)
        typed("message", str, "a string", "")
        typed("warnings", (list, tuple), "a list of strings", ())
        typed("diagnostics", Mapping, "an object", {})
        typed("provenance", Mapping, "an object", {})
        typed("written_by", Mapping, "an object", {})
        typed("parts", Mapping, "an object", {})
        typed("data", Mapping, "an object", {})
        for key in ("rms", "relative_error_percent"):
            if isinstance(d[key], bool):
                raise TypeError(f"\"{key}\" is {json.dumps(d[key])}, expected a number")
        if not all(isinstance(w, str) for w in d.get("warnings", ())):
            raise TypeError("\"warnings\" must be a list of strings")
        if not all(isinstance(params[n].get("unit"), str) for n in names):
            raise TypeError("every parameter's \"unit\" must be a string")
        bad = _table_problems(d, params, names)
        if bad:
            raise DataError("; ".join(bad))
        model = model_from_dict(d.get("model"))  # its own rules first (vs = -1: 'must be > 0')
        parts = {k: cls._part(k, v) for k, v in (d.get("parts") or {}).items()}  # each by its own rules first
        bad = _table_model_disagreement(d.get("model"), params, names, d.get("parts"))
        if bad:
            raise DataError("; ".join(bad))
        stderr = _floats([params[n]["stderr"] for n in names])
        ci95 = _floats([params[n]["ci95"] for n in names]).reshape(len(names), 2)
        # JSON has no infinity, so to_dict writes an unbounded interval end as null, like a value never
        # computed. One null end beside a number is unbounded (an unseen direction of a fit: [0, null]
        # is [0, inf)), and its standard error too; read back as NaN it showed as '[0.695, –]' (issue 13).
        for i in range(len(names)):
            lo, hi = ci95[i]
            if np.isnan(hi) and np.isfinite(lo):
                ci95[i, 1] = np.inf
            elif np.isnan(lo) and np.isfinite(hi):
                ci95[i, 0] = -np.inf
            else:
                continue
            if np.isnan(stderr[i]):
                stderr[i] = np.inf
        return cls(
            kind=d["kind"],
            model_name=d["model_name"],
            model=model,
            names=names,
            values=_floats([params[n]["value"] for n in names]),
            stderr=stderr,
            ci95=ci95,
            units=tuple(params[n]["unit"] for n in names),
            correlation=_floats(d["correlation"]).reshape(len(names), len(names)),
            rms=float(d["rms"]) if d["rms"] is not None else math.nan,
            relative_error_percent=float(d["relative_error_percent"]) if d["relative_error_percent"] is not None else math.nan,
            n_obs=int(d["n_obs"]),
            dof=int(d["dof"]),
            success=bool(d.get("success", True)),
            message=d.get("message", ""),
            warnings=tuple(d.get("warnings", ())),
            diagnostics=d.get("diagnostics", {}),
            provenance=d.get("provenance", {}),
            data={k: _floats(v) for k, v in (d.get("data") or {}).items()},
            parts=parts,
        )

    @classmethod
    def _part(cls, side: str, doc: Mapping[str, Any]) -> IdentificationResult:
        try:
            return cls.from_dict(doc)
        except DataError as exc:
            raise DataError(f"parts.{side}: {exc}") from None

    def save_json(self, path: str | Path, *, include_data: bool = True) -> Path:
        """Write the result as JSON (UTF-8, indented).

        The top level holds ``model`` (type and fields), ``parameters`` (each with
        ``value``, ``stderr``, ``ci95``, ``unit``), ``relative_error_percent``, ``rms``,
        ``correlation``, ``warnings``, ``diagnostics``, ``provenance``, ``parts``,
        ``written_by`` (frictionkit version and UTC date of the write) and, with
        ``include_data``, the fitted ``data``. Non-finite numbers become ``null``.

        Examples
        --------
        >>> res.save_json("fit.json")  # doctest: +SKIP
        >>> IdentificationResult.load_json("fit.json").params == res.params  # doctest: +SKIP
        True
        """
        from datetime import datetime, timezone

        from .. import __version__
        from .._io import atomic_write_text  # temporary file + rename: the old file survives a failed write

        p = Path(path)
        doc = self.to_dict(include_data=include_data)
        doc["written_by"] = {"frictionkit_version": __version__,
                             "date": datetime.now(timezone.utc).isoformat(timespec="seconds")}
        text = json.dumps(doc, indent=1, ensure_ascii=False) + "\n"
        atomic_write_text(p, text, encoding="utf-8")
        return p

    @classmethod
    def load_json(cls, path: str | Path) -> IdentificationResult:
        """Read a result written by :meth:`save_json`.

        Raises
        ------
        DataError
            Naming the file and what is wrong with it (not UTF-8, not JSON, not an
            identification result, a missing key or malformed value; see :meth:`from_dict`).
        OSError
            The file cannot be read.
        """
        p = Path(path)
        doc = read_json_object(p)
        try:
            return cls.from_dict(doc)
        except DataError as exc:
            raise DataError(f"file '{p}': {exc}") from None
