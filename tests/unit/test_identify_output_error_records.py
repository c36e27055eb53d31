"""Force-driven output error over several records with rests (issue 11 parts 2, 3).

The data are built piece by piece, independently of the fit's own segmentation: every
run of a drive log is simulated from rest (the drive was disabled before it, so the axis
stood still with unloaded bristles), the rests in between are logged as exactly zero
force and zero velocity. The fit gets no start values (``initial="auto"``) and must
return the true LuGre inside its 95 % intervals; the same data fitted without resets
must be worse (so the test can fail).
"""

from __future__ import annotations

import dataclasses
import json

import numpy as np
import pytest

import frictionkit as fk
from frictionkit.errors import DataError, IdentificationError, ParameterError
from frictionkit.identify import MOTION_ERROR_FIT, OUTPUT_ERROR_FIT, FitOptions, IdentificationResult
from frictionkit.identify.output_error import evaluate_output_error, fit_output_error
from frictionkit.identify.validation import validate

DT = 1e-3
LAW = fk.Stribeck(Fc=1.0, Fs=1.5, vs=1e-3, delta=2.0, sigma2=0.4)
TRUE = fk.LuGre(LAW, sigma0=1e5, sigma1=63.2)
N1, REST, N2, NB = 3500, 5, 1500, 2000  # run 1, rest, run 2, record B
COUNT = 1e-8  # encoder resolution [m]


def _sim(u):
    sim = fk.simulate(TRUE, plant=fk.Mass(1.0), force=u, dt=DT)
    assert sim.success
    return sim.x, sim.v


def _noisy(v, seed):
    rng = np.random.default_rng(seed)
    return v + 0.005 * np.abs(v).max() * rng.standard_normal(v.size)


@pytest.fixture(scope="module")
def records():
    """Record A: a 1 N triangle (below the 1.5 N breakaway), then a 2 N sine that ends sliding,
    a short rest (drive disabled: force and velocity logged 0), a 2 N sine from rest.
    Record B: a 1.8 N sine on its own time axis. Position in 10 nm counts, velocity noisy."""
    t1 = np.arange(N1) * DT
    u1 = np.where(t1 < 2.5, (2 / np.pi) * np.arcsin(np.sin(np.pi * t1 + 0.3)), 2.0 * np.sin(np.pi * (t1 - 2.5)))
    x1, v1 = _sim(u1)
    assert abs(v1[-1]) > 0.05  # still sliding when the drive is disabled
    t2 = np.arange(N2) * DT
    u2 = 2.0 * np.sin(np.pi * t2 + 0.2)
    x2, v2 = _sim(np.r_[0.0, u2])  # from rest at the last rest sample
    u_a = np.r_[u1, np.zeros(REST), u2]
    v_a = np.r_[v1, np.zeros(REST - 1), v2]
    x_a = np.r_[x1, np.full(REST - 1, x1[-1] + 1e-4), x1[-1] + 1e-4 + x2]  # the axis stopped somewhere
    tb = np.arange(NB) * DT
    u_b = 1.8 * np.sin(1.2 * np.pi * tb + 0.1)
    x_b, v_b = _sim(u_b)
    rec_a = {"t": np.arange(u_a.size) * DT, "F": u_a, "x": np.round(x_a / COUNT) * COUNT, "v": _noisy(v_a, 1)}
    rec_b = {"t": 10.0 + tb, "F": u_b, "x": np.round(x_b / COUNT) * COUNT, "v": _noisy(v_b, 2)}
    return {"A": rec_a, "B": rec_b}


@pytest.fixture(scope="module")
def fitted(records):
    return fit_output_error(records, "lugre", static=LAW, inertia=1.0)  # initial="auto": no start values


def test_auto_start_multi_record_fit_recovers_the_truth_within_its_intervals(fitted):
    res = fitted
    assert res.success, res.message
    assert res.names == ("sigma0", "sigma1")  # default free parameters of a LuGre
    for name, truth in (("sigma0", 1e5), ("sigma1", 63.2)):
        lo, hi = res.parameter(name)["ci95"]
        assert lo < truth < hi, (name, lo, hi)
    assert abs(res["sigma0"] / 1e5 - 1) < 0.05
    # the start came from the data: the sub-breakaway slope (seed 002 §3.1), within 10 %
    ini = res.diagnostics["initial"]
    assert abs(ini["sigma0"] / 1e5 - 1) < 0.10 and ini["branches"] >= 3
    assert res.provenance["procedure"]["initial"] == "auto"


