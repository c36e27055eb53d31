"""The SDSS axes (seed 002): validation, the corrected equations, the conventions we chose."""

from __future__ import annotations

import math

import numpy as np
import pytest

import frictionkit as fk
from frictionkit.identify.two_step import fit_two_step
from frictionkit.machines import discretise
from frictionkit.presets import sdss


def test_sidereal_rate_and_arcsec():
    # seed 002 / issue 10: 15 arcsec/s ~ 7.29e-5 rad/s
    assert sdss.SIDEREAL_RATE == pytest.approx(7.292e-5, rel=1e-3)
    assert sdss.SIDEREAL_RATE / sdss.ARCSEC == pytest.approx(15.04, abs=0.01)


def test_eq2_torque_with_corrected_nc():
    ax = sdss.AzimuthAxis()
    # eq. 2: T = 2 n_c K_T i with n_c = disc/capstan = 25 (paper prints capstan/disc)
    assert ax.n_c == 25.0
    assert ax.torque_constant == pytest.approx(2 * 25.0 * ax.K_T)
    with pytest.raises(fk.ParameterError, match=r"n_c = 0\.04"):
        sdss.AzimuthAxis(n_c=0.04)


def test_eq3_rederived_rotator_torque_and_inertia():
    r = sdss.RotatorAxis()
    # T_m = n n_c K_T i (the printed n_c K_T i lacks the HD ratio n)
    assert r.torque_constant == pytest.approx(r.n * r.n_c * r.K_T)
    m = r.machine(loop="open")
    parts = discretise(m, 1e-4)[4]
    # rigid mode: the motor reflected to the rotator frame carries J_m (n n_c)^2
    c = np.array([r.ratio, 1.0])  # theta_m = n n_c theta_3 when the flexspline is not deflected
    assert c @ parts["M"] @ c == pytest.approx(r.inertia)
    # rotator-side stiffness n_c^2 K1 and the flexspline mode above the paper's 10 Hz
    w2 = np.linalg.eigvals(np.linalg.solve(parts["M"], parts["K"])).real
    f = math.sqrt(max(w2)) / (2 * math.pi)
    assert f > 10.0


def test_harmonic_drive_stiffens_with_torque():
    r = sdss.RotatorAxis()
    k = r.hd_stiffness
    assert k[0] < k[1] < k[2]  # our choice against the paper's literal "compliance increases"


def test_altitude_gravity_sign_and_reference():
    alt = sdss.AltitudeAxis()
    # G2 = m g X sin(theta): zero at the hanging position, opposing positive angles (stable)
    assert alt.gravity(0.0) == 0.0
    assert alt.gravity(0.01) == pytest.approx(alt.imbalance * 0.01, rel=1e-4)  # eq. 13a small-angle form
    m = alt.machine(loop="open", theta0=0.05)
    res = fk.simulate_machine(m, dt=0.02, inputs={"i": np.zeros(200)})
    th = res.position("theta")
    # no torque: gravity pulls the axis back towards 0 until friction holds it
    assert th[-1] < 0.05


def test_axes_validate_and_name_the_value():
    with pytest.raises(fk.ParameterError, match=r"J = -1"):
        sdss.AzimuthAxis(J=-1.0)
    with pytest.raises(fk.ParameterError, match="imbalance"):
        sdss.AltitudeAxis(imbalance=-5.0)
    with pytest.raises(fk.ParameterError, match="friction"):
        sdss.AzimuthAxis(friction=fk.Stribeck(Fc=1.0, Fs=1.0, vs=1.0))
    with pytest.raises(fk.ParameterError):
        sdss.RotatorAxis(hd_stiffness=(1.0, 2.0), hd_torques=(1.0, 2.0))
    with pytest.raises(fk.ParameterError, match="counts"):
        sdss.Encoder(counts=1)
    with pytest.raises(fk.ParameterError, match="map"):
        sdss.stribeck_map(1.0, 1.5, 1e-3, 0.0, map="9c")
    with pytest.raises(fk.ParameterError, match="axis"):
        sdss.axis("declination")


def test_maps_9a_9b_and_generalised_exponent():
    a = sdss.stribeck_map(1.0, 1.5, 1e-3, 0.0, map="9a")
    b = sdss.stribeck_map(1.0, 1.5, 1e-3, 0.0)
    g = sdss.stribeck_map(1.0, 1.5, 1e-3, 0.0, delta=0.5)
    v = np.array([1e-3])
    # at v = vs: 9a gives Fc + (Fs - Fc)/2, 9b gives Fc + (Fs - Fc)/e for any exponent
    assert a.steady_state(v)[0] == pytest.approx(1.25)
    assert b.steady_state(v)[0] == pytest.approx(1.0 + 0.5 / math.e)
    assert g.steady_state(v)[0] == pytest.approx(1.0 + 0.5 / math.e)
    assert g.steady_state(4 * v)[0] == pytest.approx(1.0 + 0.5 * math.exp(-2.0))


def test_encoder_resolution():
    e = sdss.Encoder()
    assert e.resolution / sdss.ARCSEC == pytest.approx(0.0386, abs=1e-4)  # 2^25 counts/rev


def test_fit_two_step_rejects_bad_settings():
    run = {"t": np.arange(5) * 0.1, "F": np.zeros(5), "v": np.zeros(5)}
    with pytest.raises(fk.ParameterError, match="order"):
        fit_two_step(inertia=1.0, triangle=run, steady={"v": [], "F": []}, order="both")
    with pytest.raises(fk.ParameterError, match="steady"):
        fit_two_step(inertia=1.0, triangle=run)
    with pytest.raises(fk.ParameterError, match="above"):
        fit_two_step(inertia=1.0, triangle=run, order="dynamic_first")
    with pytest.raises(fk.ParameterError, match="inertia"):
        fit_two_step(inertia=0.0, triangle=run, steady={"v": [], "F": []})
    with pytest.raises(fk.DataError, match="'v'"):
        fit_two_step(inertia=1.0, triangle={"t": run["t"], "F": run["F"]}, steady={"v": [], "F": []})


def test_flags_are_matched_to_per_direction_names():
    from frictionkit.identify.two_step import is_flagged

    w = ("positive: Fc not identifiable: standard error 70.3 is 183 % of its value",
         "negative: sigma2 = 2.3e-18 is at its bound", "Fs_neg is poorly determined (standard error ...)")
    assert [is_flagged(n, w) for n in ("Fc_pos", "Fc_neg", "sigma2_neg", "sigma2_pos", "Fs_neg", "sigma0")] == \
        [True, False, True, False, True, False]
