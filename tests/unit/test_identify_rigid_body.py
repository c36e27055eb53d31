"""IDIM-LS on simulated rigid axes with known parameters."""

from __future__ import annotations

import numpy as np
import pytest

from frictionkit import CoulombViscous, Directional
from frictionkit.data import Recording
from frictionkit.errors import DataError, IdentificationError
from frictionkit.identify import RigidBody, fit_rigid_body, rigid_body_regressors

DT = 1e-3
T = np.arange(0, 12.0, DT)
# smooth back-and-forth motion: position, velocity, acceleration in closed form
W = 2 * np.pi * np.array([0.3, 0.7, 1.3])
A = np.array([0.05, 0.01, 0.004])
X = (A[:, None] * np.sin(W[:, None] * T)).sum(0)
V = (A[:, None] * W[:, None] * np.cos(W[:, None] * T)).sum(0)
ACC = -(A[:, None] * W[:, None] ** 2 * np.sin(W[:, None] * T)).sum(0)


def _rec(F, seed=0, noise=0.2, quant=5e-8):
    rng = np.random.default_rng(seed)
    x = quant * np.round(X / quant)  # encoder counts
    return Recording(t=T, x=x, F=F + noise * rng.standard_normal(T.size), name="sim")


def test_symmetric_parameters_recovered():
    truth = dict(M=95.0, Fv=200.0, Fc=20.0, offset=-3.0)
    F = truth["M"] * ACC + truth["Fv"] * V + truth["Fc"] * np.sign(V) + truth["offset"]
    res = fit_rigid_body(_rec(F))
    for k, val in truth.items():
        assert res[k] == pytest.approx(val, rel=0.02, abs=0.1), k
        lo, hi = res.ci95[res.names.index(k)]
        assert lo - 0.02 * abs(val) <= val <= hi + 0.02 * abs(val)
    assert res.units == ("kg", "N·s/m", "N", "N")
    assert isinstance(res.model, RigidBody)
    assert res.model.friction == CoulombViscous(Fc=res["Fc"], sigma2=res["Fv"])
    # relative error definition: 100 ||y - X theta|| / ||y|| on the decimated data
    y, yp = res.data["y"], res.data["y_pred"]
    assert res.relative_error_percent == pytest.approx(100 * np.linalg.norm(y - yp) / np.linalg.norm(y))
    assert res.diagnostics["condition_number"] > 1


def test_asymmetric_parameters_recovered_without_offset():
    F = 50.0 * ACC + np.where(V > 0, 150.0 * V + 18.0, 240.0 * V - 22.0)
    res = fit_rigid_body(_rec(F, seed=1), asymmetric=True)
    assert res.names == ("M", "Fv_pos", "Fc_pos", "Fv_neg", "Fc_neg")
    expect = dict(M=50.0, Fv_pos=150.0, Fc_pos=18.0, Fv_neg=240.0, Fc_neg=22.0)
    for k, val in expect.items():
        assert res[k] == pytest.approx(val, rel=0.03), k
    assert isinstance(res.model.friction, Directional)
    assert res.model.force([0.0], [-0.1]).item() == pytest.approx(-22.0 - 24.0, rel=0.03)


def test_regressors_follow_the_published_steps():
    F = 10.0 * ACC
    reg = rigid_body_regressors(_rec(F, noise=0.0), q=10, skip=49)
    n_expected = int(np.ceil((T.size - 49) / 10))
    assert reg["X"].shape == (n_expected, 4)
    assert reg["t"][0] == pytest.approx(T[49])
    # The anti-alias filter is an even-order Chebyshev I (0.05 dB ripple): its DC gain is
    # 10**(-0.05/20), squared by the zero-phase pass. y and every column get the same
    # factor, so the least-squares estimates are unaffected (as with MATLAB's decimate).
    assert np.allclose(reg["X"][:, 3], (10 ** (-0.05 / 20)) ** 2, atol=1e-9)
    assert reg["names"] == ("M", "Fv", "Fc", "offset")


def test_missing_position_and_short_recording():
    with pytest.raises(DataError, match=r"missing signal\(s\) x"):
        fit_rigid_body(Recording(t=T, F=np.zeros(T.size)))
    short = Recording(t=T[:200], x=X[:200], F=np.zeros(200))
    with pytest.raises(DataError, match=r"has 200 samples; IDIM-LS with skip=49, q=10 needs at least 369"):
        fit_rigid_body(short)


def test_one_direction_only_is_rank_deficient_for_asymmetric_fit():
    x = 0.01 * T + 0.001 * np.sin(2 * np.pi * T)  # always moving forward
    v = 0.01 + 0.002 * np.pi * np.cos(2 * np.pi * T)
    rec = Recording(t=T, x=x, F=5.0 * v + 1.0)
    with pytest.raises(IdentificationError, match=r"observation matrix has rank 3 < 5"):
        fit_rigid_body(rec, asymmetric=True)
