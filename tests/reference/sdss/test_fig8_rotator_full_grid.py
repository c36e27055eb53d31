"""Fig. 8 on the full speed grid (14 speeds, positive direction): the rotator's combined static map.

At some speeds the rotator's position loop (2 Hz, the bandwidth assumed for every axis) hunts:
the combined Stribeck map falls faster than the loop damps. Linearised on the rigid axis with the
map's slope ``-c(v)`` as negative damping, the PID of ``presets.sdss._pid_gains`` (derivative
filter included) loses stability at c* = 3.49e4 N·m·s/rad (Routh-Hurwitz without the filter:
8/3 J w = 3.52e4); the map's steepest slope is (Ts - Tc) sqrt(2/e) / vs - sigma2 = 6.1e4.
Such a run's mean torque is not the steady-state friction at its mean speed (up to -1.9 %), and
without a screen vs came out -5.3 % (the finding's limit is 5 %; session of 2026-11-23 morning).

The two-step workflow now rejects runs whose speed was not constant (eq. 10's premise; ripple
from the encoder angle above ``MAX_RIPPLE_PERCENT`` = 10 %, argued in identify/two_step.py before
its effect on vs was looked at). Both states are tested here from one campaign."""

from __future__ import annotations

import math

import numpy as np
import pytest

from frictionkit.identify.static_map import fit_static_map
from frictionkit.identify.two_step import screen_constant_velocity
from frictionkit.presets import sdss
from frictionkit.reproduce import sdss as rep

C_STAR = 3.49e4  # N·m·s/rad, the linearised loop's stability limit (docstring)


@pytest.fixture(scope="module")
def campaign():
    ax = sdss.RotatorAxis()
    speeds = rep.speed_grid(False)
    return ax, rep.constant_velocity_runs(ax, speeds[speeds > 0], seed=0)


def _negative_slope(tr, v):
    u = v / tr["vs_pos"]
    return (tr["Fs_pos"] - tr["Fc_pos"]) * 2.0 * u / tr["vs_pos"] * np.exp(-u * u) - tr["sigma2_pos"]


def test_without_the_screen_the_hunting_runs_bias_vs(campaign):
    ax, st = campaign
    tr = ax.truth()
    true_map = ax.bearing.static.steady_state(st["v"]) + ax.n_c * ax.hd_friction.static.steady_state(ax.n_c * st["v"])
    bias = st["F"] / true_map - 1.0
    kd = 3.0 * ax.inertia * 2.0 * math.pi * ax.bandwidth_hz
    slope = (tr["Fs_pos"] - tr["Fc_pos"]) * math.sqrt(2.0 / math.e) / tr["vs_pos"]
    assert kd == pytest.approx(3.96e4, rel=0.01) and slope == pytest.approx(6.2e4, rel=0.01)
    assert 8.0 / 3.0 * ax.inertia * 2.0 * math.pi * ax.bandwidth_hz == pytest.approx(C_STAR, rel=0.02)
    assert np.min(bias) == pytest.approx(-0.019, abs=0.004)
    res = fit_static_map(st["v"], st["F"], model="exponential", delta=2.0, direction="positive")
    err = res["vs_pos"] / tr["vs_pos"] - 1.0
    assert -0.07 < err < -0.04, err  # the state before the screen: -5.3 %


def test_screen_rejects_the_runs_of_the_unstable_band(campaign):
    ax, st = campaign
    c = _negative_slope(ax.truth(), st["v"])
    scr = screen_constant_velocity(st)
    assert scr.status == 0, scr.message
    # every run outside the linearly unstable band ran at constant speed (ripple at the encoder floor)
    assert scr.accepted[c < C_STAR].all(), scr.summary()
    # the two most unstable runs (c > 1.4 c*) hunt: limit cycles of tens of per cent, rejected
    assert (~scr.accepted[c > 1.4 * C_STAR]).all() and (c > 1.4 * C_STAR).sum() == 2, scr.summary()
    assert scr.ripple_percent[~scr.accepted].min() > 12.0


def test_fig8_rotator_full_grid_vs_within_5_percent(campaign):
    ax, st = campaign
    tr = ax.truth()
    scr = screen_constant_velocity(st)
    used = scr.steady()
    res = fit_static_map(used["v"], used["F"], model="exponential", delta=2.0, direction="positive")
    bad = [f"{k}: {100 * (res[f'{k}_pos'] / tr[f'{k}_pos'] - 1):+.2f} %" for k in ("Fc", "Fs", "vs", "sigma2")
           if abs(res[f"{k}_pos"] / tr[f"{k}_pos"] - 1.0) > 0.05]
    assert not bad, f"{bad} (finding: static parameters within 5 %); {scr.message}"
