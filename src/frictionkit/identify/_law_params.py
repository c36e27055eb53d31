"""A friction law as named scalar parameters, per direction, and the recipe to rebuild it.

Used by the motion-driven output-error fit (:mod:`.motion_error`). Any law that is a
frozen dataclass of numbers, number sequences and a nested static law works — LuGre,
Dahl, GMS, a ``Directional`` of one of them, or a law registered later — because the
fields are read generically:

* a float field is one parameter, named as the field (``sigma0``, ``C``, ``Fc``);
* a sequence field (GMS ``k``, ``xi``) is one parameter per entry, ``k1 .. kM``;
* a nested law (the ``static`` map) contributes its own fields (``Fc``, ``Fs``, ``vs``,
  ``delta``, ``sigma2``); strings (the Stribeck ``shape``) stay fixed.

Every parameter exists once per direction of motion (``_pos`` for ``v >= 0``, ``_neg``
for ``v < 0``, the rows the kernels read). A plain name frees both directions tied
together; a suffixed name frees one direction, and the rebuilt model is then a
``Directional`` (of the static maps only, when only static fields differ).
"""

from __future__ import annotations

import dataclasses
import re
from collections.abc import Sequence

import numpy as np

from ..errors import ParameterError
from ..models.static import Directional

_SIDES = ("pos", "neg")
_SUFFIX = re.compile(r"^(?P<base>.+)_(?P<side>pos|neg)$")
_INDEXED = re.compile(r"^(?P<field>[A-Za-z_]+?)(?P<i>\d+)$")

#: Parameters that must be > 0: fitted as logarithms, intervals by a log transform.
POSITIVE = {"sigma0", "k", "C", "vs", "delta", "J"}
#: Parameters that must be >= 0 (fitted as logarithms too, floored far below the start value).
NONNEGATIVE = {"sigma1", "Fc", "Fs", "sigma2", "xi"}


def base_name(name: str) -> str:
    """``"k2_neg"`` -> ``"k"``, ``"sigma0_pos"`` -> ``"sigma0"``, ``"Fc"`` -> ``"Fc"``."""
    m = _SUFFIX.match(name)
    core = m.group("base") if m else name
    mi = _INDEXED.match(core)
    if mi and mi.group("field") in ("k", "xi"):
        return mi.group("field")
    return core


def is_log(name: str) -> bool:
    """True for parameters fitted (and given intervals) on a log scale."""
    b = base_name(name)
    return b in POSITIVE or b in NONNEGATIVE


def _flatten(law, prefix_fields: dict, seq_len: dict) -> dict[str, float]:
    out: dict[str, float] = {}
    if not dataclasses.is_dataclass(law):
        raise ParameterError(f"{type(law).__name__} is not a friction law (a frozen dataclass of parameters)")
    for f in dataclasses.fields(law):
        if not f.init:
            continue
        val = getattr(law, f.name)
        if dataclasses.is_dataclass(val):
            if isinstance(val, Directional):
                raise ParameterError("internal: a Directional static map is split before flattening")
            out.update(_flatten(val, prefix_fields, seq_len))
        elif isinstance(val, (str, bool)) or val is None:
            continue
        elif isinstance(val, (tuple, list, np.ndarray)):
            arr = np.asarray(val, dtype=float).ravel()
            seq_len[f.name] = arr.size
            for i, x in enumerate(arr, start=1):
                out[f"{f.name}{i}"] = float(x)
        else:
            try:
                out[f.name] = float(val)
            except (TypeError, ValueError):
                continue
    return out


def _rebuild(law, values: dict[str, float]):
    """``law`` with its numeric fields replaced from ``values`` (recursively)."""
    kw = {}
    for f in dataclasses.fields(law):
        if not f.init:
            continue
        val = getattr(law, f.name)
        if dataclasses.is_dataclass(val):
            kw[f.name] = _rebuild(val, values)
        elif isinstance(val, (str, bool)) or val is None:
            continue
        elif isinstance(val, (tuple, list, np.ndarray)):
            n = np.asarray(val).size
            kw[f.name] = [values[f"{f.name}{i}"] for i in range(1, n + 1)]
        elif f.name in values:
            kw[f.name] = values[f.name]
    return dataclasses.replace(law, **kw)


def _split(model):
    """``(positive law, negative law, static_directional)`` of a (possibly Directional) law."""
    if isinstance(model, Directional):
        if getattr(model, "is_static", False):
            raise ParameterError("model0 is a static map; give a dynamic law (LuGre, Dahl, GMS) over it")
        return model.positive, model.negative, False
    st = getattr(model, "static", None)
    if isinstance(st, Directional) and any(f.name == "static" for f in dataclasses.fields(model)):
        return (dataclasses.replace(model, static=st.positive), dataclasses.replace(model, static=st.negative), True)
    return model, model, False


