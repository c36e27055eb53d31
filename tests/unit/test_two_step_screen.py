"""The constant-velocity screen of the two-step workflow (eq. 10 needs constant-speed runs):
ripple from an encoder angle, and the rejection of runs whose speed was not constant."""

from __future__ import annotations

import math

import numpy as np
import pytest

import frictionkit as fk
from frictionkit.identify.two_step import (MAX_RIPPLE_PERCENT, constant_velocity_ripple, fit_two_step,
                                           screen_constant_velocity)

DT = 1e-3
Q = 2 * math.pi / 2**25  # one count of a 2^25 counts/rev encoder [rad]


def _angle(v, amp, f, seconds, *, noise=0.0, seed=0):
    t = np.arange(int(round(seconds / DT)) + 1) * DT
    x = v * t + amp * np.sin(2 * math.pi * f * t)
    x = x + np.random.default_rng(seed).normal(0.0, noise, t.size) if noise else x
    return t, np.round(x / Q) * Q


def test_sinusoidal_ripple_is_measured_through_the_window():
    # v = 1e-3 rad/s with a 2 Hz limit cycle of velocity amplitude 2 pi f A = 30 % of v: the
    # RMS is 30 / sqrt(2) = 21.2 %, a window of 50 ms passes sinc(2 Hz * 0.05 s) = 0.9836 of it
    v, f = 1e-3, 2.0
    amp = 0.3 * v / (2 * math.pi * f)
    t, x = _angle(v, amp, f, 10.0)
    r = constant_velocity_ripple(t, x, window=0.05, resolution=Q)
    sinc = math.sin(math.pi * f * 0.05) / (math.pi * f * 0.05)
    assert r["ripple_percent"] == pytest.approx(30.0 / math.sqrt(2) * sinc, rel=0.02)
    assert r["v_mean"] == pytest.approx(v, rel=1e-3)
    assert r["windows"] == 200


def test_encoder_share_is_subtracted():
    # a constant 2e-5 rad/s read by a 2^25 encoder with half a count of noise: the raw window
    # velocities scatter by sqrt(2 (0.25 + 1/12)) counts / 50 ms = 15 % of v; the ripple left is small
    v, noise = 2e-5, 0.5 * Q
    t, x = _angle(v, 0.0, 1.0, 30.0, noise=noise, seed=3)
    r = constant_velocity_ripple(t, x, window=0.05, resolution=Q, noise=noise)
    floor = 100 * math.sqrt(2 * (noise**2 + Q**2 / 12)) / 0.05 / v
    assert r["floor_percent"] == pytest.approx(floor, rel=1e-3)  # divided by the measured mean speed
    assert floor == pytest.approx(15.3, abs=0.1)
    assert r["ripple_percent"] < 0.5 * floor
    raw = constant_velocity_ripple(t, x, window=0.05)  # without the encoder's data: the floor is read as ripple
    assert raw["ripple_percent"] > 0.8 * floor


def test_ripple_checks_its_inputs():
    t, x = _angle(1e-3, 0.0, 1.0, 1.0)
    with pytest.raises(fk.ParameterError, match="window = 0"):
        constant_velocity_ripple(t, x, window=0.0)
    with pytest.raises(fk.ParameterError, match="noise = -1"):
        constant_velocity_ripple(t, x, window=0.05, noise=-1.0)
    with pytest.raises(fk.DataError, match="fewer than 2 windows"):
        constant_velocity_ripple(t, x, window=0.9)
    with pytest.raises(fk.DataError, match="one length"):
        constant_velocity_ripple(t, x[:-1], window=0.05)


def _campaign():
    v = np.r_[np.geomspace(1e-4, 1e-1, 7), -np.geomspace(1e-4, 1e-1, 7)]
    law = fk.Stribeck(Fc=1.0, Fs=1.5, vs=1e-3, sigma2=2.0)
    F = law.steady_state(v)
    r = np.full(v.size, 1.0)
    r[[2, 9]] = [35.0, 12.0]
    F[[2, 9]] *= [0.9, 1.05]  # the hunting runs' means are off the map
    return law, {"v": v, "F": F, "ripple_percent": r}


def test_screen_rejects_and_names_the_runs_that_were_not_constant():
    _, st = _campaign()
    scr = screen_constant_velocity(st)
    assert MAX_RIPPLE_PERCENT == 10.0
    assert scr.status == 0 and scr.accepted.sum() == 12
    assert [round(x["ripple_percent"]) for x in scr.rejected()] == [35, 12]
    assert scr.rejected()[0]["speed_rad_s"] == pytest.approx(st["v"][2])
    assert "+1.000e-03 rad/s (35.0 %)" in scr.message
    assert scr.steady()["v"].size == 12 and st["v"][2] not in scr.steady()["v"]
    assert "REJECTED" in scr.summary()
    assert screen_constant_velocity(st, max_ripple_percent=20.0).accepted.sum() == 13
    low = screen_constant_velocity(st, max_ripple_percent=0.5)
    assert low.status == 1 and "too few points left in the positive and negative direction" in low.message
    scr.plot()


def test_screen_checks_its_inputs():
    _, st = _campaign()
    with pytest.raises(fk.DataError, match="ripple_percent"):
        screen_constant_velocity({"v": st["v"], "F": st["F"]})
    with pytest.raises(fk.ParameterError, match="max_ripple_percent = -1"):
        screen_constant_velocity(st, max_ripple_percent=-1.0)
    with pytest.raises(fk.ParameterError, match="min_points"):
        screen_constant_velocity(st, min_points=0)


def test_fit_two_step_screens_the_steady_points_first():
    law, st = _campaign()
    t = np.arange(301) * 0.02
    T = 0.9 * (2 / np.pi) * np.arcsin(np.sin(np.pi * t))
    full = fk.LuGre(law, sigma0=1e5, sigma1=300.0)
    sim = fk.simulate(full, plant=fk.Mass(1.0), force=T, dt=0.02)
    tri = {"t": t, "F": T, "v": sim.v, "x": sim.x}
    res = fit_two_step(inertia=1.0, steady=st, triangle=tri)
    assert res.status == 0, res.message
    assert res.screen is not None and res.screen.accepted.sum() == 12
    assert res.static.n_obs == 12
    assert res.model.static.positive.vs == pytest.approx(1e-3, rel=1e-4)
    assert "rejected" in res.summary()
    kept_all = fit_two_step(inertia=1.0, steady=st, triangle=tri, max_ripple_percent=None)
    assert kept_all.screen is None and kept_all.static.n_obs == 14
    assert abs(kept_all.model.static.positive.vs / 1e-3 - 1) > 1e-3  # the off-map run biased it
    bad = fit_two_step(inertia=1.0, steady=st, triangle=tri, max_ripple_percent=0.5)
    assert bad.status == 1 and bad.message.startswith("constant-velocity screen") and bad.model is None
