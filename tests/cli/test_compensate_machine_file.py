"""``frictionkit compensate MACHINE.json --test SPEC.toml`` and the ``format`` of compensate/study JSON.

The check that can fail: the EMPS machine saved to a file and run with a test spec that states
the preset's own experiment (0.1 m, 0.2 Hz sine, reference velocity, feed-forward at the
friction site) gives exactly the ``compensate emps`` preset's table — two routes written apart
(the preset builds its machine and feed-forward in code, :func:`frictionkit.compensate._emps`).
"""

from __future__ import annotations

import json

import numpy as np
import pytest
from typer.testing import CliRunner

import frictionkit as fk
from frictionkit.cli import _register, app
from frictionkit.compensate import CompensationTest, compensate

_register()
runner = CliRunner()

SPEC = """format = "frictionkit.compensation-test/1"
[inputs]
qg = "ref.csv:qg"
vref = "ref.csv:vref"
[score]
position = "q"
reference = "qg"
[compensation]
velocity = "vref"
site = "friction"
[compensators]
coulomb = "published.json"
"""


@pytest.fixture(scope="module")
def emps(tmp_path_factory):
    from frictionkit.presets.emps import PUBLISHED, emps_machine

    d = tmp_path_factory.mktemp("emps_comp")
    true = fk.CoulombViscous(Fc=PUBLISHED["Fc"], sigma2=PUBLISHED["Fv"])
    fk.save_model(emps_machine(M=PUBLISHED["M"], friction=true, offset=PUBLISHED["offset"]), d / "emps.json")
    fk.save_model(true, d / "published.json")
    # the preset's experiment (compensate.py module docstring): 0.1 m, 0.2 Hz sine at 1 kHz, 5 s
    t = np.arange(5001) * 1e-3
    w = 2 * np.pi * 0.2
    np.savetxt(d / "ref.csv", np.column_stack([t, 0.1 * np.sin(w * t), 0.1 * w * np.cos(w * t)]), delimiter=",",
               header="t,qg,vref", comments="", fmt="%.17g")
    (d / "test.toml").write_text(SPEC)
    preset = compensate("emps", ["none", "coulomb"], quick=True)
    return d, preset


def test_machine_file_with_test_is_the_preset(emps):
    d, preset = emps
    res = compensate(d / "emps.json", ["none", "coulomb"], test=d / "test.toml", quick=True)
    assert res.status == 0 and res.unit == "m" and res.t.size == preset.t.size == 2501
    for name in ("none", "coulomb"):
        assert res.rows[name] == preset.rows[name], name
    assert res.reversals == pytest.approx(preset.reversals)
    assert res.rows["coulomb"]["max_error"] < res.rows["none"]["max_error"]


def test_cli_json_parses_and_carries_the_format(emps):
    d, preset = emps
    out = runner.invoke(app, ["compensate", str(d / "emps.json"), "--test", str(d / "test.toml"), "--quick",
                              "--model", str(d / "published.json"), "--json", "-"])
    assert out.exit_code == 0, out.output
    doc = json.loads(out.stdout)
    assert doc["format"] == "frictionkit.compensation/1" and doc["preset"] == str(d / "emps.json")
    assert list(doc["compensators"]) == ["none", "coulomb", "model"]
    # --model with the true law is the spec's 'coulomb' compensator: the same runs
    assert doc["compensators"]["model"] == doc["compensators"]["coulomb"]
    assert doc["compensators"]["none"]["max_error"] == preset.rows["none"]["max_error"]
    table = runner.invoke(app, ["compensate", str(d / "emps.json"), "--test", str(d / "test.toml"), "--quick",
                                "--compensator", "none"])
    assert table.exit_code == 0 and f"{preset.rows['none']['max_error'] * 1e6:.3f}" in table.output


def _spec(d, text, name="bad.toml"):
    (d / name).write_text(text)
    return d / name


@pytest.mark.parametrize("args, message", [
    (["{m}"], "carries no compensation test: give one with --test SPEC.toml"),
    (["emps", "--test", "{spec}"], "--test: for a machine model file; preset 'emps' has its own test motion"),
    (["{m}", "--test", "{d}/missing.toml"], "--test '{d}/missing.toml': not found"),
    (["{m}", "--test", "{spec}", "--compensator", "sinc"], "compensator 'sinc': machine file '{m}' supports "
                                                            "none, coulomb, model"),
    (["{m}", "--test", "@" + SPEC.replace('position = "q"', 'position = "z"')],
     "position = 'z' is not a degree of freedom of machine 'EMPS' (q)"),
    (["{m}", "--test", "@" + SPEC.replace('site = "friction"', 'site = "nut"')],
     "site 'nut' not in machine 'EMPS' (sites: friction)"),
    (["{m}", "--test", "@" + SPEC.replace('qg = "ref.csv:qg"\n', 'qg = "ref.csv:qg"\n').replace(
        'vref = "ref.csv:vref"\n', '')], "velocity = 'vref' is not one of the inputs (qg)"),
    (["{m}", "--test", "@" + SPEC.replace('[score]\nposition = "q"\nreference = "qg"\n', '')],
     "[score] missing or not a table (keys position, reference)"),
    (["{m}", "--test", "@" + SPEC.replace('coulomb = "published.json"', 'none = "published.json"')],
     "compensator name 'none' is reserved"),
    (["{m}", "--test", "@speed = 3\n" + SPEC], "unknown key(s) speed"),
    (["{m}", "--test", "@" + SPEC + "fast = 3\n"], "[compensators] fast = 3: must be a law or model file name"),
    (["{m}", "--test", "@" + SPEC.replace("compensation-test/1", "compensation-test/2")],
     "format 'frictionkit.compensation-test/2'; this frictionkit reads 'frictionkit.compensation-test/1'"),
    (["{m}", "--test", "@" + SPEC.replace('"ref.csv:qg"', '"ref.csv:qq"')],
     "column 'qq' (given for input qg) not found"),
    (["{m}", "--test", "@" + SPEC.replace("[inputs]", 'dt = 0.001\n[inputs]')],
     "dt/duration come from the input files here; drop them"),
])
def test_bad_input_says_why_in_one_line(emps, args, message):
    d, _ = emps
    m = d / "emps.json"
    spec = d / "test.toml"
    argv = []
    for a in args:
        if a.startswith("@"):  # an inline spec written next to the good one
            a = str(_spec(d, a[1:]))
        argv.append(a.format(m=m, spec=spec, d=d))
    res = runner.invoke(app, ["compensate", *argv])
    assert res.exit_code == 2, res.output
    line = res.output.strip()
    assert "\n" not in line and line.startswith("error: ") and message.format(m=m, d=d) in line, line


