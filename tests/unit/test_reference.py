"""The solve_ivp reference twins against closed forms (SPEC §1-2).

Closed forms used:

* constant velocity: LuGre and GMS settle on ``Fss(v) = s(v) + sigma2 v`` (GMS weights sum to 1);
* GMS virgin curve at constant velocity ``v`` (so ``S = |s(v)|`` is constant):
  ``sum_i F_i = sum_i min(k_i x, xi_i S)`` — element ``i`` breaks away at exactly
  ``x_i = xi_i S / k_i`` and then stays at ``xi_i S`` (its slip law has that fixed point);
* after a reversal at constant ``|v|`` every element sticks again and the return curve is
  ``sum_i max(xi_i S - k_i D, -xi_i S)`` with ``D`` the distance travelled back (Masing);
* a mass under a constant force ``u > Fs`` reaches the terminal velocity ``Fss(v*) = u``.
"""

from __future__ import annotations

import numpy as np
import pytest
from scipy.optimize import brentq

import frictionkit as fk
from frictionkit.errors import DataError, ParameterError, SimulationError
from frictionkit.simulation.reference import reference_force_driven, reference_motion_driven

LAW = fk.Stribeck(Fc=1.0, Fs=1.5, vs=1e-3, sigma2=0.4)
LAW_L = fk.Stribeck(Fc=1.0, Fs=1.5, vs=1e-3, sigma2=0.4, shape="lorentzian")
K = np.array([1e4, 1e5, 1e6])
XI = np.array([0.5, 0.3, 0.2])


def lugre(law=LAW):
    return fk.LuGre(law, sigma0=1e5, sigma1=63.2)


def gms(law=LAW, C=20.0):
    return fk.GMS(law, k=K, xi=XI, C=C)


def ramp(v, dt, n):
    return v * dt * np.arange(n)


# ------------------------------------------------------------------ motion-driven, constant velocity
@pytest.mark.parametrize("v", [5e-3, -2e-2, 1e-1])
def test_lugre_constant_velocity_settles_on_stribeck(v):
    out = reference_motion_driven(lugre(LAW_L), ramp(v, 1e-4, 401), 1e-4)
    assert out["friction"][-1] == pytest.approx(float(LAW_L.steady_state(v)), rel=1e-8)
    # steady bristle deflection z = s(v) / sigma0
    assert out["states"][-1, 0] == pytest.approx(float(LAW_L.stribeck(v)) / 1e5, rel=1e-8)


@pytest.mark.parametrize("v", [5e-2, -2e-2])
def test_gms_constant_velocity_settles_on_stribeck(v):
    out = reference_motion_driven(gms(LAW_L, C=2000.0), ramp(v, 1e-4, 601), 1e-4)
    assert out["friction"][-1] == pytest.approx(float(LAW_L.steady_state(v)), rel=1e-9)
    np.testing.assert_allclose(out["states"][-1], XI * float(LAW_L.stribeck(v)), rtol=1e-9)
    assert out["slipping"][-1].all() and out["n_breakaway"] == 3


def test_directional_picks_the_row_by_direction():
    pos = fk.Stribeck(Fc=1.0, Fs=1.5, vs=1e-3, sigma2=0.4)
    neg = fk.Stribeck(Fc=2.0, Fs=2.5, vs=2e-3, sigma2=0.1)
    for model in (
        fk.Directional(positive=fk.LuGre(pos, sigma0=1e5), negative=fk.LuGre(neg, sigma0=3e5)),
        fk.Directional(positive=gms(pos, C=2000.0), negative=gms(neg, C=2000.0)),
    ):
        for v, law in ((3e-2, pos), (-3e-2, neg)):
            out = reference_motion_driven(model, ramp(v, 1e-4, 301), 1e-4)
            assert out["friction"][-1] == pytest.approx(float(law.steady_state(v)), rel=1e-8), (model, v)


