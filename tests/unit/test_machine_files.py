"""Machines as model files (issue 12 part 2): ``fk.save_model(machine, ...)`` / ``fk.load_model``.

A loaded machine must *simulate* bit-identically to the one it was saved from (every preset
and the README example), carry its controller settings, and a broken, foreign or newer file
must fail in one ``DataError`` line naming the file.
"""

from __future__ import annotations

import hashlib
import json
import math
import re
from pathlib import Path

import numpy as np
import pytest

import frictionkit as fk
from frictionkit.errors import DataError, ParameterError
from frictionkit.machines import PID, Machine, Saturation, StateSpace, Sum
from frictionkit.models.files import MACHINE_UNITS, MODEL_FORMAT, ModelFile

README = Path(__file__).resolve().parents[2] / "README.md"


# --------------------------------------------------------------------------- the machines and their inputs
def _ballscrew(nut):
    from frictionkit.presets.ballscrew import ballscrew_machine
    from frictionkit.reproduce.zhu_fujimoto import paper_controller, paper_plant, paper_sensors

    dt, n = 0.5e-3, 120
    t = np.arange(n) * dt
    th = 2e-3 * np.sin(2 * np.pi * 4 * t) / 1.59e-3
    m = ballscrew_machine(paper_plant(nut), paper_controller(), paper_sensors())
    return m, dt, {"theta_d": th, "u_f": 0.01 * np.sign(np.cos(2 * np.pi * 4 * t)), "u_ff": np.zeros(n)}


def _ballscrew_variant(kind):
    """The rigid stage (eq. 1) and the elastic one with a GMS-4 at the nut and a LuGre at the guide."""
    from frictionkit.plants.ballscrew import RigidBallScrew
    from frictionkit.presets.ballscrew import ballscrew_machine
    from frictionkit.reproduce.zhu_fujimoto import paper_controller, paper_plant, paper_sensors

    if kind == "rigid":
        m = ballscrew_machine(RigidBallScrew(), paper_controller(), paper_sensors())
    else:
        gms = fk.GMS(fk.Stribeck(Fc=1270.0, Fs=1400.0, vs=1e-3), k=[5e7, 1e8, 2e8, 4e8], xi=[0.4, 0.3, 0.2, 0.1],
                     C=20.0)
        guide = fk.LuGre(fk.Stribeck(Fc=30.0, Fs=40.0, vs=2e-3, sigma2=50.0), sigma0=1e7, sigma1=2e3)
        m = ballscrew_machine(paper_plant(), paper_controller(), paper_sensors(), nut_law=gms, guide_law=guide)
    _, dt, ins = _ballscrew("sliding")
    return m, dt, ins


def _emps():
    from frictionkit.presets.emps import PUBLISHED, emps_machine

    t = np.arange(400) * 1e-3
    m = emps_machine(M=PUBLISHED["M"], friction=fk.CoulombViscous(Fc=PUBLISHED["Fc"], sigma2=PUBLISHED["Fv"]),
                     offset=PUBLISHED["offset"], encoder_resolution=5e-8)
    return m, 1e-3, {"qg": 0.1 * np.sin(2 * np.pi * 0.2 * t)}


def _sdss(name):
    from frictionkit.presets import sdss

    t = np.arange(300) * 1e-3
    return sdss.axis(name).machine(loop="position"), 1e-3, {"r": 1e-4 * t}


def _tdms():
    from frictionkit.presets.zhang2023.plant import tdms_machine

    n, dt = 200, 250e-6
    t = np.arange(n) * dt
    z = np.zeros(n)
    ins = {"th1_ref": 20.0 * t, "th2_ref": -10.0 * t, "ff1": z, "w1": 1e-3 * np.cos(t * 3e3), "ff2": z, "w2": z}
    return tdms_machine(), dt, ins


def _readme():
    """The README's machine example (the first Python block that builds an ``fk.Machine``)."""
    blocks = re.findall(r"```python\n(.*?)```", README.read_text(encoding="utf-8"), re.S)
    src = next(b for b in blocks if "fk.Machine(" in b)
    src = src.split("dt = 0.5e-3")[0]  # the machine, not its 2 s run
    ns: dict = {}
    exec(compile(src, "README.md", "exec"), ns)  # noqa: S102 - the README's own example
    t = np.arange(400) * 0.5e-3
    return ns["m"], 0.5e-3, {"r": 1e-3 * np.sin(np.pi * t)}


