"""The ``--json`` of ``identify rigid-body``, force-driven ``output-error`` and ``presliding`` holds what a
plot of the fit needs (time, measured, predicted), and the report draws the fit over its residual from it.

Was (the new-user walk of 2026-11-23): these three verbs saved no data with the fit, so their report
section said "no plot of the fit here".
"""

from __future__ import annotations

import json

import numpy as np
import pytest
from typer.testing import CliRunner

import frictionkit as fk
import frictionkit.cli.identify  # noqa: F401  (registers the ``identify`` group)
from frictionkit.cli import app
from frictionkit.identify import IdentificationResult

runner = CliRunner()
LAW = fk.Stribeck(Fc=1.0, Fs=1.5, vs=1e-3, delta=2.0, sigma2=0.4)


def _csv(path, **cols):
    np.savetxt(path, np.column_stack(list(cols.values())), delimiter=",", header=",".join(cols), comments="",
               fmt="%.17g")
    return path


def _check(doc, t_true, y_true, tol, q=100):
    """The saved arrays: one sample per observation, increasing time inside the record, the measured
    signal equal to the file's (interpolated at the saved times) and the residual RMS that of the
    file's stated RMS."""
    d = doc["data"]
    t, y, y_pred = (np.asarray(d[k], float) for k in ("t", "y", "y_pred"))
    assert t.size == y.size == y_pred.size >= doc["n_obs"] > 0.9 * t.size  # the first sample is the start
    assert np.all(np.diff(t) > 0)
    assert np.percentile(np.abs(y - np.interp(t, t_true, y_true)), q) <= tol
    # the stated RMS is over the fitted samples only (an output-error fit leaves out each segment's start
    # sample and rests): within 1 %, which a misaligned or stale prediction misses by far
    assert np.sqrt(np.mean((y - y_pred) ** 2)) == pytest.approx(doc["rms"], rel=1e-2)


def _report_fit_axes(path, n_axes=2):
    """The fit's figure as the report draws it: fit panel over the residual panel (and, for a pre-sliding
    fit, its force–displacement loop beside them: ``n_axes`` 3)."""
    import matplotlib.pyplot as plt

    res = IdentificationResult.load_json(path)
    ax = res.plot()
    axes = ax.figure.axes
    try:
        assert len(axes) == n_axes and axes[1].get_shared_x_axes().joined(axes[0], axes[1])
        assert axes[1].get_ylabel().startswith("residual [") and axes[1].get_xlabel() == "time [s]"
        assert [ln.get_label() for ln in ax.get_legend().get_lines()][:2] == ["measured", "predicted"]
        # the legend sits right of the axes, over no data
        assert ax.get_legend().get_window_extent().x0 >= ax.get_window_extent().x1
        return ax.get_ylabel(), axes[1].get_ylabel()
    finally:
        plt.close(ax.figure)


def test_rigid_body_json_has_the_fit_data(tmp_path):
    t = np.arange(20001) * 1e-3
    x = 0.05 * np.sin(2 * np.pi * 0.5 * t)
    v = 0.05 * np.pi * np.cos(2 * np.pi * 0.5 * t)
    a = -0.05 * np.pi ** 2 * np.sin(2 * np.pi * 0.5 * t)
    F = 2.0 * a + 10.0 * v + 1.5 * np.tanh(v / 1e-3)  # M = 2 kg, Fv = 10 N·s/m, Fc = 1.5 N
    out = tmp_path / "rb.json"
    r = runner.invoke(app, ["identify", "rigid-body", str(_csv(tmp_path / "rb.csv", t=t, x=x, F=F)), "--time", "t",
                            "--position", "x", "--force", "F", "--json", str(out)])
    assert r.exit_code == 0, r.output
    doc = json.loads(out.read_text(encoding="utf-8"))
    # the fit's measured force is the file's force after the IDIM-LS low-pass (which rounds the Coulomb
    # steps at the reversals): 95 % of the samples within 2 % of its range
    _check(doc, t, F, tol=0.02 * np.ptp(F), q=95)
    assert _report_fit_axes(out) == ("force [N]", "residual [N]")


def test_output_error_force_json_has_the_fit_data(tmp_path):
    dt = 1e-3
    t = np.arange(4001) * dt
    u = 2.0 * np.sin(np.pi * t)
    sim = fk.simulate(fk.LuGre(LAW, sigma0=1e5, sigma1=63.2), plant=fk.Mass(1.0), force=u, dt=dt)
    out = tmp_path / "oe.json"
    r = runner.invoke(app, ["identify", "output-error", str(_csv(tmp_path / "oe.csv", t=t, v=sim.v, u=u)),
                            "--time", "t", "--velocity", "v", "--force", "u", "--Fc", "1.0", "--Fs", "1.5",
                            "--vs", "1e-3", "--sigma2", "0.4", "--mass", "1.0", "--json", str(out)])
    assert r.exit_code == 0, r.output
    doc = json.loads(out.read_text(encoding="utf-8"))
    _check(doc, t, sim.v, tol=1e-12)
    assert _report_fit_axes(out) == ("velocity [m/s]", "residual [m/s]")


def test_presliding_json_has_the_fit_data(tmp_path):
    dt = 1e-3
    x = np.r_[np.linspace(0, 50e-6, 1001), np.linspace(50e-6, -50e-6, 2001)[1:]]
    t = np.arange(x.size) * dt
    F = fk.simulate(fk.GMS(LAW, k=[4e5, 1e5, 2e4], xi=[0.2, 0.3, 0.5], C=20.0), position=x, dt=dt).friction
    out = tmp_path / "ps.json"
    r = runner.invoke(app, ["identify", "presliding", str(_csv(tmp_path / "ps.csv", t=t, x=x, F=F)), "--time", "t",
                            "--position", "x", "--force", "F", "--elements", "3", "--json", str(out)])
    assert r.exit_code == 0, r.output
    doc = json.loads(out.read_text(encoding="utf-8"))
    _check(doc, t, F, tol=1e-12)
    np.testing.assert_array_equal(doc["data"]["x"], x)  # every sample fitted: the loop's positions
    assert _report_fit_axes(out, n_axes=3) == ("force [N]", "residual [N]")


def test_report_names_the_measured_signal(tmp_path):
    """The report's data overview says what was measured, with its unit (was 'fitted signal (measured)')."""
    from frictionkit.report.adapters import identification_sections

    t = np.arange(2001) * 1e-3
    v = 0.05 * np.cos(2 * np.pi * t)
    x = np.sin(2 * np.pi * t) * 0.05 / (2 * np.pi)
    F = 2.0 * np.gradient(v, t) + 10.0 * v
    out = tmp_path / "rb.json"
    r = runner.invoke(app, ["identify", "rigid-body", str(_csv(tmp_path / "rb.csv", t=t, x=x, F=F)), "--time", "t",
                            "--position", "x", "--force", "F", "--json", str(out)])
    assert r.exit_code == 0, r.output
    sec = identification_sections(IdentificationResult.load_json(out), name="rb.json")[0]
    rows = dict((row[0], row[1]) for row in sec.tables[0][1][1:])
    assert "measured force [N]" in rows and rows["measured force [N]"].endswith("samples)")
