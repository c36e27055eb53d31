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
    res = fit_presliding({"t": t[:2501], "x": x[:2501], "F": convex}, elements=2, polish=False)
    assert not res.success and res.model is None and "not concave" in res.message
    assert np.isnan(res.values).all() and res.flagged is not None
    with pytest.raises(IdentificationError, match="fit_presliding: the virgin branch is not concave"):
        fit_presliding({"t": t[:2501], "x": x[:2501], "F": convex}, elements=2, polish=False, raise_on_failure=True)


def test_polish_is_the_bool_and_refine_the_old_spelling(stroke):
    """One meaning per name: FitOptions.refine counts optimised starts; the pre-sliding bool is ``polish``."""
    from frictionkit.errors import FrictionKitDeprecationWarning

    t, x, F = stroke
    data = {"t": t[:2501], "x": x[:2501], "F": F[:2501]}
    new = fit_presliding(data, elements=2, polish=False)
    with pytest.warns(FrictionKitDeprecationWarning, match="fit_presliding.refine is deprecated: use "
                                                           "fit_presliding.polish"):
        old = fit_presliding(data, elements=2, refine=False)
    np.testing.assert_array_equal(old.values, new.values)
    assert old.provenance["procedure"]["polish"] is False
    with pytest.raises(ParameterError, match="fit_presliding: refine = 2 is not used here"):
        fit_presliding(data, elements=2, refine=2)
    with pytest.raises(ParameterError, match="fit_presliding: FitOptions has no setting 'nfev'"):
        fit_presliding(data, elements=2, nfev=3)


def test_unconverged_polish_is_a_result_not_an_exception(stroke):
    t, x, F = stroke
    data = {"t": t[:7501], "x": x[:7501], "F": F[:7501] + 1e-3 * np.sin(t[:7501] * 377.0)}
    res = fit_presliding(data, elements=3, max_nfev=1)
    assert not res.success and "did not converge within max_nfev = 1" in res.message
    assert res.diagnostics["polish"] == "stopped" and isinstance(res.model, fk.GMS)
    # one evaluation: no step taken, the eq. 19 values are where it stopped
    np.testing.assert_allclose(res.values, res.diagnostics["initial_k"] + res.diagnostics["initial_xi"], rtol=1e-12)
    with pytest.raises(IdentificationError, match="polish did not converge"):
        fit_presliding(data, elements=3, max_nfev=1, raise_on_failure=True)


def test_records_at_different_periods(stroke):
    """A second record of the same stroke at twice the period is simulated at its own period (was refused)."""
    t, x, F = stroke
    coarse = {"t": t[::2], "x": x[::2], "F": fk.simulate(TRUE, position=x[::2], dt=2 * DT).friction}
    res = fit_presliding([{"t": t[:7501], "x": x[:7501], "F": F[:7501]}, coarse], elements=3, static=LAW,
                         branch="virgin", rests=None)
    assert res.success and abs(res.diagnostics["total_stiffness"] / K_TOTAL - 1) < 0.05
    assert res.rms < 1e-3  # noise-free records of the true law, each at its own period
