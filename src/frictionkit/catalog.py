"""What frictionkit models: the registered friction laws and the machine presets, with their sources.

:func:`catalog` reads both from where they are defined, so a law registered later
(:func:`frictionkit.models.register_law`) or a new preset module in
:mod:`frictionkit.presets` appears without touching this module:

* laws — the registry (name, kernel family, constructor fields with SI units); the
  source is :data:`LAW_SOURCES` for the laws shipped here, else the first line of the
  law module's docstring;
* presets — every module of :mod:`frictionkit.presets`: its title (first docstring
  line), its sources (the bullets of a ``Provenance`` section, else the rest of the
  first paragraph) and its public builders (functions named ``*_machine`` or
  ``simulate_*`` in ``__all__`` or at module level).

Examples
--------
>>> from frictionkit.catalog import catalog
>>> cat = catalog()
>>> "LuGre" in [law.name for law in cat.laws]
True
"""

from __future__ import annotations

import importlib
import inspect
import pkgutil
import re
from dataclasses import dataclass, field
from typing import Any

__all__ = ["Catalog", "CompensatorInfo", "LAW_SOURCES", "LawInfo", "PresetInfo", "catalog"]

#: Source of each law shipped with frictionkit (paper and equation; see the README's law table).
LAW_SOURCES = {
    "Stribeck": "seed 000 (Zhang et al., Actuators 2023) eq. 4; seed 002 (SDSS telescope) eqs. 9a/9b",
    "CoulombViscous": "Coulomb + viscous reference law",
    "Directional": "per-direction parameter sets: seed 000 Tables 3-6, seed 002 §3.1",
    "Dahl": "Dahl 1968 (exponent 1)",
    "LuGre": "Canudas de Wit et al. 1995; seed 002 eqs. 5-8",
    "GMS": "generalized Maxwell-slip: seed 000 eqs. 1-3, 6, 9",
}

#: Width of the family column of :meth:`Catalog.summary` (the kernel families: static, lugre, gms).
_FAMILY_WIDTH = 7


@dataclass(frozen=True)
class LawInfo:
    """One registered law: ``name``, kernel ``family``, constructor ``fields`` ({name: unit}), ``source``."""

    name: str
    family: str
    fields: dict[str, str]
    source: str

    def to_dict(self) -> dict[str, Any]:
        return {"name": self.name, "family": self.family, "fields": dict(self.fields), "source": self.source}


@dataclass(frozen=True)
class PresetInfo:
    """One preset module: ``name`` (``frictionkit.presets.<name>``), ``title``, ``sources``, ``builders``."""

    name: str
    title: str
    sources: tuple[str, ...]
    builders: tuple[str, ...]

    def to_dict(self) -> dict[str, Any]:
        return {"name": self.name, "module": f"frictionkit.presets.{self.name}", "title": self.title,
                "sources": list(self.sources), "builders": list(self.builders)}


@dataclass(frozen=True)
class CompensatorInfo:
    """One reversal compensation law of :mod:`frictionkit.models.rolling`: ``name``, ``parameters``, ``source``."""

    name: str
    parameters: tuple[str, ...]
    source: str

    def to_dict(self) -> dict[str, Any]:
        return {"name": self.name, "parameters": list(self.parameters), "source": self.source}


@dataclass(frozen=True)
class Catalog:
    """The laws and presets frictionkit knows, with their sources (see :func:`catalog`)."""

    laws: tuple[LawInfo, ...]
    presets: tuple[PresetInfo, ...]
    compensators: tuple[CompensatorInfo, ...] = ()
    errors: dict[str, str] = field(default_factory=dict)
    status: int = 0
    message: str = "ok"

    def to_dict(self) -> dict[str, Any]:
        from . import __version__

        return {"frictionkit_version": __version__, "laws": [law.to_dict() for law in self.laws],
                "presets": [p.to_dict() for p in self.presets],
                "compensators": [c.to_dict() for c in self.compensators], "errors": dict(self.errors),
                "status": self.status, "message": self.message}

    def summary(self) -> str:
        """Plain-text listing."""
        lines = ["Friction laws (frictionkit.models registry):"]
        for law in self.laws:
            fields = ", ".join(f"{k} [{u}]" if u else k for k, u in law.fields.items())
            # a family wider than its column ("any (as the laws it holds)") ran into the fields:
            # its first word in the column, the whole text on a line of its own
            fam = law.family if len(law.family) <= _FAMILY_WIDTH else law.family.split()[0]
            lines.append(f"  {law.name:<15} {fam:<{_FAMILY_WIDTH}} {fields}")
            if fam != law.family:
                lines.append(f"  {'':<15} family: {law.family}")
            lines.append(f"  {'':<15} source: {law.source}")
        lines.append("Reversal compensation laws (frictionkit.models.rolling):")
        for c in self.compensators:
            lines += [f"  {c.name:<22} ({', '.join(c.parameters)})", f"  {'':<22} source: {c.source}"]
        lines.append("Machine presets (frictionkit.presets):")
        for p in self.presets:
            lines.append(f"  {p.name:<15} {p.title}")
            if p.builders:
                lines.append(f"  {'':<15} builders: {', '.join(p.builders)}")
            for s in p.sources:
                lines.append(f"  {'':<15} source: {s}")
        for name, err in self.errors.items():
            lines.append(f"  {name:<15} could not be imported: {err}")
        return "\n".join(lines)

    def plot(self, ax=None):
        """A bar chart of the laws per kernel family; returns the matplotlib Axes."""
        import matplotlib.pyplot as plt

        if ax is None:
            _, ax = plt.subplots(figsize=(5, 3))
        fams: dict[str, int] = {}
        for law in self.laws:
            fams[law.family] = fams.get(law.family, 0) + 1
        ax.bar(list(fams), list(fams.values()))
        ax.set_ylabel("laws")
        ax.set_title(f"{len(self.laws)} laws, {len(self.presets)} presets")
        return ax


