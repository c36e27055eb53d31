"""GMS pre-sliding identification (seed 000 §5.2.1, eq. 19): round trips and error paths."""

from __future__ import annotations

import numpy as np
import pytest

import frictionkit as fk
from frictionkit.errors import DataError, IdentificationError, ParameterError
from frictionkit.identify.presliding import fit_presliding, piecewise_linear_fit

DT = 1e-3
LAW = fk.Stribeck(Fc=1.0, Fs=1.5, vs=1e-3, delta=2.0)
# breakaway displacements xi s / k at s = 1.5 N: 0.75, 4.5 and 37.5 µm
TRUE = fk.GMS(LAW, k=[4e5, 1e5, 2e4], xi=[0.2, 0.3, 0.5], C=20.0)
K_TOTAL = 5.2e5


@pytest.fixture(scope="module")
def stroke():
    """Virgin 0 -> +50 µm, then -50 µm and back to +50 µm at 20 µm/s."""
    x = np.r_[np.linspace(0, 50e-6, 2501), np.linspace(50e-6, -50e-6, 5001)[1:],
              np.linspace(-50e-6, 50e-6, 5001)[1:]]
    t = np.arange(x.size) * DT
    F = fk.simulate(TRUE, position=x, dt=DT).friction
    return t, x, F


def _measure(x, F, seed):
    rng = np.random.default_rng(seed)
    return np.round(x / 1e-8) * 1e-8, F + 0.01 * rng.standard_normal(F.size)  # 10 nm counts, 10 mN noise


@pytest.mark.parametrize("seed", [0, 1, 2])
@pytest.mark.parametrize("branch", ["virgin", "reversal"])
def test_round_trip(stroke, seed, branch):
    t, x, F = stroke
    xq, Fn = _measure(x, F, seed)
    res = fit_presliding({"t": t, "x": xq, "F": Fn}, elements=3, static=LAW, branch=branch)
    d = res.diagnostics
    assert abs(d["total_stiffness"] / K_TOTAL - 1) < 0.10
    assert abs(d["initial_total_stiffness"] / K_TOTAL - 1) < 0.10  # eq. 19 alone, before refinement
    np.testing.assert_allclose([res["k1"], res["k2"], res["k3"]], [4e5, 1e5, 2e4], rtol=0.10)
    np.testing.assert_allclose([res["xi1"], res["xi2"], res["xi3"]], [0.2, 0.3, 0.5], rtol=0.10)
    # breakpoints at xi s / k (times 2 after a reversal)
    f = 1.0 if branch == "virgin" else 2.0
    np.testing.assert_allclose(d["breakpoints"], f * np.array([0.75e-6, 4.5e-6, 37.5e-6]), rtol=0.15)
    assert d["factor"] == pytest.approx(f)
    assert isinstance(res.model, fk.GMS) and res.model.M == 3
    assert res.rms < 0.02


def test_auto_branch_and_default_static(stroke):
    t, x, F = stroke
    res = fit_presliding({"t": t, "x": x, "F": F}, elements=3)
    assert res.diagnostics["branch"] == "virgin"
    assert abs(res.diagnostics["total_stiffness"] / K_TOTAL - 1) < 0.10
    assert sum(res.model.xi) == pytest.approx(1.0, rel=0.05)  # plateau taken as the static level


def test_piecewise_linear_recovers_breaks():
    u = np.linspace(0, 10e-6, 2001)
    f = np.minimum.reduce([3e5 * u, 0.3 + 1e5 * (u - 1e-6), 0.6 + 1e4 * (u - 4e-6)])
    fit = piecewise_linear_fit(u, f, 2)
    np.testing.assert_allclose(fit["breaks"], [1e-6, 4e-6], rtol=1e-3)
    np.testing.assert_allclose(fit["slopes"], [3e5, 1e5, 1e4], rtol=1e-3)


def test_errors(stroke):
    t, x, F = stroke
    with pytest.raises(ParameterError, match="elements = 0"):
        fit_presliding({"t": t, "x": x, "F": F}, elements=0)
    with pytest.raises(ParameterError, match="branch = 'sideways'"):
        fit_presliding({"t": t, "x": x, "F": F}, elements=2, branch="sideways")
    with pytest.raises(DataError, match="does not move"):
        fit_presliding({"t": t, "x": np.zeros_like(x), "F": F}, elements=2)
    convex = 1e9 * x[:2501] ** 2  # stiffening curve: not a pre-sliding branch
    with pytest.raises(IdentificationError, match="not concave"):
        fit_presliding({"t": t[:2501], "x": x[:2501], "F": convex}, elements=2, refine=False)
