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

Units: the ``units`` entry labels the numbers, it never converts them. :func:`save_model`
writes SI labels (:data:`LINEAR_UNITS`; ``{"F": "N·m", "v": "rad/s"}`` for a rotary axis),
and the simulators read every number as SI. A law identified from data labelled otherwise
(``identify ... --force-unit V`` without a ``--force-scale`` to N) keeps that free-text label:
its numbers are in that unit, not SI. Decision (issue 13 round 7): the labels stay free text
(an identification may be in volts or counts by design), and :meth:`ModelFile.summary` says
when they are not the SI set (:data:`SI_LABELS`), so such a file is not taken for SI unseen.

Machine files
-------------
A :class:`~frictionkit.Machine` saves to the same format with ``"kind": "machine"``:
``"model"`` is :meth:`Machine.to_dict` (degrees of freedom, inertias, springs, sites with
their laws in the registry's JSON form, actuators, sensors and the controller blocks with
their settings — PID gains, state-space matrices, saturations, feed-forward laws), ``"inputs"``
lists the input arrays a run needs (:meth:`Machine.input_names`; the arrays themselves —
references, feed-forwards — are not in the file: give them to
:func:`~frictionkit.simulate_machine` as ``inputs=`` or to ``frictionkit simulate
MACHINE.json --input NAME=FILE:COLUMN``), ``"units"`` the unit of every field
(:data:`MACHINE_UNITS`), ``"provenance"`` as for a law. A file without ``"kind"`` is a law.

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

from .._validate import no_huge_number
from ..errors import DataError, FrictionKitError, ParameterError
from .base import is_law_dict, law_entry, law_from_dict, law_to_dict
from typing import TYPE_CHECKING

if TYPE_CHECKING:
    import numpy as np
    from matplotlib.axes import Axes

__all__ = ["MACHINE_UNITS", "MODEL_FORMAT", "ModelFile", "load_model", "parameter_units", "save_model"]

#: Format (and version) of the files written by :func:`save_model`.
MODEL_FORMAT = "frictionkit.model/1"

_VERSIONED = re.compile(r"^(?P<kind>frictionkit\.[a-z_]+)/(?P<version>\d+)$")

#: Unit labels of a linear axis; a rotary axis passes ``{"F": "N·m", "v": "rad/s"}``.
LINEAR_UNITS = {"F": "N", "x": "m", "v": "m/s"}

#: The SI labels per axis quantity (linear, rotary; with the ASCII spellings of N·m).
SI_LABELS = {"F": ("N", "N·m", "N*m", "Nm", "N m"), "x": ("m", "rad"), "v": ("m/s", "rad/s")}

#: What a file may hold (``"kind"``); a file without the key holds a law.
KINDS = ("law", "machine")

#: Unit of every field of a machine file (SI; labels, not conversions). A coordinate ``at``
#: ``{name: c}`` has the unit of ``c`` times its terms' unit: m for a translational degree of
#: freedom, rad for a rotational one, and a screw's ``R theta`` (R in m/rad) is in m. "u" below
#: is the unit of the coordinate a part acts on and "F(u)" its force unit (N on m, N·m on rad).
MACHINE_UNITS = {
    "time": "s (inputs and signals are sampled at the run's dt; blocks are discrete at dt)",
    "dofs.inertia": "kg (translational) or kg·m² (rotational)",
    "dofs.x0": "m or rad", "dofs.v0": "m/s or rad/s",
    "inertias.inertia": "kg or kg·m² (moving with its coordinate u: F(u)·s²/u)",
    "springs.k": "F(u)/u (N/m, N·m/rad)", "springs.c": "F(u)·s/u (N·s/m, N·m·s/rad)",
    "sites.law": "friction law in F(u) at velocity u/s (see each law's parameter units)",
    "sites.law.HertzContact": "preload N, stiffness N/m",
    "sites.law.PiecewiseLinearSpring": "stiffness F(u)/u, breaks u",
    "sites.law.SineLoad": "amplitude F(u), phase rad",
    "sites.load": "NormalLoad: reference, preload F of the spring it is on; gain, floor_gain 1",
    "sites.schedule": "a coordinate's position (u) or velocity (u/s)",
    "actuators.gain": "F(u) per command unit (K_t: N·m/A)", "actuators.limit": "command unit (null: none)",
    "actuators.delay": "samples",
    "sensors.resolution": "u (position) or u/s (velocity)", "sensors.noise": "as resolution (std)",
    "sensors.delay": "samples",
    "blocks.Sum": "terms: output unit per input unit; bias: output unit",
    "blocks.PID": "Kp output/error unit; Ki Kp/s; Kd Kp·s; tau_d s",
    "blocks.StateSpace": "discrete at dt: A 1, B state/input, C output/state, D output/input",
    "blocks.Saturation": "lo, hi: signal unit (null: unbounded)",
    "blocks.FrictionFeedforward": "law: force at the velocity of its input signal; scale: command per force",
}


