"""Model files: a friction law in JSON with its units and provenance.

One format and one loader. A model file is the law's JSON form from the registry
(:class:`~frictionkit.models.FrictionLaw`, contract point 6) inside an envelope that
says what the numbers are and where they came from::

    {
      "format": "frictionkit.model/1",
      "model": {"law": "LuGre", "static": {"law": "Stribeck", "Fc": 1.0, ...}, "sigma0": 1e5, ...},
      "units": {"F": "N", "x": "m", "v": "m/s",
                "parameters": {"static.Fc": "N", "static.vs": "m/s", "sigma0": "N/m", ...}},
      "provenance": {"frictionkit_version": "0.1.0", "created": "2026-11-23T02:00:00+00:00",
                     "method": "...", "data_sha256": "...", ...}
    }

The keys ``model`` and ``provenance`` are those of an identification result
(:meth:`frictionkit.IdentificationResult.save_json`), so :func:`load_model` reads
both, and the older forms too:

* ``frictionkit.model/1`` — this layout;
* ``frictionkit.identification/1`` — an identification result: its model (the friction
  of a rigid-body fit), its provenance (data file, SHA-256, procedure) and its units;
* a bare law ``{"law": "LuGre", ...}`` (the registry's JSON form, before model files
  existed) or ``{"type": "LuGre", ...}`` (the spelling of identification files): loads,
  with empty provenance.

A file of a newer format version (``frictionkit.model/2``), of another kind, or with a
broken model raises one :class:`~frictionkit.DataError` line naming the file and why.

Units: the numbers are SI (m, s, N; rad and N·m for a rotary axis) — the ``units``
entry labels them, it does not convert them.

Examples
--------
>>> import frictionkit as fk
>>> law = fk.LuGre(fk.Stribeck(Fc=1.0, Fs=1.5, vs=1e-3, sigma2=0.4), sigma0=1e5, sigma1=63.2)
>>> fk.save_model(law, "lugre.json", method="hand-made example")  # doctest: +SKIP
>>> fk.load_model("lugre.json") == law  # doctest: +SKIP
True
"""

from __future__ import annotations

import hashlib
import json
import re
from collections.abc import Mapping
from dataclasses import dataclass, field
from datetime import datetime, timezone
from pathlib import Path
from types import MappingProxyType
from typing import Any

from ..errors import DataError, FrictionKitError, ParameterError
from .base import is_law_dict, law_entry, law_from_dict, law_to_dict

__all__ = ["MODEL_FORMAT", "ModelFile", "load_model", "parameter_units", "save_model"]

#: Format (and version) of the files written by :func:`save_model`.
MODEL_FORMAT = "frictionkit.model/1"

_VERSIONED = re.compile(r"^(?P<kind>frictionkit\.[a-z_]+)/(?P<version>\d+)$")

#: Unit labels of a linear axis; a rotary axis passes ``{"F": "N·m", "v": "rad/s"}``.
LINEAR_UNITS = {"F": "N", "x": "m", "v": "m/s"}


def _version() -> str:
    from .. import __version__

    return __version__


def _axis_units(units: Mapping[str, str] | None) -> dict[str, str]:
    """``{"F", "x", "v"}`` unit labels; ``x`` follows ``v`` (``rad/s`` -> ``rad``)."""
    out = dict(LINEAR_UNITS)
    for key, label in (units or {}).items():
        if key not in ("F", "x", "v"):
            raise ParameterError(f"units: key {key!r} unknown; give labels for 'F', 'v' (and 'x')")
        if not isinstance(label, str) or not label.strip() or "\n" in label:
            raise ParameterError(f"units[{key!r}] = {label!r}: must be a non-empty one-line label")
        out[key] = label
    if units and "v" in units and "x" not in units:
        out["x"] = out["v"][:-2] if out["v"].endswith("/s") else out["x"]
    return out


def parameter_units(model: Any, units: Mapping[str, str] | None = None) -> dict[str, str]:
    """Unit of every number in a law's JSON form, keyed by dotted path (``"static.Fc"``).

    Parameters
    ----------
    model : friction law
        Any registered law.
    units : mapping, optional
        Axis unit labels ``{"F": ..., "v": ..., "x": ...}`` (default N, m/s, m).

    Examples
    --------
    >>> import frictionkit as fk
    >>> from frictionkit.models.files import parameter_units
    >>> parameter_units(fk.Dahl(Fc=1.0, sigma0=1e5))
    {'Fc': 'N', 'sigma0': 'N/m', 'sigma2': 'N·s/m'}
    """
    from ..identify._advice import unit

    ax = _axis_units(units)
    out: dict[str, str] = {}

    def walk(node: Mapping[str, Any], prefix: str) -> None:
        for key, val in node.items():
            if key == "law":
                continue
            if isinstance(val, Mapping):
                walk(val, f"{prefix}{key}.")
            elif not isinstance(val, str):
                out[prefix + key] = unit(key, ax)

    walk(law_to_dict(model), "")
    return out


