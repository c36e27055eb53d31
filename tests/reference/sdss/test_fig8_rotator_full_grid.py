"""Fig. 8 on the full speed grid: the rotator's combined static map misses vs by more than 5 %.

Physically consistent cause, not tuned away: at 1.7e-4 and 2.9e-4 rad/s the rotator's position
loop (2 Hz, the bandwidth assumed for every axis) hunts — its derivative damping
3 J w = 4.0e4 N·m·s/rad is below the steepest negative slope of the combined Stribeck map,
(Ts - Tc) sqrt(2/e) / vs = 6.2e4 N·m·s/rad — so the run mean is not the steady-state friction
at the mean speed (-0.26 %, -1.9 %). The paper's averaging procedure carries the same bias on
such an axis. The quick grid (8 speeds) happens to miss the worst speed and passes."""

from __future__ import annotations

import math

import numpy as np
import pytest

from frictionkit.identify.static_map import fit_static_map
from frictionkit.presets import sdss
from frictionkit.reproduce import sdss as rep


@pytest.mark.xfail(strict=True, raises=AssertionError,
                   reason="closed-loop hunting in the Stribeck region biases the run means (docstring)")
def test_fig8_rotator_full_grid_vs_within_5_percent():
    ax = sdss.RotatorAxis()
    speeds = rep.speed_grid(False)
    speeds = speeds[speeds > 0]
    st = rep.constant_velocity_runs(ax, speeds, seed=0)
    tr = ax.truth()
    true_map = ax.bearing.static.steady_state(st["v"]) + ax.n_c * ax.hd_friction.static.steady_state(ax.n_c * st["v"])
    bias = st["F"] / true_map - 1.0
    # the mechanism, measured first: derivative damping below the map's steepest slope
    kd = 3.0 * ax.inertia * 2.0 * math.pi * ax.bandwidth_hz
    slope = (tr["Fs_pos"] - tr["Fc_pos"]) * math.sqrt(2.0 / math.e) / tr["vs_pos"]
    assert kd == pytest.approx(3.96e4, rel=0.01) and slope == pytest.approx(6.2e4, rel=0.01)
    assert np.min(bias) == pytest.approx(-0.019, abs=0.004)
    res = fit_static_map(st["v"], st["F"], model="exponential", delta=2.0, direction="positive")
    err = res["vs_pos"] / tr["vs_pos"] - 1.0
    assert -0.07 < err < -0.04, err
    for k in ("Fc", "Fs", "sigma2"):
        assert abs(res[f"{k}_pos"] / tr[f"{k}_pos"] - 1.0) < 0.05
    assert abs(err) <= 0.05, f"vs {100 * err:+.1f} % (finding: within 5 %)"
