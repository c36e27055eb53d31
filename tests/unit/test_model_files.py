"""Model files (``frictionkit.model/1``): round trips, units, provenance, older and foreign files."""

from __future__ import annotations

import hashlib
import json
from datetime import datetime, timezone

import numpy as np
import pytest

import frictionkit as fk
from frictionkit.errors import DataError, ParameterError
from frictionkit.models.files import MODEL_FORMAT, ModelFile, parameter_units

ST = fk.Stribeck(Fc=1.0, Fs=1.5, vs=1e-3, sigma2=0.4)
ST_NEG = fk.Stribeck(Fc=1.2, Fs=1.6, vs=2e-3, delta=1.3, sigma2=0.5, shape="lorentzian")

LAWS = {
    "stribeck": ST,
    "lorentzian": fk.Stribeck(Fc=2.0, Fs=1.0, vs=0.01, shape="lorentzian"),
    "coulomb_viscous": fk.CoulombViscous(Fc=2.0, sigma2=10.0),
    "directional_static": fk.Directional(positive=ST, negative=ST_NEG),
    "dahl": fk.Dahl(Fc=1.0, sigma0=1e5, sigma2=0.2),
    "lugre": fk.LuGre(ST, sigma0=1e5, sigma1=63.2),
    "lugre_directional_map": fk.LuGre(fk.Directional(positive=ST, negative=ST_NEG), sigma0=2e5, sigma1=10.0),
    "gms": fk.GMS(ST, k=[1e4, 1e5, 1e6], xi=[0.5, 0.3, 0.2], C=20.0),
    "directional_gms": fk.Directional(positive=fk.GMS(ST, k=[1e4, 1e5], xi=[0.6, 0.4], C=20.0),
                                      negative=fk.GMS(ST_NEG, k=[2e4, 2e5], xi=[0.5, 0.5], C=30.0)),
}


def _one_line_error(exc_info) -> str:
    msg = str(exc_info.value)
    assert "\n" not in msg
    return msg


@pytest.mark.parametrize("name", sorted(LAWS))
def test_every_law_round_trips_with_provenance(tmp_path, name):
    law = LAWS[name]
    data = tmp_path / "log.csv"
    data.write_text("t,F\n0,1\n0.001,2\n")
    path = fk.save_model(law, tmp_path / f"{name}.json", method="hand-made test law", data=data)
    doc = json.loads(path.read_text(encoding="utf-8"))
    assert doc["format"] == "frictionkit.model/1"
    prov = doc["provenance"]
    assert prov["frictionkit_version"] == fk.__version__
    assert prov["method"] == "hand-made test law"
    assert prov["data_file"] == str(data)
    assert prov["data_sha256"] == hashlib.sha256(b"t,F\n0,1\n0.001,2\n").hexdigest()
    created = datetime.fromisoformat(prov["created"])
    assert abs((datetime.now(timezone.utc) - created).total_seconds()) < 600
    back = fk.load_model(path)
    assert back == law
    v = np.linspace(-0.02, 0.02, 41)
    np.testing.assert_array_equal(back.steady_state(v), law.steady_state(v))


def test_units_of_every_parameter_rotary():
    law = LAWS["gms"]
    u = parameter_units(law, {"F": "N·m", "v": "rad/s"})
    assert u == {"static.Fc": "N·m", "static.Fs": "N·m", "static.vs": "rad/s", "static.delta": "-",
                 "static.sigma2": "N·m·s/rad", "k": "N·m/rad", "xi": "-", "C": "N·m/s"}


def test_units_round_trip_and_label_only(tmp_path):
    law = LAWS["lugre"]
    p = fk.save_model(law, tmp_path / "rot.json", units={"F": "N·m", "v": "rad/s"})
    mf = ModelFile.load(p)
    assert dict(mf.units) == {"F": "N·m", "x": "rad", "v": "rad/s"}
    assert mf.model == law  # labels do not convert the numbers
    doc = json.loads(p.read_text(encoding="utf-8"))
    assert doc["units"]["parameters"]["sigma0"] == "N·m/rad"
    assert doc["units"]["parameters"]["sigma1"] == "N·m·s/rad"


def test_identification_result_loads_with_its_provenance(tmp_path):
    from frictionkit.identify.result import IdentificationResult

    law = LAWS["lugre"]
    res = IdentificationResult(kind="output_error", model_name="lugre", model=law, names=("sigma0", "sigma1"),
                               values=np.array([1e5, 63.2]), stderr=np.array([1e3, 1.0]),
                               ci95=np.array([[9.8e4, 1.02e5], [61.2, 65.2]]), units=("N/m", "N·s/m"),
                               correlation=np.eye(2), rms=0.01, relative_error_percent=1.0, n_obs=100, dof=98,
                               provenance={"file": "log.csv", "sha256": "ab" * 32,
                                           "units": {"F": "N", "v": "m/s", "x": "m"}})
    p = res.save_json(tmp_path / "fit.json")
    mf = ModelFile.load(p)
    assert mf.model == law
    assert mf.format == "frictionkit.identification/1"
    assert mf.provenance["data_sha256"] == "ab" * 32
    assert mf.provenance["file"] == "log.csv"
    assert "output_error" in mf.provenance["method"]
    assert mf.provenance["frictionkit_version"] == fk.__version__  # save_json records who wrote the file, and when
    created = datetime.fromisoformat(mf.provenance["created"])
    assert abs((datetime.now(timezone.utc) - created).total_seconds()) < 600


