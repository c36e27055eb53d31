"""A new user's leftovers (walk of 2026-11-24): a Python run knows its units, a pre-sliding fit saves its
positions and plots the force–displacement loop, a machine plot shows its actuators, one ranking rule for
study summaries, one SVD per static-map fit.

Each test fails on f22475c.
"""

from __future__ import annotations

import pickle
import sys
import warnings

import numpy as np
import pytest

import frictionkit as fk
from frictionkit.errors import ParameterError

ROTARY = {"F": "N·m", "v": "rad/s"}


def test_python_run_carries_its_units_to_plot_summary_and_traces():
    """``simulate(units=)``: a rotary law's plot from Python read 'displacement [µm]' and 'friction force [N]'
    (only the CLI passed the model file's units)."""
    import matplotlib.pyplot as plt

    from frictionkit.simulation.traces import trace_table

    th = 0.02 * np.sin(np.linspace(0.0, 6.0, 301))  # 20 mrad
    res = fk.simulate(fk.Dahl(Fc=0.2, sigma0=50.0), position=th, dt=1e-3, units=ROTARY)
    axes = res.plot()
    try:
        assert [a.get_xlabel() for a in axes] == ["displacement [rad]", "time [s]"]
        assert [a.get_ylabel() for a in axes] == ["friction torque [N·m]"] * 2
        np.testing.assert_array_equal(axes[0].lines[0].get_xdata(), th - th[0])  # radians, not scaled to µm
    finally:
        plt.close(axes[0].figure)
    body = res.summary().split("\n")[1]
    assert "travel 0.04 rad" in body and "rad/s" in body and body.endswith(" N·m")
    assert list(trace_table(res))[:4] == ["t [s]", "x [rad]", "v [rad/s]", "friction [N·m]"]
    assert pickle.loads(pickle.dumps(res)).units == {"F": "N·m", "v": "rad/s", "x": "rad"}  # Dask returns results
    plain = fk.simulate(fk.Dahl(Fc=0.2, sigma0=50.0), position=th, dt=1e-3)  # default: SI labels
    assert plain.units is None and list(trace_table(plain))[1] == "x [m]"
    with pytest.raises(ParameterError, match=r"units: key 'torque' unknown"):
        fk.simulate(fk.Dahl(Fc=0.2, sigma0=50.0), position=th, dt=1e-3, units={"torque": "N·m"})


def test_presliding_fit_saves_positions_and_plots_the_loop(tmp_path):
    import matplotlib.pyplot as plt

    from frictionkit.identify.presliding import fit_presliding
    from frictionkit.identify.result import IdentificationResult

    law = fk.Stribeck(Fc=1.0, Fs=1.5, vs=1e-3)
    x = np.r_[np.linspace(0, 50e-6, 501), np.linspace(50e-6, -50e-6, 1001)[1:]]
    F = fk.simulate(fk.GMS(law, k=[4e5, 1e5, 2e4], xi=[0.2, 0.3, 0.5], C=20.0), position=x, dt=1e-3).friction
    res = fit_presliding({"t": np.arange(x.size) * 1e-3, "x": x, "F": F}, elements=3, static=law, polish=False)
    back = IdentificationResult.load_json(res.save_json(tmp_path / "ps.json"))
    np.testing.assert_array_equal(back.data["x"], x)  # every sample is fitted here
    ax = back.plot()
    try:
        fit, resid, loop = ax.figure.axes
        assert fit is ax and resid.get_ylabel() == "residual [N]"
        assert (loop.get_xlabel(), loop.get_ylabel()) == ("position [µm]", "force [N]")
        measured, predicted = loop.lines
        np.testing.assert_allclose(measured.get_xdata(), 1e6 * x, rtol=1e-15)
        np.testing.assert_array_equal(measured.get_ydata(), F)
        np.testing.assert_array_equal(predicted.get_ydata(), back.data["y_pred"])
        with warnings.catch_warnings():  # the CLI's save_plot lays it out again: no layout-engine clash
            warnings.simplefilter("error")
            ax.figure.tight_layout()
    finally:
        plt.close(ax.figure)


