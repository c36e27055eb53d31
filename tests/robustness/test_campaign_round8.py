"""Issue 13, round 7's leftovers and campaign round 8 (helper r13): one test per pattern fixed, each
built from the case that exposed it."""

from __future__ import annotations

import errno
import os
import tempfile

import pytest

from _robustness_helpers import one_error_line

from frictionkit.errors import DataError

_LAW_FILE = {"format": "frictionkit.model/1", "model": {"law": "Dahl", "Fc": 1.0, "sigma0": 1e5}}


@pytest.mark.skipif(not os.path.isfile("/proc/version"), reason="needs Linux /proc")
def test_a_folder_that_takes_no_new_files_is_named_as_such():
    """Was (round 7): `export --out /proc/version` said "folder '/proc' is not writable (No such file or
    directory)" — the system's text for ENOENT, read as if the folder were missing."""
    from frictionkit._io import check_output_file

    with pytest.raises(DataError) as exc:
        check_output_file("/proc/version", option="--out")
    msg = str(exc.value)
    assert msg.startswith("--out '/proc/version': folder '/proc' is not writable (it does not accept new files")
    assert "No such file" not in msg


def test_a_read_only_file_system_is_named(monkeypatch, tmp_path):
    from frictionkit import _io

    def refuse(*a, **k):
        raise OSError(errno.EROFS, os.strerror(errno.EROFS))

    monkeypatch.setattr(tempfile, "mkstemp", refuse)
    with pytest.raises(DataError, match=r"is not writable \(read-only file system\)"):
        _io.check_output_file(tmp_path / "r.json", option="--json")


@pytest.mark.parametrize("key,value", [("provenance", []), ("provenance", None), ("provenance", ""),
                                       ("units", []), ("units", None)])
def test_an_optional_key_of_the_wrong_type_is_refused_even_when_empty(key, value):
    """Was (round 7): `"provenance": []` (or null, "") in a law file was read as no provenance without a
    word, while the identification JSON refused it. One rule now: absent is none, present must be an object."""
    from frictionkit.models.files import ModelFile

    with pytest.raises(DataError, match=rf'^"{key}" is a JSON \w+ .*expected an object'):
        ModelFile.from_dict(dict(_LAW_FILE, **{key: value}))
    assert ModelFile.from_dict(dict(_LAW_FILE, **{key: {}})).model.Fc == 1.0  # empty, right type: fine


#: The hand-written minimal machine file of tests/unit/test_machine_files.py.
_MACHINE_FILE = {"format": "frictionkit.model/1", "kind": "machine",
                 "model": {"name": "slider", "dofs": [{"name": "x", "inertia": 2.0}],
                           "sites": [{"name": "c", "role": "friction", "at": {"x": 1.0},
                                      "law": {"law": "CoulombViscous", "Fc": 1.0}}],
                           "actuators": [{"name": "u", "at": {"x": 1.0}}]}}


def test_a_machine_file_takes_the_same_rule_for_its_optional_keys():
    """Was: "inputs": null, "provenance": [] and "units": null were read as absent in a machine file."""
    from frictionkit.models.files import ModelFile

    assert ModelFile.from_dict(dict(_MACHINE_FILE, inputs=["u"], units={}, provenance={})).model.input_names() == ["u"]
    for key, value, what in (("provenance", [], "an object"), ("units", None, "an object"),
                             ("inputs", None, "a list of names"), ("inputs", {}, "a list of names")):
        with pytest.raises(DataError, match=rf'^"{key}" is a JSON \w+ .*expected {what}'):
            ModelFile.from_dict(dict(_MACHINE_FILE, **{key: value}))


