"""Monte-Carlo study on Dask: identical rows with and without Dask, resumable, the CLI."""

from __future__ import annotations

import json

import pandas as pd
from typer.testing import CliRunner

import frictionkit.cli.fleet  # noqa: F401  (registers the ``study`` command)
from frictionkit.cli import app
from frictionkit.study import StudySpec, run_study

SPEC = """
[machine]
mass = 20.0
law = "lugre"
[reference]
duration = 2.0
[spread]
Fc = 0.3
Fs = 0.3
[study]
draws = 3
seeds = 1
compensators = ["none", "static"]
"""


def test_study_dask_equals_single_process_and_resumes(cluster, tmp_path):
    spec = tmp_path / "study.toml"
    spec.write_text(SPEC)
    a = run_study(spec, out=tmp_path / "a.parquet", scheduler="none", progress=False)
    b = run_study(spec, out=tmp_path / "b.parquet", scheduler=cluster.scheduler_address, progress=False)
    cols = ["run", "draw", "compensator", "Fc", "Fs", "ok", "max_error", "rms_error", "max_error_measured"]
    pd.testing.assert_frame_equal(a.table[cols], b.table[cols], check_exact=True)
    assert len(a.table) == 6 and a.table["ok"].all()
    # the same draws for every compensator; the nominal static map as feed-forward helps
    t = a.table.pivot(index="draw", columns="compensator", values=["Fc", "max_error"])
    assert (t["Fc"]["none"] == t["Fc"]["static"]).all()
    s = a.summary()["compensators"]
    assert s["static"]["max_error_median_m"] < s["none"]["max_error_median_m"]
    parts = sorted((tmp_path / "a.parquet.parts").glob("*.parquet"))
    parts[0].unlink()
    again = run_study(spec, out=tmp_path / "a.parquet", scheduler="none", progress=False)
    assert (again.computed, again.skipped) == (1, 5)
    pd.testing.assert_frame_equal(again.table[cols], a.table[cols])


def test_study_cli_and_errors(tmp_path):
    spec = tmp_path / "study.toml"
    spec.write_text(SPEC.replace("draws = 3", "draws = 1"))
    runner = CliRunner()
    res = runner.invoke(app, ["study", str(spec), "--out", str(tmp_path / "s.parquet"), "--workers", "0",
                              "--no-progress", "--json", "-"])
    assert res.exit_code == 0, res.output
    assert json.loads(res.stdout)["runs"] == 2
    bad = tmp_path / "bad.toml"
    bad.write_text("[spread]\nmu = 0.2\n")
    res = runner.invoke(app, ["study", str(bad), "--out", str(tmp_path / "x.parquet")])
    assert res.exit_code == 2 and "spreadable" in (res.stderr if hasattr(res, "stderr") else res.output)


def test_spec_checks():
    import pytest

    from frictionkit.errors import DataError

    for kw, match in (({"machine": {"law": "gms"}}, "law"), ({"study": {"draws": 0}}, "draws"),
                      ({"study": {"compensators": ["pid"]}}, "compensators"), ({"spread": {"Fc": 1.5}}, "Fc"),
                      ({"machine": {"mass": -1.0}}, "mass")):
        with pytest.raises(DataError, match=match):
            StudySpec(**kw)