def _saturating_machine():
    m = fk.Machine("slide")
    x = m.dof("slide", inertia=2.0)
    m.friction("guide", x, law=fk.CoulombViscous(Fc=1.0, sigma2=5.0))
    m.actuator("drive", x, gain=4.0, limit=0.5, command="u")  # at most 2 N
    return m


def test_machine_plot_has_an_actuator_panel():
    """Commanded (gain * command) and applied (after the saturation) force, in the actuator's unit."""
    import matplotlib.pyplot as plt

    t = np.arange(301) * 1e-3
    u = np.sin(2 * np.pi * 5.0 * t)  # up to 4 N commanded, 2 N applied
    res = fk.simulate_machine(_saturating_machine(), dt=1e-3, inputs={"u": u})
    axes = res.plot()
    try:
        panel = axes[-1]
        assert panel.get_ylabel() == "actuator force\n[N]"
        commanded, applied = panel.lines
        assert commanded.get_label() == "drive commanded" and commanded.get_linestyle() == "--"
        assert applied.get_label() == "drive applied (limit ±2)"
        np.testing.assert_allclose(commanded.get_ydata(), 4.0 * u, rtol=1e-12)
        np.testing.assert_allclose(applied.get_ydata(), 4.0 * np.clip(u, -0.5, 0.5), rtol=1e-12, atol=1e-12)
    finally:
        plt.close(axes[0].figure)


def test_study_summary_uses_the_study_ranking_rule():
    """The report re-sorted old study summaries with its own copy of the rule; a compensator whose every run
    failed (median NaN or null) goes last, as in ``study.rank_compensators``."""
    from frictionkit.report.adapters import study_summary_sections
    from frictionkit.study import RANK_BY, rank_summaries

    comps = {"none": {RANK_BY: float("nan"), "runs": 3, "failed": 3}, "ptc": {RANK_BY: 2e-6, "runs": 3, "failed": 0},
             "coulomb": {RANK_BY: 1e-6, "runs": 3, "failed": 0}, "dob": {RANK_BY: None, "runs": 3, "failed": 3}}
    assert rank_summaries(comps) == ["coulomb", "ptc", "none", "dob"]
    sec = study_summary_sections({"runs": 12, "compensators": comps})[0]
    assert [row[0] for row in sec.table[1:]] == ["coulomb", "ptc", "none", "dob"]


def test_static_map_fit_takes_one_svd_per_direction(monkeypatch):
    """The covariance step decomposed one Jacobian twice (singular values, then the unseen directions)."""
    from frictionkit.identify import static_map

    calls = []
    svd = np.linalg.svd

    def counting(*a, **k):
        if sys._getframe(1).f_globals.get("__name__") == static_map.__name__:
            calls.append(1)
        return svd(*a, **k)

    monkeypatch.setattr(np.linalg, "svd", counting)
    v = np.r_[np.geomspace(1e-4, 0.1, 12), -np.geomspace(1e-4, 0.1, 12)]
    F = fk.Stribeck(Fc=1.0, Fs=1.5, vs=1e-2, sigma2=2.0).steady_state(v)
    res = static_map.fit_static_map(v, F, model="exponential")
    assert res.success and len(calls) == 2  # one per direction


def test_static_map_legend_outside_the_axes():
    """A real drive's breakaway points sit just right of v = 0 and high: the legend in the upper left, as wide
    as its label 'fit (directional(...))', covered them (demo report, TRO2021 drives 1 and 3)."""
    import matplotlib.pyplot as plt

    from frictionkit.identify import fit_static_map

    v = np.r_[np.geomspace(0.05, 20.0, 25), -np.geomspace(0.05, 20.0, 25)]
    law = fk.Stribeck(Fc=0.9e-3, Fs=1.3e-3, vs=0.3, sigma2=1.5e-5)
    ax = fit_static_map(v, law.steady_state(v), units={"F": "N·m", "v": "rad/s"}).plot()
    try:
        ax.figure.canvas.draw()
        assert ax.get_legend().get_window_extent().x0 >= ax.get_window_extent().x1
    finally:
        plt.close(ax.figure)


