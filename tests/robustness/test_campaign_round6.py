"""Issue 13, campaign round 6 (helper camp): one test per pattern fixed, each built from the case
that exposed it. Read-only cases run as root without the file-permission capabilities
(``setpriv``, util-linux: in every Debian image) — root's CAP_DAC_OVERRIDE made chmod not bite."""

from __future__ import annotations

import json
import os
import shutil
import subprocess
import sys
from pathlib import Path

import pytest

import frictionkit.report.demo as demo
from frictionkit.errors import DataError, IdentificationError

#: Runs a command as root with the permission bits enforced (no CAP_DAC_OVERRIDE / CAP_DAC_READ_SEARCH).
_UNPRIVILEGED = ["setpriv", "--bounding-set", "-dac_override,-dac_read_search", "--inh-caps=-all"]


def _unprivileged_python(code: str, cwd: Path) -> subprocess.CompletedProcess:
    """``python -c code`` where chmod bites: as is for a normal user, through setpriv for root."""
    cmd = [sys.executable, "-c", code]
    if os.geteuid() == 0:
        if shutil.which("setpriv") is None:
            pytest.skip("running as root and setpriv (util-linux) is not installed")
        cmd = _UNPRIVILEGED + cmd
    return subprocess.run(cmd, cwd=cwd, capture_output=True, text=True, timeout=60)


_SCRIPT = """
from frictionkit._io import atomic_write_text, check_output_file
from frictionkit.errors import DataError
from frictionkit.fleet.dataset import _candidates
try:
    check_output_file("prot.json", option="--json")
except DataError as e:
    print("check:", e)
try:
    atomic_write_text("prot.json", "new")
except PermissionError as e:
    print("write:", e.strerror)
atomic_write_text("fresh.json", "new")  # a new file in the same folder is fine
try:
    print(_candidates("fleet"))
except DataError as e:
    print("fleet:", e)
"""


@pytest.fixture(scope="module")
def unprivileged(tmp_path_factory):
    """One unprivileged run (one import of frictionkit) for both permission cases: a read-only result
    file and a fleet with an axis folder that cannot be read."""
    tmp = tmp_path_factory.mktemp("readonly")
    (tmp / "prot.json").write_text("old")
    (tmp / "prot.json").chmod(0o444)
    for axis in ("axis-0001", "axis-0002"):
        (tmp / "fleet" / axis).mkdir(parents=True)
        (tmp / "fleet" / axis / "2026-01-05.csv").write_text("t,x\n0,0\n")
    (tmp / "fleet" / "axis-0002").chmod(0o000)
    try:
        res = _unprivileged_python(_SCRIPT, tmp)
    finally:
        (tmp / "fleet" / "axis-0002").chmod(0o755)
    assert res.returncode == 0, res.stderr
    return tmp, res.stdout


def test_a_read_only_result_file_is_not_replaced(unprivileged):
    """Was: `models --json prot.json` replaced a 0444 file (the rename needs only the folder's permission)."""
    tmp, out = unprivileged
    assert "check: --json 'prot.json': the file is read-only; refusing to replace it" in out
    assert "write: cannot write 'prot.json': the file is read-only" in out
    assert (tmp / "prot.json").read_text() == "old"
    assert (tmp / "fresh.json").read_text() == "new"
    assert [p.name for p in tmp.iterdir() if p.name.endswith(".tmp")] == []


def test_an_unreadable_fleet_folder_is_named(unprivileged):
    """Was: an axis folder without read permission left that axis out of the table without a word."""
    _, out = unprivileged
    assert ("fleet: fleet dataset 'fleet': 1 folder(s) cannot be read: 'fleet/axis-0002' (Permission denied); "
            "their logs would be left out") in out


def _fast_sections(monkeypatch):
    def tiny(title):
        return lambda *a, **k: demo._Section(title, text=["ok"])

    for name in ("section_laws", "section_parity", "section_zhu_fujimoto", "section_fleet", "section_study"):
        monkeypatch.setattr(demo, name, tiny(name))


