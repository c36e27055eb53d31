"""Laws whose level reaches zero: ``Stribeck(Fc=0, Fs>0)`` (friction fading out at speed)
and ``Stribeck(Fs=0, Fc>0)`` (no breakaway level, ``g = 0`` at rest).

The kernels divide by ``g = |s(v)|`` (LuGre rate ``sigma0 |v| / g``, GMS slip rate
``C / g``). In the limit ``g -> 0`` the friction state settles on its target at once:
LuGre ``z -> sgn(v) g / sigma0 -> 0`` so ``F -> sigma2 v``, a slipping GMS element
``F_i -> xi_i s(v) -> 0``. ``kernels._stribeck.row`` floors both levels at
``G_FLOOR = 1e-9`` of the largest one (the solve_ivp twin floors ``|s|`` at the same
value), which keeps every rate finite and moves the force by at most 1.5e-9 N here.

Run: 1 kg, ``u = 2 sin(pi t)`` N at dt = 250 µs, ``Stribeck(Fc=0, Fs=1.5, vs=1e-3)``:
the mass breaks away, the friction decays to zero by 30 mm/s (the exponential term
underflows past ``vs 700^(1/2) = 26 mm/s``, where ``g`` is exactly the floor) and the
mass then accelerates freely.
"""

from __future__ import annotations

import numpy as np
import pytest

import frictionkit as fk
from frictionkit.kernels import _stribeck as S
from frictionkit.simulation.reference import reference_force_driven, reference_motion_driven

DT = 2.5e-4
FS = 1.5
FADING = fk.Stribeck(Fc=0.0, Fs=FS, vs=1e-3)


def _lugre(law=FADING):
    return fk.LuGre(law, sigma0=1e5, sigma1=63.2)


def _gms(law=FADING):
    return fk.GMS(law, k=[1e4, 1e5, 1e6], xi=[0.5, 0.3, 0.2], C=20.0)


def _u(n):
    return 2.0 * np.sin(np.pi * DT * np.arange(n))


def test_row_floors_a_zero_level():
    for law in (FADING, fk.Stribeck(Fc=1.0, Fs=0.0, vs=1e-3)):
        p = S.row(np.ascontiguousarray(law.static_rows()), 0)
        floor = S.G_FLOOR * max(law.Fc, law.Fs)
        assert min(p[S.R_FC], p[S.R_FS]) == floor
        for av in (0.0, 1e-3, 1e-2, 2 * p[S.R_VCUT]):
            assert S.g_row(p, av) >= floor and np.isfinite(S.ig_row(p, av))
    # a law with both levels well above the floor is untouched
    p = S.row(np.ascontiguousarray(fk.Stribeck(Fc=1.0, Fs=1.5, vs=1e-3).static_rows()), 1)
    assert (p[S.R_FC], p[S.R_FS], p[S.R_IFC]) == (1.0, 1.5, 1.0)


def test_lugre_force_driven_matches_solve_ivp():
    """The bristle relaxation rate passes 1e13 /s; the twin needs ``atol`` below the
    bristle scale ``g / sigma0`` (1e-14 m) to resolve it."""
    u = _u(2001)
    model = _lugre()
    ref = reference_force_driven(model, 1.0, u, DT, method="LSODA", rtol=1e-9, atol=1e-20)
    res = fk.simulate(model, plant=fk.Mass(1.0), force=u, dt=DT)
    assert res.status == 0, res.message
    assert np.isfinite(res.x).all() and np.isfinite(res.friction).all() and np.isfinite(res.states["z"]).all()
    assert res.v.max() > 0.4  # well past the speed where friction has faded out
    fast = np.abs(res.v) > 0.03
    assert np.abs(res.friction[fast]).max() <= 1e-8  # sigma2 = 0: F -> sigma2 v = 0
    # default tolerances: the collapse of g from 1.5 N to 0 within a few mm/s costs
    # accuracy in position (measured 2.0 µm); F = sigma0 z + sigma1 dz/dt amplifies the
    # bristle error by sigma1 sigma0 |v| / g there, so F is compared at a tighter rtol
    assert np.abs(res.x - ref["x"]).max() <= 3e-6
    tight = fk.simulate(model, plant=fk.Mass(1.0), force=u, dt=DT, options=fk.SimOptions(rtol=1e-7))
    assert tight.status == 0
    assert np.abs(tight.x - ref["x"]).max() <= 1e-6  # measured 0.19 µm
    assert np.abs(tight.friction - ref["friction"]).max() <= 0.01 * FS  # measured 1.4e-3 N


