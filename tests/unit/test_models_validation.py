"""Every parameter object rejects bad values with a message naming the value and the rule.

Also closed-form values of the rolling-friction compensation laws (seed 001 eqs. 5-7).
"""

from __future__ import annotations

import math

import numpy as np
import pytest

import frictionkit as fk
from frictionkit.errors import ParameterError
from frictionkit.models.rolling import coulomb_compensation, sigmoid_compensation, sinc_compensation

LAW = dict(Fc=1.0, Fs=1.5, vs=1e-3, delta=2.0, sigma2=0.4)
GMS_KW = dict(k=[1e4, 1e5, 1e6], xi=[0.5, 0.3, 0.2], C=20.0)


def law(**kw):
    return fk.Stribeck(**{**LAW, **kw})


def raises(fn, *substrings):
    """Call ``fn``; assert a ParameterError (also a ValueError) whose message holds every substring."""
    with pytest.raises(ParameterError) as info:
        fn()
    assert isinstance(info.value, ValueError)
    msg = str(info.value)
    for s in substrings:
        assert s in msg, f"{s!r} not in {msg!r}"
    return msg


# ------------------------------------------------------------------ Stribeck
@pytest.mark.parametrize("name", ["Fc", "Fs", "vs", "delta", "sigma2"])
@pytest.mark.parametrize("bad", [math.nan, math.inf, -math.inf])
def test_stribeck_rejects_non_finite(name, bad):
    raises(lambda: law(**{name: bad}), f"Stribeck.{name} = {bad!r}", "finite")


@pytest.mark.parametrize("name", ["Fc", "Fs", "sigma2"])
def test_stribeck_rejects_negative_levels(name):
    raises(lambda: law(**{name: -0.1}), f"Stribeck.{name} = -0.1", ">= 0")


@pytest.mark.parametrize("name", ["vs", "delta"])
@pytest.mark.parametrize("bad", [0.0, -1e-3])
def test_stribeck_rejects_nonpositive_vs_delta(name, bad):
    raises(lambda: law(**{name: bad}), f"Stribeck.{name} = {bad!r}", "> 0")


def test_stribeck_rejects_non_number():
    raises(lambda: law(Fc="one"), "Stribeck.Fc = 'one'", "real number")


def test_stribeck_rejects_unknown_shape():
    raises(lambda: law(shape="cubic"), "Stribeck.shape = 'cubic'", "exponential", "lorentzian")


def test_stribeck_rejects_no_friction():
    raises(lambda: law(Fc=0.0, Fs=0.0), "Fc = Fs = 0", "> 0")


def test_stribeck_accepts_fs_below_fc_and_zero_fs():
    law(Fc=2.0, Fs=1.0)
    law(Fc=1.0, Fs=0.0)


def test_stribeck_is_frozen():
    s = law()
    with pytest.raises(AttributeError):
        s.Fc = 2.0  # type: ignore[misc]


# ------------------------------------------------------------------ CoulombViscous, Dahl
@pytest.mark.parametrize(
    "kw, sub",
    [
        (dict(Fc=0.0), ("CoulombViscous.Fc = 0.0", "> 0")),
        (dict(Fc=-1.0), ("CoulombViscous.Fc = -1.0", "> 0")),
        (dict(Fc=math.nan), ("CoulombViscous.Fc = nan", "finite")),
        (dict(Fc=1.0, sigma2=-0.5), ("CoulombViscous.sigma2 = -0.5", ">= 0")),
        (dict(Fc=1.0, sigma2=math.inf), ("CoulombViscous.sigma2 = inf", "finite")),
    ],
)
def test_coulomb_viscous_rejects(kw, sub):
    raises(lambda: fk.CoulombViscous(**kw), *sub)


@pytest.mark.parametrize(
    "kw, sub",
    [
        (dict(Fc=1.0, sigma0=-1e5), ("Dahl.sigma0 = -100000.0", "> 0")),
        (dict(Fc=1.0, sigma0=0.0), ("Dahl.sigma0 = 0.0", "> 0")),
        (dict(Fc=0.0, sigma0=1e5), ("Dahl.Fc = 0.0", "> 0")),
        (dict(Fc=1.0, sigma0=math.nan), ("Dahl.sigma0 = nan", "finite")),
        (dict(Fc=1.0, sigma0=1e5, sigma2=-1.0), ("Dahl.sigma2 = -1.0", ">= 0")),
    ],
)
def test_dahl_rejects(kw, sub):
    raises(lambda: fk.Dahl(**kw), *sub)