@dataclasses.dataclass(frozen=True)
class LawTemplate:
    """Named per-direction values of a dynamic law and how to rebuild it.

    Attributes
    ----------
    laws : (law, law)
        The positive- and negative-direction laws of the start model (same class).
    values : (dict, dict)
        Every adjustable scalar of each direction, by field name (``k1``, ``Fc`` ...).
    static_fields : frozenset
        Names that belong to the static map (may differ per direction inside one law).
    directional : bool
        The start model was direction-dependent.
    """

    laws: tuple
    values: tuple
    static_fields: frozenset
    directional: bool

    @classmethod
    def of(cls, model) -> LawTemplate:
        pos, neg, _ = _split(model)
        if type(pos) is not type(neg):
            raise ParameterError("the two directions of model0 are different kinds of law")
        if not hasattr(pos, "steady_state"):
            raise ParameterError(f"model0 = {type(pos).__name__}: not a friction law")
        vp, vn = _flatten(pos, {}, {}), _flatten(neg, {}, {})
        if set(vp) != set(vn):
            raise ParameterError("the two directions of model0 have different parameters (GMS element counts?)")
        st = getattr(pos, "static", None)
        static_fields = frozenset(_flatten(st, {}, {})) if dataclasses.is_dataclass(st) else frozenset()
        return cls((pos, neg), (vp, vn), static_fields, isinstance(model, Directional) or vp != vn)

    # ------------------------------------------------------------------ names
    @property
    def fields(self) -> list[str]:
        return list(self.values[0])

    def public_names(self) -> list[str]:
        names = list(self.fields)
        if any(_INDEXED.match(n) and _INDEXED.match(n).group("field") == "k" for n in names):
            names += ["k", "xi"]
        return names + [f"{n}_{s}" for n in self.fields for s in _SIDES]

    def expand(self, free: Sequence[str], extra: Sequence[str] = ()) -> list[str]:
        """Canonical free names: ``k`` -> ``k1..kM``; ``sigma0`` stays (both directions tied)."""
        out: list[str] = []
        for name in free:
            if not isinstance(name, str):
                raise ParameterError(f"free = {tuple(free)!r}: names must be strings")
            m = _SUFFIX.match(name)
            core, side = (m.group("base"), "_" + m.group("side")) if m else (name, "")
            if core in ("k", "xi") and f"{core}1" in self.values[0]:
                n = sum(1 for f in self.fields if _INDEXED.match(f) and _INDEXED.match(f).group("field") == core)
                out += [f"{core}{i}{side}" for i in range(1, n + 1)]
            elif core in self.values[0] or (name in extra and not side):
                out.append(name)
            else:
                known = sorted(set(self.public_names()) | set(extra))
                raise ParameterError(f"unknown parameter {name!r} for {type(self.laws[0]).__name__}; known: {known}")
        if len(set(out)) != len(out):
            raise ParameterError(f"free = {tuple(free)!r} names a parameter twice")
        for n in out:
            if _SUFFIX.match(n) is None and (f"{n}_pos" in out or f"{n}_neg" in out):
                raise ParameterError(f"free names both {n!r} and a per-direction {n}_pos/{n}_neg")
        if not out:
            raise ParameterError("free is empty; name at least one parameter")
        for n in out:
            if _SUFFIX.match(n) is None and n in self.values[0] and self.values[0][n] != self.values[1][n]:
                raise ParameterError(f"{n} differs between the directions of model0 "
                                     f"({self.values[0][n]:g} / {self.values[1][n]:g}); free {n}_pos and {n}_neg")
        return out

    def get(self, name: str) -> float:
        m = _SUFFIX.match(name)
        if m:
            return float(self.values[_SIDES.index(m.group("side"))][m.group("base")])
        return float(self.values[0][name])

    # ------------------------------------------------------------------ rebuild
    def build(self, free: Sequence[str], theta) -> object:
        """The law with ``free`` set to ``theta`` (raises ParameterError for invalid values)."""
        vp, vn = dict(self.values[0]), dict(self.values[1])
        for n, x in zip(free, theta):
            m = _SUFFIX.match(n)
            if m:
                (vp if m.group("side") == "pos" else vn)[m.group("base")] = float(x)
            elif n in vp:
                vp[n] = vn[n] = float(x)
        pos, neg = _rebuild(self.laws[0], vp), _rebuild(self.laws[1], vn)
        if vp == vn and not self.directional:
            return pos
        dyn_same = all(vp[n] == vn[n] for n in vp if n not in self.static_fields)
        if dyn_same and self.static_fields:
            static = Directional(positive=pos.static, negative=neg.static)
            return dataclasses.replace(pos, static=static)
        return Directional(positive=pos, negative=neg)

