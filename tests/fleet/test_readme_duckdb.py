"""The README's DuckDB example runs on a results Parquet file and says what the table says."""

from __future__ import annotations

import re
from pathlib import Path

README = Path(__file__).resolve().parents[2] / "README.md"


def test_readme_duckdb_query(dask_run, monkeypatch):
    blocks = re.findall(r"```python\n(.*?)```", README.read_text(encoding="utf-8"), re.S)
    src = next(b for b in blocks if "duckdb.sql" in b)
    assert dask_run.out.name == "results.parquet"
    monkeypatch.chdir(dask_run.out.parent)
    ns: dict = {}
    exec(compile(src, "README.md", "exec"), ns)
    df = dask_run.table
    flagged = sorted(df.loc[df["drift_flag"], "axis"].unique())
    assert sorted(ns["flagged"]["axis"]) == flagged
    assert ns["per_day"]["axes"].sum() == int(df["ok"].sum())
    assert sorted(ns["failed"]["axis"] + " " + ns["failed"]["period"]) == \
        sorted(df.loc[~df["ok"], "axis"] + " " + df.loc[~df["ok"], "period"])