# ------------------------------------------------------------------ GMS virgin curve and reversal
def test_gms_virgin_curve_breaks_away_exactly_at_xi_s_over_k():
    v, dt, n = 1e-4, 1e-3, 1001  # x up to 1e-4 m, beyond every breakaway
    x = ramp(v, dt, n)
    out = reference_motion_driven(gms(LAW_L, C=50.0), x, dt)
    S = float(LAW_L.stribeck(v))
    x_break = XI * S / K
    expect = np.minimum(K * x[:, None], XI * S)  # per element
    np.testing.assert_allclose(out["states"], expect, rtol=0, atol=1e-12)
    np.testing.assert_allclose(out["friction"], expect.sum(axis=1) + 0.4 * v, rtol=0, atol=1e-12)
    # piecewise-linear: slopes sum(k), then k1 + k2, then k1, then 0
    assert out["n_breakaway"] == 3
    for i in range(3):
        first = int(np.argmax(out["slipping"][:, i]))
        assert x[first - 1] < x_break[i] <= x[first] + 1e-18, (i, x[first], x_break[i])
    slopes = np.diff(out["friction"]) / np.diff(x)
    assert slopes[0] == pytest.approx(K.sum(), rel=1e-9)
    mid12 = (x[:-1] > x_break[2]) & (x[1:] < x_break[1])
    mid01 = (x[:-1] > x_break[1]) & (x[1:] < x_break[0])
    np.testing.assert_allclose(slopes[mid12], K[0] + K[1], rtol=1e-8)
    np.testing.assert_allclose(slopes[mid01], K[0], rtol=1e-8)
    np.testing.assert_allclose(slopes[x[:-1] > x_break[0]], 0.0, atol=1e-6)


def test_gms_reversal_sticks_every_element_and_follows_masing():
    v, dt = 1e-4, 1e-3
    up = ramp(v, dt, 1001)
    x = np.concatenate((up, up[-1] - ramp(v, dt, 2001)[1:]))  # back by 2e-4 m
    out = reference_motion_driven(gms(LAW_L, C=50.0), x, dt)
    S = float(LAW_L.stribeck(v))
    k_rev = 1000
    D = x[k_rev] - x[k_rev:]
    expect = np.maximum(XI * S - K * D[:, None], -XI * S).sum(axis=1)
    np.testing.assert_allclose(out["states"][k_rev:].sum(axis=1), expect, rtol=0, atol=1e-11)
    assert out["slipping"][k_rev].all() and not out["slipping"][k_rev + 1].any()
    assert out["n_breakaway"] == 6
    assert out["friction"][-1] == pytest.approx(-S - 0.4 * v, rel=1e-12)


def test_gms_motion_driven_zero_velocity_freezes_states():
    x = np.concatenate((ramp(1e-4, 1e-3, 101), np.full(50, 1e-5)))
    out = reference_motion_driven(gms(), x, 1e-3)
    np.testing.assert_array_equal(out["states"][-1], out["states"][101])
    assert out["friction"][-1] == pytest.approx(out["states"][-1].sum(), rel=1e-15)  # v = 0: no viscous term


def test_lugre_motion_driven_one_interval_closed_form():
    # constant v on [0, dt]: z(dt) = (S/sigma0) (1 - exp(-sigma0 v dt / S)), S = s(v)
    dt, v = 1e-3, 1e-6
    out = reference_motion_driven(lugre(), np.array([0.0, v * dt]), dt)
    S = float(LAW.stribeck(v))
    z = S / 1e5 * -np.expm1(-1e5 * v * dt / S)
    assert out["states"][1, 0] == pytest.approx(z, rel=1e-9)
    zdot = v - 1e5 * v * z / S
    assert out["friction"][1] == pytest.approx(1e5 * z + 63.2 * zdot + 0.4 * v, rel=1e-9)
    assert out["friction"][0] == pytest.approx((63.2 + 0.4) * v, rel=1e-12)  # k = 0 uses the first interval's v


# ------------------------------------------------------------------ force-driven
def _smooth_step(t, level, t_rise):
    return level * np.where(t < t_rise, 0.5 - 0.5 * np.cos(np.pi * t / t_rise), 1.0)


def test_gms_force_below_breakaway_stays_presliding():
    dt = 1e-3
    t = dt * np.arange(701)
    out = reference_force_driven(gms(), 1.0, _smooth_step(t, 0.8, 0.5), dt)
    # pre-sliding range: the softest element breaks at xi_1 Fs / k_1 = 7.5e-5 m
    assert np.abs(out["x"]).max() < 0.5 * XI[0] * 1.5 / K[0]
    # quasi-static virgin curve: 1e4 x + 0.45 + 0.3 = 0.8 -> x = 5e-6 (stiff two slip, soft one
    # holds); the stiff elements re-stick at small oscillation reversals, hence the loose tolerance
    assert out["x"][-1] == pytest.approx(5e-6, rel=0.1)
    assert out["n_breakaway"] >= 2
    assert abs(out["friction"][-1] - 0.8) < 0.05