def test_a_two_direction_result_states_each_number_once_in_effect(static_json):
    """Was (round 7 leftover): the top-level model vs parts.<side>.model agreement was load_static_law's own
    check only, so `report`/`load_model` of a result edited in the top-level model AND its table (both 1 -> 5)
    showed 5 while its parts said 1. Now IdentificationResult.from_dict checks it for every reader, and
    load_static_law uses that one check (same message)."""
    import json

    from frictionkit.identify.result import IdentificationResult
    from frictionkit.identify.start_values import load_static_law

    doc = json.loads(static_json.read_text(encoding="utf-8"))
    fc = doc["parts"]["positive"]["model"]["Fc"]
    doc["model"]["positive"]["Fc"] = 5.0 * fc
    doc["parameters"]["Fc_pos"]["value"] = 5.0 * fc
    want = (rf'the top-level "model" \(positive.Fc = {5 * fc:g}\) disagrees with parts.positive.model '
            rf"\(Fc = {fc:g}\); the file was edited in one place only")
    with pytest.raises(DataError, match=want):
        IdentificationResult.from_dict(doc)
    p = static_json.parent / "r8_edited.json"
    p.write_text(json.dumps(doc), encoding="utf-8")
    with pytest.raises(DataError, match=want):
        load_static_law(p)
    del doc["model"]  # without a top-level model the table is held against the parts
    with pytest.raises(DataError, match=rf"parameters.Fc_pos.value = {5 * fc:g} disagrees with parts.positive.model "):
        IdentificationResult.from_dict(doc)
    for key in ("parts", "data"):  # optional keys: the same rule as model files
        with pytest.raises(DataError, match=rf'"{key}" is \[\], expected an object'):
            IdentificationResult.from_dict(dict(json.loads(static_json.read_text(encoding="utf-8")), **{key: []}))


def test_a_non_numeric_cell_is_named_with_its_row(tmp_path):
    """Was (round 8): a units row under the header ("s,m/s,N"), a NUL-byte line or a comment line above the
    header said only "column 't_s' is not numeric" / "the header names 1 column(s)"."""
    from frictionkit.data import load_recording

    body = "\n".join(f"{0.001 * k},{0.1},{1.0}" for k in range(20))
    cases = {"units": ("t_s,v_ms,F_N\ns,m/s,N\n" + body, r"is not numeric: row 0 holds 's' \(a units row"),
             "nul": ("t_s,v_ms,F_N\n" + body + "\n\x00\x00\n" + body, r"is not numeric: row 20 holds '\\x00\\x00'"),
             "comment": ("# bench 3\nt_s,v_ms,F_N\n" + body,
                         r"header names 1 column\(s\) .*\(header: '# bench 3'\) \(a comment line above the header")}
    for name, (text, want) in cases.items():
        p = tmp_path / f"{name}.csv"
        p.write_text(text)
        with pytest.raises(DataError, match=want):
            load_recording(p, time="t_s", velocity="v_ms", force="F_N")


def test_a_static_map_given_twice_is_refused(runner, tmp_path, static_json):
    """Was (round 8): `identify output-error ... --static-json S.json --Fc 0.5` fitted with the file's map and
    ignored --Fc without a word (likewise --vs/--delta/--sigma2, whose defaults hid that they were given)."""
    import numpy as np

    from frictionkit.cli import app

    t = np.arange(200) * 1e-3
    rec = tmp_path / "u.csv"
    rec.write_text("t,u\n" + "\n".join(f"{a},{b}" for a, b in zip(t, np.sin(20 * t))))
    base = ["identify", "output-error", str(rec), "--time", "t", "--force", "u", "--position", "u", "--mass", "1",
            "--static-json", str(static_json)]
    for extra, named in ((["--Fc", "0.5"], "--Fc"), (["--vs", "0.01", "--sigma2", "0"], "--vs, --sigma2")):
        res = runner.invoke(app, base + extra)
        assert res.exit_code == 2
        assert one_error_line(res) == (f"error: {named} and --static-json both give the static map; give one "
                                       "(--static-json STATIC.json, or --Fc with --Fs, --vs, --delta, --sigma2)")


def test_a_key_named_twice_in_a_json_file_is_refused(tmp_path):
    """Was (round 8): {"Fc": 1.0, "Fc": 5.0} in a law file ran with 5 (plain json keeps the last copy), and
    "written_by": "me" in a result was read as absent. Every JSON input of the package reads through
    frictionkit._io.json_loads."""
    from frictionkit.identify.result import read_json_object
    from frictionkit.models.files import ModelFile

    p = tmp_path / "dup.json"
    p.write_text('{"format": "frictionkit.model/1", "model": {"law": "Dahl", "Fc": 1.0, "Fc": 5.0, "sigma0": 1e5}}')
    with pytest.raises(DataError, match=r"key 'Fc' appears twice in one object \(values 1.0 and 5.0\)"):
        ModelFile.load(p)
    with pytest.raises(DataError, match=r"key 'Fc' appears twice"):
        read_json_object(p)
    from frictionkit.identify.result import IdentificationResult

    with pytest.raises(DataError, match=r'"written_by" is "me", expected an object'):
        IdentificationResult.from_dict({"format": "frictionkit.identification/1", "written_by": "me", "kind": "static_map",
                                        "model_name": "x", "model": None, "parameters": {}, "correlation": [],
                                        "rms": None, "relative_error_percent": None, "n_obs": 0, "dof": 0})


