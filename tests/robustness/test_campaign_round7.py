"""Issue 13, round 6's leftovers and campaign round 7 (helper r13): one test per pattern fixed, each
built from the case that exposed it."""

from __future__ import annotations

import copy
import json

import pytest

from frictionkit.errors import DataError

#: A hand-written identification result: two parameters, as ``identify static --json`` lays it out.
_FIT = {
    "format": "frictionkit.identification/1", "kind": "static_map", "model_name": "coulomb_viscous",
    "model": {"type": "Stribeck", "Fc": 1.0, "Fs": 1.0, "vs": 1e-3, "delta": 2.0, "sigma2": 0.4,
              "shape": "exponential"},
    "parameters": {"Fc": {"value": 1.0, "stderr": 0.01, "ci95": [0.98, 1.02], "unit": "N"},
                   "sigma2": {"value": 0.4, "stderr": None, "ci95": [None, None], "unit": "N·s/m"}},
    "correlation": [[1.0, 0.1], [0.1, 1.0]], "rms": 0.01, "relative_error_percent": 1.0,
    "n_obs": 20, "dof": 18, "success": True, "message": "ok",
}


def test_hand_edited_identification_table_names_every_bad_field():
    """Was (round 6): a value "1" read as 1.0 (numpy converts strings), a value null as NaN in an 'ok'
    fit, a stderr of -1 shown as is."""
    from frictionkit.identify.result import IdentificationResult

    assert IdentificationResult.from_dict(_FIT).params == {"Fc": 1.0, "sigma2": 0.4}  # null stderr/ci: fine
    doc = copy.deepcopy(_FIT)
    doc["parameters"]["Fc"]["value"] = "1"
    doc["parameters"]["sigma2"]["value"] = None
    doc["parameters"]["Fc"]["stderr"] = -1
    doc["parameters"]["sigma2"]["ci95"] = [2.0, 1.0]
    doc["correlation"][0][1] = 3.0
    doc["rms"] = -0.5
    doc["dof"] = 25
    with pytest.raises(DataError) as exc:
        IdentificationResult.from_dict(doc)
    msg = str(exc.value)
    for needle in ('parameters.Fc.value is "1", expected a finite number',
                   "parameters.sigma2.value is null, expected a finite number (null only in a failed fit's result)",
                   "parameters.Fc.stderr is -1, expected a number >= 0 or null",
                   "parameters.sigma2.ci95 is [2.0, 1.0]: the low end is above the high end",
                   "correlation[0][1] is 3.0, expected a number in [-1, 1] or null",
                   "rms is -0.5, expected a number >= 0 or null", "dof is 25, expected 0 ... n_obs = 20"):
        assert needle in msg, msg
    failed = dict(copy.deepcopy(_FIT), success=False)  # a failed fit's table may hold nulls
    failed["parameters"]["Fc"]["value"] = None
    assert IdentificationResult.from_dict(failed).success is False
    part = dict(copy.deepcopy(_FIT), parts={"positive": doc})
    with pytest.raises(DataError, match=r'^parts.positive: parameters.Fc.value is "1"'):
        IdentificationResult.from_dict(part)


def test_every_input_path_is_checked_before_the_fit(runner, tmp_path, monkeypatch):
    """Was (round 6): `identify static rec.csv ... --validate 0.5` fitted first, then failed on '0.5'."""
    import frictionkit.cli.identify  # noqa: F401  (registers the verbs)
    import frictionkit.identify as fid
    from _robustness_helpers import STATIC_ARGS, one_error_line
    from frictionkit.cli import app

    def no_fit(*a, **k):
        raise AssertionError("the fit ran before the inputs were checked")

    monkeypatch.setattr(fid, "fit_static_map", no_fit)
    rec = tmp_path / "rec.csv"
    rec.write_text("t_s,v_ms,F_N\n0,1,1\n")
    (tmp_path / "folder").mkdir()
    for bad, why in ((tmp_path / "0.5", "not found"), (tmp_path / "folder", "is a folder; give a data file")):
        res = runner.invoke(app, ["identify", "static", str(rec), *STATIC_ARGS, "--validate", str(bad)])
        assert res.exit_code == 2, res.output
        assert one_error_line(res) == f"error: --validate '{bad}'" + (": " if why[0] == "n" else " ") + why
    res = runner.invoke(app, ["identify", "static", str(tmp_path / "none.csv"), *STATIC_ARGS])
    assert one_error_line(res) == f"error: RECORDING '{tmp_path / 'none.csv'}': not found"
    other = tmp_path / "other.csv"  # the validation record's columns are checked before the fit too
    other.write_text("t,x\n0,0\n0.001,0\n")
    res = runner.invoke(app, ["identify", "static", str(rec), *STATIC_ARGS, "--validate", str(other)])
    assert one_error_line(res).startswith(f"error: file '{other}': column 't_s' (given for time) not found")


