"""``frictionkit identify`` through typer's CliRunner."""

from __future__ import annotations

import json
from pathlib import Path

from typer.testing import CliRunner

import frictionkit.cli.identify  # noqa: F401  (registers the ``identify`` group)
from frictionkit.cli import app

DATA = Path(__file__).resolve().parents[2].parent / "shared" / "data"
EMPS = DATA / "emps" / "DATA_EMPS.csv"
SCREW = DATA / "tro2021_screw_drives" / "steady_state_records.csv"
runner = CliRunner()

EMPS_ARGS = ["--time", "t_s", "--position", "qm_m", "--force", "vir_V", "--force-scale", "35.15065188248547"]


def _stderr(res) -> str:
    try:
        return res.stderr
    except ValueError:  # older click mixes the streams
        return res.output


def test_rigid_body_emps_json(tmp_path):
    out = tmp_path / "fit.json"
    png = tmp_path / "fit.png"
    res = runner.invoke(app, ["identify", "rigid-body", str(EMPS), *EMPS_ARGS, "--json", str(out), "--plot", str(png)])
    assert res.exit_code == 0, res.output
    d = json.loads(out.read_text(encoding="utf-8"))
    assert {"model", "parameters", "relative_error_percent"} <= set(d)
    assert list(d["parameters"]) == ["M", "Fv", "Fc", "offset"]
    published = {"M": (95.1089, 0.1085, "kg"), "Fv": (203.5034, 1.1460, "N·s/m"),
                 "Fc": (20.3935, 0.1012, "N"), "offset": (-3.1648, 0.0444, "N")}
    for name, (value, se, unit) in published.items():
        p = d["parameters"][name]
        assert abs(p["value"] - value) <= 3 * se
        assert 0 < p["stderr"] < 2 * se
        assert p["unit"] == unit
    assert d["relative_error_percent"] <= 4.2
    assert png.stat().st_size > 1000
    assert "M" in res.stdout and "relative error" in res.stdout


def test_rigid_body_emps_asymmetric_json(tmp_path):
    out = tmp_path / "asym.json"
    res = runner.invoke(app, ["identify", "rigid-body", str(EMPS), *EMPS_ARGS, "--asymmetric", "--json", str(out)])
    assert res.exit_code == 0, res.output
    d = json.loads(out.read_text(encoding="utf-8"))
    assert list(d["parameters"]) == ["M", "Fv_pos", "Fc_pos", "Fv_neg", "Fc_neg"]
    assert d["relative_error_percent"] <= 3.2
    assert abs(d["parameters"]["Fv_neg"]["value"] - 240.4236) <= 3 * 1.2346


def test_missing_column_is_one_line_error():
    res = runner.invoke(app, ["identify", "rigid-body", str(EMPS), "--time", "t_s", "--position", "qm",
                              "--force", "vir_V"])
    assert res.exit_code != 0
    err = _stderr(res).strip()
    assert len(err.splitlines()) == 1
    assert err.startswith("error: ") and "column 'qm' (given for position) not found" in err
    assert "Traceback" not in res.output


def test_unknown_file_type_and_missing_file(tmp_path):
    p = tmp_path / "run.xyz"
    p.write_text("1,2\n")
    res = runner.invoke(app, ["identify", "rigid-body", str(p), "--time", "t", "--position", "x", "--force", "F"])
    assert res.exit_code == 2
    assert "unknown file type '.xyz'" in _stderr(res)
    res = runner.invoke(app, ["identify", "static", str(tmp_path / "none.csv"), "--time", "t", "--velocity", "v",
                              "--force", "F"])
    assert res.exit_code == 2 and "not found" in _stderr(res)


def test_static_screw_drive_grouped(tmp_path):
    out = tmp_path / "static.json"
    res = runner.invoke(app, ["identify", "static", str(SCREW), "--time", "t_s",
                              "--velocity", "motor_velocity_rad_per_s", "--force", "motor_torque_N_m",
                              "--group", "source_file", "--where", "drive_id=1", "--direction", "both",
                              "--force-unit", "N·m", "--velocity-unit", "rad/s", "--json", str(out)])
    assert res.exit_code == 0, res.output
    assert "32 steady-state point(s)" in res.stdout  # drive 1: 16 speeds each way (README)
    d = json.loads(out.read_text(encoding="utf-8"))
    assert set(d["parts"]) == {"positive", "negative"}
    assert d["parameters"]["Fc_pos"]["unit"] == "N·m"
    assert 1.5e-3 < d["parameters"]["Fc_pos"]["value"] < 3.2e-3
    assert 2.5e-3 < d["parameters"]["Fc_neg"]["value"] < 4.0e-3


def test_static_needs_velocity_or_position(tmp_path):
    p = tmp_path / "a.csv"
    p.write_text("t,F\n0,1\n0.1,1\n")
    res = runner.invoke(app, ["identify", "static", str(p), "--time", "t", "--force", "F"])
    assert res.exit_code == 2
    assert _stderr(res).strip() == "error: give --velocity or --position"


def test_subprocess_error_has_one_stderr_line_and_nonzero_status():
    import subprocess
    import sys

    code = "import frictionkit.cli.identify; from frictionkit.cli import app; app()"
    proc = subprocess.run([sys.executable, "-c", code, "identify", "rigid-body", str(EMPS), "--time", "t_s",
                           "--position", "qm_m", "--force", "torque"], capture_output=True, text=True, timeout=60)
    assert proc.returncode == 2  # bad input
    lines = proc.stderr.strip().splitlines()
    assert len(lines) == 1 and "column 'torque' (given for force) not found" in lines[0]
    assert proc.stdout == ""