def _version() -> str:
    from .. import __version__

    return __version__


#: The axis-unit keys and their defaults, as the errors of :func:`_axis_units` name them.
_UNIT_KEYS = ", ".join(repr(k) for k in LINEAR_UNITS)
_ALLOWED_UNITS = "{" + ", ".join(f"{k!r}: {v!r}" for k, v in LINEAR_UNITS.items()) + "}"


def _axis_units(units: Mapping[str, str] | None, owner: str = "units") -> dict[str, str]:
    """``{"F", "x", "v"}`` unit labels; ``x`` follows ``v`` (``rad/s`` -> ``rad``).

    ``None`` or ``{}`` means the defaults (:data:`LINEAR_UNITS`); a key left out of a mapping
    keeps its default. ``owner`` names the argument in the errors (``"ModelFile.units"``).
    """
    out = dict(LINEAR_UNITS)
    if units is not None and not isinstance(units, Mapping):  # units=5 was "'int' object has no attribute 'items'"
        raise ParameterError(f"{owner} = {units!r}: must be None (the defaults {_ALLOWED_UNITS}) or a mapping of "
                             f"axis labels with the keys {_UNIT_KEYS}, e.g. {{'F': 'N·m', 'v': 'rad/s'}} for a rotary "
                             "axis")
    for key, label in (units or {}).items():
        if key not in LINEAR_UNITS:
            raise ParameterError(f"{owner}: key {key!r} unknown; the keys are {_UNIT_KEYS} "
                                 f"(defaults {_ALLOWED_UNITS})")
        if not isinstance(label, str) or not label.strip() or "\n" in label:
            raise ParameterError(f"{owner}[{key!r}] = {label!r}: must be a non-empty one-line label "
                                 f"(SI: {' or '.join(repr(x) for x in SI_LABELS[key][:2])})")
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

def _optional(doc: Mapping[str, Any], key: str, kind: type, what: str, default: Any) -> Any:
    """An optional key of a model file: absent -> ``default``; present -> it must be ``what``.

    One rule for every model file (law, machine, identification result: ``IdentificationResult.from_dict``
    reads its optional keys the same way): an empty or null value of the wrong JSON type
    (``"provenance": []``, ``"units": null``) is refused like any other wrong type — it was read as
    "none" without a word (issue 13). An empty value of the right type (``{}``, ``[]``) is accepted.
    """
    if key not in doc:
        return default
    x = doc[key]
    if not isinstance(x, kind):
        raise DataError(f"\"{key}\" is a JSON {'null' if x is None else type(x).__name__} ({json.dumps(x, default=str)[:60]}), expected {what}; "
                        "drop the key if there is none")
    return x