def test_a_drawn_run_on_an_unstable_loop_fails_by_the_screen_not_by_the_message(tmp_path, monkeypatch):
    """Was (round 7 leftover): study's _axis_run failed a drawn run whose loop is unstable by matching the text
    "the closed loop is unstable" in the result's note. Now it reads the screen's LoopStability.unstable: a
    mass drawn at 0.2 kg (nominal 20 kg, actuator limit 20 N) converges to a limit cycle (status 0, note) and is
    a failed row even when the note's wording changes."""
    import frictionkit as fk
    from frictionkit.machines import simulate as msim
    from frictionkit.study import _SPREADABLE, _axis_run, load_study

    p = tmp_path / "s.toml"
    p.write_text("[machine]\nlimit = 20.0\n[reference]\nduration = 0.2\n[study]\ndraws = 1\nseeds = 1\n"
                 "compensators = ['none']\n")
    spec = load_study(p)  # the nominal loop (20 kg) is stable
    run = {k: spec.machine[k] for k in _SPREADABLE if k in spec.machine}
    run.update(compensator="none", noise_seed=0)
    assert set(_axis_run(spec, run)) >= {"max_error", "rms_error"}
    real = msim.simulate_machine

    def reworded(*a, **k):  # the note's text is not the interface
        res = real(*a, **k)
        assert res.status == 0 and "unstable" in res.message  # measured first: converged, with the note
        return __import__("dataclasses").replace(res, message="ok")

    monkeypatch.setattr(fk, "simulate_machine", reworded)
    run["mass"] = 0.2
    with pytest.raises(fk.SimulationError, match=r"^the closed loop is unstable: .*; the run measured a limit cycle"):
        _axis_run(spec, run)


def test_a_flag_reported_as_false_is_right_against_the_twin():
    """Item 10 of issue 13: last session counted 3 of 18 extreme LuGre sets as flagged "yet within 1.7e-4 of the
    solve_ivp twin" — measured on x only, and only over the samples the flag kept. Over the whole run and on v
    and the friction too, all three were wrong (friction 6.8 % / 12 % of its range, v 13 %, x 1.2e-3): the check
    was right. This one (sigma0 4.57e6 N/m on 1.7 kg, (c/m) dt 4.4) keeps x and v within 1e-7 of the twin but
    not the friction; the flag must stay."""
    import warnings

    import numpy as np

    import frictionkit as fk
    from frictionkit.simulation import core
    from frictionkit.simulation.reference import reference_force_driven

    u = 2.0 * np.sin(2 * np.pi * np.arange(400) * 1e-3)
    law = fk.LuGre(fk.Stribeck(Fc=0.0309, Fs=0.04635, vs=1e-3, sigma2=0.4), sigma0=4.57e6, sigma1=7.51e3)
    ref = reference_force_driven(law, 1.7, u, 1e-3, rtol=1e-10, atol=1e-15)
    kind, pk = core._pack(law)
    raw = core._force_run(kind, pk, u, 1e-3, 1.7, 0.0, 0.0, None, fk.SimOptions(), core._f_scale(pk.static), law,
                          warn=False)
    err = {k: float(np.max(np.abs(a - ref[k])) / np.ptp(ref[k])) for k, a in
           (("x", raw.x), ("v", raw.v), ("friction", raw.friction))}
    # measured first: x and v right, the friction wrong beyond the error contract (10 rtol = 1e-4 of its range);
    # it was > 5e-2 before the kernel bounded the friction's share of the local error (kernels/lugre.py
    # F_ERROR, 2026-11-24): 1.8e-3 since, still 18x the contract
    assert raw.status == 0 and err["x"] < 1e-6 and err["v"] < 1e-6 and err["friction"] > 1e-3, err
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", RuntimeWarning)
        res = fk.simulate(law, plant=fk.Mass(1.7), force=u, dt=1e-3)
    assert res.status == 2 and "moves friction by" in res.message


