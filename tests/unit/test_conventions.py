"""The package's conventions, enforced (issue 12 part 5).

1. Every public result object has ``status`` (0 = ok), ``message``, ``summary() -> str`` and
   ``plot(ax=None)``; a JSON-ready form, where there is one, is ``to_dict()``.
2. Every documented parameter (numpydoc ``Parameters`` section) exists in the signature.
3. Unit factors are defined once, in :mod:`frictionkit.units`.
4. Unknown keywords raise, also where a function forwards ``**kwargs``.

The lists of exceptions below are a ratchet: the test fails when a listed object comes into line
(remove it from the list) and when a new object breaks a rule.
"""

from __future__ import annotations

import importlib
import inspect
import pkgutil
import re
from pathlib import Path

import numpy as np
import pytest

import frictionkit as fk

SRC = Path(fk.__file__).parent

#: Result classes that do not (yet) follow rule 1, with the rule each breaks. Shrink only.
RESULT_EXCEPTIONS: dict[str, set[str]] = {}

#: Results whose names do not end in ``Result`` but which are results all the same.
EXTRA_RESULTS = (
    "frictionkit.reproduce.sdss.SdssReproduction",
    "frictionkit.fleet.identify.FleetRun",
    "frictionkit.study.TaskRun",
    "frictionkit.reproduce.zhu_fujimoto.ReproductionResult",
)


def _public_modules():
    for info in pkgutil.walk_packages(fk.__path__, "frictionkit."):
        parts = info.name.split(".")[1:]
        if any(p.startswith("_") for p in parts) or parts[0] in ("kernels", "cli"):
            continue
        yield importlib.import_module(info.name)


def _public_objects():
    seen = set()
    for mod in _public_modules():
        for name in getattr(mod, "__all__", ()):
            obj = getattr(mod, name, None)
            if obj is None or id(obj) in seen:
                continue
            seen.add(id(obj))
            where = getattr(obj, "__module__", None) if (inspect.isclass(obj) or inspect.isfunction(obj)) else None
            yield f"{where or mod.__name__}.{getattr(obj, '__qualname__', name) if where else name}", obj


def _result_classes():
    out = {q: o for q, o in _public_objects() if inspect.isclass(o) and q.endswith("Result")}
    for path in EXTRA_RESULTS:
        mod, _, name = path.rpartition(".")
        out[path] = getattr(importlib.import_module(mod), name)
    return out


def _result_problems(cls) -> set[str]:
    fields = getattr(cls, "__dataclass_fields__", {})
    probs = {f"no {a}" for a in ("status", "message", "summary", "plot") if not (hasattr(cls, a) or a in fields)}
    if hasattr(cls, "summary"):
        ann = inspect.signature(cls.summary).return_annotation
        if ann not in ("str", str):
            probs.add("summary is not str")
    if hasattr(cls, "plot"):
        ax = inspect.signature(cls.plot).parameters.get("ax")
        if ax is None or ax.default is not None:
            probs.add("plot has no ax=None")
    return probs


def test_results_follow_the_result_convention():
    found = {q: p for q, c in _result_classes().items() if (p := _result_problems(c))}
    assert found == RESULT_EXCEPTIONS


def test_result_rules_catch_a_wrong_class():
    """The checker itself can fail: a class with a dict summary and no plot is caught."""
    class Bad:
        status = 0
        message = "ok"

        def summary(self) -> dict:
            return {}

    assert _result_problems(Bad) == {"no plot", "summary is not str"}


def test_summaries_are_text_on_real_results():
    """Built results (not only annotations): summary() is a str that mentions the status."""
    from frictionkit.models import LuGre, Stribeck
    from frictionkit.plants import Mass
    from frictionkit.simulation import simulate_batch

    law = LuGre(Stribeck(Fc=1.0, Fs=1.5, vs=1e-3, sigma2=0.4), sigma0=1e5, sigma1=300.0)
    t = np.arange(200) * 1e-3
    res = fk.simulate(law, plant=Mass(1.0), force=2.0 * np.sin(2 * np.pi * t), dt=1e-3)
    text = res.summary()
    assert isinstance(text, str) and "status 0" in text and "travel" in text
    batch = simulate_batch([law, law], masses=[1.0, 1.0], force=2.0 * np.sin(2 * np.pi * t), dt=1e-3,
                           target=res.x)
    assert isinstance(batch.summary(), str)
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    ax = batch.plot()
    assert len(ax.lines) >= 1
    plt.close(ax.figure)