@dataclass(frozen=True, kw_only=True, eq=False)
class ModelFile:
    """A friction law (or a machine) with the unit labels of its numbers and where it came from.

    Parameters
    ----------
    model : friction law or Machine
        Any registered law (``Stribeck``, ``LuGre``, ``GMS``, ``Directional`` ...), or a
        :class:`~frictionkit.Machine` (:attr:`kind` ``"machine"``).
    units : mapping or None
        Axis unit labels with the keys ``"F"``, ``"x"``, ``"v"`` (free text, never a
        conversion: the numbers stay as they are). ``None`` or ``{}`` means the defaults
        :data:`LINEAR_UNITS` (N, m, m/s); a key left out keeps its default, and ``"x"``
        follows ``"v"`` (``{"F": "N·m", "v": "rad/s"}`` gives x in rad). Any other type, or
        another key, raises :class:`~frictionkit.ParameterError` naming the keys. A
        machine's units are fixed per field (:data:`MACHINE_UNITS`): give ``None``.
    provenance : mapping
        ``frictionkit_version``, ``created`` (ISO 8601, UTC), ``method``,
        ``data_sha256`` / ``data_file`` where known, and anything the source recorded
        (an identification result's ``procedure``, ``columns``, ``records`` ...).
    format : str
        The format the file was read from (``frictionkit.model/1``,
        ``frictionkit.identification/1`` or ``"law"`` for a bare law).
    """

    model: Any
    units: Mapping[str, str] | None = field(default_factory=lambda: dict(LINEAR_UNITS))
    provenance: Mapping[str, Any] = field(default_factory=dict)
    format: str = MODEL_FORMAT

    def __post_init__(self) -> None:
        if self.provenance is not None and not isinstance(self.provenance, Mapping):  # provenance="x" was "dictionary update sequence ..." (round 11)
            raise ParameterError(f"ModelFile.provenance = {self.provenance!r}: must be a mapping (name -> JSON data)")
        if not isinstance(self.format, str):
            raise ParameterError(f"ModelFile.format = {self.format!r}: must be a string such as {MODEL_FORMAT!r}")
        if _is_machine(self.model):
            if dict(self.units or {}) not in ({}, LINEAR_UNITS, MACHINE_UNITS):
                raise ParameterError(f"ModelFile.units = {dict(self.units)!r}: a machine file's units are fixed per "
                                     "field (SI, MACHINE_UNITS); give None (axis labels {'F', 'v'} are for a "
                                     "friction law)")
            object.__setattr__(self, "units", MappingProxyType(dict(MACHINE_UNITS)))
        else:
            law_entry(self.model)  # raises ParameterError naming the type when it is not a law or machine
            object.__setattr__(self, "units", MappingProxyType(_axis_units(self.units, "ModelFile.units")))
        object.__setattr__(self, "provenance", MappingProxyType(dict(self.provenance or {})))

    @property
    def kind(self) -> str:
        """``"machine"`` for a :class:`~frictionkit.Machine`, else ``"law"``."""
        return "machine" if _is_machine(self.model) else "law"

    # ------------------------------------------------------------------ JSON
    def to_dict(self) -> dict[str, Any]:
        """The JSON document of format :data:`MODEL_FORMAT`."""
        if self.kind == "machine":
            return {"format": MODEL_FORMAT, "kind": "machine", "model": self.model.to_dict(),
                    "inputs": self.model.input_names(), "units": dict(MACHINE_UNITS),
                    "provenance": _jsonable(dict(self.provenance))}
        return {
            "format": MODEL_FORMAT,
            "model": law_to_dict(self.model),
            "units": {**dict(self.units), "parameters": parameter_units(self.model, self.units)},
            "provenance": _jsonable(dict(self.provenance)),
        }

    def save(self, path: str | Path) -> Path:
        """Write the file atomically (UTF-8, indented); returns the path."""
        from .._io import atomic_write_text

        target = _file_path("ModelFile.save", "path", path)
        try:
            text = json.dumps(self.to_dict(), indent=2, ensure_ascii=False) + "\n"
        except (TypeError, ValueError) as exc:  # provenance={"a": object()} raised json's TypeError (round 11)
            raise ParameterError(f"provenance: {_one_line(exc)}; entries must be JSON data (numbers, text, lists, "
                                 "mappings)") from None
        return atomic_write_text(target, text)

    @classmethod
    def load(cls, path: str | Path, *, kind: str | None = "law") -> ModelFile:
        """Read any model file :func:`load_model` reads, with its units and provenance.

        ``kind``: ``"law"`` (default: the callers that need a friction law refuse a machine
        file in one line), ``"machine"``, or ``None`` for either.
        """
        if kind is not None and kind not in KINDS:
            raise ParameterError(f"ModelFile.load kind = {kind!r}: must be one of {KINDS} or None")
        p = _file_path("load_model", "path", path)
        where = f"model file '{p}'"
        out = cls._load(p, where)
        if kind is not None and out.kind != kind:
            what = {"law": "a friction law", "machine": "a machine"}
            raise DataError(f"{where}: holds {what[out.kind]} (kind {out.kind!r}); {what[kind]} is expected here")
        return out

    @classmethod
    def _load(cls, p: Path, where: str) -> ModelFile:
        from .._io import DuplicateKeyError, json_loads, read_input_bytes

        raw = read_input_bytes(p, where, expected="a JSON file")

        try:
            doc = json_loads(raw.decode("utf-8"))
        except DuplicateKeyError as exc:
            raise DataError(f"{where}: {exc}") from None
        except UnicodeDecodeError as exc:
            raise DataError(f"{where}: not UTF-8 text (byte {exc.start}); expected JSON") from None
        except json.JSONDecodeError as exc:
            raise DataError(f"{where}: not valid JSON ({exc.msg} at line {exc.lineno}, column {exc.colno})") from None
        except RecursionError:
            raise DataError(f"{where}: JSON nested too deeply") from None
        except ValueError as exc:  # an integer of > 4,300 digits (CPython's int-parsing limit)
            raise DataError(f"{where}: not readable JSON ({_one_line(exc)})") from None
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

                no_huge_number(doc, "law")
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
        kind = doc.get("kind", "law")
        if kind not in KINDS:
            raise DataError(f"\"kind\" is {kind!r}: this frictionkit ({_version()}) reads {list(KINDS)} "
                            "(a newer frictionkit may have written it)")
        if kind == "machine":
            return cls._machine_from_dict(doc, fmt)
        if not is_law_dict(doc["model"]):
            raise DataError("\"model\" is not a friction law in JSON form ({\"law\": ..., ...})")
        unknown = sorted(set(doc) - {"format", "kind", "model", "units", "provenance"})
        if unknown:  # as a machine file: a misspelt "provenence" or "unit" was ignored without a word (round 9)
            raise DataError(f"law file: unknown key(s) {unknown}; known: ['format', 'kind', 'model', 'provenance', "
                            "'units'] (notes go under \"provenance\")")
        units = _optional(doc, "units", Mapping, "an object", {})
        prov = _optional(doc, "provenance", Mapping, "an object", {})
        no_huge_number(doc["model"], "model")  # as a machine file's numbers (Machine.from_dict), round 11
        return cls(model=law_from_dict(doc["model"]), units={k: v for k, v in units.items() if k != "parameters"},
                   provenance=prov, format=fmt)

    @classmethod
    def _machine_from_dict(cls, doc: Mapping[str, Any], fmt: str) -> ModelFile:
        from ..machines import Machine

        unknown = sorted(set(doc) - {"format", "kind", "model", "inputs", "units", "provenance"})
        if unknown:
            raise DataError(f"machine file: unknown key(s) {unknown}")
        prov = _optional(doc, "provenance", Mapping, "an object", {})
        for key, label in _optional(doc, "units", Mapping, "an object", {}).items():
            # the units are fixed (SI): an edited label was ignored without a word, so "dofs.inertia": "g"
            # ran grams as kilograms (issue 13 round 6); a missing entry or block is fine (derived)
            # (a key this version does not list, e.g. an older file's, is left alone)
            if key in MACHINE_UNITS and label != MACHINE_UNITS[key]:
                raise DataError(f"\"units\"[{key!r}] = {json.dumps(label, default=str)[:60]}: a machine file's units "
                                f"are fixed (SI) and not read — this field is in {MACHINE_UNITS[key]!r}; convert "
                                "the numbers and restore or drop the entry")
        machine = Machine.from_dict(doc["model"])
        listed = _optional(doc, "inputs", list, "a list of names", None)  # written for the reader; derived
        if listed is not None and sorted(map(str, listed)) != sorted(machine.input_names()):
            # an edited list would otherwise be ignored without a word (campaign round 5)
            raise DataError(f"\"inputs\" lists {listed} but the machine reads {machine.input_names()}: the list is "
                            "derived from the blocks and actuators (edit those, or fix or drop the list)")
        return cls(model=machine, provenance=prov, format=fmt)

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
        if self.kind == "machine":
            m = self.model
            lines = [f"{m!r} ({self.format})", f"  inputs: {', '.join(m.input_names()) or 'none'}"]
            lines += [f"  dof {d.name}: {d.kind}, inertia {_fmt(d.inertia)} "
                      f"{'kg' if d.kind == 'translational' else 'kg·m²'}" for d in m.dofs]
            lines += [f"  site {s.name}: {s.role}, {type(s.law).__name__}" for s in m.sites]
            lines += [f"  block {type(b).__name__} -> {', '.join(b.outputs)}" for b in m.blocks]
            lines += [f"  {k}: {self.provenance[k]}" for k in ("method", "created", "frictionkit_version", "data_file",
                                                                 "data_sha256") if k in self.provenance]
            return "\n".join(lines)
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
        odd = {k: v for k, v in self.units.items() if k in SI_LABELS and v not in SI_LABELS[k]}
        if odd:
            lines.append("  note: unit labels " + ", ".join(f"{k} = {v!r}" for k, v in odd.items()) + " are not SI; "
                         "the numbers are in those units, while simulate and compensate read them as SI")
        return "\n".join(lines)

    def plot(self, ax: Axes | None=None) -> Axes | np.ndarray:
        """The steady-state map ``Fss(v)``; returns the matplotlib Axes."""
        import matplotlib.pyplot as plt
        import numpy as np

        if ax is None:
            _, ax = plt.subplots(figsize=(6, 4))
        if self.kind == "machine":  # the steady state of every friction site
            sites = [s for s in self.model.sites if s.role == "friction"]
            vmax = max([_speed_scale(s.law) for s in sites] or [1.0])
            v = np.linspace(-vmax, vmax, 801)
            for s in sites:
                ax.plot(v, s.law.steady_state(v), lw=1.5, label=f"{s.name} ({law_entry(s.law).name})")
            ax.axhline(0.0, color="0.7", lw=0.8)
            units = {getattr(s, "unit", "N") for s in sites}  # each site's own (Machine.friction unit=)
            F_u, v_u = ("N", "m/s") if units == {"N"} else ("N·m", "rad/s") if units == {"N·m"} else \
                ("N or N·m", "m/s or rad/s")
            ax.set_xlabel(f"site velocity [{v_u}]")
            ax.set_ylabel(f"friction [{F_u}]")
            ax.set_title(f"{self.model.name}: friction sites, steady state")
            if sites:  # friction opposes motion: the v < 0, F > 0 quadrant holds no curve
                ax.legend(fontsize=8, loc="upper left")
            return ax
        vmax = _speed_scale(self.model)
        v = np.linspace(-vmax, vmax, 801)
        ax.plot(v, self.model.steady_state(v), lw=1.5)
        ax.axhline(0.0, color="0.7", lw=0.8)
        ax.axvline(0.0, color="0.7", lw=0.8)
        ax.set_xlabel(f"v [{self.units['v']}]")
        ax.set_ylabel(f"friction [{self.units['F']}]")
        ax.set_title(f"{law_entry(self.model).name}: steady state")
        ax.locator_params(axis="x", nbins=6)  # ±10 vs: labels like -0.0075 ran together in a half-width panel
        return ax