def test_demo_leaves_out_a_section_naming_the_missing_file_or_the_failure(tmp_path, monkeypatch):
    """Was: DATA_EMPS.csv present without emps_constants.json, or a truncated screw-drive CSV, ended
    the whole demo (after a minute of work) with FileNotFoundError / IdentificationError."""
    _fast_sections(monkeypatch)
    shared = tmp_path / "shared"
    (shared / "emps").mkdir(parents=True)
    (shared / "emps" / "DATA_EMPS.csv").write_text("t_s,qm_m\n0,0\n")

    def failing_fit(_shared):
        raise IdentificationError("positive direction: 1 steady-state point(s)")

    monkeypatch.setattr(demo, "section_screw", failing_fit)
    res = demo.run_demo(tmp_path / "out", shared=shared)
    assert res["skipped"] == [
        f"EMPS identification: left out, '{shared / 'emps' / 'emps_constants.json'}' not found",
        f"screw-drive static maps: left out, its data under '{shared}' failed (IdentificationError: positive "
        "direction: 1 steady-state point(s))"]
    assert "section_study" in res["sections"]  # the rest of the demo ran
    summary = (tmp_path / "out" / "summary.txt").read_text(encoding="utf-8")
    assert "emps_constants.json' not found" in summary

    def bug(*_):  # a failure outside the real-data sections is not hidden
        raise IdentificationError("x")

    monkeypatch.setattr(demo, "section_parity", bug)
    with pytest.raises(IdentificationError):
        demo.run_demo(tmp_path / "out2", shared=shared)


def _compensation_doc(preset: str) -> dict:
    return {"format": "frictionkit.compensation/1", "preset": preset, "quick": True, "model": None,
            "duration_s": 2.5, "reversals_s": [1.25], "reversal_window_s": [-0.05, 0.1], "units": {"error": "m"},
            "compensators": {"none": {"ok": True, "message": "ok", "max_error": 8.2e-4, "rms_error": 5.5e-4,
                                      "reversal_error": 1.2e-4}}}


def test_report_names_a_machine_file_compensation_as_such():
    """Was: "Compensation on the /tmp/x/emps.json preset"; a hand-edited "preset": null was titled 'None'."""
    from frictionkit.report.adapters import compensation_sections

    sec = compensation_sections(_compensation_doc("/tmp/x/emps.json"))[0]
    assert sec.title.startswith("Compensation on the machine file '/tmp/x/emps.json' (2.5 s")
    assert sec.figures[0][0] == "compensate_emps.png"
    assert compensation_sections(_compensation_doc("emps"))[0].title.startswith("Compensation on the emps preset")
    for bad in (None, 5, ""):
        with pytest.raises(DataError, match=r'"preset" = .*: expected a preset name \(ballscrew, emps, sdss\)'):
            compensation_sections(_compensation_doc(bad))


def test_a_compensation_spec_without_format_is_read_as_version_1(tmp_path):
    """Decision (round 6): `format` is optional, as documented in the README and CompensationTest.load;
    a spec naming another format is refused."""
    from frictionkit.compensate import TEST_FORMAT, CompensationTest

    assert TEST_FORMAT == "frictionkit.compensation-test/1"
    (tmp_path / "ref.csv").write_text("t,qg,vref\n0,0,1\n0.001,0.001,1\n0.002,0.002,-1\n")
    doc = {"format": TEST_FORMAT, "inputs": {"qg": "ref.csv:qg", "vref": "ref.csv:vref"},
           "score": {"position": "q", "reference": "qg"}, "compensation": {"velocity": "vref", "site": "friction"}}
    (tmp_path / "with.json").write_text(json.dumps(doc))
    (tmp_path / "without.json").write_text(json.dumps({k: v for k, v in doc.items() if k != "format"}))
    a, b = CompensationTest.load(tmp_path / "with.json"), CompensationTest.load(tmp_path / "without.json")
    assert a.n == b.n == 3 and sorted(a.inputs) == sorted(b.inputs) == ["qg", "vref"]
    (tmp_path / "v2.json").write_text(json.dumps(dict(doc, format="frictionkit.compensation-test/2")))
    with pytest.raises(DataError, match="format 'frictionkit.compensation-test/2'; this frictionkit reads"):
        CompensationTest.load(tmp_path / "v2.json")


def test_the_cli_says_when_numba_jit_is_disabled(runner, monkeypatch):
    """NUMBA_DISABLE_JIT=1 ran the README examples to the same results (bit for bit, measured), but the first
    one took 429 s instead of seconds without a word: one warning line now."""
    import frictionkit.cli.models  # noqa: F401  (registers the verb)
    from frictionkit.cli import app
    from frictionkit.cli._errors import jit_disabled_note

    monkeypatch.delenv("NUMBA_DISABLE_JIT", raising=False)
    assert jit_disabled_note() is None
    monkeypatch.setenv("NUMBA_DISABLE_JIT", "0")
    assert jit_disabled_note() is None
    monkeypatch.setenv("NUMBA_DISABLE_JIT", "1")
    res = runner.invoke(app, ["models"])
    assert res.exit_code == 0, res.output
    assert res.stderr.startswith("warning: NUMBA_DISABLE_JIT=1: the simulation kernels run as plain Python")


