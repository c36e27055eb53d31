"""``frictionkit fleet`` through typer's CliRunner: simulate, identify (no Dask), monitor, errors."""

from __future__ import annotations

import json

import pandas as pd
import pytest
from typer.testing import CliRunner

import frictionkit.cli.fleet  # noqa: F401  (registers the ``fleet`` group)
from frictionkit.cli import app

runner = CliRunner()


def _stderr(res) -> str:
    try:
        return res.stderr
    except ValueError:  # older click mixes the streams
        return res.output


def test_simulate_identify_monitor(tmp_path):
    fleet = tmp_path / "fleet"
    res = runner.invoke(app, ["fleet", "simulate", "--axes", "2", "--days", "2", "--out", str(fleet), "--seed", "3",
                              "--broken", "1", "--json", "-"])
    assert res.exit_code == 0, res.output
    doc = json.loads(res.stdout)
    assert doc["files"] == 4 and len(doc["broken"]) == 1
    assert (fleet / "broken.txt").read_text().strip() == doc["broken"][0]

    out = tmp_path / "r.parquet"
    summary = tmp_path / "s.json"
    res = runner.invoke(app, ["fleet", "identify", str(fleet), "--out", str(out), "--workers", "0", "--no-progress",
                              "--json", str(summary)])
    assert res.exit_code == 0, res.output
    s = json.loads(summary.read_text())
    assert (s["tasks"], s["ok"], s["errors"], s["scheduler"]) == (4, 3, 1, "none")
    df = pd.read_parquet(out)
    assert {"axis", "period", "ok", "error", "Fc_pos", "Fc_neg", "drift_flag"} <= set(df.columns)
    assert "1 with an error" in res.stdout
    assert "warning: 1 of 4 log file(s) failed" in _stderr(res)  # partial failure: exit 0, counted
    assert "match no [layout] pattern" not in _stderr(res)  # the simulator's truth.csv ... are not recordings

    res = runner.invoke(app, ["fleet", "identify", str(fleet), "--out", str(out), "--workers", "0", "--no-progress",
                              "--json", "-"])
    assert res.exit_code == 0 and json.loads(res.stdout)["skipped"] == 4

    out2 = tmp_path / "m.parquet"
    res = runner.invoke(app, ["fleet", "monitor", str(out), "--out", str(out2), "--min-periods", "3", "--json", "-"])
    assert res.exit_code == 0, res.output
    assert json.loads(res.stdout)["axes"] == 2
    assert "drift_flag" in pd.read_parquet(out2).columns


def test_identify_exits_1_when_every_log_failed(tmp_path):
    fleet = tmp_path / "fleet"
    res = runner.invoke(app, ["fleet", "simulate", "--axes", "1", "--days", "2", "--out", str(fleet), "--broken", "2"])
    assert res.exit_code == 0, res.output
    broken = (fleet / "broken.txt").read_text().split()
    assert len(broken) == 2
    out = tmp_path / "r.parquet"
    res = runner.invoke(app, ["fleet", "identify", str(fleet), "--out", str(out), "--workers", "0", "--no-progress",
                              "--json", str(tmp_path / "s.json")])
    err = _stderr(res).strip()
    assert res.exit_code == 1, res.output
    assert len(err.splitlines()) == 1 and err.startswith("error: all 2 log file(s) failed"), err
    df = pd.read_parquet(out)  # the rows with their errors are still written, and the summary
    assert len(df) == 2 and not df["ok"].any() and df["error"].iloc[0] in err
    assert json.loads((tmp_path / "s.json").read_text())["errors"] == 2


@pytest.mark.parametrize("args, needle", [
    (["fleet", "simulate", "--axes", "0", "--days", "1", "--out", "x"], "--axes 0"),
    (["fleet", "simulate", "--axes", "1", "--days", "1", "--out", "x", "--format", "xlsx"], "--format"),
    (["fleet", "identify", "{fleet}", "--out", "{tmp}/r.parquet", "--scheduler", "not an address"], "--scheduler"),
    (["fleet", "identify", "{fleet}", "--out", "{tmp}/r.parquet", "--scheduler", "tcp://h:1", "--workers", "2"],
     "drop --workers"),
    (["fleet", "identify", "{fleet}", "--out", "{tmp}/r.csv", "--workers", "0"], ".parquet"),
    (["fleet", "identify", "{tmp}", "--out", "{tmp}/r.parquet"], "no configuration"),
    (["fleet", "identify", "{fleet}", "--out", "{tmp}/r.parquet", "--config", "{tmp}/none.toml"], "--config"),
    (["fleet", "monitor", "{tmp}/none.parquet"], "not found"),
    (["fleet", "monitor", "{fleet}/fleet.toml"], "cannot be read as Parquet"),
    (["fleet", "monitor", "{fleet}/fleet.toml", "--alpha", "0.9"], "--alpha"),
])
def test_errors_are_one_line(tmp_path, small_fleet, args, needle):
    args = [a.format(fleet=small_fleet.root, tmp=tmp_path) for a in args]
    res = runner.invoke(app, args)
    err = _stderr(res).strip()
    assert res.exit_code == 2, res.output
    assert len(err.splitlines()) == 1 and err.startswith("error: ") and needle in err, err


def test_bad_config_is_one_line(tmp_path, small_fleet):
    cfg = tmp_path / "bad.toml"
    cfg.write_text('[columns]\ntime = "t_s"\nforce = "F_N"\nvelocity = "v"\n[units]\nforce = "furlong"\n')
    res = runner.invoke(app, ["fleet", "identify", str(small_fleet.root), "--out", str(tmp_path / "r.parquet"),
                              "--config", str(cfg)])
    assert res.exit_code == 2 and "unknown unit" in _stderr(res) and len(_stderr(res).strip().splitlines()) == 1


def test_help_has_an_example():
    for verb in ("simulate", "identify", "monitor", "report"):
        res = runner.invoke(app, ["fleet", verb, "--help"])
        assert res.exit_code == 0 and "Example" in res.output and f"frictionkit fleet {verb}" in res.output


def test_report_page(dask_run, tmp_path):
    out = tmp_path / "fleet.html"
    res = runner.invoke(app, ["fleet", "report", str(dask_run.out), "--out", str(out), "--json", "-"])
    assert res.exit_code == 0, res.output
    doc = json.loads(res.stdout)
    assert (doc["axes"], doc["rows"], doc["errors"]) == (4, 12, 4)
    page = out.read_text(encoding="utf-8")
    assert "fleet report" in page and page.count("data:image/png;base64,") == 1 + len(doc["drawn"])
    assert "Files that failed (4)" in page and "not finite" in page
    bad = runner.invoke(app, ["fleet", "report", str(dask_run.out), "--out", str(tmp_path / "x.png")])
    assert bad.exit_code == 2 and ".html" in _stderr(bad)
