"""Monte-Carlo study on Dask: identical rows with and without Dask, resumable, the CLI."""

from __future__ import annotations

import json
from pathlib import Path

import numpy as np
import pandas as pd
from typer.testing import CliRunner

import frictionkit.cli.fleet  # noqa: F401  (registers the ``study`` command)
from frictionkit.cli import app
from frictionkit.study import StudySpec, load_study, run_study

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
    s = a.to_dict()["compensators"]
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


def test_study_on_the_emps_preset(tmp_path):
    spec = tmp_path / "emps.toml"
    spec.write_text('[machine]\npreset = "emps"\n[reference]\nduration = 2.0\n[spread]\nFc = 0.3\nsigma2 = 0.2\n'
                    '[study]\ndraws = 2\nseeds = 1\ncompensators = ["none", "coulomb"]\n')
    res = run_study(spec, out=tmp_path / "e.parquet", scheduler="none", progress=False)
    df = res.table
    assert len(df) == 4 and df["ok"].all(), df["error"].tolist()
    assert (df["mass"] == 95.1089).all()  # README of the EMPS data: published M, not spread here
    # the benchmark's P position loop (kp = 160.18 1/s, README) lags a ramp by v/kp: the 0.1 m,
    # 0.2 Hz sine peaks at 0.126 m/s -> 0.78 mm; friction adds about F/(gtau kv kp) ~ 30 um
    lag = 0.1 * 2 * np.pi * 0.2 / 160.18
    assert np.all(np.abs(df["max_error"] / lag - 1) < 0.08)
    t = df.pivot(index="draw", columns="compensator", values="max_error")
    assert (t["coulomb"] < t["none"]).all()  # the nominal friction feed-forward helps on every draw
    from frictionkit.errors import DataError
    import pytest

    with pytest.raises(DataError, match="preset"):
        StudySpec(machine={"preset": "hexapod"})


EXAMPLES = Path(__file__).resolve().parents[2] / "examples" / "study"


def test_study_on_the_ballscrew_stage_dask_equals_single_process(cluster, tmp_path):
    """The example spec, cut to 2 draws x 4 compensators of the first reversal (0.65 s)."""
    from frictionkit.compensate import compensate
    from frictionkit.presets import zhu_fujimoto as zf

    ex = load_study(EXAMPLES / "ballscrew.toml")
    assert ex.machine["preset"] == "ballscrew" and ex.study["compensators"] == ["none", "coulomb", "sinc", "sigmoid"]
    spec = StudySpec(machine=ex.machine, reference={**ex.reference, "duration": 0.65}, spread=ex.spread,
                     study={**ex.study, "draws": 2, "seeds": 1})
    a = run_study(spec, out=tmp_path / "a.parquet", workers=0, progress=False)
    b = run_study(spec, out=tmp_path / "b.parquet", scheduler=cluster.scheduler_address, progress=False)
    cols = ["run", "draw", "compensator", "guide_friction", "nut_friction", "presliding_length", "ok", "max_error",
            "rms_error", "reversal_error", "max_error_measured", "max_force"]
    # the same numbers, to 1e-9 relative rather than bit for bit: a Dask worker runs BLAS single-threaded
    # (the nanny sets OPENBLAS/OMP_NUM_THREADS=1) and since the machine kernel's site solves stop at SITE_XTOL
    # 1e-15 m the last bits of the linear algebra reach the errors (draw 0, none: 7.704678243430907e-06 m here,
    # 7.70467824247334e-06 m with OPENBLAS_NUM_THREADS=1 in this process too: 1.2e-10 relative)
    pd.testing.assert_frame_equal(a.table[cols], b.table[cols], check_exact=False, rtol=1e-9, atol=0.0)
    df = a.table
    assert len(df) == 8 and df["ok"].all(), df["error"].tolist()
    # draws within the spread around the preset's assumptions, the same for every compensator
    assert np.all(np.abs(df["guide_friction"] / zf.GUIDE_FRICTION - 1) <= 0.3)
    assert np.all(np.abs(df["nut_friction"] * zf.R / zf.NUT_FRICTION_TORQUE - 1) <= 0.3)
    assert df.groupby("draw")["nut_friction"].nunique().eq(1).all()
    assert df.loc[df["compensator"] == "none", "max_error"].nunique() == 2  # the draws reach the plant
    # seed 001 Table 3: each compensator lowers the reversal error of the uncompensated stage, on every draw
    t = df.pivot(index="draw", columns="compensator", values="max_error")
    for comp in ("coulomb", "sinc", "sigmoid"):
        assert (t[comp] < t["none"]).all(), comp
    # zero spread: the study's machine is the one of `frictionkit compensate ballscrew`
    nominal = StudySpec(machine={"preset": "ballscrew"}, reference={"duration": 0.65}, spread={},
                        study={"draws": 1, "compensators": ["sinc"]})
    row = run_study(nominal, out=tmp_path / "n.parquet", workers=0, progress=False).table.iloc[0]
    ref = compensate("ballscrew", ["sinc"], quick=True).rows["sinc"]
    assert (row["max_error"], row["rms_error"], row["reversal_error"]) == (
        ref["max_error"], ref["rms_error"], ref["reversal_error"])


def test_ballscrew_spec_checks():
    import pytest

    from frictionkit.errors import DataError

    for kw, match in (({"spread": {"Fc": 0.2}}, "spreadable"), ({"study": {"compensators": ["static"]}}, "compensators"),
                      ({"reference": {"dt": 1e-3}}, "dt"), ({"machine": {"preset": "ballscrew", "law": "lugre"}}, "law"),
                      ({"machine": {"preset": "ballscrew", "nut_model": "rolling"}}, "nut_model"),
                      ({"machine": {"preset": "ballscrew", "guide_friction": -1.0}}, "guide_friction")):
        kw = {**kw, "machine": kw.get("machine", {"preset": "ballscrew"})}
        with pytest.raises(DataError, match=match):
            StudySpec(**kw)


def test_study_cli_exits_1_when_every_run_failed(tmp_path):
    from typer.testing import CliRunner

    spec = tmp_path / "bad_runs.toml"  # a valid spec whose plant every run refuses: flank friction > nut level
    spec.write_text('[machine]\npreset = "ballscrew"\nnut_model = "flank"\nnut_friction = 1.0\n[reference]\n'
                    'duration = 0.65\n[spread]\n[study]\ndraws = 2\ncompensators = ["none"]\n')
    res = CliRunner().invoke(app, ["study", str(spec), "--out", str(tmp_path / "s.parquet"), "--workers", "0",
                                   "--no-progress"])
    err = (res.stderr if hasattr(res, "stderr") else res.output).strip()
    assert res.exit_code == 1, res.output
    assert len(err.splitlines()) == 1 and err.startswith("error: all 2 run(s) failed") and "nut_friction" in err, err
    assert not pd.read_parquet(tmp_path / "s.parquet")["ok"].any()
