"""Legends sit where they cover no data: outside on the right for time series and bar charts, in the
empty v < 0, F > 0 quadrant for friction maps. Was (the new-user walk of 2026-11-23): 'best' placements
over the EMPS fit's peaks, the demo's GMS loops and the last reversal's error peak."""

from __future__ import annotations

import matplotlib

matplotlib.use("Agg")

import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

import frictionkit as fk  # noqa: E402
from frictionkit.compensate import CompensationResult  # noqa: E402
from frictionkit.identify import fit_static_map  # noqa: E402
from frictionkit.report import adapters  # noqa: E402


def _outside_right(ax) -> bool:
    ax.figure.canvas.draw()
    return ax.get_legend().get_window_extent().x0 >= ax.get_window_extent().x1


def _points_under_legend(ax) -> int:
    """Plotted vertices (lines and error-bar markers) whose display position falls inside the legend."""
    ax.figure.canvas.draw()
    box = ax.get_legend().get_window_extent()
    n = 0
    for ln in ax.lines:
        xy = np.column_stack([ln.get_xdata(), ln.get_ydata()]).astype(float)
        xy = xy[np.all(np.isfinite(xy), axis=1)]
        if xy.size and ln.get_label() not in ("_nolegend_",) and ln.get_transform() == ax.transData:
            d = ax.transData.transform(xy)
            n += int(np.sum((d[:, 0] >= box.x0) & (d[:, 0] <= box.x1) & (d[:, 1] >= box.y0) & (d[:, 1] <= box.y1)))
    return n


def test_static_map_legend_in_the_empty_quadrant():
    law = fk.Stribeck(Fc=1.0, Fs=1.5, vs=0.01, sigma2=4.0)  # a steep viscous slope fills the upper right
    v = np.r_[np.linspace(1e-3, 0.3, 30), -np.linspace(1e-3, 0.3, 30)]
    ax = fit_static_map(v, law.steady_state(v), model="exponential").plot()
    try:
        assert _points_under_legend(ax) == 0
    finally:
        plt.close(ax.figure)


def test_compensation_plot_legend_outside():
    t = np.linspace(0.0, 2.0, 2001)
    peaks = sum(np.exp(-((t - t0) / 0.01) ** 2) for t0 in (0.5, 1.0, 1.5, 1.98))  # a peak at the end
    res = CompensationResult(preset="test", rows={}, t=t, errors={"none": 6e-6 * peaks, "sinc": 2e-6 * peaks},
                             reversals=[0.5, 1.0, 1.5, 1.98])
    ax = res.plot()
    try:
        assert _outside_right(ax) and [t.get_text() for t in ax.get_legend().get_texts()][:2] == ["none", "sinc"]
    finally:
        plt.close(ax.figure)


def test_report_bar_chart_legend_outside(monkeypatch):
    figs = []
    monkeypatch.setattr(adapters, "figure_png", lambda fig: figs.append(fig) or b"")
    doc = {"format": "frictionkit.compensation/1", "preset": "test", "units": {"error": "m"},
           "compensators": {"none": {"max_error": 6e-6, "rms_error": 1e-6, "reversal_error": 6e-6, "ok": True},
                            "sinc": {"max_error": 2e-6, "rms_error": 4e-7, "reversal_error": 2e-6, "ok": True}}}
    adapters.compensation_sections(doc)
    try:
        assert len(figs) == 1 and _outside_right(figs[0].axes[0])
    finally:
        plt.close("all")


def test_fleet_axis_row_has_one_legend_below_the_panels():
    import pandas as pd

    from frictionkit.plotting.fleet import plot_axis_histories

    days = pd.date_range("2026-01-05", periods=8).strftime("%Y-%m-%d")
    y = 20.0 + 0.2 * np.arange(8)
    df = pd.DataFrame({"axis": "a1", "ok": True, "period": days, "Fc_pos": y, "Fc_pos_lo": y - 0.1,
                       "Fc_pos_hi": y + 0.1, "drift_Fc_pos_trend": y, "Fs_pos": y + 5, "Fs_pos_lo": y + 4.9,
                       "Fs_pos_hi": y + 5.1, "drift_Fs_pos_trend": y + 5})
    fig = plot_axis_histories(df, "a1", ["Fc_pos", "Fs_pos"])
    try:
        fig.canvas.draw()
        assert all(ax.get_legend() is None for ax in fig.axes) and len(fig.legends) == 1
        box = fig.legends[0].get_window_extent()
        assert all(box.y1 <= ax.get_window_extent().y0 for ax in fig.axes)  # below every panel
        assert [t.get_text() for t in fig.legends[0].get_texts()] == ["trend (temperature + wear)",
                                                                       "daily fit, 95 % interval"]
    finally:
        plt.close(fig)


def test_reversal_plot_in_micrometres():
    """A reversal fit on a linear axis is drawn in µm (in m the axis read '1e-5' beside its ticks)."""
    from frictionkit.control import RollingCompensator
    from frictionkit.identify import IdentificationResult

    res = IdentificationResult(kind="reversal", model_name="rolling", model=RollingCompensator(F0=2.0, xs=1e-5,
                               sigma=2e-6), names=("F0",), values=[2.0], stderr=[0.01], ci95=[[1.98, 2.02]],
                               units=("N",), correlation=[[1.0]], rms=0.01, relative_error_percent=1.0, n_obs=3,
                               dof=2, data={"xi": [-2e-5, 1e-6, 2e-5], "F": [-2.0, 0.4, 2.0]},
                               provenance={"units": {"x": "m", "F": "N"}})
    ax = res.plot()
    try:
        assert ax.get_xlabel() == "displacement from the reversal point [µm]"
        np.testing.assert_allclose(ax.lines[0].get_xdata(), [-20.0, 1.0, 20.0])
        assert "xs = 10 µm" in [t.get_text() for t in ax.get_legend().get_texts()][1]
        assert _points_under_legend(ax) == 0
    finally:
        plt.close(ax.figure)


def test_static_map_title_carries_the_unit():
    law = fk.Stribeck(Fc=1.0, Fs=1.5, vs=0.01, sigma2=4.0)
    v = np.r_[np.linspace(1e-3, 0.3, 30), -np.linspace(1e-3, 0.3, 30)]
    ax = fit_static_map(v, law.steady_state(v), model="exponential", units={"F": "N·m", "v": "rad/s"}).plot()
    try:
        assert ax.get_title().endswith(" N·m") and ax.get_ylabel() == "friction [N·m]"
    finally:
        plt.close(ax.figure)
