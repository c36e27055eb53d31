"""Closed forms of the static maps (SPEC §1; seed 000 eq. 4, seed 002 eqs. 9a, 9b)."""

from __future__ import annotations

import math

import numpy as np
import pytest

import frictionkit as fk

Fc, Fs, vs, s2 = 1.0, 1.5, 1e-3, 0.4


@pytest.fixture(params=["exponential", "lorentzian"])
def shape(request):
    return request.param


def phi(r, shape, delta=2.0):
    return math.exp(-(r**delta)) if shape == "exponential" else 1.0 / (1.0 + r * r)


def test_breakaway_level_at_zero_plus(shape):
    law = fk.Stribeck(Fc=Fc, Fs=Fs, vs=vs, sigma2=s2, shape=shape)
    assert law.stribeck(1e-12 * vs) == pytest.approx(Fs, rel=1e-12)
    assert law.stribeck(-1e-12 * vs) == pytest.approx(-Fs, rel=1e-12)
    assert law.stribeck(0.0) == 0.0  # sgn(0) = 0
    assert law.steady_state(0.0) == 0.0


def test_coulomb_level_at_high_speed(shape):
    law = fk.Stribeck(Fc=Fc, Fs=Fs, vs=vs, sigma2=s2, shape=shape)
    v = 1e4 * vs
    tail = 0.0 if shape == "exponential" else (Fs - Fc) / (1 + 1e8)
    assert law.stribeck(v) == pytest.approx(Fc + tail, rel=1e-14)
    assert law.steady_state(v) == pytest.approx(Fc + tail + s2 * v, rel=1e-14)


@pytest.mark.parametrize("r", [0.1, 0.5, 1.0, 2.0, 3.7])
def test_closed_form_at_multiples_of_vs(shape, r):
    law = fk.Stribeck(Fc=Fc, Fs=Fs, vs=vs, sigma2=s2, shape=shape)
    expect = Fc + (Fs - Fc) * phi(r, shape)
    assert law.stribeck(r * vs) == pytest.approx(expect, rel=1e-14)
    assert law.steady_state(-r * vs) == pytest.approx(-expect - s2 * r * vs, rel=1e-14)


def test_value_at_vs():
    e = fk.Stribeck(Fc=Fc, Fs=Fs, vs=vs, delta=0.7)
    lor = fk.Stribeck(Fc=Fc, Fs=Fs, vs=vs, shape="lorentzian")
    assert e.stribeck(vs) == pytest.approx(Fc + (Fs - Fc) / math.e, rel=1e-14)  # any delta
    assert lor.stribeck(vs) == pytest.approx(Fc + (Fs - Fc) / 2, rel=1e-14)


def test_delta_effect():
    v = np.array([0.5, 2.0]) * vs
    f = {d: fk.Stribeck(Fc=Fc, Fs=Fs, vs=vs, delta=d).stribeck(v) for d in (1.0, 2.0, 4.0)}
    # below vs a larger exponent keeps the curve nearer Fs; above vs it falls faster to Fc
    assert f[1.0][0] < f[2.0][0] < f[4.0][0]
    assert f[1.0][1] > f[2.0][1] > f[4.0][1]
    assert f[1.0][1] == pytest.approx(Fc + (Fs - Fc) * math.exp(-2.0), rel=1e-14)
    assert f[4.0][1] == pytest.approx(Fc + (Fs - Fc) * math.exp(-16.0), rel=1e-14)


def test_lorentzian_ignores_delta():
    a = fk.Stribeck(Fc=Fc, Fs=Fs, vs=vs, delta=1.0, shape="lorentzian")
    b = fk.Stribeck(Fc=Fc, Fs=Fs, vs=vs, delta=5.0, shape="lorentzian")
    v = np.linspace(-5 * vs, 5 * vs, 11)
    np.testing.assert_array_equal(a.stribeck(v), b.stribeck(v))


def test_fs_below_fc_rises_with_speed(shape):
    # seed 000 Table 5: corrected curves may rise with speed
    law = fk.Stribeck(Fc=2.0, Fs=1.2, vs=vs, shape=shape)
    v = np.linspace(1e-9, 20 * vs, 400)
    s = law.stribeck(v)
    assert s[0] == pytest.approx(1.2, rel=1e-9)
    assert np.all(np.diff(s) >= 0) and s[-1] > 1.99