# ------------------------------------------------------------------ LuGre
@pytest.mark.parametrize(
    "kw, sub",
    [
        (dict(sigma0=-1e5), ("LuGre.sigma0 = -100000.0", "> 0")),
        (dict(sigma0=0.0), ("LuGre.sigma0 = 0.0", "> 0")),
        (dict(sigma0=math.inf), ("LuGre.sigma0 = inf", "finite")),
        (dict(sigma0=1e5, sigma1=-63.2), ("LuGre.sigma1 = -63.2", ">= 0")),
        (dict(sigma0=1e5, sigma1=math.nan), ("LuGre.sigma1 = nan", "finite")),
    ],
)
def test_lugre_rejects(kw, sub):
    raises(lambda: fk.LuGre(law(), **kw), *sub)


@pytest.mark.parametrize("static", [None, 1.0, "stribeck"])
def test_lugre_rejects_non_static_map(static):
    raises(lambda: fk.LuGre(static, sigma0=1e5), "LuGre.static", "Stribeck")


def test_lugre_rejects_dynamic_law_as_static():
    inner = fk.LuGre(law(), sigma0=1e5)
    raises(lambda: fk.LuGre(inner, sigma0=1e5), "LuGre.static = LuGre", "must be Stribeck")


# ------------------------------------------------------------------ GMS
@pytest.mark.parametrize(
    "kw, sub",
    [
        (dict(k=[1e4, -1e5, 1e6]), ("GMS.k[1] = -100000.0", "> 0")),
        (dict(k=[1e4, 0.0, 1e6]), ("GMS.k[1] = 0.0", "> 0")),
        (dict(k=[1e4, 1e5, math.nan]), ("GMS.k[2] = nan", "finite")),
        (dict(k=[math.inf, 1e5, 1e6]), ("GMS.k[0] = inf", "finite")),
        (dict(xi=[0.5, -0.3, 0.2]), ("GMS.xi[1] = -0.3", ">= 0")),
        (dict(xi=[0.5, 0.3, math.nan]), ("GMS.xi[2] = nan", "finite")),
        (dict(C=0.0), ("GMS.C = 0.0", "> 0")),
        (dict(C=-20.0), ("GMS.C = -20.0", "> 0")),
        (dict(C=math.nan), ("GMS.C = nan", "finite")),
    ],
)
def test_gms_rejects_bad_values(kw, sub):
    raises(lambda: fk.GMS(law(), **{**GMS_KW, **kw}), *sub)


def test_gms_rejects_mismatched_lengths():
    raises(
        lambda: fk.GMS(law(), k=[1e4, 1e5, 1e6], xi=[0.5, 0.5], C=20.0),
        "k has 3 entries", "xi has 2", "one weight per element",
    )


def test_gms_rejects_empty_k():
    raises(lambda: fk.GMS(law(), k=[], xi=[], C=20.0), "GMS.k", "non-empty")


def test_gms_rejects_2d_k():
    raises(lambda: fk.GMS(law(), k=[[1e4, 1e5]], xi=[0.5, 0.5], C=20.0), "GMS.k", "1-D")


def test_gms_rejects_all_zero_weights():
    raises(lambda: fk.GMS(law(), k=[1e4, 1e5], xi=[0.0, 0.0], C=20.0), "GMS.xi = [0.0, 0.0]", "at least one weight must be > 0")


def test_gms_rejects_non_static_map():
    raises(lambda: fk.GMS(fk.Dahl(Fc=1.0, sigma0=1e5), **GMS_KW), "GMS.static = Dahl", "must be Stribeck")


def test_gms_parameters_are_read_only():
    g = fk.GMS(law(), **GMS_KW)
    with pytest.raises(ValueError):
        g.k[0] = 1.0


# ------------------------------------------------------------------ Directional
def test_directional_rejects_mixed_kinds():
    raises(
        lambda: fk.Directional(positive=law(), negative=fk.CoulombViscous(Fc=1.0)),
        "same kind of law", "Stribeck", "CoulombViscous",
    )
    raises(
        lambda: fk.Directional(positive=fk.LuGre(law(), sigma0=1e5), negative=fk.GMS(law(), **GMS_KW)),
        "same kind of law", "LuGre", "GMS",
    )


def test_directional_rejects_gms_with_different_element_counts():
    p = fk.GMS(law(), **GMS_KW)
    n = fk.GMS(law(), k=[1e4, 1e5], xi=[0.5, 0.5], C=20.0)
    raises(lambda: fk.Directional(positive=p, negative=n), "element counts differ", "M=3", "M=2")


