"""Seed 001 Fig. 2: frequency response of the stage from current to motor position theta_m.

What the seed gives: the caption and "Fig. 2 shows the frequency response of the
experimental device, and the fitted model is shown by the solid line", the fitted model being
eq. 1, ``K_tau / (J s^2 + B s)`` with J = 0.01 kg·m², B = 0.1 N·m·s/rad. The figure itself
is not in the seed text and no resonance frequency is printed, so no resonance can be
compared with a number. Reading used instead (loose, stated): the stage behaves as the
rigid eq. 1 body wherever the paper relies on that model, at least up to the 80 Hz cut-off
of the disturbance observer built on it (§2.2) — so the elastic chain's first
anti-resonance/resonance must lie above 80 Hz, for the preset and every ±30 % stiffness
variant. The level of the response in the rigid band is compared with the fitted line too:
the ``"fig2"`` stage is calibrated to it (its motor inertia makes the rigid-body inertia the
identified J = 0.01), the ``"table1"`` stage is not.
"""

import numpy as np
import pytest

from frictionkit.presets import zhu_fujimoto as zf
from frictionkit.reproduce.zhu_fujimoto import fig2, paper_plant, scaled_plant

from ._variants import STAGES, numbers

stages = pytest.mark.parametrize("stage", STAGES)


def _variants(stage):
    out = [("preset", paper_plant(stage=stage))]
    for name in zf.ASSUMED_STIFFNESSES:
        for f in (0.7, 1.3):
            out.append((f"{name}x{f:g}", scaled_plant(name, f, stage=stage)))
    return out


@stages
def test_frequency_response_rigid_asymptote_and_first_pair(stage):
    p = paper_plant(stage=stage)
    # low frequency: the rigid body (sum of inertias and viscosities at the motor)
    J = p.J_m + zf.J_b + zf.M_t * zf.R**2
    assert J == pytest.approx({"table1": 4.30e-3, "fig2": zf.J_n}[stage], rel=1e-3)
    B = zf.B_m + zf.B_b + zf.C_t * zf.R**2
    f = np.array([0.5, 1.0, 2.0])
    s = 2j * np.pi * f
    G = p.frequency_response(f)
    assert np.allclose(G, zf.K_tau / (J * s * s + B * s), rtol=2e-3)
    # the same response from the state-space form (x' = A x + B u): C (sI - A)^-1 B
    A, Bw = p.linear_chain().state_space()
    fs = np.array([50.0, 150.0, 400.0])
    Gss = [np.linalg.solve(2j * np.pi * fi * np.eye(12) - A, Bw[:, 0])[0] for fi in fs]
    assert np.allclose(p.frequency_response(fs), Gss, rtol=1e-9)
    # the notch and the peak of |G| (rigid slope removed) sit at the undamped pair
    fg = np.linspace(100.0, 220.0, 2401)
    m = np.abs(p.frequency_response(fg)) * fg**2
    r = fig2(plant=p)
    # fig2: the pair is closer (140 / 150 Hz), so the 2 % damping moves the extrema by ~2 %
    rel = {"table1": 0.01, "fig2": 0.03}[stage]
    assert fg[np.argmin(m)] == pytest.approx(r.antiresonance_hz, rel=rel)
    assert fg[np.argmax(m)] == pytest.approx(r.resonance_hz, rel=rel)
    assert r.antiresonance_hz < r.resonance_hz


def test_frequency_response_validation():
    from frictionkit.errors import ParameterError

    p = paper_plant()
    with pytest.raises(ParameterError, match=r"f\[1\] = -1.0"):
        p.frequency_response([1.0, -1.0])
    with pytest.raises(ParameterError, match="output = 'speed'"):
        p.frequency_response([1.0], output="speed")


@stages
def test_fig2_first_elastic_pair_above_the_dob_band(stage):
    """Preset: anti-resonance 139.9 Hz, resonance 165.9 Hz (table1) / 149.7 Hz (fig2)
    (±30 % variants 128-148 / 137-176 Hz): above the 80 Hz the rigid model is used to."""
    bad = {}
    for label, p in _variants(stage):
        r = fig2(plant=p)
        if not min(r.antiresonance_hz, r.resonance_hz) > zf.DOB_CUTOFF_HZ:
            bad[label] = (r.antiresonance_hz, r.resonance_hz)
    assert not bad, bad


TABLE1_XFAIL = pytest.mark.xfail(strict=True, raises=AssertionError, reason=(
    "table1 stage: the model's current -> theta_m response lies +6.2 to +7.2 dB above the eq. 1 "
    "line fitted to Fig. 2 over 5-50 Hz (all nut models and stiffness variants, the contact is "
    "linearised): Table 1's inertias sum to J_m + J_b + M_t R^2 = 4.30e-3 kg·m² against the "
    "identified J = 0.01 (factor 2.33 = 7.3 dB). Mass, not stiffness: the assumed stiffnesses "
    "only move the first pair (140/166 Hz), outside the band. The fig2 stage is calibrated to it."))


@pytest.mark.parametrize("stage", [pytest.param("table1", marks=TABLE1_XFAIL), "fig2"])
def test_fig2_level_within_1_db_of_the_fitted_eq1_line(stage):
    """fig2 stage: -0.16 to +0.09 dB over 5-50 Hz (every stiffness variant within 1 dB)."""
    offs = {label: fig2(plant=p).gain_offset_db for label, p in _variants(stage)}
    if stage == "table1":
        numbers(all(6.1 < lo and hi < 7.3 for lo, hi in offs.values()), f"{offs}")
    bad = {k: v for k, v in offs.items() if not (-1.0 < v[0] and v[1] < 1.0)}
    assert not bad, bad
