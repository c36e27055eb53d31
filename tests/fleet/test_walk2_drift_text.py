"""The drift text names what a scheduling coefficient is per: it read '%/unit', as if the unit were
called 'unit' (the results table keeps no unit of a scheduling column). Fails on f22475c."""

from __future__ import annotations

from frictionkit.fleet import drift_summary, monitor_drift

from _synth import results_table


def test_drift_text_says_per_unit_of_the_scheduling_variable():
    df = results_table(3, 25, seed=4, t_trend=0.3, k_visc=0.03, drifting=(0,), rate=0.01, onset=0)
    detail = drift_summary(monitor_drift(df, schedule=["temperature"], n_null=200)).set_index("axis")
    text = detail.loc["axis-0000", "drift_detail"]
    assert "% per unit of temperature" in text and "%/unit" not in text
