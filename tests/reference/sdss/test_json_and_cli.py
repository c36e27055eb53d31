"""The JSON of ``frictionkit reproduce sdss`` has the issue's layout; the command checks its options first."""

from __future__ import annotations

import json
import math

import numpy as np
from typer.testing import CliRunner

import frictionkit.cli.reproduce  # noqa: F401  (registers the command group)
from frictionkit.cli import app
from frictionkit.presets import sdss
from frictionkit.reproduce import sdss as rep


def test_summary_layout(azimuth, altitude, rotator):
    r = rep.SdssReproduction(axes={"azimuth": azimuth, "altitude": altitude, "rotator": rotator},
                             tracking={"no_compensation": 0.1, "lugre_feedforward": 0.05}, quick=True, seed=0)
    doc = json.loads(json.dumps(r.to_dict()))
    text = r.summary()
    assert all(f"  {axis}:" in text for axis in doc["axes"]) and "sidereal tracking" in text
    assert set(doc["axes"]) == {"azimuth", "altitude", "rotator"}
    assert set(doc["sidereal_tracking_rms_arcsec"]) == {"no_compensation", "lugre_feedforward"}
    for name, ax in doc["axes"].items():
        assert {"truth", "identified", "velocity_nrmse_percent"} <= set(ax)
        for p in ax["identified"].values():
            assert set(p) == {"value", "ci95"} and len(p["ci95"]) == 2
        assert set(ax["identified"]) <= set(ax["truth"])
    assert doc["axes"]["rotator"]["velocity_nrmse_percent"] is None  # the paper fits only its static map
    assert doc["axes"]["azimuth"]["velocity_nrmse_percent"] == azimuth.nrmse["fig4a_triangle"]
    assert doc["axes"]["altitude"]["velocity_nrmse_percent"] == altitude.nrmse["fig6b_above"]
    # ours: the constant-velocity runs rejected before eq. 10 are named with their ripple
    for name, key in (("azimuth", "constant_velocity_screen"), ("rotator", "constant_velocity_screen"),
                      ("rotator", "hd_bench_screen")):
        scr = doc["axes"][name][key]
        assert scr["kept"] + len(scr["rejected"]) == scr["runs"] == 16
        assert all(r["ripple_percent"] > scr["max_ripple_percent"] for r in scr["rejected"])
        # where the encoder alone scatters the 50 ms window velocities by more than the threshold
        # (sqrt(2 (noise^2 + q^2/12)) / Tw / v: 15 % at 2e-5 rad/s), the screen says it cannot judge
        axis = {"azimuth": sdss.AzimuthAxis, "rotator": sdss.RotatorAxis}[name]()
        enc, tw = axis.encoder, 0.1 / axis.bandwidth_hz
        floor = 100 * math.sqrt(2 * (enc.noise**2 + enc.resolution**2 / 12)) / tw / np.abs(rep.speed_grid(True))
        expect = rep.speed_grid(True)[floor > scr["max_ripple_percent"]]
        assert expect.size == 2 and np.allclose(sorted(scr["not_resolvable_rad_s"]), sorted(expect), rtol=0.01)
    assert "constant_velocity_screen" not in doc["axes"]["altitude"]  # no constant-velocity runs (paper §3.2)


def test_cli_refuses_bad_options_before_running(tmp_path):
    out = tmp_path / "s.json"
    res = CliRunner().invoke(app, ["reproduce", "sdss", "--quick", "--seed", "-1", "--json", str(out)])
    assert res.exit_code == 2 and not out.exists()
    res = CliRunner().invoke(app, ["reproduce", "sdss", "--json", str(out), "--plot", str(tmp_path / "p.xyz")])
    assert res.exit_code == 2 and not out.exists()


def test_figure_marks_the_rejected_runs(azimuth, altitude, rotator):
    import matplotlib.pyplot as plt

    r = rep.SdssReproduction(axes={"azimuth": azimuth, "altitude": altitude, "rotator": rotator},
                             tracking={"no_compensation": 0.1, "lugre_feedforward": 0.05}, quick=True, seed=0)
    fig, axs = r.plot()
    try:
        labels = [ln.get_label() for ln in axs[2, 1].get_lines()]  # Fig. 8 analogue
        n_rej = len(rotator.extra["screen"].rejected())
        assert n_rej > 0 and any(lb.startswith("rejected: ripple > 10 %") for lb in labels)
        rej = [ln for ln in axs[2, 1].get_lines() if ln.get_label().startswith("rejected")][0]
        assert rej.get_xdata().size == n_rej
    finally:
        plt.close(fig)
