"""Exact sensitivities of the motion-driven GMS (kernels/sensitivity_gms.py, issue 11 part 6).

The force must be fk.simulate(position=)'s; the sensitivities must match central differences of
fk.simulate (the GMS update is piecewise smooth: away from switching points the difference
quotient of the discrete map converges to the exact derivative); a motion-driven fit that uses
them must end at an equal or lower cost than the same fit with differences. The truths are
simulated laws set here.
"""

from __future__ import annotations

import numpy as np
import pytest

import frictionkit as fk
from frictionkit.identify import _jacobian, fit_motion_error, fit_output_error
from frictionkit.identify._law_params import LawTemplate

ST = fk.Stribeck(Fc=1.0, Fs=1.5, vs=1e-3, sigma2=0.4)
TRUE = fk.GMS(ST, k=[4e5, 1e5, 2e4], xi=[0.2, 0.3, 0.5], C=20.0)
DT = 1e-4

# one worker: the force-drive tests compile kernels.sensitivity_gms.gms_force_sens (~18 s CPU cold),
# which nothing outside this module reaches (clean clone: it compiled on both xdist workers)
pytestmark = pytest.mark.xdist_group("sensitivity_gms")


def _stroke(n: int) -> np.ndarray:
    t = np.arange(n) * DT
    return 30e-6 * np.sin(2 * np.pi * 3 * t) * (1 + 3 * (t > t[-1] / 2)) + 2e-4 * np.sin(2 * np.pi * 0.3 * t)


@pytest.mark.parametrize("directional", [False, True], ids=["symmetric", "directional"])
def test_force_is_simulates_and_sensitivities_match_central_differences(directional):
    law = TRUE if not directional else fk.Directional(
        positive=TRUE, negative=fk.GMS(fk.Stribeck(Fc=1.2, Fs=1.6, vs=2e-3), k=[3e5, 8e4, 1e4], xi=[0.3, 0.3, 0.4],
                                       C=30.0))
    x = _stroke(8001)
    tmpl = LawTemplate.of(law)
    base = [f"k{i}" for i in (1, 2, 3)] + [f"xi{i}" for i in (1, 2, 3)] + ["C"]
    names = tmpl.expand(base if not directional else [f"{n}_{s}" for n in base for s in ("pos", "neg")])
    theta = np.array([tmpl.get(n) for n in names])

    def build(q):
        return tmpl.build(names, q), 1.0, 0.0

    F, S, status = _jacobian.gms_motion_driven(build, theta, x, DT)
    assert status == 0
    np.testing.assert_array_equal(F, fk.simulate(law, position=x, dt=DT).friction)
    for j, name in enumerate(names):
        h = 1e-6 * theta[j]
        a, b = theta.copy(), theta.copy()
        a[j] += h
        b[j] -= h
        d = (fk.simulate(build(a)[0], position=x, dt=DT).friction
             - fk.simulate(build(b)[0], position=x, dt=DT).friction) / (2 * h)
        assert np.linalg.norm(S[:, j] - d) <= 1e-6 * np.linalg.norm(d), name


@pytest.mark.parametrize("shape", ["exponential", "lorentzian"])
def test_static_fields_match_central_differences(shape):
    """The map's fields reach the update through g (breakaway and slip targets, the slip decay) and
    the output's sigma2 v: checked per field against central differences of fk.simulate."""
    st = (fk.Stribeck(Fc=1.0, Fs=1.5, vs=1e-3, delta=1.5, sigma2=0.4) if shape == "exponential"
          else fk.Stribeck(Fc=1.0, Fs=1.5, vs=1e-3, sigma2=0.4, shape="lorentzian"))
    law = fk.GMS(st, k=[4e5, 1e5, 2e4], xi=[0.2, 0.3, 0.5], C=20.0)
    x = _stroke(8001)
    tmpl = LawTemplate.of(law)
    names = tmpl.expand(("Fc", "Fs", "vs", "sigma2", "C", "k2") + (("delta",) if shape == "exponential" else ()))
    theta = np.array([tmpl.get(n) for n in names])

    def build(q):
        return tmpl.build(names, q), 1.0, 0.0

    F, S, status = _jacobian.gms_motion_driven(build, theta, x, DT)
    assert status == 0
    np.testing.assert_array_equal(F, fk.simulate(law, position=x, dt=DT).friction)
    for j, name in enumerate(names):
        h = 1e-6 * theta[j]
        a, b = theta.copy(), theta.copy()
        a[j] += h
        b[j] -= h
        d = (fk.simulate(build(a)[0], position=x, dt=DT).friction
             - fk.simulate(build(b)[0], position=x, dt=DT).friction) / (2 * h)
        assert np.linalg.norm(S[:, j] - d) <= 1e-6 * np.linalg.norm(d), name


