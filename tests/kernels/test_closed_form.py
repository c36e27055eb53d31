"""Closed-form checks of the simulation kernels (steady state, breakaway, stiffness, memory)."""

from __future__ import annotations

import numpy as np
import pytest

import frictionkit as fk

DT = 2.5e-4


def _ramp_to(v_const: float, n: int = 4000, dt: float = DT) -> np.ndarray:
    """Position that moves at constant velocity from rest (v piecewise constant)."""
    return v_const * dt * np.arange(n)


SHAPES = [
    fk.Stribeck(Fc=1.0, Fs=1.5, vs=1e-3, delta=2.0, sigma2=0.4),
    fk.Stribeck(Fc=1.0, Fs=1.5, vs=1e-3, delta=0.7, sigma2=0.4),
    fk.Stribeck(Fc=1.0, Fs=1.5, vs=2e-3, sigma2=0.4, shape="lorentzian"),
    fk.Stribeck(Fc=1.2, Fs=0.8, vs=1e-3, delta=1.0, sigma2=0.0),  # Fs < Fc (seed 000 Table 5)
]


@pytest.mark.parametrize("law", SHAPES, ids=["exp2", "exp0.7", "lorentz", "rising"])
@pytest.mark.parametrize("v_const", [-3e-3, -2e-4, 5e-4, 2e-3, 0.05])
def test_constant_velocity_settles_on_static_map(law, v_const):
    expected = float(law.steady_state(v_const))
    models = [
        fk.LuGre(law, sigma0=1e5, sigma1=50.0),
        fk.GMS(law, k=[1e4, 1e5, 1e6], xi=[0.5, 0.3, 0.2], C=200.0),
    ]
    for model in models:
        res = fk.simulate(model, position=_ramp_to(v_const, n=20000), dt=DT)
        assert res.success
        np.testing.assert_allclose(res.friction[-1], expected, rtol=1e-6, err_msg=type(model).__name__)


def test_directional_steady_state_uses_each_branch():
    pos = fk.Stribeck(Fc=1.0, Fs=1.5, vs=1e-3, sigma2=0.4)
    neg = fk.Stribeck(Fc=2.0, Fs=2.2, vs=3e-3, sigma2=0.1, shape="lorentzian")
    for model in (
        fk.Directional(positive=fk.LuGre(pos, sigma0=1e5, sigma1=10.0), negative=fk.LuGre(neg, sigma0=3e5, sigma1=10.0)),
        fk.LuGre(fk.Directional(positive=pos, negative=neg), sigma0=1e5, sigma1=10.0),
        fk.GMS(fk.Directional(positive=pos, negative=neg), k=[1e5, 1e6], xi=[0.6, 0.4], C=500.0),
    ):
        for v in (-4e-3, 4e-3):
            res = fk.simulate(model, position=_ramp_to(v, n=20000), dt=DT)
            want = float((pos if v > 0 else neg).steady_state(v))
            np.testing.assert_allclose(res.friction[-1], want, rtol=1e-6)


@pytest.mark.parametrize("which", ["lugre", "gms"])
def test_slow_force_ramp_breaks_away_at_Fs(which, lugre, gms, law):
    model = lugre if which == "lugre" else gms
    rate = 0.5  # N/s: slow against the pre-sliding dynamics
    t = np.arange(int(4.0 / DT) + 1) * DT
    u = rate * t
    res = fk.simulate(model, plant=fk.Mass(1.0), force=u, dt=DT)
    assert res.success
    # breakaway: the first time the mass slides faster than the Stribeck velocity
    kb = int(np.argmax(res.v > law.vs))
    assert kb > 0, "never broke away"
    assert u[kb] == pytest.approx(law.Fs, rel=0.03)
    # below breakaway the displacement stays inside the pre-sliding range
    below = u <= 0.9 * law.Fs
    if which == "lugre":
        # quasi-static LuGre: dz/dt = v (1 - sigma0 z / Fs) with sigma0 z = u, so
        # x = -(Fs / sigma0) ln(1 - u / Fs): the familiar logarithmic pre-sliding creep
        x_qs = -(law.Fs / model.sigma0) * np.log1p(-u[below] / law.Fs)
        np.testing.assert_allclose(res.x[below], x_qs, rtol=0.02, atol=0.01 * law.Fs / model.sigma0)
    else:
        # every element sticks until it carries xi_i Fs: x never exceeds the largest xi_i Fs / k_i
        presliding = float(np.max(model.xi * law.Fs / model.k))
        assert np.abs(res.x[below]).max() <= presliding * 1.001
        assert np.abs(res.x[below]).max() >= 0.5 * presliding  # it did deform


def test_presliding_stiffness(lugre, gms):
    # 20 nm out and back: far below any breakaway displacement
    x = np.concatenate([np.linspace(0, 20e-9, 201), np.linspace(20e-9, 0, 201)[1:]])
    for model, stiffness in ((lugre, lugre.sigma0), (gms, gms.presliding_stiffness)):
        res = fk.simulate(model, position=x, dt=1e-3)
        # slope from the quasi-static part (velocity 1e-7 m/s makes the sigma1/sigma2 terms tiny)
        slope = np.polyfit(res.x[50:150], res.friction[50:150], 1)[0]
        assert slope == pytest.approx(stiffness, rel=1e-3), type(model).__name__


def _legs(corners, step):
    pts = [np.array([corners[0]])]
    for a, b in zip(corners[:-1], corners[1:]):
        n = max(int(round(abs(b - a) / step)), 1)
        pts.append(np.linspace(a, b, n + 1)[1:])
    return np.concatenate(pts)


def _rejoin_error(model) -> float:
    """max |F difference| after a minor loop, against the same path without the loop.

    Major loop 0 -> +20 µm -> -20 µm -> back up; 4 µm after the reversal, while
    the softest element (breakaway stroke 2 xi Fs / k = 7.5 µm) still sticks, a
    minor loop -16 -> -18 -> -16 µm is inserted. After it, a model with
    return-point memory continues on the major-loop curve where it left it.
    """
    step = 1e-8  # 10 nm per sample at 1 ms: 10 µm/s
    head = _legs([0.0, 20e-6, -20e-6, -16e-6], step)
    loop = _legs([-16e-6, -18e-6, -16e-6], step)[1:]
    tail = _legs([-16e-6, 20e-6], step)[1:]
    a = fk.simulate(model, position=np.concatenate([head, loop, tail]), dt=1e-3).friction
    b = fk.simulate(model, position=np.concatenate([head, tail]), dt=1e-3).friction
    # the first tail sample follows one interval after the loop's end; compare the tails
    return float(np.abs(a[-tail.size :] - b[-tail.size :]).max())


def test_gms_nonlocal_memory_lugre_has_none(law):
    # large C: slip follows xi*s(v) closely, so the memory is the Maxwell-slip one
    gms = fk.GMS(law, k=[2e5, 1e6, 5e6], xi=[0.5, 0.3, 0.2], C=1e4)
    lugre = fk.LuGre(law, sigma0=2e5, sigma1=0.0)
    err_gms = _rejoin_error(gms)
    err_lugre = _rejoin_error(lugre)
    assert err_gms < 0.01 * law.Fs
    assert err_lugre > 0.05 * law.Fs