def test_segments_and_rests(fitted):
    res = fitted
    seg = res.diagnostics["segments"]
    assert [len(seg[k]["segments"]) for k in ("A", "B")] == [2, 1]
    assert seg["A"]["rest_samples"] == REST
    assert seg["A"]["segments"][1][0] == N1 + REST  # the second run starts after the rest
    # fitted samples: every run sample but a record's very first; the rest samples never
    assert res.n_obs == (N1 - 1) + N2 + (NB - 1)
    # the second run of A is predicted from rest: its first predicted sample (the last rest
    # sample) is the unloaded state
    assert res.data["y_pred"][N1] == pytest.approx(0.0, abs=1e-12)


def test_without_resets_the_same_data_fit_worse(records, fitted):
    start = fk.LuGre(LAW, sigma0=fitted["sigma0"], sigma1=fitted["sigma1"])
    ev_reset = evaluate_output_error(TRUE, records, inertia=1.0)
    ev_none = evaluate_output_error(TRUE, records, inertia=1.0, rests=None)
    assert ev_none["rms"] > 3 * ev_reset["rms"]  # the truth explains the data only with resets
    res = fit_output_error(records, start, inertia=1.0, rests=None)
    # without resets the fit wanders to sigma0 ~ 6.7e7 N/m (omega dt 8, damping ratio 0.0075 on 1 kg),
    # where simulate's accuracy check (issue 13) flags the run: a flagged fit is no better fit either
    assert res.status != 0 or res.rms > 2 * fitted.rms


def test_a_mask_gives_the_rests(records, fitted):
    a = records["A"]
    mask = np.zeros(a["t"].size, bool)
    mask[N1:N1 + REST] = True
    ev = evaluate_output_error(fitted.model, {"A": a}, inertia=1.0, rests={"A": mask})
    ev_auto = evaluate_output_error(fitted.model, {"A": a}, inertia=1.0)
    assert ev["n"] == ev_auto["n"] and ev["rms"] == pytest.approx(ev_auto["rms"], rel=1e-12)
    with pytest.raises(DataError, match="rest mask has 5 samples"):
        evaluate_output_error(fitted.model, {"A": a}, inertia=1.0, rests={"A": mask[:5]})


def test_validate_and_json_round_trip(records, fitted, tmp_path):
    rep = validate(fitted, [fk.data.Recording(**records["B"], name="B")])
    assert rep["rms"] < 2 * fitted.rms
    path = fitted.save_json(tmp_path / "oe.json")
    back = IdentificationResult.load_json(path)
    assert isinstance(back.model, fk.LuGre) and back.model.sigma0 == pytest.approx(fitted["sigma0"])
    # a file written before rests and segments existed still loads and validates (whole records)
    doc = json.loads(path.read_text(encoding="utf-8"))
    for key in ("rests", "min_rest", "initial", "drive", "free"):
        doc["provenance"]["procedure"].pop(key, None)
    for key in ("segments", "initial"):
        doc["diagnostics"].pop(key, None)
    old = IdentificationResult.from_dict(doc)
    rep_old = validate(old, [fk.data.Recording(**records["B"], name="B")])
    assert rep_old["rms"] == pytest.approx(rep["rms"], rel=1e-9)  # B has no rests: same answer


def test_static_map_from_a_result_or_its_json(records, tmp_path):
    v = np.r_[np.geomspace(2e-4, 0.2, 12), -np.geomspace(2e-4, 0.2, 12)]
    F = np.asarray(LAW.steady_state(v), float)
    st = fk.identify.fit_static_map(v, F, model="exponential", delta=2.0)
    path = st.save_json(tmp_path / "static.json")
    one = {"A": records["A"]}
    kw = dict(inertia=1.0, initial={"sigma0": 1e5, "sigma1": 63.2}, max_nfev=1)
    by_result = fit_output_error(one, "lugre", static=st, **kw)
    by_path = fit_output_error(one, "lugre", static=str(path), **kw)
    assert by_result.model.static == by_path.model.static
    assert by_path.model.static.positive.Fs == pytest.approx(1.5, rel=1e-3)
    bad = tmp_path / "bad.json"
    bad.write_text("{", encoding="utf-8")
    with pytest.raises(DataError, match="bad.json"):
        fit_output_error(one, "lugre", static=bad, **kw)


