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
    assert set(doc["table3"]) == {"sinc", "coulomb", "sigmoid"}
    assert all(v["max_error_um"] > 0 for v in doc["table3"].values())
    assert set(doc["ld"]) == {"slow_reverse", "fast_reverse", "slow_non_reverse", "fast_non_reverse"}
    assert all(0.5 < v["min_ratio_before_zero"] < 1.5 for v in doc["ld"].values())
    assert {"mixed_max_error_um", "best_fixed_max_error_um"} <= set(doc["selector"])
    assert (tmp_path / "zf.png").stat().st_size > 10_000


def test_reproduce_requires_json():
    res = CliRunner().invoke(app, ["reproduce", "zhu-fujimoto", "--quick"])
    assert res.exit_code != 0


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
    assert res.exit_code != 0


def test_reproduce_zhu_fujimoto_hertz_nut_model_and_fig2(tmp_path):
    out = tmp_path / "zf.json"
    res = CliRunner().invoke(app, ["reproduce", "zhu-fujimoto", "--quick", "--no-plot", "--nut-model", "hertz",
                                   "--json", str(out)])
    assert res.exit_code == 0, res.output
    doc = json.loads(out.read_text())
    assert doc["nut_model"] == "hertz"
    assert doc["fig2"]["first_antiresonance_hz"] < doc["fig2"]["first_resonance_hz"]
    assert "Fig. 2 check" in res.output