def test_odd_symmetry(shape):
    law = fk.Stribeck(Fc=Fc, Fs=Fs, vs=vs, delta=1.3, sigma2=s2, shape=shape)
    v = np.geomspace(1e-9, 10.0, 200)
    np.testing.assert_array_equal(law.stribeck(-v), -law.stribeck(v))
    np.testing.assert_array_equal(law.steady_state(-v), -law.steady_state(v))


def test_array_shape_is_kept():
    law = fk.Stribeck(Fc=Fc, Fs=Fs, vs=vs)
    v = np.full((3, 4), 2e-3)
    assert law.steady_state(v).shape == (3, 4)


def test_static_rows_layout():
    law = fk.Stribeck(Fc=Fc, Fs=Fs, vs=vs, delta=1.5, sigma2=s2, shape="lorentzian")
    rows = law.static_rows()
    assert rows.shape == (2, 6)
    assert rows[0].tolist() == [Fc, Fs, vs, 1.5, s2, 1.0]
    np.testing.assert_array_equal(rows[0], rows[1])


def test_coulomb_viscous():
    law = fk.CoulombViscous(Fc=0.8, sigma2=0.3)
    v = np.array([-2.0, -1e-9, 0.0, 1e-9, 5.0])
    np.testing.assert_allclose(law.steady_state(v), 0.8 * np.sign(v) + 0.3 * v, rtol=1e-15)
    np.testing.assert_allclose(law.stribeck(v), 0.8 * np.sign(v), rtol=1e-15)


def test_directional_picks_branch_by_sign():
    pos = fk.Stribeck(Fc=1.0, Fs=1.2, vs=1e-3, sigma2=0.1)
    neg = fk.Stribeck(Fc=1.5, Fs=1.8, vs=2e-3, sigma2=0.2, shape="lorentzian")
    d = fk.Directional(positive=pos, negative=neg)
    v = np.array([-3e-3, -1e-3, -1e-12, 0.0, 1e-12, 1e-3, 3e-3])
    expect = np.where(v < 0, neg.steady_state(v), pos.steady_state(v))
    np.testing.assert_allclose(d.steady_state(v), expect, rtol=1e-15)
    np.testing.assert_allclose(d.stribeck(v), np.where(v < 0, neg.stribeck(v), pos.stribeck(v)), rtol=1e-15)
    assert d.steady_state(1e-12) == pytest.approx(1.2, rel=1e-9)
    assert d.steady_state(-1e-12) == pytest.approx(-1.8, rel=1e-9)
    rows = d.static_rows()
    assert rows[0].tolist() == pos.static_rows()[0].tolist()
    assert rows[1].tolist() == neg.static_rows()[1].tolist()
    assert d.is_static


def test_directional_of_dynamic_laws_delegates():
    pos = fk.Stribeck(Fc=1.0, Fs=1.2, vs=1e-3)
    neg = fk.Stribeck(Fc=1.5, Fs=1.8, vs=2e-3)
    d = fk.Directional(positive=fk.LuGre(pos, sigma0=1e5), negative=fk.LuGre(neg, sigma0=2e5))
    assert not d.is_static
    assert d.steady_state(1.0) == pytest.approx(1.0)
    assert d.steady_state(-1.0) == pytest.approx(-1.5)


def test_dynamic_models_share_the_static_steady_state():
    law = fk.Stribeck(Fc=Fc, Fs=Fs, vs=vs, sigma2=s2)
    v = np.array([-0.1, -1e-3, 2e-3, 0.05])
    np.testing.assert_array_equal(fk.LuGre(law, sigma0=1e5).steady_state(v), law.steady_state(v))
    gms = fk.GMS(law, k=[1e4, 1e5], xi=[0.3, 0.5], C=20.0)  # weights sum to 0.8
    np.testing.assert_allclose(gms.steady_state(v), 0.8 * law.stribeck(v) + s2 * v, rtol=1e-14)
    dahl = fk.Dahl(Fc=0.7, sigma0=1e5, sigma2=0.2)
    np.testing.assert_allclose(dahl.steady_state(v), 0.7 * np.sign(v) + 0.2 * v, rtol=1e-15)