def _sha256(path: Path) -> str:
    h = hashlib.sha256()
    with path.open("rb") as fh:
        for chunk in iter(lambda: fh.read(1 << 20), b""):
            h.update(chunk)
    return h.hexdigest()


@dataclass(frozen=True, kw_only=True, eq=False)
class ModelFile:
    """A friction law with the unit labels of its numbers and where it came from.

    Parameters
    ----------
    model : friction law
        Any registered law (``Stribeck``, ``LuGre``, ``GMS``, ``Directional`` ...).
    units : mapping
        Axis unit labels ``{"F", "x", "v"}``; default N, m, m/s.
    provenance : mapping
        ``frictionkit_version``, ``created`` (ISO 8601, UTC), ``method``,
        ``data_sha256`` / ``data_file`` where known, and anything the source recorded
        (an identification result's ``procedure``, ``columns``, ``records`` ...).
    format : str
        The format the file was read from (``frictionkit.model/1``,
        ``frictionkit.identification/1`` or ``"law"`` for a bare law).
    """

    model: Any
    units: Mapping[str, str] = field(default_factory=lambda: dict(LINEAR_UNITS))
    provenance: Mapping[str, Any] = field(default_factory=dict)
    format: str = MODEL_FORMAT

    def __post_init__(self) -> None:
        law_entry(self.model)  # raises ParameterError naming the type when it is not a law
        object.__setattr__(self, "units", MappingProxyType(_axis_units(self.units)))
        object.__setattr__(self, "provenance", MappingProxyType(dict(self.provenance or {})))

    # ------------------------------------------------------------------ JSON
    def to_dict(self) -> dict[str, Any]:
        """The JSON document of format :data:`MODEL_FORMAT`."""
        return {
            "format": MODEL_FORMAT,
            "model": law_to_dict(self.model),
            "units": {**dict(self.units), "parameters": parameter_units(self.model, self.units)},
            "provenance": _jsonable(dict(self.provenance)),
        }

    def save(self, path: str | Path) -> Path:
        """Write the file atomically (UTF-8, indented); returns the path."""
        from .._io import atomic_write_text

        text = json.dumps(self.to_dict(), indent=2, ensure_ascii=False) + "\n"
        return atomic_write_text(Path(path), text)

    @classmethod
    def load(cls, path: str | Path) -> ModelFile:
        """Read any model file :func:`load_model` reads, with its units and provenance."""
        p = Path(path)
        where = f"model file '{p}'"
        try:
            raw = p.read_bytes()
        except IsADirectoryError:
            raise DataError(f"{where}: is a folder, expected a JSON file") from None
        except FileNotFoundError:
            raise DataError(f"{where}: no such file") from None
        try:
            doc = json.loads(raw.decode("utf-8"))
        except UnicodeDecodeError as exc:
            raise DataError(f"{where}: not UTF-8 text (byte {exc.start}); expected JSON") from None
        except json.JSONDecodeError as exc:
            raise DataError(f"{where}: not valid JSON ({exc.msg} at line {exc.lineno}, column {exc.colno})") from None
        except RecursionError:
            raise DataError(f"{where}: JSON nested too deeply") from None
        try:
            return cls.from_dict(doc, source=p)
        except DataError as exc:
            raise DataError(f"{where}: {_one_line(exc)}") from None
        except ParameterError as exc:
            raise DataError(f"{where}: {_one_line(exc)}") from None
        except FrictionKitError as exc:
            raise DataError(f"{where}: {_one_line(exc)}") from None
        except RecursionError:
            raise DataError(f"{where}: JSON nested too deeply") from None
        except (KeyError, TypeError, ValueError, AttributeError, IndexError) as exc:
            detail = f"missing key {exc.args[0]!r}" if isinstance(exc, KeyError) else _one_line(exc)
            raise DataError(f"{where}: malformed content ({type(exc).__name__}: {detail})") from None

    @classmethod
    def from_dict(cls, doc: Any, *, source: str | Path | None = None) -> ModelFile:
        """Read a parsed JSON document (see the module docstring for the accepted forms)."""
        if not isinstance(doc, Mapping):
            raise DataError(f"the top level is a JSON {type(doc).__name__}, expected an object")
        fmt = doc.get("format")
        if fmt is None:
            if "law" in doc or "type" in doc:  # a bare law, before model files existed
                from ..identify.result import model_from_dict

                return cls(model=model_from_dict(doc), provenance={"source_format": "law JSON without envelope"},
                           format="law")
            raise DataError(f"not a frictionkit model: no \"format\" key and no \"law\" key (keys: {sorted(doc)[:8]})")
        m = _VERSIONED.match(fmt) if isinstance(fmt, str) else None
        if m is None:
            raise DataError(f"not a frictionkit model (\"format\" is {fmt!r}, expected {MODEL_FORMAT!r})")
        from ..identify.result import JSON_FORMAT

        readable = {MODEL_FORMAT: "model", JSON_FORMAT: "identification"}
        if fmt not in readable:
            known = [f for f in readable if f.split("/")[0] == m.group("kind")]
            if not known:
                raise DataError(f"a {fmt!r} file is not a friction model; expected {MODEL_FORMAT!r} "
                                f"or an identification result {JSON_FORMAT!r}")
            have = int(known[0].split("/")[1])
            if int(m.group("version")) > have:
                raise DataError(f"format {fmt!r} was written by a newer frictionkit; this one "
                                f"({_version()}) reads {known[0]!r}: upgrade frictionkit")
            raise DataError(f"format {fmt!r} is not one frictionkit ever wrote; this one reads {known[0]!r}")
        if readable[fmt] == "identification":
            return cls._from_identification(doc)
        if "model" not in doc:
            raise DataError("missing key 'model'")
        if not is_law_dict(doc["model"]):
            raise DataError("\"model\" is not a friction law in JSON form ({\"law\": ..., ...})")
        units = doc.get("units") or {}
        if not isinstance(units, Mapping):
            raise DataError(f"\"units\" is a JSON {type(units).__name__}, expected an object")
        prov = doc.get("provenance") or {}
        if not isinstance(prov, Mapping):
            raise DataError(f"\"provenance\" is a JSON {type(prov).__name__}, expected an object")
        return cls(model=law_from_dict(doc["model"]), units={k: v for k, v in units.items() if k != "parameters"},
                   provenance=prov, format=fmt)

    @classmethod
    def _from_identification(cls, doc: Mapping[str, Any]) -> ModelFile:
        from ..identify.result import IdentificationResult
        from ..plants.rigid_body import RigidBody

        res = IdentificationResult.from_dict(doc)
        model = res.model
        prov: dict[str, Any] = dict(res.provenance)
        if isinstance(model, RigidBody):  # the friction of a rigid-body fit; keep the rest in the provenance
            prov["rigid_body"] = {"M": model.M, "offset": model.offset}
            model = model.friction
        if model is None:
            raise DataError(f"the identification result ({res.kind}) holds no model")
        prov.setdefault("method", f"identification: {res.kind} ({res.model_name})")
        written = doc.get("written_by") if isinstance(doc.get("written_by"), Mapping) else {}
        if "frictionkit_version" in written:
            prov.setdefault("frictionkit_version", written["frictionkit_version"])
        if "date" in written:
            prov.setdefault("created", written["date"])
        if "sha256" in prov and "data_sha256" not in prov:
            prov["data_sha256"] = prov["sha256"]
        records = prov.get("records") if isinstance(prov.get("records"), list) else []
        hashes = sorted({r["sha256"] for r in records if isinstance(r, Mapping) and isinstance(r.get("sha256"), str)})
        if hashes and "data_sha256" not in prov:  # a fit over several records (or files)
            prov["data_sha256"] = hashes[0] if len(hashes) == 1 else hashes
        units = prov.get("units") if isinstance(prov.get("units"), Mapping) else {}
        units = {k: v for k, v in units.items() if k in ("F", "v", "x")}
        return cls(model=model, units=units, provenance=prov, format=str(doc["format"]))

    # ------------------------------------------------------------------ presentation
    def summary(self) -> str:
        """Law, parameters with units, and provenance, as plain text."""
        units = parameter_units(self.model, self.units)
        flat = _flatten(law_to_dict(self.model))
        lines = [f"{law_entry(self.model).name} model ({self.format})"]
        for key, val in flat.items():
            if isinstance(val, str):
                lines.append(f"  {key:<22} {val}")
            else:
                lines.append(f"  {key:<22} {_fmt(val)} {units.get(key, '')}".rstrip())
        for key in ("method", "created", "frictionkit_version", "data_file", "file", "data_sha256"):
            if key in self.provenance:
                lines.append(f"  {key}: {self.provenance[key]}")
        return "\n".join(lines)

    def plot(self, ax=None):
        """The steady-state map ``Fss(v)``; returns the matplotlib Axes."""
        import matplotlib.pyplot as plt
        import numpy as np

        if ax is None:
            _, ax = plt.subplots(figsize=(6, 4))
        vmax = _speed_scale(self.model)
        v = np.linspace(-vmax, vmax, 801)
        ax.plot(v, self.model.steady_state(v), lw=1.5)
        ax.axhline(0.0, color="0.7", lw=0.8)
        ax.axvline(0.0, color="0.7", lw=0.8)
        ax.set_xlabel(f"v [{self.units['v']}]")
        ax.set_ylabel(f"F [{self.units['F']}]")
        ax.set_title(f"{law_entry(self.model).name}: steady state")
        return ax


