"""The fleet histogram's legend counts its axes and does not call an unmonitored table "not flagged"
(README walk, walk3: a fleet report of 6 axes, none flagged, showed an empty "drift flagged" entry, and a
results table without the monitor's columns labelled every axis "not flagged")."""

from __future__ import annotations

import matplotlib

matplotlib.use("Agg")

import pandas as pd  # noqa: E402

from frictionkit.plotting.fleet import plot_parameter_distribution  # noqa: E402


def _table(monitored: bool) -> pd.DataFrame:
    rows = [{"axis": f"a{i}", "period": "2026-01-01", "ok": True, "Fc_pos": 1.0 + 0.1 * i} for i in range(5)]
    df = pd.DataFrame(rows)
    if monitored:
        df["drift_flag"] = [False, False, False, False, True]
    return df


def _legend(ax) -> list[str]:
    return [t.get_text() for t in ax.get_legend().get_texts()]


def test_monitored_legend_counts_flagged_and_not():
    assert _legend(plot_parameter_distribution(_table(True), "Fc_pos")) == ["not flagged (4)", "drift flagged (1)"]


def test_unmonitored_table_is_not_called_not_flagged():
    assert _legend(plot_parameter_distribution(_table(False), "Fc_pos")) == ["axes (5; not monitored)"]


def test_report_says_one_axis_flagged():
    """The report's fleet section said "1 axes" (the demo's fleet, one wearing axis)."""
    from frictionkit.report.adapters import fleet_sections

    df = _table(True)
    for c, v in (("drift_alarm_period", "2026-01-01"), ("drift_detail", "wear")):
        df[c] = [None] * 4 + [v]
    sec, flagged = fleet_sections(df)  # the flagged axis has a section of its own
    assert dict(sec.table[1:])["drift flagged"] == "1 axis"
    assert flagged.title == "Fleet: flagged axes (1)"