PARAM_HEADER = re.compile(r"Parameters\n\s*-{3,}\n(.*?)(?:\n\s*\n\s*[A-Z][A-Za-z ]+\n\s*-{3,}|\Z)", re.S)


def _documented_parameters(doc: str) -> list[str]:
    m = PARAM_HEADER.search(doc)
    if not m:
        return []
    lines = [ln for ln in m.group(1).split("\n") if ln.strip()]
    indent = min(len(ln) - len(ln.lstrip()) for ln in lines)
    names = []
    for ln in lines:
        if len(ln) - len(ln.lstrip()) == indent and (mm := re.match(r"\s*([*A-Za-z_][\w, *]*?)\s*:", ln)):
            names += [n.strip().lstrip("*") for n in mm.group(1).split(",")]
    return [n for n in names if n]


def test_documented_parameters_exist():
    wrong, checked = [], 0
    for qual, obj in _public_objects():
        targets = [(qual, obj)]
        if inspect.isclass(obj):
            targets += [(f"{qual}.{k}", v) for k, v in vars(obj).items() if inspect.isfunction(v) and not k.startswith("_")]
        for name, f in targets:
            try:
                sig = inspect.signature(f)
            except (TypeError, ValueError):
                continue
            if any(p.kind is p.VAR_KEYWORD for p in sig.parameters.values()):
                continue
            known = set(sig.parameters) | set(getattr(f, "__dataclass_fields__", {}))
            for p in _documented_parameters(inspect.getdoc(f) or ""):
                checked += 1
                if p not in known:
                    wrong.append(f"{name}: documents {p!r}, signature {sig}")
    assert checked > 300, checked          # the parser still finds the sections
    assert not wrong, "\n".join(wrong)


def test_parameter_parser_reads_numpydoc():
    doc = "Do.\n\nParameters\n----------\nx, y : float\n    Values.\n*args : tuple\n\nReturns\n-------\nz : float\n"
    assert _documented_parameters(doc) == ["x", "y", "args"]


UNIT_NAMES = ("MM", "UM", "NM", "RPM", "DEG", "ARCSEC", "MM_PER_S", "N_PER_MM")


def test_unit_factors_defined_once():
    pat = re.compile(rf"^({'|'.join(UNIT_NAMES)})\s*=", re.M)
    where = [f"{p.relative_to(SRC)}: {m.group(1)}" for p in SRC.rglob("*.py") if p.name != "units.py"
             for m in pat.finditer(p.read_text(encoding="utf-8"))]
    assert where == [], where


@pytest.mark.parametrize("call", [
    lambda: fk.models.Directional(positive=fk.models.Stribeck(Fc=1.0, Fs=1.5, vs=0.01, delta=2.0, sigma2=0.1),
                                  negative=fk.models.Stribeck(Fc=1.0, Fs=1.5, vs=0.01, delta=2.0, sigma2=0.1)
                                  ).steady_state(np.array([0.1]), bogus=1),
    lambda: fk.simulate(fk.models.LuGre(fk.models.Stribeck(Fc=1.0, Fs=1.5, vs=1e-3), sigma0=1e5, sigma1=300.0),
                        plant=fk.plants.Mass(1.0), force=np.zeros(3), dt=1e-3, bogus=1),
], ids=["Directional.steady_state", "simulate"])
def test_unknown_keywords_raise(call):
    with pytest.raises(TypeError, match="bogus"):
        call()


def test_one_name_each_for_the_function_and_its_package():
    """``fk.simulate`` is the function; its package is ``frictionkit.simulation`` (before, ``import
    frictionkit.simulate as m`` gave the function because the package had the function's name)."""
    import types

    import frictionkit.simulation as pkg

    assert isinstance(pkg, types.ModuleType) and callable(fk.simulate) and pkg.simulate is fk.simulate
    assert not (SRC / "simulate").exists()
