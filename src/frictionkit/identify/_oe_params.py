"""Parameters of the force-driven output-error fit: names, log scale, units, and the model they rebuild.

Part of :mod:`.output_error` (split from it without a change of behaviour)."""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass

import numpy as np

from ..errors import ParameterError
from ..models.gms import GMS
from ..models.lugre import Dahl, LuGre
from ..models.static import CoulombViscous, Directional, Stribeck

_STATIC_FIELDS = ("Fc", "Fs", "vs", "delta", "sigma2")
_LOG = {"sigma0", "vs", "delta", "C", "m"}  # strictly positive: optimised as log
_NONNEG = {"sigma1", "Fc", "Fs", "sigma2"}
#: The fields a Dahl law has (its map is Coulomb-viscous: no Stribeck hump, no bristle damping).
_DAHL_FIELDS = ("Fc", "sigma2")


# --------------------------------------------------------------------------- parameter handling
def _stribeck_fields(law) -> dict:
    if isinstance(law, Stribeck):
        return {"Fc": law.Fc, "Fs": law.Fs, "vs": law.vs, "delta": law.delta, "sigma2": law.sigma2,
                "shape": law.shape}
    if isinstance(law, CoulombViscous):  # a flat Stribeck curve (same packed rows)
        return {"Fc": law.Fc, "Fs": law.Fc, "vs": 1.0, "delta": 1.0, "sigma2": law.sigma2,
                "shape": "exponential"}
    raise ParameterError(f"static law {type(law).__name__} is not supported")


