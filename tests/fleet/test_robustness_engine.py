"""The study engine (``frictionkit.study.run_tasks``) under the reproductions' robustness sweeps:
a real two-worker LocalCluster gives the same rows as this process, a rerun skips what is done,
and ``reproduce zhang2023 --robustness`` takes --workers/--scheduler/--out.

Sizes: the zhu-fujimoto sweep is cut to two variants (noise seeds 0 and 1, no stiffness
factors) at ``quick`` size, about 1 s each.
"""

from __future__ import annotations

import json
import math

import pandas as pd
import pytest

from frictionkit.errors import ParameterError
from frictionkit.reproduce import zhang2023 as zr
from frictionkit.reproduce import zhu_fujimoto as zfr
from frictionkit.study import Task, run_tasks


def test_zhu_fujimoto_sweep_on_two_workers_equals_this_process_and_resumes(cluster, tmp_path):
    kw = dict(quick=True, seeds=(0, 1), factors=())
    local = zfr.robustness(**kw, out=tmp_path / "local", workers=0)
    dask = zfr.robustness(**kw, out=tmp_path / "dask", scheduler=cluster.scheduler_address)
    assert list(local) == ["seed=0", "seed=1"]
    assert dask == local  # every number of both summaries, exactly
    # the two seeds are different runs (the noise reaches Table 3), not one result twice
    assert local["seed=0"]["table3"] != local["seed=1"]["table3"]
    a = pd.read_parquet(tmp_path / "local" / "zhu_fujimoto_robustness.parquet")
    b = pd.read_parquet(tmp_path / "dask" / "zhu_fujimoto_robustness.parquet")
    assert list(a["variant"]) == ["seed=0", "seed=1"] and a["ok"].all()
    pd.testing.assert_frame_equal(a[["variant", "ok", "summary"]], b[["variant", "ok", "summary"]], check_exact=True)

    # resumable: a rerun computes nothing; without one part only that variant
    seen = []
    again = zfr.robustness(**kw, out=tmp_path / "dask", workers=0, progress=seen.append)
    assert again == local and seen == []
    parts = sorted((tmp_path / "dask" / "zhu_fujimoto_robustness.parquet.parts").glob("seed=1__*.parquet"))
    assert len(parts) == 1
    parts[0].unlink()
    again = zfr.robustness(**kw, out=tmp_path / "dask", workers=0, progress=seen.append)
    assert again == local and seen == ["seed=1"]


def test_engine_rows_failures_and_checks(tmp_path):
    tasks = [Task(label="a", func=dict, kwargs={"x": 1.5, "nested": {"k": [1, 2]}}),
             Task(label="b", func=math.sqrt, kwargs={"x": 4.0})]  # sqrt takes no keywords: a failing task
    res = run_tasks(tasks, out=tmp_path / "t.parquet", workers=0, progress=False)
    t = res.table
    assert list(t["task"]) == ["a", "b"] and list(t["ok"]) == [True, False]
    assert t.loc[0, "x"] == 1.5 and json.loads(t.loc[0, "nested"]) == {"k": [1, 2]}
    assert t.loc[1, "error"].startswith("TypeError")
    assert res.status == 1 and "b" in res.message and res.to_dict()["failed"] == ["b"]
    # a changed argument changes the tag: recomputed, not reused
    again = run_tasks([Task(label="a", func=dict, kwargs={"x": 2.5}), tasks[1]], out=tmp_path / "t.parquet",
                      workers=0, progress=False)
    assert (again.computed, again.skipped) == (1, 1) and again.table.loc[0, "x"] == 2.5
    with pytest.raises(ParameterError, match="duplicate"):
        run_tasks([tasks[0], tasks[0]], workers=0)
    with pytest.raises(ParameterError, match="label"):
        Task(label="a/b", func=dict)
    with pytest.raises(ParameterError, match="workers"):
        run_tasks(tasks, workers=-1)


def test_zhang2023_cli_robustness_options(monkeypatch, tmp_path):
    from typer.testing import CliRunner

    from frictionkit.cli import _register, app

    _register()
    calls = []

    def fake(**kw):
        calls.append(kw)
        return {"runtime_s": 1.0, "variants": {}, "holds_fraction": {"t7_same0_acim_better": 0.5},
                "sensitivity": {}, "ranking": ["guide_level"], "quick": True, "failed": {}, "computed": 2,
                "skipped": 0, "out": str(tmp_path / "r" / "zhang2023_robustness.parquet")}

    monkeypatch.setattr(zr, "robustness", fake)
    run = CliRunner().invoke
    res = run(app, ["reproduce", "zhang2023", "--robustness", "--quick", "--workers", "2", "--out",
                    str(tmp_path / "r"), "--json", str(tmp_path / "r.json")])
    assert res.exit_code == 0, res.output
    assert calls[-1]["workers"] == 2 and calls[-1]["scheduler"] is None and calls[-1]["out"] == tmp_path / "r"
    assert json.loads((tmp_path / "r.json").read_text())["computed"] == 2
    res = run(app, ["reproduce", "zhang2023", "--robustness", "--scheduler", "tcp://10.0.0.5:8786", "--json",
                    str(tmp_path / "s.json")])
    assert res.exit_code == 0, res.output
    assert calls[-1]["scheduler"] == "tcp://10.0.0.5:8786" and calls[-1]["workers"] is None
    n = len(calls)
    for bad, word in ((["--robustness", "--workers", "-1"], "--workers"),
                      (["--robustness", "--workers", "2", "--scheduler", "tcp://h:1"], "--scheduler"),
                      (["--robustness", "--scheduler", "not an address"], "--scheduler"),
                      (["--workers", "2"], "--robustness")):
        res = run(app, ["reproduce", "zhang2023", *bad, "--json", str(tmp_path / "x.json")])
        assert res.exit_code != 0 and word in res.output, (bad, res.output)
    assert len(calls) == n  # refused before any run


