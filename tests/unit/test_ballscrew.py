"""Ball-screw plants (seed 001 eq. 1, Fig. 7) and the stage on the machine core."""

import dataclasses
import math

import numpy as np
import pytest
from scipy.integrate import solve_ivp

from frictionkit.control.loop import Sensors, simulate_closed_loop
from frictionkit.control.trajectories import cosine_reference
from frictionkit.errors import ParameterError, SimulationError
from frictionkit.plants.ballscrew import DAHL_SPAN, ElasticBallScrew, RigidBallScrew
from frictionkit.presets import zhu_fujimoto as zf
from frictionkit.reproduce.zhu_fujimoto import paper_controller, paper_plant, paper_sensors

from _ballscrew_open_loop import open_loop


def _open_loop(plant, current, T=0.5e-3, nsub=10):
    res, xt, th, _, _ = open_loop(plant, current, T, nsub)
    return res.success, xt, th


def test_rigid_plant_is_eq1():
    p = RigidBallScrew(K_tau=0.715, J=0.01, B=0.1)
    num, den = p.transfer_function()
    assert num.tolist() == [0.715] and den.tolist() == [0.01, 0.1, 0.0]
    A, B = p.linear_chain().state_space()
    # steady velocity under 1 A: K_tau / B
    assert -A[1, 1] == pytest.approx(0.1 / 0.01) and B[1, 0] == pytest.approx(0.715 / 0.01)


@pytest.mark.parametrize("name", ["k_nut", "k_bearing", "J_m", "M_t"])
def test_elastic_plant_rejects_nonpositive(name):
    kw = zf.plant_kwargs()
    kw[name] = -1.0
    with pytest.raises(ParameterError, match=name):
        ElasticBallScrew(**kw)


def test_elastic_plant_rejects_nan_and_bad_damping():
    kw = zf.plant_kwargs()
    with pytest.raises(ParameterError, match="k_coupling"):
        ElasticBallScrew(**{**kw, "k_coupling": float("nan")})
    with pytest.raises(ParameterError, match="damping_ratio"):
        ElasticBallScrew(**{**kw, "damping_ratio": 1.5})


def test_elastic_plant_static_ratio_and_first_mode():
    p = paper_plant()
    assert p.R == pytest.approx(zf.L_p / (2 * math.pi))
    f1 = p.modes()[0] / (2 * math.pi)
    assert 100.0 < f1 < 300.0  # ball-screw first axial/torsional mode: low hundreds of Hz
    # rigid-body mode: the chain moves x_t = R theta_m without deflection
    ch = p.linear_chain()
    q = np.array([1.0, 1.0, 0.0, 0.0, 0.0, p.R])
    assert np.allclose(ch.K @ q, 0.0, atol=1e-6 * np.abs(ch.K).max())


def test_elastic_plant_low_frequency_matches_rigid_sum():
    """Constant current, no friction: terminal velocity K_tau / (B_m + B_b + C_t R^2)."""
    p = paper_plant(guide_friction=0.0, nut_friction=0.0)
    Phi, Gam = p.linear_chain().discretize(1e-3)
    X = np.zeros(12)
    for _ in range(3000):
        X = Phi @ X + Gam @ np.array([1.0, 0.0, 0.0])
    B_tot = p.B_m + p.B_b + p.C_t * p.R**2
    assert X[6] == pytest.approx(p.K_tau / B_tot, rel=1e-6)


def test_presliding_stiffness_from_length():
    p = paper_plant()
    ch = p.linear_chain()
    assert ch.sigma0[0] == pytest.approx(DAHL_SPAN * p.guide_friction / p.presliding_length)
    assert (ch.Fc * p.R).sum() == pytest.approx(zf.F0_MEASURED)


