"""Controller parts of seed 001 §2.2, compensators (eqs. 5-7), zero-speed analysis (§3, Table 2)."""

import dataclasses
import math

import numpy as np
import pytest

from frictionkit.control.compensators import RollingCompensator
from frictionkit.control.dob import DisturbanceObserver
from frictionkit.control.loop import simulate_closed_loop
from frictionkit.control.pid import PID
from frictionkit.control.ptc import PerfectTrackingControl
from frictionkit.control.trajectories import (
    Reference,
    cosine_reference,
    mixed_reference,
    piecewise_reference,
    zero_speed_reference,
)
from frictionkit.control.zero_speed import (
    TABLE2,
    classify_crossings,
    deformation_ratio,
    find_crossings,
    min_ratio_before_zero,
    select_compensators,
)
from frictionkit.errors import DataError, ParameterError
from frictionkit.plants.ballscrew import RigidBallScrew
from frictionkit.presets import zhu_fujimoto as zf
from frictionkit.reproduce.zhu_fujimoto import paper_controller

NOM = dict(K_tau=0.715, J=0.01, B=0.1)


# ---------------------------------------------------------------- PID / PTC / DOB
def test_pid_pole_placement_places_triple_pole_at_20_hz():
    c = PID.pole_placement(**NOM, bandwidth_hz=20.0)
    J, B, K = NOM["J"], NOM["B"], NOM["K_tau"]
    poles = np.roots([J, B + K * c.Kd, K * c.Kp, K * c.Ki])
    assert np.allclose(poles, -2 * math.pi * 20.0, rtol=1e-3)


def test_pid_validation_names_parameter():
    with pytest.raises(ParameterError, match="Kp"):
        PID(Kp=-1.0, Ki=0.0, Kd=0.0)
    with pytest.raises(ParameterError, match="bandwidth_hz"):
        PID.pole_placement(**NOM, bandwidth_hz=0.0)


def test_ptc_is_exact_at_frames_and_stable():
    ptc = PerfectTrackingControl(**NOM)
    ref = cosine_reference(duration=1.0)
    R = zf.R
    u, th = ptc.feedforward(ref.x / R, ref.v / R)
    assert np.allclose(th[::2], ref.x[::2] / R, atol=1e-12)
    assert np.abs(th - ref.x / R).max() < 1e-3  # intersample deviation small
    # stable inverse: bounded input for a bounded reference
    assert np.abs(u).max() < 20.0


def test_ptc_rejects_short_or_mismatched_reference():
    ptc = PerfectTrackingControl(**NOM)
    with pytest.raises(DataError, match="omega_ref"):
        ptc.feedforward([0.0, 1.0, 2.0], [0.0, 1.0])
    with pytest.raises(DataError, match="PTC frame"):
        ptc.feedforward([0.0, 1.0], [0.0, 1.0])
    with pytest.raises(ParameterError, match="n"):
        PerfectTrackingControl(**NOM, n=1)


def test_closed_loop_on_nominal_plant_tracks_exactly():
    """PTC + PID on the exact nominal plant, ideal sensors: the error stays at round-off."""
    res = simulate_closed_loop(RigidBallScrew(**NOM), paper_controller(), cosine_reference(duration=0.6))
    assert res.success
    assert np.abs(res.error).max() < 1e-6


def test_dob_rejects_constant_disturbance():
    ref = cosine_reference(duration=1.2)
    plant = RigidBallScrew(**NOM, friction=2.0 / zf.R)  # 2 N·m Coulomb at the motor
    on = simulate_closed_loop(plant, paper_controller(), ref)
    off = simulate_closed_loop(plant, dataclasses.replace(paper_controller(), dob=None), ref)
    sel = (ref.t > 0.45) & (ref.t < 0.65)  # the friction step at the reversal
    assert np.abs(on.error[sel]).max() < 0.5 * np.abs(off.error[sel]).max()


