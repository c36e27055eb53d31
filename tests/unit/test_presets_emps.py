"""The EMPS preset on the machine core, on synthetic references (no data needed)."""

from __future__ import annotations

import numpy as np
import pytest

import frictionkit as fk
from frictionkit.errors import ParameterError
from frictionkit.identify import emps_closed_loop
from frictionkit.presets import emps_machine
from frictionkit.presets.emps import EMPS_CONSTANTS, PUBLISHED

C = EMPS_CONSTANTS
LAW = fk.CoulombViscous(Fc=PUBLISHED["Fc"], sigma2=PUBLISHED["Fv"])


def _run(qg, *, offset=PUBLISHED["offset"], substeps=10, **kw):
    m = emps_machine(M=PUBLISHED["M"], friction=LAW, offset=offset, **kw)
    res = fk.simulate_machine(m, dt=C["dt"], inputs={"qg": qg}, substeps=substeps)
    assert res.success, res.message
    return m, res


def _controller(qg, qm):
    """The benchmark's law in NumPy: qf, vf, nu (saturated), all memories zero at k = 0."""
    qm_prev = np.r_[0.0, qm[:-1]]
    qf = 0.5 * (qm + qm_prev)
    vf = (qf - np.r_[0.0, qf[:-1]]) / C["dt"]
    return np.clip(C["kv"] * (C["kp"] * (qg - qm) - vf), -C["vmax"], C["vmax"])


def test_step_response_settles_within_the_friction_band():
    qg = np.r_[np.zeros(10), np.full(1990, 1e-3)]
    _, res = _run(qg)
    q = res.position("q")
    # a P position loop against Coulomb friction stops where kp kv gtau |e| <= Fc + |offset|
    band = (PUBLISHED["Fc"] + abs(PUBLISHED["offset"])) / (C["kp"] * C["kv"] * C["gtau"])
    assert abs(q[-1] - 1e-3) <= band * 1.001
    assert abs(q[-1] - 1e-3) < 2e-5
    assert res.v[-1, 0] == 0.0  # the static site sticks exactly at rest


def test_saturation_is_respected_and_reached():
    qg = np.r_[np.zeros(5), np.full(995, 0.05)]  # kp kv 0.05 m = 1950 V before saturation
    _, res = _run(qg)
    nu, nu_c = res.signal("nu"), res.signal("nu_c")
    assert np.abs(nu).max() <= C["vmax"]
    assert np.abs(nu).max() == C["vmax"] and np.abs(nu_c).max() > 100.0
    assert np.abs(res.u[:, res.actuator_names.index("motor")]).max() <= C["vmax"]


def test_one_sample_delay_tau_k_is_gtau_nu_k_minus_1():
    qg = np.r_[np.zeros(5), np.linspace(0.0, 0.02, 500), np.full(495, 0.02)]
    _, res = _run(qg)
    applied = res.u[:, res.actuator_names.index("motor")]
    nu = res.signal("nu")
    assert applied[0] == 0.0
    assert np.array_equal(applied[1:], nu[:-1])
    out = emps_closed_loop(qg, M=PUBLISHED["M"], friction=LAW, offset=PUBLISHED["offset"], substeps=10)
    assert np.array_equal(out["tau"], C["gtau"] * applied)
    assert np.array_equal(out["nu"], nu)
    assert np.array_equal(out["q"], res.position("q"))


def test_controller_blocks_equal_the_benchmark_equations():
    qg = 0.1 * (1.0 - np.cos(np.linspace(0.0, 2.0 * np.pi, 1500)))
    _, res = _run(qg)
    qm = res.signal("qm")
    assert np.array_equal(qm, res.position("q"))  # unquantised by default
    np.testing.assert_allclose(res.signal("nu"), _controller(qg, qm), rtol=0, atol=1e-9)
    np.testing.assert_allclose(res.signal("vf"), np.gradient(qm, C["dt"]), atol=0.1)  # a velocity


def test_offset_is_a_constant_force_opposing_tau():
    # open loop in effect: hold the reference at the start, compare with and without offset
    qg = np.zeros(300)
    _, r0 = _run(qg, offset=0.0)
    _, r1 = _run(qg, offset=-30.0)  # |offset| > Fc: the axis creeps in +q and the loop holds it
    assert np.all(r0.position("q") == 0.0)
    assert r1.position("q")[-1] > 0.0
    assert np.all(r1.signal("offset_force") == 30.0)
    m0 = emps_machine(M=95.0, friction=LAW)
    assert [a.name for a in m0.actuators] == ["motor"]


def test_encoder_resolution_quantises_qm():
    qg = np.r_[np.zeros(5), np.full(495, 1.234567e-3)]
    _, res = _run(qg, encoder_resolution=5e-8)
    counts = res.signal("qm") / 5e-8
    np.testing.assert_allclose(counts, np.round(counts), atol=1e-6)


def test_any_law_runs_on_the_preset():
    law = fk.LuGre(fk.Stribeck(Fc=20.0, Fs=25.0, vs=0.01, sigma2=200.0), sigma0=1e7, sigma1=2e3)
    m = emps_machine(M=95.0, friction=law)
    res = fk.simulate_machine(m, dt=1e-3, inputs={"qg": np.r_[np.zeros(5), np.full(495, 1e-3)]})
    assert res.success and abs(res.position("q")[-1] - 1e-3) < 5e-5


@pytest.mark.parametrize("kw, msg", [
    ({"M": -1.0}, "M"),
    ({"constants": {"kpp": 1.0}}, "unknown keys"),
    ({"constants": {"vmax": 0.0}}, "vmax"),
])
def test_bad_parameters_are_named(kw, msg):
    args = {"M": 95.0, "friction": LAW, **kw}
    with pytest.raises(ParameterError, match=msg):
        emps_machine(**args)