def test_a_study_whose_loop_is_unstable_is_refused(tmp_path):
    """Was (round 6): Kp = 1e300 ran 'ok' with a 4.2 mm max error on a 1 mm reference (simulate's note
    'the closed loop is unstable ... actuator at its limit in 99.9 % of the samples' was dropped)."""
    from frictionkit.study import load_study

    p = tmp_path / "s.toml"
    p.write_text("[machine]\nKp = 1e300\n")
    with pytest.raises(DataError, match=r"\[machine\] Kp = 1e\+300, .*the closed loop is unstable: .*a 1000 Hz mode "
                                        r"grows .*; the runs would measure a limit cycle"):
        load_study(p)
    p.write_text("[machine]\nKp = 2e5\n")  # the documented default loop
    assert load_study(p).machine["Kp"] == 2e5


def test_batch_message_names_the_accuracy_check_apart_from_the_budget():
    """Was (round 6): a set flagged by simulate_batch's accuracy check (status 2) was reported as
    'status 2 (sub-step budget exhausted inside one sample interval)'."""
    import numpy as np

    from frictionkit.simulation.core import BatchResult

    res = BatchResult(np.array([1.0, np.inf, np.inf]), np.array([0, 2, 2]), 10, "Set 1: tolerance not met", (1,))
    msg = res.message
    assert msg.startswith("2 of 3 parameter sets failed (sse = inf): 1 with status 2 (sub-step budget exhausted "
                          "inside one sample interval); 1 with status 2 (the accuracy check failed: run alone by "
                          "simulate(), the set does not meet the tolerance)"), msg
    only = BatchResult(np.array([np.inf]), np.array([2]), 10, "Set 0: x", (0,)).message
    assert "sub-step budget" not in only and "1 with status 2 (the accuracy check failed" in only


def test_an_unreadable_folder_under_a_fleet_glob_is_named(tmp_path, monkeypatch):
    """Was (round 6): `fleet 'fleet/axis-*/*.csv'` left an unreadable axis folder out without a word
    (glob skips what it cannot list); a folder dataset already named it. The unreadable folder is
    simulated in-process (os.scandir refuses it, as the kernel does for a 0000 folder; round 6's
    setpriv subprocess checked the real permission for folder datasets)."""
    import os

    from frictionkit.fleet.dataset import _candidates

    for axis in ("axis-0001", "axis-0002"):
        (tmp_path / "fleet" / axis).mkdir(parents=True)
        (tmp_path / "fleet" / axis / "2026-01-05.csv").write_text("t,x\n0,0\n")
    real = os.scandir

    def scandir(path="."):
        if os.fspath(path).rstrip("/").endswith("axis-0002"):
            raise PermissionError(13, "Permission denied", os.fspath(path))
        return real(path)

    monkeypatch.chdir(tmp_path)
    monkeypatch.setattr(os, "scandir", scandir)
    for pat in ("fleet/axis-*/*.csv", "fleet/**/*.csv", "fleet"):
        with pytest.raises(DataError) as exc:
            _candidates(pat)
        assert str(exc.value) == (f"fleet dataset '{pat}': 1 folder(s) cannot be read: 'fleet/axis-0002' (Permission "
                                  "denied); their logs would be left out — make them readable, or give the other "
                                  "folders or a glob")
    assert len(_candidates("fleet/axis-0001/*.csv")[1]) == 1  # a pattern that does not reach the folder is fine


@pytest.mark.parametrize("vref, note", [
    (1e-3, "note: the reference velocity 'vref' never changes sign: no reversal, so there is no reversal error"),
    (0.0, "note: the reference velocity 'vref' is zero throughout: the compensators never acted")])
def test_compensate_without_a_reversal_says_so(tmp_path, monkeypatch, vref, note):
    """Was (round 6): a machine file's test whose reference velocity never reverses reported 'ok' with
    '-' at reversals and no word; with vref = 0 the feed-forward never acted. The machine run is
    replaced by a stand-in (the note depends on the inputs only)."""
    import types

    import numpy as np

    import frictionkit as fk
    import frictionkit.machines as fm
    from frictionkit.compensate import compensate
    from frictionkit.presets.emps import PUBLISHED, emps_machine

    fk.save_model(emps_machine(M=PUBLISHED["M"], friction=fk.CoulombViscous(Fc=20.0, sigma2=200.0), offset=0.0),
                  tmp_path / "emps.json")
    t = np.arange(201) * 1e-3
    (tmp_path / "ref.csv").write_text("t,qg,vref\n" + "".join(f"{a},{vref * a},{vref}\n" for a in t))
    (tmp_path / "test.toml").write_text('[inputs]\nqg = "ref.csv:qg"\nvref = "ref.csv:vref"\n[score]\nposition = "q"\n'
                                        'reference = "qg"\n[compensation]\nvelocity = "vref"\nsite = "friction"\n')

    def run(machine, *, dt, inputs, seed=0):
        n = len(inputs["qg"])
        return types.SimpleNamespace(status=0, message="ok", position=lambda _name: np.full(n, 1e-6))

    monkeypatch.setattr(fm, "simulate_machine", run)
    res = compensate(tmp_path / "emps.json", ["none", "model"], model=fk.CoulombViscous(Fc=20.0, sigma2=200.0),
                     test=tmp_path / "test.toml")
    assert res.status == 0 and res.reversals == []
    assert res.message.startswith("ok; " + note), res.message
    assert note in res.summary() and res.to_dict()["message"] == res.message


