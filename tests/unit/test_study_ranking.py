"""A study lists its compensators best first by the median of the runs' max tracking error — in the
summary, its JSON, its plot and the report — and says so. Was (the new-user walk of 2026-11-23): in the
table's order, i.e. alphabetically by run label."""

from __future__ import annotations

import numpy as np
import pandas as pd

from frictionkit.report.adapters import study_sections, study_summary_sections
from frictionkit.study import StudyResult

# max tracking error [m] per run: alphabetical order (coulomb, none, sinc, static) is not the merit order
RUNS = {"coulomb": [3e-6, 5e-6, 4e-6], "none": [9e-6, 8e-6, 7e-6], "sinc": [1e-6, 6e-6, 2e-6],
        "static": [np.nan, np.nan, np.nan]}  # every static run failed: it goes last


def _table():
    rows = []
    for comp in sorted(RUNS):
        for i, e in enumerate(RUNS[comp]):
            rows.append({"run": f"{comp}-{i}", "draw": i, "noise_seed": 0, "compensator": comp, "ok": bool(np.isfinite(e)),
                         "max_error": e, "rms_error": e / 3, "max_force": 1.0, "study_sha256": "ab" * 32,
                         "error": "" if np.isfinite(e) else "diverged"})
    return pd.DataFrame(rows)


def _expected():
    med = {c: np.median(v) for c, v in RUNS.items() if np.all(np.isfinite(v))}
    return sorted(med, key=med.get) + [c for c in RUNS if c not in med]  # sinc 2, coulomb 4, none 8, static


def test_study_result_ranks_best_first(tmp_path):
    import matplotlib.pyplot as plt

    res = StudyResult(out=tmp_path / "s.parquet", table=_table(), runs=12, computed=12, skipped=0, elapsed=1.0)
    want = _expected()
    assert want == ["sinc", "coulomb", "none", "static"]
    d = res.to_dict()
    assert list(d["compensators"]) == want and d["ranked_by"] == "max_error_median_m, best first"
    text = res.summary()
    assert "best first" in text
    assert [text.index(f"  {c} ") for c in want] == sorted(text.index(f"  {c} ") for c in want)
    ax = res.plot()
    try:
        assert [t.get_text() for t in ax.get_xticklabels()] == want[:3]
    finally:
        plt.close(ax.figure)


def test_report_ranks_best_first(tmp_path):
    want = _expected()
    sec = study_sections(_table())[0]
    assert [r[0] for r in sec.table[1:]] == want and any("best first" in t for t in sec.text)
    doc = StudyResult(out=tmp_path / "s.parquet", table=_table(), runs=12, computed=12, skipped=0,
                      elapsed=1.0).to_dict()
    doc["compensators"] = dict(sorted(doc["compensators"].items()))  # an older file: alphabetical
    sec = study_summary_sections(doc)[0]
    assert [r[0] for r in sec.table[1:]] == want and any("best first" in t for t in sec.text)
