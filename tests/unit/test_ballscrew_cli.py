"""``frictionkit reproduce zhu-fujimoto --quick --json OUT`` writes the documented JSON and a PNG."""

import json

from typer.testing import CliRunner

from frictionkit.cli import app
import frictionkit.cli.reproduce  # noqa: F401  (registers the command group)


def test_reproduce_zhu_fujimoto_quick(tmp_path):
    out = tmp_path / "zf.json"
    res = CliRunner().invoke(app, ["reproduce", "zhu-fujimoto", "--quick", "--json", str(out)])
    assert res.exit_code == 0, res.output
    doc = json.loads(out.read_text())
    assert set(doc["table3"]) == {"sinc", "coulomb", "sigmoid", "sigmoid_post_only"}
    assert all(v["max_error_um"] > 0 for v in doc["table3"].values())
    assert doc["table3"]["sigmoid_post_only"]["paper_um"] is None
    assert doc["stage"] == "fig2"  # the default stage
    # Fig. 5(b) on the fig2 stage: the motor input turns to braking ~55 ms before zero speed
    assert 30.0 < doc["fig5b"]["motor_input_reverses_before_zero_ms"] < 80.0
    assert set(doc["fig5"]) == {"slow_reverse", "fast_reverse"}
    assert doc["table2_fast_non_reverse"]["redesigned"]["kind"] == "slow_non_reverse"
    assert set(doc["ld"]) == {"slow_reverse", "fast_reverse", "slow_non_reverse", "fast_non_reverse"}
    assert all(0.5 < v["min_ratio_before_zero"] < 1.5 for v in doc["ld"].values())
    assert {"mixed_max_error_um", "best_fixed_max_error_um"} <= set(doc["selector"])
    assert (tmp_path / "zf.png").stat().st_size > 10_000


def test_reproduce_requires_json():
    res = CliRunner().invoke(app, ["reproduce", "zhu-fujimoto", "--quick"])
    assert res.exit_code == 2 and "Missing option '--json'" in res.output, res.output


def test_reproduce_zhu_fujimoto_flank_nut_model(tmp_path):
    out = tmp_path / "zf.json"
    res = CliRunner().invoke(app, ["reproduce", "zhu-fujimoto", "--quick", "--no-plot", "--nut-model", "flank",
                                   "--json", str(out)])
    assert res.exit_code == 0, res.output
    doc = json.loads(out.read_text())
    assert doc["nut_model"] == "flank"
    assert all(v["max_error_um"] > 0 for v in doc["table3"].values())


def test_reproduce_rejects_unknown_nut_model(tmp_path):
    res = CliRunner().invoke(app, ["reproduce", "zhu-fujimoto", "--quick", "--nut-model", "lost",
                                   "--json", str(tmp_path / "x.json")])
    assert res.exit_code == 2 and "--nut-model 'lost'" in res.output and "sliding" in res.output, res.output
    assert not (tmp_path / "x.json").exists()


def test_reproduce_zhu_fujimoto_hertz_nut_model_and_fig2(tmp_path):
    out = tmp_path / "zf.json"
    res = CliRunner().invoke(app, ["reproduce", "zhu-fujimoto", "--quick", "--no-plot", "--nut-model", "hertz",
                                   "--json", str(out)])
    assert res.exit_code == 0, res.output
    doc = json.loads(out.read_text())
    assert doc["nut_model"] == "hertz"
    assert doc["fig2"]["first_antiresonance_hz"] < doc["fig2"]["first_resonance_hz"]
    assert "Fig. 2 check" in res.output


def test_reproduce_zhu_fujimoto_table1_stage(tmp_path):
    out = tmp_path / "zf.json"
    res = CliRunner().invoke(app, ["reproduce", "zhu-fujimoto", "--quick", "--no-plot", "--stage", "table1",
                                   "--json", str(out)])
    assert res.exit_code == 0, res.output
    doc = json.loads(out.read_text())
    assert doc["stage"] == "table1"
    assert "fig5b" in doc and doc["fig5b"]["motor_input_reverses_before_zero_ms"] is None  # null in the JSON
    assert '"motor_input_reverses_before_zero_ms": null' in out.read_text()
    assert doc["fig2"]["gain_offset_vs_eq1_db"][0] > 6.0
    assert "stage: table1" in res.output


def test_reproduce_rejects_unknown_stage(tmp_path):
    res = CliRunner().invoke(app, ["reproduce", "zhu-fujimoto", "--quick", "--stage", "measured",
                                   "--json", str(tmp_path / "x.json")])
    assert res.exit_code == 2
    assert "--stage 'measured': must be one of table1" in res.output
    assert not (tmp_path / "x.json").exists()