def test_demo_fleet_error_drops_the_temporary_folder(tmp_path):
    """The demo report named the broken log by a temporary path deleted before anyone reads it."""
    from frictionkit.report.demo import _short_error

    root = tmp_path / "logs"
    err = f"file '{root}/axis-0001/2026-01-11.csv', column 'x_mm', row 12162: value nan is not finite"
    assert _short_error(err, root) == "column 'x_mm', row 12162: value nan is not finite"
    assert _short_error(f"'{root}/axis-0002/x.csv': Permission denied", root) == "'axis-0002/x.csv': Permission denied"


def test_report_takes_a_machine_run(tmp_path, monkeypatch):
    """``Report.add_result(MachineResult)`` was refused as 'not a result the report knows'."""
    from frictionkit.report import Report, adapters

    figs = []
    monkeypatch.setattr(adapters, "figure_png", lambda fig: figs.append(fig) or b"")
    t = np.arange(301) * 1e-3
    res = fk.simulate_machine(_saturating_machine(), dt=1e-3, inputs={"u": np.sin(2 * np.pi * 5.0 * t)})
    (sec,) = Report("machine").add_result(res, name="run")
    assert sec.title.startswith("Machine run: slide, 301 samples") and sec.kind == "machine-run"
    assert "guide: max |F| = " in " ".join(sec.text) and ["u.drive", "-0.5", "0.5"] in sec.table
    assert [a.get_ylabel() for a in figs[0].axes][-1] == "actuator force\n[N]"


def test_redesign_drive_force_panel_names_the_stops_like_its_neighbour():
    """Table 2's drive-force panel said 'original (fast non reverse)' beside 'original stop, 51 ms' and its
    legend sat on the ringing after zero speed; now the same stop names, and headroom above the traces."""
    from types import SimpleNamespace as NS

    import matplotlib.pyplot as plt

    from frictionkit.plotting.ballscrew import plot_redesign

    t = np.linspace(-0.2, 0.1, 3001)
    ring = np.where(t > 0, 300 * np.exp(-t / 0.01) * np.cos(2 * np.pi * 200 * t), 0.0)
    original = np.where(t < -0.05, 600.0, 600.0 + 15e3 * (t + 0.05)) + ring + np.where(t > 0, 500.0 + 3e3 * t, 0.0)
    runs = {"original": NS(t=t, drive_force=original, error=0 * t),
            "redesigned": NS(t=t, drive_force=np.where(t < 0, 100.0, 800.0) + ring, error=0 * t)}
    result = NS(runs=runs, crossings={k: [NS(t0=0.0)] for k in runs}, stop_ms={"original": 51.0, "redesigned": 126.0},
                max_error_um={"original": 4.4, "redesigned": 2.8},
                kind={"original": "fast_non_reverse", "redesigned": "slow_non_reverse"})
    ax = plot_redesign(result, signal="drive_force")
    try:
        assert [t.get_text() for t in ax.get_legend().get_texts()] == [
            "original stop, 51 ms: fast non reverse", "redesigned stop, 126 ms: slow non reverse"]
        ax.figure.canvas.draw()
        box = ax.get_legend().get_window_extent()
        for ln in ax.lines[:2]:
            d = ax.transData.transform(np.column_stack([ln.get_xdata(), ln.get_ydata()]))
            assert not ((d[:, 0] >= box.x0) & (d[:, 0] <= box.x1) & (d[:, 1] >= box.y0) & (d[:, 1] <= box.y1)).any()
    finally:
        plt.close(ax.figure)


def test_site_units_of_a_machine_run():
    """``site_units`` takes the run too (the CLI's ``simulate MACHINE --json`` needs each site's unit beside
    its peak force)."""
    from frictionkit.simulation.traces import site_units

    t = np.arange(11) * 1e-3
    res = fk.simulate_machine(_saturating_machine(), dt=1e-3, inputs={"u": 0 * t})
    assert site_units(res) == site_units(res.machine) == ["N"]