def test_test_object_validates_itself():
    with pytest.raises(fk.ParameterError, match=r"dt = -1: must be a finite number > 0"):
        CompensationTest(inputs={"r": np.zeros(3)}, dt=-1, position="q", reference="r", velocity="r", site="s")
    with pytest.raises(fk.DataError, match=r"inputs must be 1-D arrays of one length"):
        CompensationTest(inputs={"r": np.zeros(3), "v": np.zeros(4)}, dt=1e-3, position="q", reference="r",
                         velocity="v", site="s")
    with pytest.raises(fk.ParameterError, match=r"settle_fraction = 1.0: must be in \[0, 1\)"):
        CompensationTest(inputs={"r": np.zeros(3)}, dt=1e-3, position="q", reference="r", velocity="r", site="s",
                         settle_fraction=1.0)


# --------------------------------------------------------------------------- format dispatch in the report
def test_report_dispatches_on_format_and_still_reads_old_files(tmp_path):
    from frictionkit.report.adapters import sections_from_file

    row = {"ok": True, "message": "ok", "max_error": 1e-6, "rms_error": 1e-6, "reversal_error": None}
    comp = {"format": "frictionkit.compensation/1", "preset": "p", "quick": True, "model": None, "duration_s": 1.0,
            "reversals_s": [], "units": {"error": "m"}, "compensators": {"none": row}, "status": 0, "message": "ok"}
    summ = {"format": "frictionkit.study/1", "out": "s.parquet", "runs": 2, "computed": 2, "skipped": 0,
            "other_version": 0, "elapsed_s": 1.0,
            "compensators": {"none": {"runs": 2, "failed": 0, "max_error_median_m": 1e-6, "max_error_p95_m": 2e-6,
                                      "rms_error_median_m": 5e-7}}}
    for doc, kind in ((comp, "compensation"), (summ, "study-summary")):
        for with_format in (True, False):
            d = dict(doc) if with_format else {k: v for k, v in doc.items() if k != "format"}
            p = tmp_path / f"{kind}_{with_format}.json"
            p.write_text(json.dumps(d))
            assert sections_from_file(p)[0] == kind, (kind, with_format)
    # the format decides, not the keys: a compensation document labelled as a study is read as one
    p = tmp_path / "mislabelled.json"
    p.write_text(json.dumps({**comp, "format": "frictionkit.study/1"}))
    assert sections_from_file(p)[0] == "study-summary"
    p.write_text(json.dumps({**comp, "format": "frictionkit.compensation/9"}))
    with pytest.raises(fk.DataError, match=r"'frictionkit.compensation/1', 'frictionkit.study/1'"):
        sections_from_file(p)


def test_study_json_carries_its_format(tmp_path):
    """A StudyResult's --json form names its format, and the report reads it back by that format."""
    import pandas as pd

    from frictionkit.report.adapters import sections_from_file
    from frictionkit.study import StudyResult

    table = pd.DataFrame({"compensator": ["none", "none", "coulomb", "coulomb"], "ok": [True] * 4,
                          "max_error": [3e-6, 4e-6, 1e-6, 2e-6], "rms_error": [1e-6, 1e-6, 5e-7, 5e-7]})
    doc = StudyResult(out=tmp_path / "s.parquet", table=table, runs=4, computed=4, skipped=0, elapsed=0.1).to_dict()
    assert doc["format"] == "frictionkit.study/1"
    (tmp_path / "s.json").write_text(json.dumps(doc))
    kind, (sec,) = sections_from_file(tmp_path / "s.json")
    # best first by the median max tracking error (study.RANK_BY): coulomb 1.5 um before none 3.5 um
    assert kind == "study-summary" and [r[0] for r in sec.table[1:]] == ["coulomb", "none"]


def test_a_row_whose_error_statistics_overflow_is_not_ok(emps, tmp_path):
    """A spec with vref = 1e300 drove the feed-forward to ~1e302 m errors: the coulomb row said 'ok'
    with RMS inf (issue 13 round 4, found by helper rob)."""
    d, _ = emps
    spec = tmp_path / "huge.toml"
    spec.write_text(SPEC.replace('vref = "ref.csv:vref"', "vref = 1e300").replace('"published.json"',
                                                                                  f'"{d / "published.json"}"'))
    for f in ("ref.csv",):
        (tmp_path / f).write_bytes((d / f).read_bytes())
    res = compensate(d / "emps.json", ["none", "coulomb"], test=spec, quick=True)
    assert res.rows["none"]["ok"]
    row = res.rows["coulomb"]
    assert not row["ok"] and row["rms_error"] is None and "overflow" in row["message"]
    assert res.status == 1 and "coulomb" in res.message