def test_lugre_force_below_breakaway_stays_presliding():
    dt = 1e-3
    t = dt * np.arange(701)
    out = reference_force_driven(lugre(), 1.0, _smooth_step(t, 0.8, 0.5), dt)
    z = out["states"][:, 0]
    assert np.abs(z).max() < 1.5 / 1e5  # bristles below Fs / sigma0
    assert np.abs(out["x"]).max() < 1.5 / 1e5
    assert z[-1] == pytest.approx(0.8 / 1e5, rel=1e-3)
    assert np.abs(out["v"][-100:]).max() < 1e-6


def test_gms_all_sticking_start_is_elastic():
    dt = 1e-4
    t = dt * np.arange(51)
    out = reference_force_driven(gms(), 1.0, 5.0 * t, dt)  # 0.025 N: nothing breaks
    assert out["n_events"] == 0
    np.testing.assert_allclose(out["friction"], K.sum() * out["x"] + 0.4 * out["v"], rtol=1e-9, atol=1e-14)


@pytest.mark.parametrize("model", [lugre(), gms()], ids=["lugre", "gms"])
def test_terminal_velocity_under_constant_force(model):
    u = 2.0
    v_star = brentq(lambda v: float(LAW.steady_state(v)) - u, 1e-3, 10.0)
    out = reference_force_driven(model, 0.01, np.full(601, u), 1e-3)
    assert out["v"][-1] == pytest.approx(v_star, rel=1e-8)
    assert out["friction"][-1] == pytest.approx(u, rel=1e-8)


def test_dahl_force_driven_saturates_at_fc():
    dahl = fk.Dahl(Fc=1.0, sigma0=1e5, sigma2=0.4)
    out = reference_force_driven(dahl, 0.01, np.full(601, 2.0), 1e-3)
    assert out["v"][-1] == pytest.approx((2.0 - 1.0) / 0.4, rel=1e-8)


def _stick_slip_input(T=1.3, fs=4000.0):
    dt = 1.0 / fs
    t = dt * np.arange(int(round(T / dt)) + 1)
    return 2.0 * np.sin(2 * np.pi * 0.5 * t), dt


def test_breakaway_happens_near_fs_on_a_slow_ramp():
    u, dt = _stick_slip_input(T=0.5, fs=1000.0)
    out = reference_force_driven(gms(), 1.0, u, dt)
    pre = u < 1.4
    assert np.abs(out["x"][pre]).max() < XI[0] * 1.5 / K[0]  # still pre-sliding below Fs
    assert out["x"][-1] > 1e-3  # gross sliding once u passed Fs


@pytest.mark.parametrize("model", [lugre(), gms()], ids=["lugre", "gms"])
def test_rk45_and_lsoda_agree_on_stick_slip(model):
    u, dt = _stick_slip_input()
    a = reference_force_driven(model, 1.0, u, dt, method="LSODA")
    b = reference_force_driven(model, 1.0, u, dt, method="RK45")
    assert a["x"].max() > 1e-3 and a["v"].min() < 0.0  # slid, then reversed
    for key in ("x", "v"):
        scale = np.abs(a[key]).max()
        np.testing.assert_allclose(b[key], a[key], rtol=0, atol=1e-7 * scale)
    np.testing.assert_allclose(b["friction"], a["friction"], rtol=0, atol=1e-4)
    assert a["n_events"] == b["n_events"]
    if isinstance(model, fk.GMS):
        assert a["n_reversal"] >= 1 and a["n_breakaway"] >= 3


# ------------------------------------------------------------------ errors
def test_event_cap_raises():
    u, dt = _stick_slip_input(T=0.5, fs=1000.0)
    with pytest.raises(SimulationError, match="max_events = 2"):
        reference_force_driven(gms(), 1.0, u, dt, max_events=2)


