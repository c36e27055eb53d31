"""The package's conventions, enforced (issue 12 part 5).

1. Every public result object has ``status`` (0 = ok), ``message``, ``summary() -> str`` and
   ``plot(ax=None)``; a JSON-ready form, where there is one, is ``to_dict()``.
2. Every documented parameter (numpydoc ``Parameters`` section) exists in the signature.
3. Unit factors are defined once, in :mod:`frictionkit.units`.
4. Unknown keywords raise, also where a function forwards ``**kwargs``.
5. ``F`` is the force on the axis (recorded/applied); a simulated friction force is ``friction``,
   a machine's site forces ``site_forces`` (old spellings warn for one release).
6. The viscous coefficient is ``sigma2`` (``Fv`` only as the EMPS paper's symbol, in listed
   modules); a public ``M`` is a mass (listed), a GMS element count is ``elements``.

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


# --------------------------------------------------------------------------- 5. forces: F vs friction
#: Public classes with a field ``F``: each is a force/torque ACTING ON THE AXIS, recorded or
#: applied (README "Forces"). A simulated friction force is ``friction``; machine site forces are
#: ``site_forces``. Adding a class here needs that argument.
F_IS_THE_FORCE_ON_THE_AXIS = {
    "frictionkit.data.recording.Recording",                      # recorded/applied force or torque
    "frictionkit.data.segmentation.SteadyStatePoints",           # mean measured force per plateau
    "frictionkit.identify.two_step.ConstantVelocityScreen",      # mean measured torque per run
}


def _classes_with_field(name: str) -> set[str]:
    out = set()
    for q, o in _public_objects():
        if inspect.isclass(o) and name in getattr(o, "__dataclass_fields__", {}):
            out.add(f"{o.__module__}.{o.__qualname__}")
    return out


def test_F_is_the_force_on_the_axis_only():
    assert _classes_with_field("F") == F_IS_THE_FORCE_ON_THE_AXIS
    results = {f"{c.__module__}.{c.__qualname__}" for c in _result_classes().values()}
    assert not (results & _classes_with_field("F")), "a result names a simulated force F: use friction"
    assert {"frictionkit.simulation.core.SimulationResult", "frictionkit.control.loop.ClosedLoopResult"} \
        <= _classes_with_field("friction")
    assert {"frictionkit.machines.simulate.MachineResult", "frictionkit.machines.reference.ReferenceResult"} \
        <= _classes_with_field("site_forces")


def test_old_F_names_warn_and_still_read():
    """One release of grace: ``res.F``, ``machine_res.F`` and ``twin["F"]`` give the new values
    with a FrictionKitDeprecationWarning naming the new spelling."""
    from frictionkit.errors import FrictionKitDeprecationWarning
    from frictionkit.simulation.reference import reference_motion_driven

    law = fk.Dahl(Fc=1.0, sigma0=1e5)
    x = 1e-5 * np.sin(np.linspace(0.0, 6.0, 61))
    res = fk.simulate(law, position=x, dt=1e-3)
    with pytest.warns(FrictionKitDeprecationWarning, match=r"SimulationResult\.F is deprecated: use "
                      r"SimulationResult\.friction"):
        assert res.F is res.friction
    twin = reference_motion_driven(law, x, 1e-3)
    with pytest.warns(FrictionKitDeprecationWarning, match='use "friction"'):
        assert twin["F"] is twin["friction"]
    m = fk.machines.Machine("slider")
    q = m.dof("q", inertia=1.0)
    m.friction("contact", q, law=fk.CoulombViscous(Fc=1.0))
    m.actuator("motor", q)
    mres = fk.machines.simulate_machine(m, dt=1e-3, duration=0.01, inputs={"motor": np.full(11, 2.0)})
    with pytest.warns(FrictionKitDeprecationWarning, match=r"MachineResult\.F is deprecated: use "
                      r"MachineResult\.site_forces"):
        assert mres.F is mres.site_forces
    assert mres.force("contact") is not None


def test_old_trace_columns_still_load_in_the_report(tmp_path):
    """A traces CSV written before the rename (column ``F [N]``) reads as today's ``friction [N]``."""
    from frictionkit.report.adapters import sections_from_file

    t = np.arange(50) * 1e-3
    for col in ("F [N]", "friction [N]"):
        p = tmp_path / f"{col[0]}.csv"
        p.write_text(f"t [s],x [m],v [m/s],{col}\n" + "\n".join(f"{a},{a * 1e-3},1e-3,{np.sin(a)}" for a in t))
        kind, secs = sections_from_file(p)
        assert kind == "traces" and secs[0].figures, col


