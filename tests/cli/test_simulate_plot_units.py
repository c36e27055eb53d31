"""``frictionkit simulate MODEL --plot`` labels a rotary law's run in rad and N·m (the model file's units).
Was (the walk of 2026-11-24, README's `simulate lugre1.json --velocity ...`): 'displacement [mm]' with
98 rad drawn as 98,000 and 'friction force [N]' for newton-metres."""

from __future__ import annotations

import numpy as np
from typer.testing import CliRunner

import frictionkit as fk
import frictionkit.cli._common as chk
import frictionkit.cli.simulate  # noqa: F401  (registers the verb)
from frictionkit.cli import app


def _labels(tmp_path, monkeypatch, units):
    import matplotlib.pyplot as plt

    law = fk.LuGre(fk.Stribeck(Fc=2e-3, Fs=3e-3, vs=0.5, sigma2=1e-5), sigma0=1.0, sigma1=1e-3)
    fk.save_model(law, tmp_path / "law.json", units=units)
    t = np.arange(2001) * 1e-3
    np.savetxt(tmp_path / "x.csv", np.column_stack([t, 0.5 * np.sin(2 * np.pi * t)]), delimiter=",",
               header="t,x", comments="")
    figs = []
    monkeypatch.setattr(chk, "save_figure", lambda fig, path, **kw: figs.append(fig))
    r = CliRunner().invoke(app, ["simulate", str(tmp_path / "law.json"), "--position", str(tmp_path / "x.csv"),
                                 "--plot", str(tmp_path / "p.png")])
    assert r.exit_code == 0, r.output
    axes = figs[0].axes
    try:
        return [(a.get_xlabel(), a.get_ylabel()) for a in axes], axes[0].lines[0].get_xdata()
    finally:
        plt.close("all")


def test_rotary_law_plot_in_rad_and_newton_metres(tmp_path, monkeypatch):
    labels, x = _labels(tmp_path, monkeypatch, {"F": "N·m", "x": "rad", "v": "rad/s"})
    assert labels == [("displacement [rad]", "friction torque [N·m]"), ("time [s]", "friction torque [N·m]")]
    assert np.max(np.abs(x)) == np.max(np.abs(0.5 * np.sin(2 * np.pi * np.arange(2001) * 1e-3)))  # rad, unscaled


def test_linear_law_plot_in_mm(tmp_path, monkeypatch):
    labels, x = _labels(tmp_path, monkeypatch, None)
    assert labels[0] == ("displacement [mm]", "friction force [N]")  # 0.5 m of travel: mm
    assert np.isclose(np.max(np.abs(x)), 500.0, rtol=1e-6)