def _twin(plant, current, T=0.5e-3):
    """Slow, obviously-correct twin: solve_ivp (Radau) on [q, q', F] period by period."""
    ch = plant.linear_chain()
    A, Bw = ch.state_space()
    n2 = A.shape[0]
    Cv = np.zeros((ch.C.shape[0], n2))
    Cv[:, n2 // 2:] = ch.C

    def rhs(t, y, i):
        X, F = y[:n2], y[n2:]
        v = Cv @ X
        dF = np.where(ch.Fc > 0, ch.sigma0 * v * (1 - F * np.sign(v) / np.where(ch.Fc > 0, ch.Fc, 1.0)), 0.0)
        return np.concatenate((A @ X + Bw @ np.concatenate(([i], F)), dF))

    y = np.zeros(n2 + ch.Fc.size)
    xt, th = [], []
    for i in current:
        xt.append(ch.table @ y[: n2 // 2])
        th.append(ch.motor @ y[: n2 // 2])
        y = solve_ivp(rhs, (0, T), y, args=(i,), method="Radau", rtol=1e-8, atol=1e-12).y[:, -1]
    return np.array(xt), np.array(th)


def test_core_stage_matches_solve_ivp_twin_with_friction():
    plant = paper_plant()
    t = np.arange(160) * 0.5e-3
    current = 12.0 * np.sin(2 * np.pi * 12.5 * t)  # reverses twice, through pre-sliding
    ok, xt, th = _open_loop(plant, current)
    xt2, th2 = _twin(plant, current)
    assert ok
    scale = np.abs(xt2).max()
    assert scale > 50e-6
    # tolerance: 1e-4 of the travel (measured 8e-7 on the core; the deleted kernel's explicit
    # Dahl update gave 3e-6)
    assert np.abs(xt - xt2).max() < 1e-4 * scale
    assert np.abs(th - th2).max() < 1e-4 * np.abs(th2).max()


def test_core_stage_exact_for_linear_chain():
    plant = paper_plant(guide_friction=0.0, nut_friction=0.0)
    t = np.arange(40) * 0.5e-3
    current = 5.0 * np.sin(2 * np.pi * 100 * t)
    _, xt, _ = _open_loop(plant, current, nsub=1)
    xt2, _ = _twin(plant, current)
    assert np.abs(xt - xt2).max() < 1e-6 * np.abs(xt2).max()


def test_nonfinite_state_ends_run_with_status_and_message():
    ref = cosine_reference(duration=0.05)
    ctrl = dataclasses.replace(paper_controller(), i_max=1e308)
    u_f = np.zeros(len(ref))
    u_f[10:15] = 1e308  # N·m: the rigid stage's acceleration overflows
    with pytest.warns(RuntimeWarning, match="non-finite"):
        res = simulate_closed_loop(RigidBallScrew(), ctrl, ref, compensation=u_f)
    assert res.status == 1 and not res.success
    assert "non-finite" in res.message
    assert np.isnan(res.x_t[-1])
    with pytest.raises(SimulationError, match="non-finite"), pytest.warns(RuntimeWarning):
        simulate_closed_loop(RigidBallScrew(), ctrl, ref, compensation=u_f, raise_on_failure=True)


def test_sensors_quantise():
    ref = cosine_reference(duration=0.1)
    res = simulate_closed_loop(paper_plant(), paper_controller(), ref, sensors=Sensors())
    q = zf.SCALE_RESOLUTION
    assert np.allclose(res.x_t_meas / q, np.round(res.x_t_meas / q), atol=1e-6)
    assert np.all(res.x_t_meas <= res.x_t + 1e-15) and np.all(res.x_t - res.x_t_meas < q + 1e-15)


def test_noise_seed_reproducible_and_different():
    ref = cosine_reference(duration=0.1)
    a = simulate_closed_loop(paper_plant(), paper_controller(), ref, sensors=paper_sensors(), seed=1)
    b = simulate_closed_loop(paper_plant(), paper_controller(), ref, sensors=paper_sensors(), seed=1)
    c = simulate_closed_loop(paper_plant(), paper_controller(), ref, sensors=paper_sensors(), seed=2)
    assert np.array_equal(a.x_t_meas, b.x_t_meas)
    assert not np.array_equal(a.x_t_meas, c.x_t_meas)


def test_reference_period_must_match_controller():
    ref = cosine_reference(duration=0.1, T=1e-3)
    from frictionkit.errors import DataError

    with pytest.raises(DataError, match="control period"):
        simulate_closed_loop(paper_plant(), paper_controller(), ref)


def test_current_limit_respected():
    ctrl = dataclasses.replace(paper_controller(), i_max=5.0)
    res = simulate_closed_loop(paper_plant(), ctrl, cosine_reference(duration=0.3))
    assert np.abs(res.i).max() <= 5.0 + 1e-12


def test_linear_chain_of_the_sliding_nut_has_no_contact_site():
    ch = paper_plant().linear_chain()
    assert ch.n_friction == ch.C.shape[0] == 2 and ch.contact_site == -1 and ch.contact_q is None
