"""Intervals of eq. 10 from run means (``covariance="run_robust"``) and the constant-velocity
screen where the encoder cannot resolve its threshold (issue 10, session of 2026-11-23)."""

from __future__ import annotations

import math

import numpy as np
import pytest
from scipy.stats import t as student_t

import frictionkit as fk
from frictionkit.identify import fit_static_map
from frictionkit.identify.two_step import (MAX_RIPPLE_PERCENT, constant_velocity_ripple, fit_two_step,
                                           ripple_rejection_limit, screen_constant_velocity)

Q = 2 * math.pi / 2**25  # one count of a 2^25 counts/rev encoder [rad]


def _hc3_by_hand(X, y):
    """Textbook OLS with the HC3 sandwich (MacKinnon & White 1985), written out directly."""
    XtXi = np.linalg.inv(X.T @ X)
    beta = XtXi @ X.T @ y
    e = y - X @ beta
    h = np.array([x @ XtXi @ x for x in X])
    meat = sum(np.outer(x, x) * ei**2 / (1 - hi) ** 2 for x, ei, hi in zip(X, e, h))
    n, p = X.shape
    return beta, np.sqrt(np.diag(XtXi @ meat @ XtXi)), np.sqrt(np.diag(XtXi) * (e @ e) / (n - p))


def test_run_robust_is_the_larger_of_the_residual_and_the_hc3_error_on_a_linear_map():
    # Coulomb + viscous is linear in (Fc, sigma2): the fit and both variances have closed forms.
    # The fastest run (high leverage) carries its own error; the others a small common scatter.
    v = np.r_[np.linspace(0.01, 0.1, 9), 0.4]
    e = np.array([1, -1, 1, -1, 1, -1, 1, -1, 1, 0]) * 2e-3
    e[-1] = 0.05
    F = 2.0 + 3.0 * v + e
    beta, se_hc3, se_res = _hc3_by_hand(np.column_stack([np.ones_like(v), v]), F)
    expect = np.maximum(se_hc3, se_res)
    assert se_hc3[1] > 1.5 * se_res[1]  # the case the option exists for
    res = fit_static_map(v, F, model="coulomb_viscous", direction="positive", covariance="run_robust")
    assert [res["Fc_pos"], res["sigma2_pos"]] == pytest.approx(beta, rel=1e-7)
    assert res.stderr == pytest.approx(expect, rel=1e-5)
    tq = student_t.ppf(0.975, v.size - 2)
    assert res.parameter("sigma2_pos")["ci95"] == pytest.approx([beta[1] - tq * expect[1], beta[1] + tq * expect[1]],
                                                               rel=1e-5)
    plain = fit_static_map(v, F, model="coulomb_viscous", direction="positive")
    assert plain.stderr == pytest.approx(se_res, rel=1e-5)  # the default is unchanged
    assert res.parts["positive"].diagnostics["covariance"] == "run_robust"
    assert res.parts["positive"].diagnostics["max_leverage"] > 0.5


def test_one_run_off_the_map_inside_the_stribeck_transition_is_carried_by_the_run_robust_interval():
    # twelve runs, four in the transition; one of them 0.05 N·m off (a small limit cycle kept by
    # the screen, as the SDSS rotator's 4.85e-4 rad/s run): the fit bends to it (small residual),
    # vs moves by more than its residual interval, the run-robust interval still holds the truth
    law = fk.Stribeck(Fc=90.0, Fs=119.0, vs=4e-4, sigma2=1250.0)
    v = np.geomspace(2e-5, 2e-2, 12)
    F = law.steady_state(v) + 5e-4 * np.random.default_rng(1).standard_normal(v.size)
    k = int(np.argmin(np.abs(v - 4.8e-4)))
    F[k] += 0.05
    res = fit_static_map(v, F, model="exponential", delta=2.0, direction="positive")
    rob = fit_static_map(v, F, model="exponential", delta=2.0, direction="positive", covariance="run_robust")
    lo, hi = res.parameter("vs_pos")["ci95"]
    assert not lo <= 4e-4 <= hi, (lo, hi, res["vs_pos"])
    lo, hi = rob.parameter("vs_pos")["ci95"]
    assert lo <= 4e-4 <= hi, (lo, hi, rob["vs_pos"])
    assert rob["vs_pos"] == res["vs_pos"]  # same estimate, only the interval differs
    assert np.all(rob.stderr >= res.stderr * (1 - 1e-12))