def test_dob_pole_and_validation():
    d = DisturbanceObserver(**NOM, cutoff_hz=80.0, T=0.5e-3)
    assert d.a == pytest.approx(math.exp(-2 * math.pi * 80 * 0.5e-3))
    with pytest.raises(ParameterError, match="cutoff_hz"):
        DisturbanceObserver(**NOM, cutoff_hz=-1.0)


def test_controller_rejects_mismatched_periods_and_feedback():
    c = paper_controller()
    with pytest.raises(ParameterError, match="feedback"):
        dataclasses.replace(c, feedback="scale")
    with pytest.raises(ParameterError, match="pid.T"):
        dataclasses.replace(c, pid=dataclasses.replace(c.pid, T=1e-3))


# ---------------------------------------------------------------- trajectories
def test_piecewise_reference_is_exact():
    ref = piecewise_reference([(0.2, 0.5), (0.1, 0.0), (0.2, -0.5)])
    assert ref.v.max() == pytest.approx(0.1)
    assert ref.x[-1] == pytest.approx(0.5 * 0.5 * 0.04 * 2 + 0.1 * 0.1)
    assert np.allclose(np.gradient(ref.x, ref.T)[5:-5], ref.v[5:-5], atol=1e-3)


def test_reference_validation():
    with pytest.raises(DataError, match="Reference.x"):
        Reference(t=[0.0, 1.0], x=[0.0, np.nan], v=[0.0, 0.0], a=[0.0, 0.0], T=1.0)
    with pytest.raises(ParameterError, match="pattern"):
        mixed_reference(speed=0.05, slow_decel=0.05, fast_decel=1.0, pattern="sx")
    with pytest.raises(ParameterError, match="direction"):
        zero_speed_reference(reverse=True, speed=0.05, decel=1.0, direction=0)


# ---------------------------------------------------------------- compensators
def _one_reversal():
    return cosine_reference(duration=0.75)  # + -> - at 0.5 s


def test_compensators_around_a_reversal():
    ref = _one_reversal()
    comp = RollingCompensator(F0=2.65, xs=10e-6, sigma=2e-6)
    k0 = 1000  # t = 0.5 s
    u_sinc = comp.signal(ref, "sinc")
    u_coul = comp.signal(ref, "coulomb")
    u_sig = comp.signal(ref, "sigmoid")
    before = k0 - 20  # 10 ms before: 49 µm from the reversal point
    assert u_sinc[before] == pytest.approx(2.65) and u_coul[before] == pytest.approx(2.65)
    assert u_sig[before] == pytest.approx(2.65, rel=1e-3)
    # sigmoid starts before zero speed (Fig. 11): at |xi| = sigma it is F0/sqrt(2)
    d = np.abs(ref.x - ref.x[k0])
    j = np.flatnonzero((ref.t < 0.5) & (d <= 2e-6))[0]
    assert u_sig[j] == pytest.approx(2.65 / math.sqrt(2), rel=0.1)
    assert u_sinc[j] == pytest.approx(2.65)  # sinc waits for zero speed
    # after the pre-sliding length all laws give -F0
    after = np.flatnonzero((ref.t > 0.5) & (d >= 10e-6))[0]
    assert u_sinc[after] == pytest.approx(-2.65) and u_coul[after] == pytest.approx(-2.65)
    # Coulomb switches exactly at zero speed
    assert u_coul[k0 + 1] == pytest.approx(-2.65)


def test_compensator_validation():
    ref = _one_reversal()
    comp = RollingCompensator(F0=1.0)
    with pytest.raises(ParameterError, match="law"):
        comp.signal(ref, "lugre")
    with pytest.raises(ParameterError, match="one per crossing"):
        comp.signal(ref, ["sinc", "sinc"])
    with pytest.raises(ParameterError, match="sigma"):
        RollingCompensator(F0=1.0, sigma=0.0)


def test_compensation_zero_at_rest_before_motion():
    ref = zero_speed_reference(reverse=True, speed=0.05, decel=1.0)
    u = RollingCompensator(F0=1.0).signal(ref, "sinc")
    assert u[0] == 0.0