@pytest.mark.parametrize("text, want", [
    ("[reference]\nduration = 0.0\n", r"\[reference\] duration = 0.0: must be > 0"),
    ("[machine]\nmass = -1.0\n", r"\[machine\] mass = -1.0: must be a finite number >= 0"),
])
def test_a_study_value_is_named_with_its_section_and_value(tmp_path, text, want):
    """Was (round 8): "duration must be > 0" — neither the section nor the value, unlike the study's other errors."""
    from frictionkit.study import load_study

    p = tmp_path / "s.toml"
    p.write_text(text)
    with pytest.raises(DataError, match=rf"^study '{p}': {want}$"):
        load_study(p)


@pytest.mark.parametrize("Fc, sigma0", [(1e100, 1e5), (1e30, 1.0)])
def test_a_position_driven_lugre_far_from_its_breakaway_stays_a_spring(Fc, sigma0):
    # Round 8: with g / sigma0 far above the travel (a = sigma0 |v| / g, a dt < 1e-16), the exact
    # update zss + (z - zss) exp(-a dt) cancelled and z stayed at 0: status ok, friction half its
    # range off. Then the bristle follows the motion: z = x, F = sigma0 x + (sigma1 + sigma2) v.
    import numpy as np

    import frictionkit as fk

    dt = 1e-3
    t = np.arange(2001) * dt
    x = 1e-6 * np.sin(2 * np.pi * t)
    law = fk.LuGre(fk.Stribeck(Fc=Fc, Fs=1.5 * Fc, vs=1e-3, sigma2=0.4), sigma0=sigma0, sigma1=2.0)
    res = fk.simulate(law, dt=dt, position=x)
    assert res.status == 0, res.message
    v = np.diff(x) / dt
    spring = sigma0 * x[1:] + (2.0 + 0.4) * v
    err = np.max(np.abs(res.friction[1:] - spring)) / np.ptp(spring)
    assert err < 1e-6, f"friction {err:.3g} of its range off the spring-damper"


def test_a_run_that_passes_its_accuracy_check_agrees_with_the_twin():
    # Reproducer from round 8's random extreme sets (LuGre, light bristle damping, a contact much
    # faster than the samples). The twin interpolates the force linearly, as simulate() documents;
    # with the force held (ZOH) it is 60 % off instead, so it is not an input-convention mismatch.
    # Was (issue 13, until 2026-11-24): status 0 "accuracy check passed" with v 4.44 % and x 4.16e-4
    # of their ranges off the twin at every rtol (1e-5 ... 1e-7 the same): single-sample spanning
    # steps of kernels/lugre.py across 2.4 periods of the pre-sliding ringing, whose remainder
    # estimate saw the samples only. The twin was confirmed by a fixed-step RK4 at dt/1e5 (v within
    # 1e-6 of its range) and Radau at rtol 1e-11 (1.5e-8). Now those intervals are checked between
    # the samples (RING_RESOLVE, _ring_misfit) and go to ROS2 sub-steps.
    import numpy as np

    import frictionkit as fk
    from frictionkit.simulation.reference import reference_force_driven

    law = fk.LuGre(fk.Stribeck(Fc=59.219588350501375, Fs=92.22536041851625, vs=0.008048392326818447,
                               sigma2=0.981540665931343), sigma0=12965.363569760966, sigma1=0.0003903342103826283)
    m, dt = 0.23981716678647486, 0.06393863621993491
    t = np.arange(int(50 / dt)) * dt
    u = 24.545966556843315 * np.sin(2 * np.pi * 0.04038165796668075 * t)
    res = fk.simulate(law, dt=dt, plant=fk.Mass(m), force=u)
    assert res.status == 0 and "accuracy check passed" in res.message
    tw = reference_force_driven(law, m, u, dt)
    v_err = float(np.max(np.abs(res.v - tw["v"])) / np.ptp(tw["v"]))
    x_err = float(np.max(np.abs(res.x - tw["x"])) / np.ptp(tw["x"]))
    F_err = float(np.max(np.abs(res.friction - tw["friction"])) / np.ptp(tw["friction"]))
    rtol = fk.SimOptions().rtol
    # README error contract: 10 rtol of the ranges of x and the friction; v: the accuracy check's
    # own bound (CHECK_BOUND_RATE rtol = 1 %). Measured 2026-11-24: x 3.7e-6, F 9.8e-7, v 7.5e-4.
    assert x_err < 10 * rtol and F_err < 10 * rtol, (x_err, F_err)
    assert v_err < 0.01, f"v {v_err:.3g} of its range off the twin although the check passed"