#: Field names whose unit :func:`frictionkit.identify._advice.unit` knows; others are listed without one.
_KNOWN_UNITS = {"Fc", "Fs", "vs", "delta", "sigma0", "sigma1", "sigma2", "k", "xi", "C",
                "Fc0", "Fs0", "Fc1", "Fs1", "eps"}  # the last five: TDMSSC's (they were listed without a unit)


def _sentence(text: str, limit: int = 200) -> str:
    """The first sentence of ``text``, at most ``limit`` characters."""
    text = " ".join(text.replace("``", "").split())
    # Sphinx roles read as their target: ':class:`~frictionkit.machines.Machine`' -> 'Machine'
    text = re.sub(r":[a-z]+:`(~?)([^`]+)`", lambda g: g.group(2).rsplit(".", 1)[-1] if g.group(1) else g.group(2), text)
    m = re.search(r"(?<=[a-z0-9)\]])\.\s(?=[A-Z])", text[20:])
    if m:
        text = text[: 20 + m.start() + 1]
    return text if len(text) <= limit else text[: limit - 3].rstrip() + "..."


def _first_line(doc: str | None) -> str:
    return " ".join((doc or "").strip().split("\n\n")[0].split()) if doc else ""


def _law_fields(entry) -> dict[str, str]:
    import dataclasses

    from .identify._advice import unit

    ax = {"F": "N", "x": "m", "v": "m/s"}
    out = {}
    if dataclasses.is_dataclass(entry.cls):
        for f in dataclasses.fields(entry.cls):
            if not f.init:
                continue
            out[f.name] = unit(f.name, ax) if f.name in _KNOWN_UNITS else ""
    return out


def _law_source(entry) -> str:
    if entry.name in LAW_SOURCES:
        return LAW_SOURCES[entry.name]
    mod = inspect.getmodule(entry.cls)
    return _first_line(mod.__doc__ if mod else None) or "no source recorded"


def _sources(doc: str) -> tuple[str, ...]:
    """Bullets of a ``Provenance`` section, else the text after the first line of the first paragraph."""
    m = re.search(r"\nProvenance\n-+\n(.*?)(\n\S[^\n]*\n-+\n|\Z)", doc, re.S)
    if m:
        items = re.split(r"\n\* ", "\n" + m.group(1).strip())
        return tuple(_sentence(i) for i in items if i.strip())
    paras = doc.strip().split("\n\n")
    rest = _sentence(paras[1]) if len(paras) > 1 else ""
    return (rest,) if rest else ()


def _builders(mod) -> tuple[str, ...]:
    names = getattr(mod, "__all__", None) or [n for n in vars(mod) if not n.startswith("_")]
    out = []
    for n in names:
        obj = getattr(mod, n, None)
        # a package preset (zhang2023) defines its builders in submodules: tdms_machine was not listed
        home = getattr(obj, "__module__", None) or ""
        if inspect.isfunction(obj) and (home == mod.__name__ or home.startswith(mod.__name__ + ".")) and (
                n.endswith("_machine") or n.startswith("simulate_")):
            out.append(n)
    return tuple(out)


def catalog() -> Catalog:
    """The registered friction laws and the preset modules, with their sources.

    A preset module that fails to import is listed in ``errors`` (status 1) instead of
    hiding the others.

    Returns
    -------
    Catalog
    """
    from . import presets
    from .models import registered_laws

    laws = []
    for name, entry in sorted(registered_laws().items()):
        fam = entry.family if isinstance(entry.family, str) else "any (as the laws it holds)"
        laws.append(LawInfo(name=name, family=fam, fields=_law_fields(entry), source=_law_source(entry)))
    found, errors = [], {}
    for info in sorted(pkgutil.iter_modules(presets.__path__), key=lambda m: m.name):
        if info.name.startswith("_"):
            continue
        try:
            mod = importlib.import_module(f"{presets.__name__}.{info.name}")
        except Exception as exc:  # noqa: BLE001 - one broken preset must not hide the rest
            errors[info.name] = f"{type(exc).__name__}: {' '.join(str(exc).split())}"
            continue
        doc = mod.__doc__ or ""
        found.append(PresetInfo(name=info.name, title=_sentence(doc.strip().split("\n\n")[0]),
                                sources=_sources(doc), builders=_builders(mod)))
    from .models import rolling

    comps = []
    for name, fn in sorted(vars(rolling).items()):
        if inspect.isfunction(fn) and fn.__module__ == rolling.__name__ and name.endswith("_compensation"):
            params = tuple(p for p in inspect.signature(fn).parameters)
            comps.append(CompensatorInfo(name=name, parameters=params, source=_sentence(_first_line(fn.__doc__))))
    status, message = (1, f"{len(errors)} preset module(s) failed to import") if errors else (0, "ok")
    return Catalog(laws=tuple(laws), presets=tuple(found), compensators=tuple(comps), errors=errors, status=status, message=message)