def test_data_hashes_of_a_fit_over_several_records(tmp_path):
    from frictionkit.identify.result import IdentificationResult

    res = IdentificationResult(kind="output_error", model_name="lugre", model=LAWS["lugre"], names=("sigma0",),
                               values=np.array([1e5]), stderr=np.array([1e3]), ci95=np.array([[9.8e4, 1.02e5]]),
                               units=("N/m",), correlation=np.eye(1), rms=0.01, relative_error_percent=1.0,
                               n_obs=100, dof=99,
                               provenance={"records": [{"name": "a", "sha256": "22" * 32},
                                                       {"name": "b", "sha256": "11" * 32},
                                                       {"name": "c", "sha256": "22" * 32}]})
    mf = ModelFile.load(res.save_json(tmp_path / "fit.json"))
    assert mf.provenance["data_sha256"] == ["11" * 32, "22" * 32]


def test_rigid_body_result_gives_its_friction(tmp_path):
    from frictionkit.identify.result import IdentificationResult

    friction = fk.CoulombViscous(Fc=20.3935, sigma2=203.5034)
    res = IdentificationResult(kind="rigid_body", model_name="rigid_body_symmetric",
                               model=fk.RigidBody(M=95.1089, friction=friction, offset=-3.1648),
                               names=("M",), values=np.array([95.1089]), stderr=np.array([0.1]),
                               ci95=np.array([[94.9, 95.3]]), units=("kg",), correlation=np.eye(1), rms=1.0,
                               relative_error_percent=4.0, n_obs=10, dof=9)
    mf = ModelFile.load(res.save_json(tmp_path / "rb.json"))
    assert mf.model == friction
    assert mf.provenance["rigid_body"] == {"M": 95.1089, "offset": -3.1648}


# Files as older frictionkit versions wrote them: a bare law in the registry's JSON form, and the
# "type"-spelled model of identification files (written by hand here, as an old file would be).
OLD_FILES = {
    "registry_law": {"law": "LuGre", "static": {"law": "Stribeck", "Fc": 1.0, "Fs": 1.5, "vs": 0.001, "delta": 2.0,
                                                "sigma2": 0.4, "shape": "exponential"},
                     "sigma0": 100000.0, "sigma1": 63.2},
    "type_spelled": {"type": "LuGre", "static": {"type": "Stribeck", "Fc": 1.0, "Fs": 1.5, "vs": 0.001,
                                                 "delta": 2.0, "sigma2": 0.4, "shape": "exponential"},
                     "sigma0": 100000.0, "sigma1": 63.2},
}


@pytest.mark.parametrize("kind", sorted(OLD_FILES))
def test_older_files_load(tmp_path, kind):
    p = tmp_path / "old.json"
    p.write_text(json.dumps(OLD_FILES[kind]))
    mf = ModelFile.load(p)
    assert mf.model == LAWS["lugre"]
    assert mf.format == "law"


BAD = {
    "newer_model": ({"format": "frictionkit.model/2", "model": {}}, "newer frictionkit"),
    "newer_identification": ({"format": "frictionkit.identification/3"}, "newer frictionkit"),
    "never_written": ({"format": "frictionkit.model/0", "model": {}}, "not one frictionkit ever wrote"),
    "other_kind": ({"format": "frictionkit.fleet/1"}, "is not a friction model"),
    "foreign": ({"format": "acme-sim 2.0"}, "not a frictionkit model"),
    "no_format": ({"params": [1, 2]}, "no \"format\" key and no \"law\" key"),
    "list": ([1, 2, 3], "the top level is a JSON list"),
    "unknown_law": ({"format": MODEL_FORMAT, "model": {"law": "Karnopp", "Fc": 1.0}}, "'Karnopp' is not registered"),
    "unknown_field": ({"format": MODEL_FORMAT, "model": {"law": "Dahl", "Fc": 1.0, "sigma0": 1e5, "mu": 0.1}},
                      "unknown field 'mu'"),
    "bad_value": ({"format": MODEL_FORMAT, "model": {"law": "Dahl", "Fc": 1.0, "sigma0": -1e5}}, "sigma0"),
    "no_model": ({"format": MODEL_FORMAT}, "missing key 'model'"),
    "units_not_object": ({"format": MODEL_FORMAT, "model": {"law": "Dahl", "Fc": 1.0, "sigma0": 1e5},
                          "units": "SI"}, "\"units\" is a JSON str"),
}