def test_directional_rejects_nesting_and_non_laws():
    d = fk.Directional(positive=law(), negative=law(Fc=1.2))
    raises(lambda: fk.Directional(positive=d, negative=d), "must not themselves be Directional")
    raises(lambda: fk.Directional(positive=1.0, negative=2.0), "float", "not a friction law")


def test_mass_rejects_nonpositive():
    raises(lambda: fk.Mass(0.0), "Mass.m = 0.0", "> 0")
    raises(lambda: fk.Mass(math.nan), "Mass.m = nan", "finite")


# ------------------------------------------------------------------ rolling laws (seed 001 eqs 5-7)
F0, SIGMA, XS = 2.431, 2e-6, 10e-6


def test_sigmoid_closed_form_odd_bounded():
    x = np.linspace(-50 * SIGMA, 50 * SIGMA, 2001)
    f = sigmoid_compensation(x, F0=F0, sigma=SIGMA)
    np.testing.assert_array_equal(sigmoid_compensation(-x, F0=F0, sigma=SIGMA), -f)  # odd
    assert np.all(np.abs(f) < F0)  # bounded by F0, never reached
    assert np.all(np.diff(f) > 0)  # strictly increasing
    assert sigmoid_compensation(0.0, F0=F0, sigma=SIGMA) == 0.0
    assert sigmoid_compensation(SIGMA, F0=F0, sigma=SIGMA) == pytest.approx(F0 / math.sqrt(2), rel=1e-14)
    assert sigmoid_compensation(1e3 * SIGMA, F0=F0, sigma=SIGMA) == pytest.approx(F0, rel=1e-6)
    # slope at the reversal point is F0 / sigma
    h = 1e-6 * SIGMA
    slope = (sigmoid_compensation(h, F0=F0, sigma=SIGMA) - sigmoid_compensation(-h, F0=F0, sigma=SIGMA)) / (2 * h)
    assert slope == pytest.approx(F0 / SIGMA, rel=1e-9)


def test_sinc_closed_form_and_continuity():
    f = lambda x: sinc_compensation(x, F0=F0, xs=XS)  # noqa: E731
    # continuous at 0 (value -F0 on both sides) and at xs (value F0 on both sides)
    assert f(-1e-15) == pytest.approx(-F0, abs=1e-12)
    assert f(0.0) == pytest.approx(-F0, abs=1e-12)
    assert f(1e-22 * XS) == pytest.approx(-F0, abs=1e-9)  # rises like 2 F0 sqrt(x/xs)
    assert f(XS * (1 - 1e-12)) == pytest.approx(F0, abs=1e-9)
    assert f(XS) == pytest.approx(F0, abs=1e-12)
    assert f(2 * XS) == F0
    # x = xs/4 -> y = -1/2, sinc(-1/2) = 2/pi
    assert f(XS / 4) == pytest.approx(4 * F0 / math.pi - F0, rel=1e-12)
    # monotone rise over the pre-sliding length, within [-F0, F0]
    x = np.linspace(0.0, XS, 1001)
    y = f(x)
    assert np.all(np.diff(y) > 0)
    assert np.all(np.abs(y) <= F0 + 1e-12)


def test_coulomb_compensation_signs():
    out = coulomb_compensation([-1.0, -1e-12, 0.0, 1e-12, 3.0], F0=F0)
    assert out.tolist() == [-F0, -F0, F0, F0, F0]


@pytest.mark.parametrize(
    "call, sub",
    [
        (lambda: sigmoid_compensation(0.0, F0=-1.0, sigma=SIGMA), ("sigmoid_compensation.F0 = -1.0", ">= 0")),
        (lambda: sigmoid_compensation(0.0, F0=1.0, sigma=0.0), ("sigmoid_compensation.sigma = 0.0", "> 0")),
        (lambda: sinc_compensation(0.0, F0=math.nan, xs=XS), ("sinc_compensation.F0 = nan", "finite")),
        (lambda: sinc_compensation(0.0, F0=1.0, xs=-XS), ("sinc_compensation.xs = -1e-05", "> 0")),
        (lambda: coulomb_compensation(0.0, F0=-2.0), ("coulomb_compensation.F0 = -2.0", ">= 0")),
    ],
)
def test_rolling_laws_reject_bad_parameters(call, sub):
    raises(call, *sub)