def _speed_scale(model: Any) -> float:
    """A velocity range that shows a law's Stribeck region: 10 x the largest ``vs`` (or 1)."""
    vs = [v for k, v in _flatten(law_to_dict(model)).items() if k.split(".")[-1] == "vs"]
    return 10.0 * max(vs) if vs else 1.0


def _flatten(node: Mapping[str, Any], prefix: str = "") -> dict[str, Any]:
    out: dict[str, Any] = {}
    for key, val in node.items():
        if key == "law":
            continue
        if isinstance(val, Mapping):
            out.update(_flatten(val, f"{prefix}{key}."))
        else:
            out[prefix + key] = val
    return out


def _fmt(val: Any) -> str:
    if isinstance(val, list):
        return "[" + ", ".join(f"{x:.6g}" for x in val) + "]"
    return f"{val:.6g}" if isinstance(val, float) else str(val)


def _one_line(exc: BaseException) -> str:
    return " ".join(str(exc).split())


def _jsonable(x: Any) -> Any:
    from ..identify.result import _jsonable as conv

    return conv(x)


# --------------------------------------------------------------------------- public shorthands
def save_model(model: Any, path: str | Path, *, units: Mapping[str, str] | None = None, method: str | None = None,
               data: str | Path | None = None, provenance: Mapping[str, Any] | None = None) -> Path:
    """Write a friction law to a model file (format :data:`MODEL_FORMAT`), atomically.

    Parameters
    ----------
    model : friction law
        Any registered law (its numbers in SI).
    path : path-like
        The JSON file to write.
    units : mapping, optional
        Axis unit labels ``{"F": ..., "v": ...}``; default N and m/s (``{"F": "N·m",
        "v": "rad/s"}`` for a rotary axis).
    method : str, optional
        How the parameters were obtained ("seed 002 Table 2", "identify output-error" ...).
    data : path-like, optional
        The data file the parameters came from: its name and SHA-256 are recorded.
    provenance : mapping, optional
        Further entries (kept as given; ``method`` and ``data`` win).

    Returns
    -------
    Path

    Examples
    --------
    >>> import frictionkit as fk
    >>> fk.save_model(fk.Dahl(Fc=1.0, sigma0=1e5), "dahl.json", method="catalogue values")  # doctest: +SKIP
    PosixPath('dahl.json')
    """
    prov: dict[str, Any] = dict(provenance or {})
    prov.setdefault("frictionkit_version", _version())
    prov.setdefault("created", datetime.now(timezone.utc).isoformat(timespec="seconds"))
    if method is not None:
        prov["method"] = str(method)
    if data is not None:
        d = Path(data)
        if not d.is_file():
            raise DataError(f"save_model: data = '{d}': no such file (the file the parameters came from)")
        prov["data_file"] = str(d)
        prov["data_sha256"] = _sha256(d)
    return ModelFile(model=model, units=units or {}, provenance=prov).save(path)


def load_model(path: str | Path) -> Any:
    """The friction law in a model file, an identification result JSON or a bare law JSON.

    Use :meth:`ModelFile.load` for its units and provenance too.

    Raises
    ------
    DataError
        One line naming the file and what is wrong: missing, not JSON, another kind of
        file, a newer format version, an unknown law or field, or a parameter that
        breaks its rule.

    Examples
    --------
    >>> import frictionkit as fk
    >>> fk.load_model("fit.json")  # doctest: +SKIP
    LuGre(static=Stribeck(Fc=1.0, ...), sigma0=100000.0, sigma1=63.2)
    """
    return ModelFile.load(path).model