def test_given_start_values_are_used_and_the_rest_computed(records):
    one = {"B": records["B"]}
    res = fit_output_error(one, "lugre", static=LAW, inertia=1.0, initial={"sigma0": 7e4}, max_nfev=1)
    # sigma1 from critical damping of the linearised oscillator: 2 sqrt(sigma0 m) - sigma2
    assert res.diagnostics["initial"]["sigma1"] == pytest.approx(2 * np.sqrt(7e4) - 0.4)
    assert res.provenance["procedure"]["initial"] == "auto, some given"


def test_gms_start_from_the_data(records):
    res = fit_output_error({"A": records["A"]}, "gms", static=LAW, inertia=1.0, elements=2, max_nfev=1)
    k = np.asarray(res.model.k) if not res.success else np.asarray(res.diagnostics["initial"]["k_total"])
    ini = res.diagnostics["initial"]
    assert abs(ini["k_total"] / 1e5 - 1) < 0.10  # the sub-breakaway slope is the total stiffness
    assert res.names == ("k1", "k2") and k.size >= 1
    with pytest.raises(ParameterError, match="initial gives k without xi"):
        fit_output_error(records, "gms", static=LAW, inertia=1.0, initial={"k": [1e5]})


@pytest.mark.parametrize("kwargs, error, match", [
    ({"model0": "lugre"}, ParameterError, "give the static map"),
    ({"model0": "maxwell", "static": LAW}, ParameterError, "model0 = 'maxwell'"),
    ({"model0": TRUE, "static": LAW}, ParameterError, "static= is for a model name"),
    ({"model0": TRUE, "initial": {"sigma0": 1.0}}, ParameterError, "its values are the start"),
    ({"model0": "lugre", "static": LAW, "initial": {"sigma9": 1.0}}, ParameterError, "initial has 'sigma9'"),
    ({"model0": "lugre", "static": LAW, "initial": "guess"}, ParameterError, "initial = 'guess'"),
    ({"model0": TRUE, "starts": "auto"}, ParameterError, "motion-driven start grid"),
    ({"model0": TRUE, "profile": True}, ParameterError, "profile = True is not used here"),
    ({"model0": TRUE, "max_iter": 3}, ParameterError, "FitOptions has no setting 'max_iter'"),
    ({"model0": TRUE, "refine": 0}, ParameterError, "FitOptions.refine = 0: must be >= 1"),
    ({"model0": TRUE, "fit": {"starts": 2}}, ParameterError, "must be a FitOptions"),
    ({"model0": TRUE, "rests": "sometimes"}, ParameterError, "rests = 'sometimes'"),
])
def test_bad_input_is_one_named_error(records, kwargs, error, match):
    kw = {"inertia": 1.0, **kwargs}
    with pytest.raises(error, match=match):
        fit_output_error({"B": records["B"]}, **kw)


def test_no_motion_and_no_branch_are_data_errors():
    t = np.arange(200) * DT
    with pytest.raises(DataError, match="no motion to fit"):
        fit_output_error({"t": t, "F": np.zeros(200), "v": np.zeros(200)}, TRUE, inertia=1.0)
    with pytest.raises(DataError, match="initial='auto' found no pre-sliding branch"):
        fit_output_error({"t": t, "F": np.ones(200), "v": np.zeros(200)}, "lugre", static=LAW, inertia=1.0)


def test_fit_options_are_one_validated_object():
    assert OUTPUT_ERROR_FIT.starts == 1 and MOTION_ERROR_FIT.starts == "auto"
    with pytest.raises(dataclasses.FrozenInstanceError):
        OUTPUT_ERROR_FIT.max_nfev = 3  # type: ignore[misc]
    for bad, match in (({"starts": 0}, "starts = 0"), ({"starts": "many"}, "'auto' or an integer"),
                       ({"optimiser": "bfgs"}, "must be 'trf'"), ({"ftol": -1.0}, "ftol = -1.0: must be > 0"),
                       ({"raise_on_failure": 1}, "True or False"), ({"diff_step": 2.0}, "must be < 1"),
                       ({"seed": True}, "seed = True")):
        with pytest.raises(ParameterError, match=match):
            FitOptions(**bad)
    # the motion drive takes the same object and refuses the force drive's settings
    t = np.arange(300) * DT
    data = {"t": t, "x": 1e-5 * np.sin(2 * np.pi * t), "F": np.ones(300)}
    with pytest.raises(ParameterError, match="workers = 2 is not used here"):
        fk.identify.fit_motion_error(data, TRUE, workers=2)