def test_a_column_given_twice_to_where_is_refused():
    """Was: `--where drive_id=1 --where drive_id=2` fitted drive 2 only (the last value replaced the first)."""
    from frictionkit.cli._common import where_items

    assert where_items(["drive_id=1", "drive_id = 1", "side=a"]) == {"drive_id": "1", "side": "a"}
    with pytest.raises(DataError, match=r"--where drive_id=1 and --where drive_id=2: one value per column"):
        where_items(["drive_id=1", "drive_id=2"])


def test_report_of_a_flagged_run_summary_keeps_its_status(tmp_path):
    """Was: report followed a simulate summary to its traces and dropped the summary's status 2 and
    message (the traces do not carry them): a flagged run read as a good one."""
    from frictionkit.report.adapters import _json_file

    (tmp_path / "traces.csv").write_text("t [s],x [m],v [m/s],friction [N]\n0,0,0,0\n0.001,1e-6,1e-3,0.5\n")
    doc = {"format": "frictionkit.simulation/1", "drive": "position", "samples": 2, "status": 2,
           "message": "the accuracy check failed\nat t = 1 s", "outputs": {"traces": "traces.csv"}}
    (tmp_path / "run.json").write_text(json.dumps(doc))
    kind, secs = _json_file(tmp_path / "run.json", "result file 'run.json'")
    assert kind == "traces"
    assert secs[0].text[0] == ("Run status 2 (from the summary, result file 'run.json'): the accuracy check failed "
                               "at t = 1 s")
    (tmp_path / "run.json").write_text(json.dumps(dict(doc, status=0, message="ok")))
    assert not any("Run status" in t for t in _json_file(tmp_path / "run.json", "x")[1][0].text)


@pytest.mark.parametrize("machine", ["resolution = 1e300", "noise = 0.01", 'preset = "emps"\nresolution = 1.0'])
def test_a_study_scale_coarser_than_the_motion_is_refused(tmp_path, machine):
    """Was: resolution = 1e300 ran with status ok (the scale read 0 throughout, 'max error 3309 µm')."""
    from frictionkit.study import load_study

    p = tmp_path / "s.toml"
    p.write_text(f"[machine]\n{machine}\n")
    with pytest.raises(DataError, match=r"not finer than the reference amplitude .* the scale cannot see the motion"):
        load_study(p)


def test_an_edited_machine_unit_is_refused(tmp_path):
    """Was: "dofs.inertia": "g" in a machine file's units was ignored (the numbers ran as kg)."""
    import frictionkit as fk
    from frictionkit.presets.emps import PUBLISHED, emps_machine

    path = fk.save_model(emps_machine(M=PUBLISHED["M"], friction=fk.CoulombViscous(Fc=20.0, sigma2=200.0),
                                      offset=0.0), tmp_path / "emps.json")
    doc = json.loads(path.read_text())
    doc["units"]["dofs.inertia"] = "g"
    (tmp_path / "g.json").write_text(json.dumps(doc))
    with pytest.raises(DataError, match=r"\"units\"\['dofs.inertia'\] = \"g\": a machine file's units are fixed"):
        fk.load_model(tmp_path / "g.json")
    del doc["units"]["dofs.inertia"]  # a dropped entry (or "units") is fine: derived
    (tmp_path / "ok.json").write_text(json.dumps(doc))
    assert fk.load_model(tmp_path / "ok.json").input_names() == ["qg"]


@pytest.mark.parametrize("edit, match", [
    ({"max_error": "1"}, r"compensator 'none': max_error = \"1\": expected a finite error >= 0"),
    ({"rms_error": True}, "rms_error = true"), ({"reversal_error": -1}, "reversal_error = -1"),
    ({"ok": "x"}, r"ok = \"x\": expected true or false"), ("units", r"\"units\" = \{\"error\": \"x\"\}: expected")])
def test_report_refuses_a_hand_edited_compensation_row(edit, match):
    """Was: "max_error": "1" shown as 1e6 µm, true as 1 m, -1 as a negative error; units 'x' labelled metres x."""
    from frictionkit.report.adapters import compensation_sections

    d = _compensation_doc("emps")
    if edit == "units":
        d["units"] = {"error": "x"}
    else:
        d["compensators"]["none"].update(edit)
    with pytest.raises(DataError, match=match):
        compensation_sections(d)