# --------------------------------------------------------------------------- 6. sigma2 vs Fv, M
#: The viscous coefficient is ``sigma2`` [N·s/m] on every law and in every model file. ``Fv``
#: survives only as the EMPS paper's symbol (PUBLISHED values and the rigid-body IDIM fit's
#: regression-parameter names ``M, Fv, Fc, offset``, whose ``.model`` is a
#: ``CoulombViscous(sigma2=Fv)``), in these modules. Shrink only.
FV_MODULES = {
    "identify/rigid_body.py", "identify/rigid_body_stribeck.py", "identify/emps_dynamic.py",
    "presets/emps.py", "cli/identify.py", "report/demo.py", "compensate.py",
}

#: Public parameters / fields named ``M``: a mass [kg], the symbol of the paper the object comes
#: from (EMPS, the rigid-body model). A GMS element count is ``elements``; a mass matrix is never
#: public. Shrink only.
M_IS_A_MASS = {
    "frictionkit.plants.rigid_body.RigidBody",
    "frictionkit.presets.emps.emps_machine",
    "frictionkit.identify.emps_dynamic.emps_closed_loop",
    "frictionkit.identify.emps_dynamic.emps_closed_loop_errors",
}


def _public_callables():
    for qual, obj in _public_objects():
        targets = [(qual, obj)]
        if inspect.isclass(obj):
            targets += [(f"{qual}.{k}", v) for k, v in vars(obj).items()
                        if inspect.isfunction(v) and not k.startswith("_")]
        yield from targets


def _names_of(obj) -> set[str]:
    out = set(getattr(obj, "__dataclass_fields__", {}))
    try:
        out |= set(inspect.signature(obj).parameters)
    except (TypeError, ValueError):
        pass
    return out


def test_viscous_coefficient_is_sigma2():
    public = sorted(q for q, o in _public_callables() if "Fv" in _names_of(o))
    assert public == [], f"a public signature or field spells the viscous coefficient Fv: {public}"
    where = {str(p.relative_to(SRC)) for p in SRC.rglob("*.py")
             if re.search(r"\bFv\b", p.read_text(encoding="utf-8"))}
    assert where <= FV_MODULES, sorted(where - FV_MODULES)
    # every law with a viscous term names it sigma2
    law = fk.CoulombViscous(Fc=1.0, sigma2=0.5)
    assert law.sigma2 == 0.5


def test_M_is_a_mass_where_public_and_elements_count_gms_elements():
    with_M = {q for q, o in _public_callables() if "M" in _names_of(o)}
    assert with_M == M_IS_A_MASS
    counts = {q for q, o in _public_callables()
              if {"n_elements", "n_elem", "num_elements"} & _names_of(o)}
    assert counts == set(), "a GMS element count is `elements`"


# --------------------------------------------------------------------------- 7. typed public signatures
#: Exported callables (``frictionkit.__all__`` and every sub-package's ``__all__``) whose
#: signature is not fully annotated, with why. Shrink only.
UNTYPED = {
    "frictionkit.models.FrictionLaw": "abstract base: a law's signature is its subclass's dataclass fields",
}


def _exported_callables():
    mods = [fk]
    for info in pkgutil.iter_modules(fk.__path__, "frictionkit."):
        leaf = info.name.rsplit(".", 1)[1]
        if info.ispkg and not leaf.startswith("_") and leaf not in ("kernels", "cli"):
            mods.append(importlib.import_module(info.name))
    seen = set()
    for m in mods:
        for n in getattr(m, "__all__", ()):
            o = getattr(m, n, None)
            if o is None or id(o) in seen or not callable(o):
                continue
            seen.add(id(o))
            yield f"{m.__name__}.{n}", o
            if inspect.isclass(o):
                for k, v in vars(o).items():
                    if inspect.isfunction(v) and not k.startswith("_"):
                        yield f"{m.__name__}.{n}.{k}", v


def _unannotated(obj) -> list[str]:
    try:
        sig = inspect.signature(obj)
    except (TypeError, ValueError):
        return []
    bad = [p.name for p in sig.parameters.values() if p.name not in ("self", "cls") and p.annotation is p.empty]
    if not inspect.isclass(obj) and sig.return_annotation is sig.empty:
        bad.append("return")
    return bad


def test_exported_signatures_are_typed():
    items = list(_exported_callables())
    assert len(items) > 200, len(items)  # the walk still finds the API (239 on 2026-11-23)
    found = {q: ", ".join(b) for q, o in items if (b := _unannotated(o))}
    assert set(found) == set(UNTYPED), {q: found.get(q, "typed now: remove from UNTYPED") for q in
                                        set(found) ^ set(UNTYPED)}


def test_typed_check_catches_a_missing_annotation():
    def f(x: int, y) -> int:
        return x

    def g(x: int):
        return x

    assert _unannotated(f) == ["y"] and _unannotated(g) == ["return"]