def test_a_law_file_with_non_si_labels_says_so(tmp_path):
    """Decision (round 6 leftover): law-file unit labels stay free text (identify --force-unit V is a
    legitimate label), the docstring no longer promises SI numbers for every file, and the summary
    names labels that are not SI (a hand-edited "F": "kN" read as N without a word before)."""
    import frictionkit as fk
    from frictionkit.models.files import ModelFile

    path = fk.save_model(fk.CoulombViscous(Fc=1.0, sigma2=0.4), tmp_path / "law.json")
    assert "note:" not in ModelFile.load(path).summary()
    doc = json.loads(path.read_text())
    doc["units"]["F"] = "kN"
    (tmp_path / "kn.json").write_text(json.dumps(doc))
    text = ModelFile.load(tmp_path / "kn.json").summary()
    assert "note: unit labels F = 'kN' are not SI; the numbers are in those units, while simulate and compensate " \
           "read them as SI" in text, text


def test_demo_checks_its_result_files_before_the_work(tmp_path, monkeypatch):
    """Was (round 6): a read-only out/report.html (or a folder of that name) failed the demo after
    its minute of work."""
    import frictionkit.report.demo as demo

    def no_work(*a, **k):
        raise AssertionError("the demo worked before checking its result files")

    monkeypatch.setattr(demo, "section_laws", no_work)
    (tmp_path / "a" / "report.html").mkdir(parents=True)
    with pytest.raises(DataError, match=r"demo output '.*report.html' is a folder; give a file name"):
        demo.run_demo(tmp_path / "a", shared=tmp_path)
    (tmp_path / "b").mkdir()
    (tmp_path / "b" / "summary.txt").symlink_to("/dev/null")
    with pytest.raises(DataError, match=r"summary.txt' \(a link to '/dev/null'\) is not a regular file"):
        demo.run_demo(tmp_path / "b", shared=tmp_path)


def test_a_header_name_with_spaces_is_pointed_out(tmp_path):
    """Round 7: a header ' t_s , v_ms ' gave "column 't_s' not found; available columns: t_s , v_ms" —
    the name it asked for seemed to be there."""
    from frictionkit.data import load_recording

    p = tmp_path / "r.csv"
    p.write_text(" t_s , v_ms , F_N \n0,1,1\n0.001,1,1\n0.002,1,1\n")
    with pytest.raises(DataError, match=r"available columns: ' t_s ', ' v_ms ', ' F_N ' \(the header has 't_s' "
                                        r"with surrounding spaces: remove them from the file's header\)"):
        load_recording(p, time="t_s", velocity="v_ms", force="F_N")
    with pytest.raises(DataError, match=r"column 'zz' \(given for time\) not found; available columns: ' t_s ', "
                                        r"' v_ms ', ' F_N '$"):
        load_recording(p, time="zz", velocity="v_ms", force="F_N")


def test_a_result_edited_in_one_place_only_is_refused():
    """Round 7: `report` of a result whose model was edited (positive.Fc 1 -> 5) and table not showed
    the table's 1 beside curves of the model's 5 (only `--static-json` checked the agreement)."""
    from frictionkit.identify.result import IdentificationResult

    doc = copy.deepcopy(_FIT)
    doc["model"]["Fc"] = 2.0
    with pytest.raises(DataError, match=r"^parameters.Fc.value = 1 disagrees with model.Fc = 2; the file was edited "
                                        r"in one place only — make them agree$"):
        IdentificationResult.from_dict(doc)
    lugre = dict(copy.deepcopy(_FIT), model={"type": "LuGre", "static": _FIT["model"], "sigma0": 1e5, "sigma1": 300.0})
    assert IdentificationResult.from_dict(lugre).params["Fc"] == 1.0  # a dynamic law's Fc is its static.Fc
    lugre["model"]["static"]["sigma2"] = 0.5
    with pytest.raises(DataError, match=r"parameters.sigma2.value = 0.4 disagrees with model.static.sigma2 = 0.5"):
        IdentificationResult.from_dict(lugre)
