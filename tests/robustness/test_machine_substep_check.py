"""Issue 13: ``simulate_machine``'s general path must not return a wrong answer with status 0.

The campaign's case: a LuGre slider forced by u = 2 sin(4 pi t) N, run on the general path
(a prescribed motion in the machine keeps it off the one-DOF fast path), default 10
sub-steps, no ``atol``: at 1e-9 / 1e-7 / 1e-5 kg the peak friction came back as 74.9 / 99.4 /
3.55 N with status 0. The expected values below are physics, not the code's output: on a
light mass the inertia force ``m a`` is negligible, so the friction force follows the applied
force and its peak is ~2 N.
"""

from __future__ import annotations

import math

import numpy as np
import pytest

import frictionkit as fk
from frictionkit.machines.simulate import COUPLING_CHECK, STATUS_TOLERANCE, site_coupling
from frictionkit.simulation.inputs import example_gms

DT = 1e-3
T = np.arange(501) * DT
U = 2.0 * np.sin(2.0 * np.pi * 2.0 * T)  # N
LUGRE = fk.LuGre(fk.Stribeck(Fc=1.0, Fs=1.5, vs=1e-3, sigma2=0.4), sigma0=1e5, sigma1=300.0)
STRIBECK = fk.Stribeck(Fc=1.0, Fs=1.5, vs=1e-3, sigma2=0.4)


def slider(law, mass):
    m = fk.Machine("slider")
    x = m.dof("x", inertia=mass)
    m.motion("p")  # unused by the plant; keeps the machine off the one-DOF fast path (as in the campaign)
    m.friction("site", x, law=law)
    m.actuator("u", x)
    return m


def run(law, mass, **kw):
    return fk.simulate_machine(slider(law, mass), dt=DT, inputs={"u": U, "p": np.zeros(T.size)}, **kw)


@pytest.mark.parametrize("mass", [1e-9, 1e-7, 1e-5])
def test_light_lugre_slider_is_flagged_not_returned_as_ok(mass):
    res = run(LUGRE, mass)
    # the run is wrong: on a near-massless slider the friction follows the drive (m a < 1e-4 N; a run at 2,000
    # sub-steps of the 1e-5 kg slider is within 0.004 N of u at every sample), and these runs are more than 1 N
    # off it somewhere (the peak alone no longer shows it at 1e-5 kg: 2.0 N, but 2.96 N off u at one sample)
    off = float(np.max(np.abs(res.site_forces[:, 0] - U)))
    assert off > 1.0, off
    assert res.status == STATUS_TOLERANCE and not res.success, res.message
    assert "substeps" in res.message and "atol=" in res.message and "'site'" in res.message


def test_one_gram_lugre_slider_is_accurate_and_passes_the_check():
    """1e-3 kg: the sub-step is coarse for its time scales (checked), but the run is right."""
    res = run(LUGRE, 1e-3)
    assert res.status == 0, res.message
    assert "sub-step check passed" in res.message
    assert abs(float(np.max(np.abs(res.site_forces))) - 2.0) < 0.02  # peak friction = peak drive (m a ~ 1e-5 N)


def test_normal_mass_runs_no_check():
    """1 kg: the site's time scales span many sub-steps, so nothing extra runs (message unchanged)."""
    mach = slider(LUGRE, 1.0)
    assert site_coupling(mach, DT, 10).max() < 0.1 * COUPLING_CHECK
    res = run(LUGRE, 1.0)
    assert res.status == 0 and res.message == "ok"


@pytest.mark.parametrize("law,k,c", [(LUGRE, 1e5, 300.0 + 0.4), (fk.Dahl(Fc=1.0, sigma0=2e5, sigma2=0.4), 2e5, 0.4)])
def test_site_coupling_of_a_free_mass_is_the_closed_form(law, k, c):
    """On a free mass m over h = dt / n: a held force F moves it by F h^2 / (2 m) and changes
    its speed by F h / m, so r = k h^2 / (2 m) + c h / m."""
    m, n = 0.5, 10
    h = DT / n
    r = site_coupling(slider(law, m), DT, n)
    assert r[0] == pytest.approx(k * h * h / (2 * m) + c * h / m, rel=1e-9)


def test_light_static_slider_is_flagged():
    """A static Stribeck site on 1e-7 kg: velocities 25 % of their range off a 2,560-sub-step run
    (measured when this was written); its site has no state but a steep Stribeck slope."""
    res = run(STRIBECK, 1e-7)
    assert res.status == STATUS_TOLERANCE, res.message
    heavy = run(STRIBECK, 1.0)
    assert heavy.status == 0 and heavy.message == "ok"


def test_gms_error_that_a_4x_check_would_miss_is_flagged():
    """GMS-3 on 1e-4 kg at 40 sub-steps: 40 and 160 sub-steps agree with each other but are both
    ~9 % of the stroke off the adaptive single-axis kernel; 640 sub-steps agree with it (1e-6).
    The check therefore compares with 16x the sub-steps."""
    law = example_gms(3)
    res = run(law, 1e-4, substeps=40)
    ref = fk.simulate(law, plant=fk.Mass(1e-4), force=U, dt=DT)  # adaptive, error-controlled
    assert ref.status == 0
    err = float(np.max(np.abs(res.q[:, 0] - ref.x)) / np.ptp(ref.x))
    assert err > 0.02, err  # the coarse run is wrong...
    assert res.status == STATUS_TOLERANCE, res.message  # ...and says so
    assert math.isfinite(err)


def test_atol_run_whose_positions_agree_but_forces_ring_is_flagged():
    """atol bounds positions only: 1e-9 kg with atol = 1e-3 m was accepted at 20 sub-steps
    (positions 10 -> 20 moved 1e-6 m) with status 0 and a peak friction of 193 N for a 2 N drive."""
    res = run(LUGRE, 1e-9, atol=1e-3)
    assert float(np.max(np.abs(res.site_forces))) > 3.0  # still wrong (see the module docstring)
    assert res.status == STATUS_TOLERANCE, res.message
    assert "Raise substeps" in res.message and "positions only" in res.message