def test_motion_fit_uses_them_and_ends_at_equal_or_lower_cost():
    x = _stroke(20001)
    F = fk.simulate(TRUE, position=x, dt=DT).friction + 0.01 * np.random.default_rng(4).standard_normal(x.size)
    start = fk.GMS(ST, k=[2e5, 2e5, 1e4], xi=[0.2, 0.3, 0.5], C=40.0)
    fits = {jac: fit_motion_error({"t": np.arange(x.size) * DT, "x": x, "F": F}, start, free=("k", "C"), starts=1,
                                  refine=1, profile=False, jacobian=jac) for jac in ("auto", "fd")}
    ex, fd = fits["auto"], fits["fd"]
    assert ex.success and fd.success
    assert ex.diagnostics["sensitivity_runs"] >= ex.diagnostics["nfev"] and fd.diagnostics["sensitivity_runs"] == 0
    assert "exact Jacobian" in ex.provenance["procedure"]["optimiser"]
    # equal cost within the flat valley's tolerance: measured RMS 0.03248936 (exact) vs 0.03248926 (differences)
    # here, and a lower cost for the exact fit on the 50,001-sample record of benchmarks/identify.py
    assert ex.rms <= fd.rms * (1 + 1e-5)
    np.testing.assert_allclose([ex["k1"], ex["k2"], ex["k3"]], [4e5, 1e5, 2e4], rtol=0.2)


def test_a_gms_fit_that_frees_a_static_field_uses_them_too():
    x = _stroke(4001)
    F = fk.simulate(TRUE, position=x, dt=DT).friction
    start = fk.GMS(fk.Stribeck(Fc=0.9, Fs=1.5, vs=1e-3, sigma2=0.4), k=[3e5, 1e5, 2e4], xi=[0.2, 0.3, 0.5], C=20.0)
    fits = {jac: fit_motion_error({"t": np.arange(x.size) * DT, "x": x, "F": F}, start, free=("k1", "Fc"), starts=1,
                                  refine=1, profile=False, jacobian=jac) for jac in ("auto", "fd")}
    ex, fd = fits["auto"], fits["fd"]
    assert ex.success and ex.diagnostics["sensitivity_runs"] > 0 and fd.diagnostics["sensitivity_runs"] == 0
    assert "exact Jacobian" in ex.provenance["procedure"]["optimiser"]
    np.testing.assert_allclose([ex["k1"], ex["Fc"]], [4e5, 1.0], rtol=1e-6)  # noise-free: the truth
    assert ex.rms <= fd.rms * (1 + 1e-5) + 1e-12


# --------------------------------------------------------------------------- force drive (opt-in)
FORCE_TRUE = fk.GMS(fk.Stribeck(Fc=1.0, Fs=1.5, vs=1e-3, sigma2=0.4), k=[4e4, 6e4], xi=[0.4, 0.6], C=20.0)


def _force_record(n=3001, amp=2.0, dt=1e-3):
    t = np.arange(n) * dt
    return t, amp * np.sin(np.pi * t)


def test_force_drive_sensitivities_match_central_differences():
    """Stick-slip (breakaways at ~0.2 vs, reversals): every column against central differences of
    simulations at rtol 1e-9 (the stiffnesses' differences themselves scatter by ~5e-3 between
    steps 1e-3 and 1e-5 there: the switches are located to 1e-6 dt). Measured 1e-4 ... 5e-3."""
    from frictionkit.simulation.core import SimOptions

    opt = SimOptions(rtol=1e-9)
    t, u = _force_record()
    tmpl = LawTemplate.of(FORCE_TRUE)
    names = tmpl.expand(("k1", "k2", "xi1", "C", "Fc", "Fs", "vs", "sigma2"))
    theta = np.array([tmpl.get(n) for n in names] + [1.0])  # and the mass

    def build(q):
        return tmpl.build(names, q[:-1]), q[-1], 0.0

    y, S, status = _jacobian.gms_force_driven(build, theta, u, 1e-3, opt, [(0, u.size)], "v")
    assert status == 0

    def sim(q):
        law, m, _ = build(q)
        return fk.simulate(law, plant=fk.Mass(m), force=u, dt=1e-3, options=opt).v

    np.testing.assert_array_equal(y, sim(theta))
    for j, name in enumerate(names + ["m"]):
        h = 1e-4 * theta[j]
        a, b = theta.copy(), theta.copy()
        a[j] += h
        b[j] -= h
        d = (sim(a) - sim(b)) / (2 * h)
        assert np.linalg.norm(S[:, j] - d) <= 1e-2 * np.linalg.norm(d), name