CASES = {"ballscrew_sliding": lambda: _ballscrew("sliding"), "ballscrew_flank": lambda: _ballscrew("flank"),
         "ballscrew_hertz": lambda: _ballscrew("hertz"), "emps": _emps, "sdss_azimuth": lambda: _sdss("azimuth"),
         "sdss_altitude": lambda: _sdss("altitude"), "sdss_rotator": lambda: _sdss("rotator"), "tdms": _tdms,
         "readme": _readme, "ballscrew_rigid": lambda: _ballscrew_variant("rigid"),
         "ballscrew_gms_lugre": lambda: _ballscrew_variant("gms")}


@pytest.mark.parametrize("name", list(CASES))
def test_loaded_machine_simulates_bit_identically(tmp_path, name):
    m, dt, inputs = CASES[name]()
    p = fk.save_model(m, tmp_path / f"{name}.json", method="test")
    m2 = fk.load_model(p)
    assert isinstance(m2, Machine) and m2 is not m and repr(m2) == repr(m)
    assert m2.to_dict() == m.to_dict()
    a = fk.simulate_machine(m, dt=dt, inputs=inputs, seed=3)
    b = fk.simulate_machine(m2, dt=dt, inputs=inputs, seed=3)
    # the README machine is flagged by the sub-step check on this short run (status 2): the
    # check itself must come out the same for the loaded machine
    assert a.status == 0 or (name == "readme" and a.status == 2), a.message
    assert (b.status, b.message, b.substeps) == (a.status, a.message, a.substeps)
    assert b.signal_names == a.signal_names and b.site_names == a.site_names
    for f in ("q", "v", "site_forces", "signals", "u"):
        np.testing.assert_array_equal(getattr(b, f), getattr(a, f), err_msg=f)
    assert float(np.max(np.abs(a.v))) > 0.0  # something moved
    # the file lists the inputs a run needs, and they are exactly the ones given here
    doc = json.loads(p.read_text(encoding="utf-8"))
    assert sorted(doc["inputs"]) == sorted(inputs)
    # saving the loaded machine writes the same document
    q = fk.save_model(m2, tmp_path / "again.json", provenance=dict(ModelFile.load(p, kind="machine").provenance))
    assert json.loads(q.read_text(encoding="utf-8")) == doc


# --------------------------------------------------------------------------- what the file holds
def _hand_machine() -> Machine:
    """A two-mass drive written by hand: every kind of part, values typed here."""
    m = Machine("hand")
    th = m.dof("motor", inertia=2e-4, kind="rotational", x0=0.1)
    x = m.dof("table", inertia=20.0, v0=-1e-3)
    far = m.motion("far_end")
    m.inertia(0.002 * th, 1.5)
    m.spring(0.002 * th, x, k=1e8, c=2e3, name="screw")
    m.spring(x, far, k=50.0, name="pull")
    m.compliance("hd", th, law=fk.machines.PiecewiseLinearSpring(stiffness=(1e4, 3e4), breaks=(1e-3,)), c=0.5)
    m.load("imbalance", th, law=fk.machines.SineLoad(amplitude=0.2, phase=0.3))
    m.friction("guide", x, law=fk.LuGre(fk.Stribeck(Fc=8.0, Fs=10.0, vs=2e-3), sigma0=1e7, sigma1=2e3),
               load=fk.machines.NormalLoad(on="screw", reference=100.0, preload=100.0, gain=0.5))
    m.actuator("drive", th, gain=0.5, command="i")
    m.sensor("scale", x, resolution=100e-9, noise=1e-8, delay=1)
    m.sensor("tach", th, quantity="velocity")
    m.add(Sum("e", {"r": 1.0, "scale": -1.0}, bias=1e-6),
          PID("i_pid", "e", Kp=2e4, Ki=2e5, Kd=60.0, tau_d=2e-4, antiwindup="drive"),
          StateSpace(outputs=("y_f",), inputs=("tach",), A=[[0.9]], B=[[0.1]], C=[[1.0]], D=[[0.0]], x0=[0.5]),
          fk.machines.FrictionFeedforward("ff", "v_ref", law=fk.CoulombViscous(Fc=8.0, sigma2=1.0), scale=2.0),
          Sum("i_c", {"i_pid": 1.0, "ff": 1.0, "y_f": -0.1}),
          Saturation("i", "i_c", -10.0, math.inf))
    return m