def test_fit_object_and_keywords_agree_and_raising_is_on_request(records):
    one = {"B": records["B"]}
    start = fk.LuGre(LAW, sigma0=3e4, sigma1=100.0)
    a = fit_output_error(one, start, inertia=1.0, max_nfev=2)
    b = fit_output_error(one, start, inertia=1.0, fit=OUTPUT_ERROR_FIT.replace(max_nfev=2))
    assert not a.success and a.diagnostics["status"] == 0 and "max_nfev = 2" in a.message
    np.testing.assert_array_equal(a.values, b.values)
    with pytest.raises(IdentificationError, match="did not converge"):
        fit_output_error(one, start, inertia=1.0, fit=FitOptions(max_nfev=2, raise_on_failure=True))


def test_motion_start_model_keeps_given_values_and_computes_the_rest():
    from frictionkit.identify.motion_error import motion_start
    from frictionkit.identify.start_values import motion_error_start

    t = np.arange(2001) * DT
    data = {"t": t, "x": 1e-3 * np.sin(2 * np.pi * t), "F": np.ones(t.size)}
    auto = motion_start("lugre", LAW, fk.identify.motion_data(data))
    got = motion_error_start("lugre", LAW, data, given={"sigma1": 7.0})
    assert got.sigma1 == 7.0 and got.sigma0 == pytest.approx(auto.sigma0)
    gms = motion_error_start("gms", LAW, data, given={"k": [1e5, 1e4], "xi": [0.4, 0.6]})
    assert list(gms.k) == [1e5, 1e4] and gms.C == pytest.approx(motion_start("gms", LAW, data, elements=2).C)
    with pytest.raises(ParameterError, match="initial has 'sigma1', not a start value of dahl"):
        motion_error_start("dahl", LAW, data, given={"sigma1": 1.0})
    with pytest.raises(ParameterError, match="give both, or neither"):
        motion_error_start("gms", LAW, data, given={"xi": [1.0]})


def test_motion_fit_takes_a_model_name_and_auto_start_values_too():
    true = fk.LuGre(LAW, sigma0=1e5, sigma1=30.0)
    dt = 1e-4
    t = np.arange(4001) * dt
    x = 20e-6 * np.sin(2 * np.pi * 5 * t)
    F = fk.simulate(true, position=x, dt=dt).friction
    res = fk.identify.fit_motion_error({"t": t, "x": x, "F": F}, "lugre", static=LAW, profile=False)
    assert res.success and res["sigma0"] == pytest.approx(1e5, rel=1e-3)
    with pytest.raises(ParameterError, match="static= and initial= are for a model name"):
        fk.identify.fit_motion_error({"t": t, "x": x, "F": F}, true, static=LAW)


def test_presliding_resets_at_a_rest_inside_a_record():
    """Two strokes of a GMS stage with the drive disabled in between (force logged exactly 0):
    the second stroke starts from unloaded elements, which only the cut at the rest explains."""
    from frictionkit.identify.presliding import fit_presliding

    gms = fk.GMS(LAW, k=[4e5, 1e5, 2e4], xi=[0.2, 0.3, 0.5], C=20.0)
    x1 = np.r_[np.linspace(0, 50e-6, 1001), np.linspace(50e-6, -30e-6, 1601)[1:]]
    x2 = np.r_[np.linspace(0, -40e-6, 801)[1:], np.linspace(-40e-6, 40e-6, 1601)[1:]]  # moves at once
    F1 = fk.simulate(gms, position=x1, dt=DT).friction
    F2 = fk.simulate(gms, position=np.r_[0.0, x2], dt=DT).friction  # from rest at the last rest sample
    rest = 10
    x = np.r_[x1, np.full(rest - 1, x1[-1]), x1[-1] + np.r_[0.0, x2]]
    F = np.r_[F1, np.zeros(rest), F2[1:]]  # the disabled drive logs exactly 0 (F2[0] is sigma2 v, not 0)
    data = {"t": np.arange(x.size) * DT, "x": x, "F": F}
    res = fit_presliding(data, elements=3, static=LAW)
    assert res.diagnostics["segments"]["arrays"]["segments"] == [[0, x1.size], [x1.size + rest, x.size]]
    assert abs(res.diagnostics["total_stiffness"] / 5.2e5 - 1) < 0.05
    none = fit_presliding(data, elements=3, static=LAW, rests=None)
    assert none.rms > 5 * res.rms