def test_gms_force_driven_matches_solve_ivp():
    u = _u(1601)
    model = _gms()
    ref = reference_force_driven(model, 1.0, u, DT, method="LSODA", rtol=1e-10, atol=1e-14)
    res = fk.simulate(model, plant=fk.Mass(1.0), force=u, dt=DT)
    assert res.status == 0, res.message
    assert np.isfinite(res.x).all() and np.isfinite(res.friction).all()
    assert res.v.max() > 0.3
    fast = np.abs(res.v) > 0.03
    assert np.abs(res.friction[fast]).max() <= 1e-8  # every element slipping, F_i -> xi_i s = 0
    assert np.abs(res.x - ref["x"]).max() <= 1e-6  # measured 0.5 µm
    assert np.abs(res.friction - ref["friction"]).max() <= 0.01 * FS  # measured 3.8e-4 N


def test_gms_motion_driven_matches_solve_ivp():
    x = 0.05 * np.sin(np.pi * DT * np.arange(1601))  # reversal at 0.5 s, 157 mm/s peak
    model = _gms(fk.Stribeck(Fc=0.0, Fs=FS, vs=1e-3, sigma2=0.4))
    ref = reference_motion_driven(model, x, DT, method="LSODA", rtol=1e-10, atol=1e-14)
    res = fk.simulate(model, position=x, dt=DT)
    assert res.status == 0 and np.isfinite(res.friction).all()
    np.testing.assert_allclose(res.friction, ref["friction"], atol=1e-6)


@pytest.mark.parametrize("v", [2e-3, 0.1])
def test_lugre_motion_driven_constant_velocity_closed_form(v):
    """Ramp ``x = v t``: ``dz/dt = v - a z`` with constant ``a = sigma0 v / g``, so
    ``z(t) = z_ss (1 - exp(-a t))``, ``z_ss = g / sigma0`` and
    ``F = sigma0 z + sigma1 (v - a z) + sigma2 v``. At 2 mm/s ``g = Fs exp(-4)``
    (a = 7.3e3 /s, resolved over the samples); at 0.1 m/s ``g`` is the floor, ``a`` is
    ~7e12 /s and ``F = sigma2 v`` (plus the floor, 1.5e-9 N) from the first interval on.
    (The LSODA twin fails on this one with its repeated restarts; see the module notes.)"""
    law = fk.Stribeck(Fc=0.0, Fs=FS, vs=1e-3, sigma2=0.4)
    model = _lugre(law)
    n = 401
    t = DT * np.arange(n)
    res = fk.simulate(model, position=v * t, dt=DT)
    assert res.status == 0 and np.isfinite(res.friction).all()
    g = max(FS * np.exp(-((v / 1e-3) ** 2)), S.G_FLOOR * FS)
    a = model.sigma0 * v / g
    z = g / model.sigma0 * -np.expm1(-a * t)
    F = model.sigma0 * z + model.sigma1 * (v - a * z) + law.sigma2 * v
    np.testing.assert_allclose(res.friction[1:], F[1:], rtol=1e-9, atol=1e-8)
    assert res.friction[-1] == pytest.approx(law.steady_state(v), abs=2e-9)


def test_zero_breakaway_level_runs_at_rest():
    """``Fs = 0``: ``g(0) = 0``, so the LuGre rate at rest is 0/0 without the floor."""
    law = fk.Stribeck(Fc=1.0, Fs=0.0, vs=1e-3, sigma2=0.4)
    u = _u(2001)
    for model in (_lugre(law), _gms(law)):
        res = fk.simulate(model, plant=fk.Mass(1.0), force=u, dt=DT)
        assert res.status == 0, res.message
        assert np.isfinite(res.x).all() and np.isfinite(res.friction).all()
        res = fk.simulate(model, position=np.zeros(50), dt=DT)
        assert res.status == 0 and np.all(res.friction == 0.0)


@pytest.mark.xdist_group("batch_kernel")  # method='fixed' compiles kernels.batch's parallel kernel: once, with test_batch.py
def test_batch_runs_fading_laws():
    u = _u(2001)
    for model in (_lugre(), _gms()):
        one = fk.simulate(model, plant=fk.Mass(1.0), force=u, dt=DT)
        batch = fk.simulate_batch([model, model], masses=1.0, force=u, dt=DT, target=one.v, compare="v")
        assert batch.status.tolist() == [0, 0] and batch.sse.tolist() == [0.0, 0.0]
    # the fixed-step method has no error control; it must not raise, and with enough
    # sub-steps it follows the adaptive run
    model = _lugre()
    one = fk.simulate(model, plant=fk.Mass(1.0), force=u, dt=DT)
    batch = fk.simulate_batch([model], masses=1.0, force=u, dt=DT, target=one.v, compare="v",
                              method="fixed", options=fk.SimOptions(batch_substeps=32))
    assert batch.status.tolist() == [0]
    assert np.sqrt(batch.sse[0] / (u.size - 1)) <= 1e-5  # RMS velocity error [m/s]
