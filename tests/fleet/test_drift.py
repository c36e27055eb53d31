"""Drift monitoring: known drifting axes flagged, temperature told apart from wear, the
false-alarm rate on drift-free axes, and the checks of the arguments."""

from __future__ import annotations

from dataclasses import replace

import numpy as np
import pandas as pd
import pytest

from frictionkit.errors import DataError, ParameterError
from frictionkit.fleet import drift_summary, identify_fleet, load_config, monitor_drift, simulate_fleet

from _synth import results_table


def test_known_drifting_axes_are_flagged(cluster, tmp_path):
    fleet = simulate_fleet(tmp_path / "fleet", axes=4, days=10, seed=3, drifting=0.5, broken=0,
                           wear_rate=(0.01, 0.02))
    cfg = replace(load_config(fleet.config), dynamic={"lugre": False})  # the monitor tracks the static map
    run = identify_fleet(fleet.root, out=tmp_path / "r.parquet", config=cfg, scheduler=cluster.scheduler_address,
                         progress=False)
    df = run.table
    assert "drift_flag" in df and df["ok"].all()
    axes = drift_summary(df).set_index("axis")
    truth = fleet.truth.set_index("axis")
    assert axes["drift_flag"].to_dict() == truth["drifting"].to_dict()
    for axis in truth.index[truth["drifting"]]:
        alarm = axes.loc[axis, "drift_alarm_period"]
        assert alarm >= truth.loc[axis, "wear_onset_period"]  # never before the wear starts
        assert df.loc[(df["axis"] == axis) & (df["period"] >= alarm), "drift_flag"].all()
        assert not df.loc[(df["axis"] == axis) & (df["period"] < alarm), "drift_flag"].any()
        # the wear slope of Fc (relative, per day) is the simulated rate within 4 standard errors
        slope, se = axes.loc[axis, "drift_Fc_pos_wear_per_day"], axes.loc[axis, "drift_Fc_pos_wear_per_day_se"]
        assert slope > 0 and se > 0
        assert "drift from" in axes.loc[axis, "drift_detail"]


def test_temperature_is_told_apart_from_wear():
    # temperature rises 0.3 °C/day and lowers sigma2 by 3 %/K: 9 %/month that is not wear
    df = results_table(6, 25, seed=4, t_trend=0.3, k_visc=0.03, drifting=(0,), rate=0.01, onset=0)
    with_t = drift_summary(monitor_drift(df, schedule=["temperature"], n_null=1000)).set_index("axis")
    without = drift_summary(monitor_drift(df, schedule=[], n_null=1000)).set_index("axis")
    assert with_t["drift_flag"].tolist() == [True] + [False] * 5
    assert without["drift_flag"].all()  # ignoring the logged temperature, every axis "drifts"
    coef, se = with_t["drift_sigma2_pos_temperature_coef"], with_t["drift_sigma2_pos_temperature_coef_se"]
    assert (np.abs(coef + 0.03) < 4 * se).all()  # the viscosity law recovered, per kelvin
    w, wse = with_t.loc["axis-0000", "drift_Fc_pos_wear_per_day"], with_t.loc["axis-0000", "drift_Fc_pos_wear_per_day_se"]
    assert abs(w - np.log1p(0.01)) < 4 * wse  # wear: +1 %/day, apart from the temperature effect


def test_false_alarm_rate_on_drift_free_axes():
    df = results_table(100, 20, seed=5)
    flagged = int(drift_summary(monitor_drift(df, n_null=1000))["drift_flag"].sum())
    assert flagged <= 3  # alpha = 1 % over 100 axes x 16 looks x 6 parameters (binomial: P(>= 4) = 1.9 %)


def test_monitor_is_idempotent_and_keeps_rows():
    df = results_table(3, 8, seed=6)
    df.loc[2, "ok"] = False
    m1 = monitor_drift(df, n_null=500)
    m2 = monitor_drift(m1, n_null=500)
    pd.testing.assert_frame_equal(m1, m2)
    assert len(m1) == len(df) and list(m1.columns[: len(df.columns)]) == list(df.columns)


def test_too_few_periods_is_said():
    df = results_table(1, 4, seed=7)
    m = monitor_drift(df, n_null=500)
    assert not m["drift_flag"].any() and m["drift_detail"].str.startswith("not monitored").all()


@pytest.mark.parametrize("kw, match", [({"alpha": 0.0}, "alpha"), ({"alpha": 0.7}, "alpha"),
                                       ({"min_periods": 2}, "min_periods"), ({"n_null": 10}, "n_null"),
                                       ({"weights": "x"}, "weights"), ({"scale": "x"}, "scale")])
def test_bad_arguments(kw, match):
    with pytest.raises(ParameterError, match=match):
        monitor_drift(results_table(1, 6, seed=8), **kw)


def test_missing_columns():
    with pytest.raises(DataError, match="'ok'"):
        monitor_drift(pd.DataFrame({"axis": ["a"], "period": ["2026-01-01"]}))
    with pytest.raises(DataError, match="scheduling column 'oil'"):
        monitor_drift(results_table(1, 6, seed=8), schedule=["oil"])


def test_slope_method_runs_and_flags_the_wearing_axis():
    df = results_table(3, 20, seed=9, drifting=(0,), rate=0.01, onset=0)
    axes = drift_summary(monitor_drift(df, method="slope", n_null=500)).set_index("axis")
    assert axes.loc["axis-0000", "drift_flag"] and (axes["drift_method"] == "slope").all()
    assert axes.loc["axis-0000", "drift_detail"].startswith("drift from")


def test_report_draws_flagged_axes_over_time(tmp_path):
    from frictionkit.fleet import fleet_report

    df = monitor_drift(results_table(4, 15, seed=10, drifting=(1,), rate=0.01, onset=3), n_null=1000)
    df["unit_F"], df["unit_v"], df["frictionkit_version"], df["file"], df["error"] = "N", "m/s", "x", "f", None
    doc = fleet_report(df, tmp_path / "f.html")
    assert doc["flagged"] == ["axis-0001"] and doc["drawn"] == ["axis-0001"]
    text = (tmp_path / "f.html").read_text(encoding="utf-8")
    assert "axis-0001" in text
    assert "<td>1 axis (monitor: cusum)</td>" in text  # was "1 axes"
    fleet_report(df, tmp_path / "g.html", max_axes=0)
    assert "1 more flagged axis not drawn" in (tmp_path / "g.html").read_text(encoding="utf-8")