@pytest.mark.parametrize(
    "kw, err, sub",
    [
        (dict(model=LAW), ParameterError, "needs a dynamic law"),
        (dict(m=0.0), ParameterError, "m = 0.0"),
        (dict(dt=-1e-3), ParameterError, "dt = -0.001"),
        (dict(method="Euler"), ParameterError, "method = 'Euler'"),
        (dict(rtol=0.0), ParameterError, "rtol = 0.0"),
        (dict(u=[0.0, np.nan, 1.0]), DataError, "u[1] = nan"),
        (dict(u=[1.0]), DataError, "at least 2"),
        (dict(u=np.zeros((3, 2))), DataError, "1-D"),
    ],
)
def test_force_driven_rejects_bad_input(kw, err, sub):
    args = dict(model=lugre(), m=1.0, u=np.zeros(5), dt=1e-3) | kw
    with pytest.raises(err) as info:
        reference_force_driven(args.pop("model"), args.pop("m"), args.pop("u"), args.pop("dt"), **args)
    assert sub in str(info.value)


def test_motion_driven_rejects_bad_input():
    with pytest.raises(DataError, match=r"x\[2\] = inf"):
        reference_motion_driven(gms(), [0.0, 1e-6, np.inf], 1e-3)
    with pytest.raises(ParameterError, match="dt = 0.0"):
        reference_motion_driven(gms(), [0.0, 1e-6], 0.0)
    with pytest.raises(ParameterError, match="needs a dynamic law"):
        reference_motion_driven(fk.CoulombViscous(Fc=1.0), [0.0, 1e-6], 1e-3)


def test_mass_object_accepted():
    a = reference_force_driven(lugre(), fk.Mass(2.0), np.full(11, 0.1), 1e-3)
    b = reference_force_driven(lugre(), 2.0, np.full(11, 0.1), 1e-3)
    np.testing.assert_array_equal(a["x"], b["x"])
    assert set(a) >= {"t", "x", "v", "friction", "nfev", "wall_s"}


def test_rk45_and_lsoda_agree_when_fs_below_fc():
    # Fs < Fc: elements re-stuck at a reversal may already be past their threshold at v = 0+,
    # and reversals follow each other quickly; event times must not carry dense-output error.
    model = fk.GMS(fk.Stribeck(Fc=1.5, Fs=1.0, vs=1e-3, sigma2=0.4), k=K, xi=XI, C=20.0)
    u, dt = _stick_slip_input()
    a = reference_force_driven(model, 1.0, u, dt, method="LSODA")
    b = reference_force_driven(model, 1.0, u, dt, method="RK45")
    assert [e[1:] for e in a["event_log"]] == [e[1:] for e in b["event_log"]]
    assert a["n_reversal"] >= 3
    np.testing.assert_allclose([e[0] for e in b["event_log"]], [e[0] for e in a["event_log"]], rtol=0, atol=1e-7)
    np.testing.assert_allclose(b["x"], a["x"], rtol=0, atol=1e-7 * np.abs(a["x"]).max())


def test_zero_weight_element_carries_no_force():
    model = fk.GMS(LAW, k=K, xi=[0.5, 0.0, 0.5], C=20.0)
    u, dt = _stick_slip_input(T=0.5, fs=1000.0)
    out = reference_force_driven(model, 1.0, u, dt)
    assert np.all(out["states"][:, 1] == 0.0)
    ref = reference_force_driven(fk.GMS(LAW, k=K[[0, 2]], xi=[0.5, 0.5], C=20.0), 1.0, u, dt)
    np.testing.assert_array_equal(out["x"], ref["x"])


def test_directional_gms_force_driven_uses_negative_row():
    pos = fk.Stribeck(Fc=1.0, Fs=1.5, vs=1e-3, sigma2=0.4)
    neg = fk.Stribeck(Fc=0.7, Fs=0.9, vs=2e-3, sigma2=0.25)
    model = fk.Directional(
        positive=fk.GMS(pos, k=K, xi=XI, C=20.0), negative=fk.GMS(neg, k=2 * K, xi=XI, C=30.0)
    )
    u = -2.0
    v_star = brentq(lambda v: float(neg.steady_state(v)) - u, -20.0, -1e-3)
    out = reference_force_driven(model, 0.004, np.full(601, u), 1e-3)  # m / sigma2 = 16 ms
    assert out["v"][-1] == pytest.approx(v_star, rel=1e-8)
    # pre-sliding stiffness of the negative row before the first breakaway
    first = out["event_log"][0][0]
    early = out["t"] < first
    np.testing.assert_allclose(out["friction"][early], 2 * K.sum() * out["x"][early] + 0.25 * out["v"][early], rtol=1e-8, atol=1e-15)