@dataclass(frozen=True)
class _Template:
    """A model split into named scalar values and the recipe to rebuild it."""

    kind: str  # "lugre", "gms" or "dahl"
    values: dict  # every adjustable scalar, by name
    static_free: bool
    orig_static: object
    M: int

    @classmethod
    def of(cls, model, mass: float, offset: float) -> _Template:
        if isinstance(model, Directional) and isinstance(model.positive, Dahl) and isinstance(model.negative, Dahl):
            if model.positive.sigma0 != model.negative.sigma0:
                raise ParameterError(
                    "fit_output_error: a Directional of Dahl laws must share sigma0 (the bristle stiffness; "
                    f"got {model.positive.sigma0:g} and {model.negative.sigma0:g}); the levels Fc, sigma2 may differ")
            st = Directional(positive=model.positive.static, negative=model.negative.static)
            return cls._dahl(st, model.positive.sigma0, mass, offset)
        if isinstance(model, Directional):
            raise ParameterError(
                "fit_output_error: a Directional of dynamic laws is not supported; put the direction "
                "dependence in the static map, e.g. LuGre(Directional(positive=..., negative=...), ...)"
            )
        if isinstance(model, Dahl):
            return cls._dahl(model.static, model.sigma0, mass, offset)
        if not isinstance(model, (LuGre, GMS)):
            raise ParameterError(f"fit_output_error: model0 = {type(model).__name__}: must be LuGre, GMS or Dahl")
        vals: dict = {"m": float(mass), "offset": float(offset)}
        st = model.static
        pos, neg = (st.positive, st.negative) if isinstance(st, Directional) else (st, st)
        for side, law in (("pos", pos), ("neg", neg)):
            for f, v in _stribeck_fields(law).items():
                vals[f"{f}_{side}"] = v
        if isinstance(model, LuGre):
            vals.update(sigma0=model.sigma0, sigma1=model.sigma1)
            return cls("lugre", vals, False, st, 0)
        for i, (k, xi) in enumerate(zip(model.k, model.xi), start=1):
            vals[f"k{i}"] = float(k)
            vals[f"xi{i}"] = float(xi)
        vals["C"] = model.C
        return cls("gms", vals, False, st, model.M)

    @classmethod
    def _dahl(cls, static, sigma0: float, mass: float, offset: float) -> _Template:
        """A Dahl law (or a Directional of two sharing ``sigma0``): ``Fc``, ``sigma2`` per direction."""
        vals: dict = {"m": float(mass), "offset": float(offset), "sigma0": float(sigma0)}
        pos, neg = (static.positive, static.negative) if isinstance(static, Directional) else (static, static)
        for side, law in (("pos", pos), ("neg", neg)):
            vals[f"Fc_{side}"] = float(law.Fc)
            vals[f"sigma2_{side}"] = float(law.sigma2)
        return cls("dahl", vals, False, static, 0)

    def expand(self, free: Sequence[str]) -> list[str]:
        """Canonical names: ``Fc`` -> both directions tied, ``k`` -> every element."""
        out: list[str] = []
        for name in free:
            if not isinstance(name, str):
                raise ParameterError(f"fit_output_error: free = {free!r}: names must be strings")
            if name == "k" and self.kind == "gms":
                out += [f"k{i}" for i in range(1, self.M + 1)]
            elif name == "xi" and self.kind == "gms":
                out += [f"xi{i}" for i in range(1, self.M + 1)]
            elif self.kind == "dahl" and name in _STATIC_FIELDS and name not in _DAHL_FIELDS:
                raise ParameterError(f"fit_output_error: Dahl has no {name!r} (its map is Coulomb-viscous: "
                                     "free sigma0, Fc, sigma2, m, offset; Fc/sigma2 with _pos/_neg per direction)")
            elif name in _STATIC_FIELDS or name in self.values:
                out.append(name)
            else:
                known = sorted(set(self._public_names()))
                raise ParameterError(f"fit_output_error: unknown parameter {name!r}; known: {known}")
        if len(set(out)) != len(out):
            raise ParameterError(f"fit_output_error: free = {tuple(free)!r} names a parameter twice")
        for f in _STATIC_FIELDS:
            if f in out and (f"{f}_pos" in out or f"{f}_neg" in out):
                raise ParameterError(f"fit_output_error: free has both {f!r} and a per-direction {f}_pos/{f}_neg")
        if not out:
            raise ParameterError("fit_output_error: free is empty; name at least one parameter")
        return out

    def _public_names(self) -> list[str]:
        names = [n for n in self.values if not n.startswith("shape")]
        names += list(_DAHL_FIELDS if self.kind == "dahl" else _STATIC_FIELDS)
        return names + (["k", "xi"] if self.kind == "gms" else [])

    def get(self, name: str) -> float:
        if name in _STATIC_FIELDS:
            return float(self.values[f"{name}_pos"])
        return float(self.values[name])

    def build(self, free: Sequence[str], theta: np.ndarray):
        """``(model, mass, offset)`` with ``free`` set to ``theta``."""
        v = dict(self.values)
        for n, x in zip(free, theta):
            if n in _STATIC_FIELDS:
                v[f"{n}_pos"] = v[f"{n}_neg"] = float(x)
            else:
                v[n] = float(x)
        static_touched = any(n.split("_")[0] in _STATIC_FIELDS for n in free)
        if self.kind == "dahl":
            laws = [Dahl(Fc=v[f"Fc_{s}"], sigma0=v["sigma0"], sigma2=v[f"sigma2_{s}"]) for s in ("pos", "neg")]
            per_dir = any(n.endswith(("_pos", "_neg")) for n in free) or isinstance(self.orig_static, Directional)
            model = Directional(positive=laws[0], negative=laws[1]) if per_dir or laws[0] != laws[1] else laws[0]
            return model, v["m"], v["offset"]
        if static_touched:
            laws = [Stribeck(**{f: v[f"{f}_{s}"] for f in (*_STATIC_FIELDS, "shape")}) for s in ("pos", "neg")]
            per_dir = any(n.endswith(("_pos", "_neg")) for n in free) or isinstance(self.orig_static, Directional)
            static = Directional(positive=laws[0], negative=laws[1]) if per_dir or laws[0] != laws[1] else laws[0]
        else:
            static = self.orig_static
        if self.kind == "lugre":
            model = LuGre(static, sigma0=v["sigma0"], sigma1=v["sigma1"])
        else:
            model = GMS(static, k=[v[f"k{i}"] for i in range(1, self.M + 1)],
                        xi=[v[f"xi{i}"] for i in range(1, self.M + 1)], C=v["C"])
        return model, v["m"], v["offset"]


def _is_log(name: str) -> bool:
    base = name.split("_")[0]
    return base in _LOG or (name[0] == "k" and name[1:].isdigit())


def _unit(name: str, Fu: str, xu: str) -> str:
    base = name.split("_")[0]
    vu = f"{xu}/s"
    if base in ("sigma0",) or (name[0] == "k" and name[1:].isdigit()):
        return f"{Fu}/{xu}"
    if base in ("sigma1", "sigma2"):
        return f"{Fu}·s/{xu}"
    if base in ("Fc", "Fs", "offset"):
        return Fu
    if base == "vs":
        return vu
    if base == "C":
        return f"{Fu}/s"
    if base == "m":
        return "kg" if xu == "m" else f"{Fu}·s²/{xu}"
    from ._advice import DIMENSIONLESS

    return DIMENSIONLESS