def _is_machine(model: Any) -> bool:
    from ..machines import Machine

    return isinstance(model, Machine)


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


def _file_path(owner: str, name: str, value: Any) -> Path:
    """``value`` as a Path, or a ParameterError naming the argument (``load_model(5)`` raised pathlib's
    TypeError, issue 13 rounds 10-11)."""
    if isinstance(value, bytes) or not isinstance(value, (str, Path)) and not hasattr(value, "__fspath__"):
        raise ParameterError(f"{owner}: {name} = {value!r}: must be a file path (str or os.PathLike)")
    try:
        return Path(value)
    except TypeError:  # an __fspath__ that returns bytes
        raise ParameterError(f"{owner}: {name} = {value!r}: must be a file path (str or os.PathLike)") from None


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
    """Write a friction law or a machine to a model file (format :data:`MODEL_FORMAT`), atomically.

    Parameters
    ----------
    model : friction law or Machine
        Any registered law (its numbers in SI), or a :class:`~frictionkit.Machine` with its
        controller blocks (``"kind": "machine"``; see the module docstring).
    path : path-like
        The JSON file to write.
    units : mapping, optional
        Axis unit labels ``{"F": ..., "v": ...}``; default N and m/s (``{"F": "N·m",
        "v": "rad/s"}`` for a rotary axis). Not for a machine (its units are per field).
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
    if provenance is not None and not isinstance(provenance, Mapping):  # was "'int' object is not iterable"
        raise ParameterError(f"save_model: provenance = {provenance!r}: must be a mapping (name -> JSON data)")
    if method is not None and not isinstance(method, str):  # method=object() was written as "<object object at ...>"
        raise ParameterError(f"save_model: method = {method!r}: must be a string (how the parameters were obtained)")
    if units is not None and not isinstance(units, Mapping):
        _axis_units(units, "save_model: units")  # raises, naming this function's argument and the allowed keys
    prov: dict[str, Any] = dict(provenance or {})
    prov.setdefault("frictionkit_version", _version())
    prov.setdefault("created", datetime.now(timezone.utc).isoformat(timespec="seconds"))
    if method is not None:
        prov["method"] = method
    if data is not None:
        d = _file_path("save_model", "data", data)
        if not d.is_file():
            raise DataError(f"save_model: data = '{d}': no such file (the file the parameters came from)")
        prov["data_file"] = str(d)
        prov["data_sha256"] = _sha256(d)
    return ModelFile(model=model, units=units or {}, provenance=prov).save(_file_path("save_model", "path", path))


def load_model(path: str | Path) -> Any:
    """The friction law (or :class:`~frictionkit.Machine`) in a model file, an identification
    result JSON or a bare law JSON.

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
    return ModelFile.load(path, kind=None).model