@pytest.mark.parametrize("case", sorted(BAD))
def test_bad_files_say_why_in_one_line(tmp_path, case):
    doc, why = BAD[case]
    p = tmp_path / f"{case}.json"
    p.write_text(json.dumps(doc))
    with pytest.raises(DataError) as ei:
        fk.load_model(p)
    msg = _one_line_error(ei)
    assert msg.startswith(f"model file '{p}': ")
    assert why in msg


def test_not_json_and_missing_file(tmp_path):
    p = tmp_path / "x.json"
    p.write_text('{"format": "frictionkit.model/1",')
    with pytest.raises(DataError, match=r"not valid JSON .*line 1"):
        fk.load_model(p)
    p.write_bytes(b"\xff\xfe\x00")
    with pytest.raises(DataError, match="not UTF-8"):
        fk.load_model(p)
    with pytest.raises(DataError, match="no such file"):
        fk.load_model(tmp_path / "missing.json")


def test_model_file_validates_itself(tmp_path):
    with pytest.raises(ParameterError, match="dict is not a registered friction law"):
        ModelFile(model={"Fc": 1.0})
    with pytest.raises(ParameterError, match=r"units\['F'\] = ''"):
        ModelFile(model=ST, units={"F": ""})
    with pytest.raises(ParameterError, match="key 'T' unknown"):
        ModelFile(model=ST, units={"T": "K"})
    with pytest.raises(DataError, match="no such file"):
        fk.save_model(ST, tmp_path / "m.json", data=tmp_path / "nothere.csv")


def test_summary_and_plot(tmp_path):
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    mf = ModelFile.load(fk.save_model(LAWS["lugre"], tmp_path / "m.json", method="m1"))
    text = mf.summary()
    assert "sigma0" in text and "100000 N/m" in text and "method: m1" in text
    ax = mf.plot()
    line = ax.lines[0]
    # the plotted curve is the steady state Fc + (Fs - Fc) exp(-(v/vs)^2) + sigma2 v (seed 002 eq. 9b), near 1 mm/s
    i = int(np.argmin(np.abs(line.get_xdata() - 1e-3)))
    v = line.get_xdata()[i]
    assert line.get_ydata()[i] == pytest.approx(1.0 + 0.5 * np.exp(-(v / 1e-3) ** 2) + 0.4 * v, rel=1e-12)
    plt.close(ax.figure)


# --------------------------------------------------------------------------- any edit: a law or one line
from hypothesis import HealthCheck, given, settings  # noqa: E402
from hypothesis import strategies as st  # noqa: E402

_JSON = st.recursive(st.none() | st.booleans() | st.integers(-3, 3) | st.floats(allow_nan=True) | st.text(max_size=5),
                     lambda kids: st.lists(kids, max_size=3) | st.dictionaries(st.text(max_size=4), kids, max_size=3),
                     max_leaves=6)


def _paths(node, prefix=()):
    yield prefix
    if isinstance(node, dict):
        for k, v in node.items():
            yield from _paths(v, (*prefix, k))


@settings(max_examples=80, deadline=None, derandomize=True, suppress_health_check=[HealthCheck.function_scoped_fixture])
@given(data=st.data())
def test_any_edit_loads_or_fails_in_one_line(tmp_path, data):
    doc = ModelFile(model=LAWS["directional_gms"], provenance={"method": "m"}).to_dict()
    paths = list(_paths(doc))[1:]
    path = data.draw(st.sampled_from(paths))
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
        mf = ModelFile.load(p)
    except DataError as exc:
        assert "\n" not in str(exc) and str(exc).startswith(f"model file '{p}': ")
    else:
        assert mf.model is not None


def test_model_file_units_none_is_documented_and_a_wrong_value_names_the_allowed_ones():
    # None meant "the defaults" by behaviour only; the docstring now says so (units : mapping or None)
    assert dict(ModelFile(model=ST, units=None).units) == {"F": "N", "x": "m", "v": "m/s"}
    units_doc = ModelFile.__doc__.split("units :")[1].split("provenance :")[0]
    assert "``None``" in units_doc and "defaults" in units_doc
    # a wrong value named neither the keys nor what None gives ("must be a mapping of axis labels {'F': ..., 'v': ...}")
    with pytest.raises(ParameterError, match=r"ModelFile\.units = 5: must be None \(the defaults \{'F': 'N', 'x': 'm', "
                                             r"'v': 'm/s'\}\) or a mapping of axis labels with the keys 'F', 'x', 'v'"):
        ModelFile(model=ST, units=5)
    with pytest.raises(ParameterError, match=r"ModelFile\.units: key 'T' unknown; the keys are 'F', 'x', 'v'"):
        ModelFile(model=ST, units={"T": "K"})