def test_a_part_from_another_frictionkit_version_is_recomputed_and_said(tmp_path):
    import frictionkit

    tasks = [Task(label="a", func=dict, kwargs={"x": 1.0}), Task(label="b", func=dict, kwargs={"x": 2.0})]
    run_tasks(tasks, out=tmp_path / "t.parquet", workers=0, progress=False)
    parts = tmp_path / "t.parquet.parts"
    (part_a,) = parts.glob("a__*.parquet")
    assert part_a.name.endswith(f"__fk{frictionkit.__version__}.parquet")  # the version is in the part's name
    part_a.rename(parts / part_a.name.replace(f"__fk{frictionkit.__version__}", "__fk0.0.1"))
    (part_b,) = parts.glob("b__*.parquet")
    part_b.rename(parts / part_b.name.replace(f"__fk{frictionkit.__version__}", ""))  # before parts had one
    with pytest.warns(UserWarning, match=r"2 result\(s\) .* another frictionkit version \(0\.0\.1, unversioned"):
        again = run_tasks(tasks, out=tmp_path / "t.parquet", workers=0, progress=False)
    assert (again.computed, again.skipped, again.other_version) == (2, 0, 2)
    assert again.to_dict()["other_version"] == 2
    third = run_tasks(tasks, out=tmp_path / "t.parquet", workers=0, progress=False)  # now current: reused
    assert (third.computed, third.skipped, third.other_version) == (0, 2, 0)


def test_zhu_fujimoto_cli_robustness_options(monkeypatch, tmp_path):
    from typer.testing import CliRunner

    from frictionkit.cli import _register, app

    _register()
    calls = []

    def fake(**kw):
        calls.append(kw)
        t3 = {"seed=0": (2.8, 2.4, 2.2), "k_nutx0.7": (2.8, 2.2, 2.4)}  # made-up numbers: the CLI only reports them
        return {k: {"table3": {law: {"max_error_um": v, "paper_um": None} for law, v in
                               zip(("coulomb", "sinc", "sigmoid"), vals)}} for k, vals in t3.items()}

    monkeypatch.setattr(zfr, "robustness", fake)
    run = CliRunner().invoke
    res = run(app, ["reproduce", "zhu-fujimoto", "--robustness", "--quick", "--stage", "table1", "--workers", "2",
                    "--out", str(tmp_path / "r"), "--json", str(tmp_path / "r.json")])
    assert res.exit_code == 0, res.output
    kw = calls[-1]
    assert (kw["workers"], kw["scheduler"], kw["out"], kw["quick"], kw["stage"]) == (2, None, tmp_path / "r", True,
                                                                                     "table1")
    doc = json.loads((tmp_path / "r.json").read_text())
    assert doc["table3_order_holds"] == ["seed=0"] and doc["table3_max_error_um"]["k_nutx0.7"]["sinc"] == 2.2
    assert "holds in 1 of 2 variants" in res.output
    assert not (tmp_path / "r.png").exists()  # no plot with --robustness
    res = run(app, ["reproduce", "zhu-fujimoto", "--robustness", "--scheduler", "tcp://10.0.0.5:8786", "--json",
                    str(tmp_path / "s.json")])
    assert res.exit_code == 0, res.output
    assert calls[-1]["scheduler"] == "tcp://10.0.0.5:8786" and calls[-1]["workers"] is None
    n = len(calls)
    for bad, word in ((["--robustness", "--workers", "-1"], "--workers"),
                      (["--robustness", "--workers", "2", "--scheduler", "tcp://h:1"], "--scheduler"),
                      (["--robustness", "--out", str(tmp_path / "x.json")], "same path"),
                      (["--out", str(tmp_path / "o")], "--robustness")):
        res = run(app, ["reproduce", "zhu-fujimoto", *bad, "--json", str(tmp_path / "x.json")])
        assert res.exit_code == 2 and word in res.output, (bad, res.output)
    assert len(calls) == n  # refused before any run


def test_seed_is_refused_with_robustness(tmp_path):
    """--robustness runs its own noise seeds: a --seed beside it was silently ignored."""
    from typer.testing import CliRunner

    from frictionkit.cli import _register, app

    _register()
    for which in ("zhu-fujimoto", "zhang2023"):
        res = CliRunner().invoke(app, ["reproduce", which, "--robustness", "--seed", "3", "--json",
                                       str(tmp_path / "r.json")])
        assert res.exit_code == 2 and "--seed goes with a single run" in res.output, res.output
        assert not (tmp_path / "r.json").exists()