# ---------------------------------------------------------------- zero speed / Table 2
def test_find_crossings_reverse_and_touch():
    rev = zero_speed_reference(reverse=True, speed=0.05, decel=1.0)
    non = zero_speed_reference(reverse=False, speed=0.05, decel=1.0)
    (c1,) = find_crossings(rev.t, rev.v, rev.x)
    (c2,) = find_crossings(non.t, non.v, non.x)
    assert c1.reverse and (c1.before, c1.after) == (1, -1)
    assert not c2.reverse and (c2.before, c2.after) == (1, 1)
    assert c1.t0 == pytest.approx(0.05 + 0.1 + 0.05, abs=1e-3)
    smooth = cosine_reference(amplitude=0.01, period=1.0, duration=0.99)
    # a smooth cruise with a speed dip that stays well above zero is not a crossing
    dip = piecewise_reference([(0.05, 1.0), (0.02, -1.0), (0.02, 1.0)])
    assert find_crossings(dip.t, dip.v) == []
    assert [c.t0 for c in find_crossings(smooth.t, smooth.v)] == [pytest.approx(0.5)]


@pytest.mark.parametrize("reverse", [True, False])
@pytest.mark.parametrize("decel,fast", [(zf.LD_SLOW_DECEL, False), (zf.LD_FAST_DECEL, True)])
def test_classify_by_drive_force_reversal(reverse, decel, fast):
    ref = zero_speed_reference(reverse=reverse, speed=0.05, decel=decel, direction=-1)
    (c,) = classify_crossings(ref, table_mass=273.0, guide_friction=100.0, guide_viscosity=1e4)
    assert c.fast is fast
    assert c.kind == ("fast_" if fast else "slow_") + ("reverse" if reverse else "non_reverse")
    # just before zero speed the predicted drive force opposes the motion iff fast
    assert (c.before * c.drive_force < 0) is fast


def test_selector_follows_table2():
    kinds = {}
    for reverse in (True, False):
        for decel in (zf.LD_SLOW_DECEL, zf.LD_FAST_DECEL):
            ref = zero_speed_reference(reverse=reverse, speed=0.05, decel=decel)
            (s,) = select_compensators(classify_crossings(ref, table_mass=273.0, guide_friction=100.0))
            kinds[s.crossing.kind] = (s.law, s.needs_new_reference)
    assert kinds == {"slow_reverse": ("sinc", False), "fast_reverse": ("sigmoid", False),
                     "slow_non_reverse": ("hold", False), "fast_non_reverse": ("hold", True)}
    assert set(TABLE2) == set(kinds)
    with pytest.raises(DataError, match="classif"):
        ref = zero_speed_reference(reverse=True, speed=0.05, decel=1.0)
        select_compensators(find_crossings(ref.t, ref.v, ref.x))


def test_deformation_ratio_detects_lost_motion():
    t = np.arange(0, 0.2, 0.5e-3)
    R = zf.R
    th = 50.0 * t
    lag = np.where(t > 0.1, 2e-6 * (t - 0.1) / 0.1, 0.0)  # table falls behind by 2 µm
    d = deformation_ratio(t, R * th - lag, th, R=R, Tp=10e-3)
    assert min_ratio_before_zero(d, t_start=0.0, t_zero=0.1) == pytest.approx(1.0)
    assert min_ratio_before_zero(d, t_start=0.1, t_zero=0.2) == pytest.approx(1 - 2e-6 / 0.1 / (50 * R), rel=1e-6)


def test_deformation_ratio_masks_small_motion_and_validates():
    t = np.arange(0, 0.1, 1e-3)
    th = np.zeros_like(t)
    d = deformation_ratio(t, th, th, R=1e-3, Tp=5e-3)
    assert np.isnan(d.ld).all()
    with pytest.raises(DataError, match="no evaluable"):
        min_ratio_before_zero(d, t_start=0.0, t_zero=0.1)
    with pytest.raises(DataError, match="Tp"):
        deformation_ratio(t, th, th, R=1e-3, Tp=1.0)
    with pytest.raises(DataError, match="increasing"):
        deformation_ratio(t[::-1], th, th, R=1e-3, Tp=5e-3)