def test_controller_settings_units_and_provenance_are_in_the_file(tmp_path):
    data = tmp_path / "log.csv"
    data.write_bytes(b"t,x\n0,0\n")
    p = fk.save_model(_hand_machine(), tmp_path / "hand.json", method="typed by hand", data=data)
    doc = json.loads(p.read_text(encoding="utf-8"))
    assert (doc["format"], doc["kind"]) == (MODEL_FORMAT, "machine")
    blocks = doc["model"]["blocks"]
    assert blocks[1] == {"type": "PID", "out": "i_pid", "error": "e", "Kp": 2e4, "Ki": 2e5, "Kd": 60.0, "tau_d": 2e-4,
                         "derivative_error": None, "antiwindup": "drive"}
    assert blocks[2]["A"] == [[0.9]] and blocks[2]["x0"] == [0.5]
    assert blocks[3]["law"] == {"law": "CoulombViscous", "Fc": 8.0, "sigma2": 1.0} and blocks[3]["scale"] == 2.0
    assert blocks[5] == {"type": "Saturation", "out": "i", "inp": "i_c", "lo": -10.0, "hi": None}  # +inf: null
    acts = doc["model"]["actuators"]
    assert acts == [{"name": "drive", "at": {"motor": 1.0}, "gain": 0.5, "limit": None, "delay": 0, "command": "i"}]
    assert doc["model"]["springs"][0]["at"] == {"motor": 0.002, "table": -1.0}
    assert doc["model"]["springs"][2] == {"name": "hd.damper", "at": {"motor": 1.0}, "k": 0.0, "c": 0.5}
    assert doc["model"]["sites"][2]["load"]["reference"] == 100.0
    # references and feed-forward arrays are not in the file; their names are
    assert doc["inputs"] == ["far_end", "r", "v_ref"]
    assert doc["units"] == MACHINE_UNITS and doc["units"]["dofs.inertia"].startswith("kg")
    prov = doc["provenance"]
    assert prov["method"] == "typed by hand" and prov["frictionkit_version"] == fk.__version__
    assert prov["data_sha256"] == hashlib.sha256(b"t,x\n0,0\n").hexdigest()
    m2 = fk.load_model(p)
    assert m2.blocks[5].hi == math.inf and m2.actuators[0].limit == math.inf
    assert m2.to_dict() == _hand_machine().to_dict()
    mf = ModelFile.load(p, kind="machine")
    assert mf.kind == "machine" and "inputs: far_end, r, v_ref" in mf.summary()
    import matplotlib.pyplot as plt

    ax = mf.plot()
    assert len(ax.lines) >= 1
    plt.close(ax.figure)


def test_kinds_are_checked_in_one_line(tmp_path):
    mp = fk.save_model(_hand_machine(), tmp_path / "m.json")
    lp = fk.save_model(fk.Dahl(Fc=1.0, sigma0=1e5), tmp_path / "law.json")
    with pytest.raises(DataError, match=rf"^model file '{re.escape(str(mp))}': holds a machine .*friction law is expected"):
        ModelFile.load(mp)  # the law readers (export, compensate --model) refuse a machine
    with pytest.raises(DataError, match=r"holds a friction law \(kind 'law'\); a machine is expected here$"):
        ModelFile.load(lp, kind="machine")
    assert isinstance(fk.load_model(lp), fk.Dahl)
    doc = json.loads(mp.read_text(encoding="utf-8"))
    for change, msg in ((("kind", "robot"), r"\"kind\" is 'robot': this frictionkit .* reads \['law', 'machine'\]"),
                        (("format", "frictionkit.model/2"), r"written by a newer frictionkit"),
                        (("format", "frictionkit.sequence/1"), r"not a friction model")):
        bad = dict(doc, **{change[0]: change[1]})
        (tmp_path / "bad.json").write_text(json.dumps(bad))
        with pytest.raises(DataError, match=msg) as exc:
            fk.load_model(tmp_path / "bad.json")
        assert "\n" not in str(exc.value) and str(exc.value).startswith(f"model file '{tmp_path / 'bad.json'}': ")
    with pytest.raises(ParameterError, match="units"):
        fk.save_model(_hand_machine(), tmp_path / "u.json", units={"F": "N·m", "v": "rad/s"})


@pytest.mark.parametrize("edit, msg", [
    (lambda d: d["model"]["springs"][0]["at"].update(wheel=1.0), r"machine.springs\[0\].at: 'wheel' is no degree"),
    (lambda d: d["model"]["blocks"][1].update(Kp=-1.0), r"machine.blocks\[1\]: PID.Kp = -1.0"),
    (lambda d: d["model"]["blocks"][1].update(Kq=1.0), r"machine.blocks\[1\] \(PID\): unknown field\(s\) \['Kq'\]"),
    (lambda d: d["model"]["blocks"][0].update(type="Integrator"), r"type 'Integrator' unknown"),
    (lambda d: d["model"]["dofs"][0].pop("inertia"), r"machine.dofs\[0\]: missing key\(s\) \['inertia'\]"),
    (lambda d: d["model"]["sites"][2]["law"].update(law="Coulomb2"), r"law 'Coulomb2' is not registered"),
    (lambda d: d["model"]["sites"][2].update(role="brake"), r"role = 'brake'"),
    (lambda d: d["model"].update(dofs={}), r"machine.dofs: a JSON dict, expected a list"),
])
def test_broken_parts_are_named(tmp_path, edit, msg):
    doc = ModelFile(model=_hand_machine()).to_dict()
    edit(doc)
    p = tmp_path / "edited.json"
    p.write_text(json.dumps(doc))
    with pytest.raises(DataError, match=msg) as exc:
        fk.load_model(p)
    assert "\n" not in str(exc.value) and str(exc.value).startswith(f"model file '{p}': ")