def test_a_run_that_alone_fixes_a_parameter_gives_an_unbounded_run_robust_interval():
    # two runs at one speed and one at another: the line passes through the lone run (leverage 1)
    v = np.array([0.1, 0.1, 0.2])
    F = np.array([2.31, 2.29, 2.6])
    res = fit_static_map(v, F, model="coulomb_viscous", direction="positive", covariance="run_robust")
    assert not np.isfinite(res.stderr).any() or np.all(res.stderr > 1e6)
    assert any("sigma2 not identifiable" in w for w in res.warnings)


def test_covariance_option_is_checked():
    v = np.linspace(0.01, 0.1, 6)
    with pytest.raises(fk.ParameterError, match="covariance = 'sandwich'"):
        fit_static_map(v, 1 + v, model="coulomb_viscous", direction="positive", covariance="sandwich")
    with pytest.raises(fk.ParameterError, match="needs loss='linear'"):
        fit_static_map(v, 1 + v, model="coulomb_viscous", direction="positive", covariance="run_robust",
                       loss="huber")
    with pytest.raises(fk.ParameterError, match="fit_two_step: covariance = 'x'"):
        fit_two_step(inertia=1.0, triangle={}, steady={"v": [], "F": []}, covariance="x")


# ----------------------------------------------------------------- the screen at the encoder floor
def _run(v, ripple, seed, *, f=2.0, seconds=3.0, dt=1e-3, window=0.05):
    """A constant-velocity run read by a 2^25 encoder (half a count of noise) with a 2 Hz velocity
    ripple of ``ripple`` RMS (relative) as seen through the 50 ms windows."""
    rng = np.random.default_rng(seed)
    t = np.arange(int(round(seconds / dt)) + 1) * dt
    sinc = math.sin(math.pi * f * window) / (math.pi * f * window)
    amp = ripple * math.sqrt(2) / sinc * v / (2 * math.pi * f)
    x = v * t + amp * np.sin(2 * math.pi * f * t + rng.uniform(0, 2 * math.pi)) + rng.normal(0, 0.5 * Q, t.size)
    return constant_velocity_ripple(t, np.round(x / Q) * Q, window=window, resolution=Q, noise=0.5 * Q)


def _campaign(v, ripple, n):
    rs = [_run(v, ripple, s) for s in range(n)]
    return {"v": np.array([r["v_mean"] for r in rs]), "F": np.ones(n),
            "ripple_percent": np.array([r["ripple_percent"] for r in rs]),
            "floor_percent": np.array([r["floor_percent"] for r in rs]),
            "windows": np.array([r["windows"] for r in rs])}


def test_screen_does_not_reject_slow_runs_for_the_encoder_noise():
    # 2e-5 rad/s: the encoder's share is 15 % of the speed (> the 10 % threshold); with no ripple at
    # all the plain comparison rejects some runs by chance, the confidence rule none; every run is
    # named "not resolvable"
    st = _campaign(2e-5, 0.0, 300)
    assert np.median(st["floor_percent"]) == pytest.approx(15.3, abs=0.2)
    assert (st["ripple_percent"] > MAX_RIPPLE_PERCENT).sum() >= 3
    scr = screen_constant_velocity(st)
    assert scr.accepted.all()
    assert not scr.resolvable.any() and "not resolvable" in scr.message and "not resolvable" in scr.summary()


@pytest.mark.parametrize("v, ripple, rate_lo, rate_hi", [
    (2e-5, 0.10, 0.0, 0.08),   # at the threshold: rejected at most ~5 % of the time (95 % confidence)
    (1e-3, 0.10, 0.0, 0.08),
    (2e-5, 0.30, 0.95, 1.0),   # a hunting loop (tens of per cent) is still rejected at the floor
    (1e-3, 0.14, 0.95, 1.0),   # where the encoder is fine, 14 % is rejected
])
def test_screen_rejection_rate_against_a_known_ripple(v, ripple, rate_lo, rate_hi):
    scr = screen_constant_velocity(_campaign(v, ripple, 200))
    rate = 1.0 - scr.accepted.mean()
    assert rate_lo <= rate <= rate_hi, (rate, np.median(scr.ripple_percent))


def test_rejection_limit_follows_the_chi_square_bound():
    # no encoder share and many windows: the limit tends to the threshold itself
    assert ripple_rejection_limit(10.0, 0.0, 1e7) == pytest.approx(10.0, rel=2e-3)
    lim = ripple_rejection_limit(10.0, [0.0, 15.3], [60, 60])
    assert 10.0 < lim[0] < lim[1]