def test_force_drive_gms_fit_with_sensitivities_is_opt_in():
    t, u = _force_record(2001)
    v = fk.simulate(FORCE_TRUE, plant=fk.Mass(1.0), force=u, dt=1e-3).v
    v = v + 1e-3 * np.random.default_rng(5).standard_normal(v.size)  # noise above the integrator's floor
    start = fk.GMS(fk.Stribeck(Fc=0.95, Fs=1.5, vs=1e-3, sigma2=0.4), k=[3e4, 7e4], xi=[0.4, 0.6], C=25.0)
    fits = {jac: fit_output_error({"t": t, "F": u, "v": v}, start, inertia=1.0, free=("k", "C", "Fc"), jacobian=jac)
            for jac in ("auto", "sensitivity", "fd")}
    assert fits["auto"].diagnostics["sensitivity_runs"] == 0  # auto keeps differences for GMS here
    # ... and says so (result, summary, provenance)
    assert fits["auto"].diagnostics["jacobian"] == "differences (auto: GMS force drive)"
    assert "Jacobian: differences (auto: GMS force drive)" in fits["auto"].summary()
    assert "jacobian='sensitivity' opts in" in fits["auto"].provenance["procedure"]["optimiser"]
    assert fits["sensitivity"].diagnostics["jacobian"] == "sensitivities"
    assert fits["fd"].diagnostics["jacobian"] == "differences"
    sens, fd = fits["sensitivity"], fits["fd"]
    assert sens.diagnostics["sensitivity_runs"] > 0 and "along the simulated trajectory" in \
        sens.provenance["procedure"]["optimiser"]
    assert sens.success and fd.success
    # measured: RMS 1.0604e-3 with sensitivities vs 1.0140e-3 with differences (noise 1e-3) from this
    # one start; over random starts neither ends lower on balance (benchmarks/identify.py's GMS force
    # section), and a sensitivity Jacobian costs more CPU — why "auto" keeps differences
    assert sens.rms <= 1.1 * fd.rms
    np.testing.assert_allclose([sens["C"], sens["Fc"]], [20.0, 1.0], rtol=0.1)


def test_force_drive_sweep_blown_up_at_a_grazing_switch_is_refused():
    """A point a 6-field fit visited (2026-11-23, sens): an element breaks away just after a reversal
    under a stiff spring ringing at omega dt 0.85 (sample 3445), a switch crossed almost tangentially;
    the sweep's sensitivities there jumped to ~4e8 and grew to ~1e141, and trf stopped at once
    (``xtol``, 6,500x the noise floor). Such a sweep is refused (``GMS_SENS_GROWTH``: the caller
    differences); healthy sweeps measured below ~40."""
    from frictionkit.kernels import sensitivity_gms as _kg
    from frictionkit.simulation.core import SimOptions

    dt = 5e-4
    t = np.arange(3601) * dt
    u = 3.0 * np.sin(2 * np.pi * 1.5 * t) + 0.5 * np.sin(2 * np.pi * 7 * t)
    tmpl = LawTemplate.of(fk.GMS(fk.Stribeck(Fc=2.0, Fs=2.6, vs=2e-3, sigma2=1.0), k=[2e5, 5e4, 1e4],
                                 xi=[0.2, 0.3, 0.5], C=50.0))
    names = tmpl.expand(("k", "C", "Fc", "Fs", "vs", "sigma2"))
    theta = np.array([439271.4704363155, 2511198.183484168, 12624.756543260972, 30.987105022995085,
                      1.9845969947454802, 1.8191865324461562, 0.0018243602034920302, 0.5791472969134847])

    def build(q):
        return tmpl.build(names, q), 1.0, 0.0

    opt = SimOptions()
    # the sweep itself, unguarded: measured first
    law, m, off, pk, (dk, dxi, dC, dst), dm, doff = _jacobian._gms_coefficients(build, theta, None)
    res = fk.simulate(law, plant=fk.Mass(m), force=u, dt=dt, options=opt)
    sx, sv = np.empty((u.size, theta.size)), np.empty((u.size, theta.size))
    nsub = int(np.ceil(np.sqrt(pk.k.sum(axis=1).max() / m) * dt / _jacobian.GMS_SENS_OMEGA_H))
    _kg.gms_force_sens(u, dt, m, pk.static, pk.k, pk.xi, pk.C, res.x, res.v,
                       np.ascontiguousarray(res.states["F_elements"]), np.ascontiguousarray(res.states["stick"]),
                       dk, dxi, dC, dst, dm, doff, nsub, sx, sv)
    growth = np.max(np.abs(sv) * theta, axis=1) / np.max(np.abs(res.v))
    assert growth[:3440].max() < 40.0, growth[:3440].max()  # healthy before the grazing switch
    assert growth.max() > 1e6 * _jacobian.GMS_SENS_GROWTH, growth.max()  # blown up after it
    y, S, status = _jacobian.gms_force_driven(build, theta, u, dt, opt, [(0, u.size)], "v")
    assert status == _jacobian.UNRESOLVED and S is None