# --------------------------------------------------------------------------- any edit: a machine or one line
from hypothesis import HealthCheck, given, settings  # noqa: E402
from hypothesis import strategies as st  # noqa: E402

_JSON = st.recursive(st.none() | st.booleans() | st.integers(-3, 3) | st.floats(allow_nan=True) | st.text(max_size=5),
                     lambda kids: st.lists(kids, max_size=3) | st.dictionaries(st.text(max_size=4), kids, max_size=3),
                     max_leaves=6)
_DOC = ModelFile(model=_hand_machine(), provenance={"method": "m"}).to_dict()


def _paths(node, prefix=()):
    yield prefix
    items = node.items() if isinstance(node, dict) else enumerate(node) if isinstance(node, list) else ()
    for k, v in items:
        yield from _paths(v, (*prefix, k))


_PATHS = list(_paths(_DOC))[1:]


@settings(max_examples=250, deadline=None, derandomize=True, suppress_health_check=[HealthCheck.function_scoped_fixture])
@given(data=st.data())
def test_any_edit_loads_or_fails_in_one_line(tmp_path, data):
    doc = json.loads(json.dumps(_DOC))
    path = data.draw(st.sampled_from(_PATHS))
    node = doc
    for key in path[:-1]:
        node = node[key]
    if data.draw(st.booleans()):
        node[path[-1]] = data.draw(_JSON)
    else:
        del node[path[-1]]
    p = tmp_path / "edited.json"
    p.write_text(json.dumps(doc))
    try:
        m = fk.load_model(p)
    except DataError as exc:
        assert "\n" not in str(exc) and str(exc).startswith(f"model file '{p}': ")
    else:
        assert isinstance(m, Machine)


def test_a_hand_written_minimal_file_loads_and_runs(tmp_path):
    """Only the required keys (defaults as in Python: translational, at rest, gain 1, no limit)."""
    doc = {"format": "frictionkit.model/1", "kind": "machine",
           "model": {"name": "slider", "dofs": [{"name": "x", "inertia": 2.0}],
                     "sites": [{"name": "c", "role": "friction", "at": {"x": 1.0},
                                "law": {"law": "CoulombViscous", "Fc": 1.0}}],
                     "actuators": [{"name": "u", "at": {"x": 1.0}}]}}
    p = tmp_path / "slider.json"
    p.write_text(json.dumps(doc))
    m = fk.load_model(p)
    assert m.input_names() == ["u"] and ModelFile.load(p, kind="machine").provenance == {}
    res = fk.simulate_machine(m, dt=1e-3, inputs={"u": np.full(1001, 5.0)})
    # Newton by hand: (5 N - 1 N) / 2 kg = 2 m/s² for 1 s -> v = 2 m/s, x = 1 m
    assert res.v[-1, 0] == pytest.approx(2.0, rel=1e-9) and res.q[-1, 0] == pytest.approx(1.0, rel=1e-3)


def test_attached_inertia_and_the_earlier_masses_key():
    """``Machine.inertia(at, j)`` round-trips as ``"inertias"``; a file written before the
    rename (``"masses"`` / ``"mass"``) loads to the same mass matrix."""
    m = fk.Machine("table on a screw")
    th = m.dof("screw", inertia=1e-4, kind="rotational")
    m.inertia(0.002 * th, 1.5)                      # 1.5 kg at R = 2 mm/rad: 1.5 * 0.002**2 kg·m²
    assert m.mass_matrix()[0, 0] == pytest.approx(1e-4 + 1.5 * 0.002 ** 2, rel=1e-12)
    d = m.to_dict()
    assert [e["inertia"] for e in d["inertias"]] == [1.5]
    old = dict(d)
    old["masses"] = [{"at": e["at"], "mass": e["inertia"]} for e in old.pop("inertias")]
    assert np.array_equal(fk.Machine.from_dict(old).mass_matrix(), m.mass_matrix())
