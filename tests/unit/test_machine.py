"""The machine description and the compiled loop's controller, sensors and actuators.

Expected values come from closed forms or from an independent NumPy/SciPy re-implementation
of the discrete loop written here (scipy.signal.cont2discrete for the plant), never from the
kernel itself.
"""

from __future__ import annotations

import math

import numpy as np
import pytest
from scipy.signal import cont2discrete, dlsim

import frictionkit as fk
from frictionkit.errors import DataError, ParameterError
from frictionkit.machines import (PID, FrictionFeedforward, HertzContact, Machine, PiecewiseLinearSpring,
                                  Saturation, SineLoad, StateSpace, Sum, simulate_machine)


def slider(law=None, m=1.0):
    mc = Machine("slider")
    x = mc.dof("x", inertia=m)
    if law is not None:
        mc.friction("contact", x, law=law)
    mc.actuator("u", x)
    return mc, x


# --------------------------------------------------------------------------- validation
@pytest.mark.parametrize(
    "build, match",
    [
        (lambda m: m.dof("w", inertia=-1.0), r"inertia = -1.0: must be >= 0"),
        (lambda m: m.dof("y", inertia=1.0, kind="linear"), r"kind = 'linear'"),
        (lambda m: m.dof("x", inertia=1.0), r"name 'x' is already used"),
        (lambda m: m.spring(m.coord("x"), k=-3.0), r"k = -3.0: must be >= 0"),
        (lambda m: m.spring(m.coord("x")), r"k = c = 0 couples nothing"),
        (lambda m: m.friction("f", m.coord("x"), law=3.0), r"law = float: float is not a registered friction law"),
        (lambda m: m.friction("f", Machine().dof("z", inertia=1.0), law=fk.CoulombViscous(Fc=1.0)),
         r"is not a coordinate of machine 'm'"),
        (lambda m: m.actuator("a", m.coord("x"), limit=0.0), r"limit = 0.0: must be > 0"),
        (lambda m: m.actuator("a", m.coord("x"), delay=1.5), r"delay = 1.5: must be an integer >= 0"),
        (lambda m: m.sensor("s", m.coord("x"), quantity="acceleration"), r"quantity = 'acceleration'"),
        (lambda m: m.coord("nope"), r"has no degree of freedom or motion 'nope'"),
        (lambda m: m.compliance("c", m.coord("x"), law=fk.CoulombViscous(Fc=1.0)),
         r"must be HertzContact or PiecewiseLinearSpring"),
        (lambda m: m.add(object()), r"object is not a controller block"),
        (lambda m: m.coord("x") * "2", r"can only be scaled by a number"),
    ],
)
def test_machine_parts_are_validated_with_a_message(build, match):
    m = Machine("m")
    m.dof("x", inertia=1.0)
    with pytest.raises(ParameterError, match=match):
        build(m)


def test_singular_mass_matrix_names_the_massless_dof():
    m = Machine("m")
    x = m.dof("x", inertia=1.0)
    y = m.dof("y", inertia=0.0)
    m.spring(x, y, k=1.0)
    with pytest.raises(ParameterError, match=r"\['y'\] carry no inertia"):
        simulate_machine(m, dt=1e-3, n_samples=10)


def test_simulation_inputs_are_validated():
    m, x = slider(fk.CoulombViscous(Fc=1.0))
    with pytest.raises(DataError, match=r"actuator 'u' follows signal 'u'"):
        simulate_machine(m, dt=1e-3, n_samples=10)
    with pytest.raises(DataError, match=r"input 'v' has 5 samples, expected 10"):
        simulate_machine(m, dt=1e-3, inputs={"u": np.zeros(10), "v": np.zeros(5)})
    with pytest.raises(ParameterError, match=r"substeps = 0"):
        simulate_machine(m, dt=1e-3, inputs={"u": np.zeros(10)}, substeps=0)
    with pytest.raises(DataError, match=r"inputs\['u'\]\[3\] = nan"):
        simulate_machine(m, dt=1e-3, inputs={"u": [0, 0, 0, np.nan]})
    p = m.motion("pull")
    m.spring(x, p, k=1.0)
    with pytest.raises(DataError, match=r"prescribed motion 'pull' needs an input array"):
        simulate_machine(m, dt=1e-3, inputs={"u": np.zeros(10)})
    m.add(Sum("e", {"ref": 1.0}))
    with pytest.raises(DataError, match=r"reads signal 'ref', which nothing produces"):
        simulate_machine(m, dt=1e-3, inputs={"u": np.zeros(10), "pull": np.zeros(10)})


def test_transmission_mass_matrix_of_the_differential_feed():
    """Seed 000: table at x_t = R (theta1 + theta2); its mass adds m R^2 [[1, 1], [1, 1]]."""
    R, mt, J1, J2 = 0.8e-3, 20.0, 2e-4, 3e-4
    m = Machine("tdms")
    th1 = m.dof("screw", inertia=J1, kind="rotational")
    th2 = m.dof("nut", inertia=J2, kind="rotational")
    m.inertia(R * (th1 + th2), mt)
    expected = np.array([[J1 + mt * R**2, mt * R**2], [mt * R**2, J2 + mt * R**2]])
    np.testing.assert_allclose(m.mass_matrix(), expected, rtol=1e-15)


# --------------------------------------------------------------------------- closed forms
def test_coulomb_slider_sticks_below_and_accelerates_above_the_breakaway():
    """Coulomb: u < Fc -> no motion at all; u > Fc from rest -> x = (u - Fc) t^2 / (2 m)."""
    m, _ = slider(fk.CoulombViscous(Fc=1.0), m=2.0)
    dt = 1e-3
    r = simulate_machine(m, dt=dt, inputs={"u": np.full(501, 0.999)})
    assert r.status == 0 and np.abs(r.q).max() == 0.0
    np.testing.assert_allclose(r.force("contact")[1:], 0.999, rtol=1e-12)  # the holding force
    r = simulate_machine(m, dt=dt, inputs={"u": np.full(501, 3.0)})
    np.testing.assert_allclose(r.q[:, 0], (3.0 - 1.0) * r.t**2 / 4.0, rtol=1e-9, atol=1e-15)


def test_stribeck_breakaway_at_Fs_under_a_slow_ramp():
    law = fk.Stribeck(Fc=1.0, Fs=1.5, vs=1e-3)
    m, _ = slider(law)
    dt = 1e-3
    u = np.linspace(0.0, 2.0, 2001)  # 1 N/s
    r = simulate_machine(m, dt=dt, inputs={"u": u})
    assert np.abs(r.v[u < 1.49, 0]).max() < 1e-12
    k = np.flatnonzero(r.v[:, 0] > 1e-9)[0]
    # sticks until the input passes Fs: break-away within one sample of u = 1.5 N
    assert abs(u[k] - 1.5) <= 2e-3


def test_sine_load_is_a_pendulum():
    """A rotor with SineLoad(m g X) and no friction: small oscillations at sqrt(m g X / J)."""
    J, mgX = 0.5, 2.0
    m = Machine("pendulum")
    th = m.dof("theta", inertia=J, kind="rotational", x0=1e-3)
    m.load("gravity", th, law=SineLoad(amplitude=mgX))
    r = simulate_machine(m, dt=1e-3, n_samples=4001, substeps=20)
    w = math.sqrt(mgX / J)
    np.testing.assert_allclose(r.q[:, 0], 1e-3 * np.cos(w * r.t), atol=2e-8)


def test_compliance_laws():
    hz = HertzContact(preload=3500.0, stiffness=8e8)
    d = np.linspace(-3 * hz.d0, 3 * hz.d0, 101)
    k_num = (hz.force(1e-12) - hz.force(-1e-12)) / 2e-12
    assert k_num == pytest.approx(8e8, rel=1e-6)
    assert hz.force(0.0) == 0.0
    # one set unloads beyond 2^1.5 P: then F = c (d0 + d)^1.5
    big = d[d > hz.d0]
    np.testing.assert_allclose(hz.force(big), hz.c * (hz.d0 + big) ** 1.5, rtol=1e-12)
    hd = PiecewiseLinearSpring.from_torque_breaks((1e4, 2e4, 3e4), (5.0, 20.0))
    assert hd.force(hd.breaks[0]) == pytest.approx(5.0)
    assert hd.force(hd.breaks[1]) == pytest.approx(20.0)
    assert hd.force(-hd.breaks[1] - 1e-4) == pytest.approx(-(20.0 + 3.0))
    with pytest.raises(ParameterError, match="strictly increasing"):
        PiecewiseLinearSpring(stiffness=(1.0, 2.0, 3.0), breaks=(2.0, 1.0))


# --------------------------------------------------------------------------- controller twin
def _loop_twin(J, B, dt, r, *, Kp, Ki, Kd, tau_d, limit, q_res, delay):
    """The discrete loop written out in NumPy: exact ZOH plant J q'' + B q' = u."""
    A = np.array([[0.0, 1.0], [0.0, -B / J]])
    Bm = np.array([[0.0], [1.0 / J]])
    Ad, Bd, *_ = cont2discrete((A, Bm, np.eye(2), np.zeros((2, 1))), dt, method="zoh")
    X = np.zeros(2)
    integ = dterm = 0.0
    ed_prev = None
    buf = [0.0] * delay
    qs, us = [], []
    for k in range(r.size):
        y = math.floor(X[0] / q_res) * q_res
        e = r[k] - y
        if ed_prev is None:
            ed_prev = e
        dterm = (tau_d * dterm + Kd * (e - ed_prev)) / (tau_d + dt)
        ed_prev = e
        u = Kp * e + integ + dterm
        sat = abs(u) > limit
        u = min(max(u, -limit), limit)
        if not sat:
            integ += Ki * dt * e
        buf.append(u)
        u_app = buf.pop(0)
        qs.append(X[0])
        us.append(u_app)
        X = Ad @ X + Bd[:, 0] * u_app
    return np.array(qs), np.array(us)


@pytest.mark.parametrize("delay", [0, 2])
def test_pid_loop_with_quantised_sensor_saturation_and_delay_matches_a_numpy_twin(delay):
    J, B, dt = 0.01, 0.1, 0.5e-3
    gains = dict(Kp=40.0, Ki=800.0, Kd=0.6, tau_d=1e-3)
    m = Machine("axis")
    th = m.dof("theta", inertia=J, kind="rotational")
    m.damper(th, c=B)
    m.actuator("motor", th, limit=5.0, delay=delay, command="i")
    m.sensor("enc", th, resolution=2 * math.pi / 2**16)
    m.add(Sum("e", {"r": 1.0, "enc": -1.0}), PID("i", "e", antiwindup="motor", **gains))
    r = np.r_[np.zeros(20), np.full(1980, 0.5)]  # a step large enough to saturate
    res = simulate_machine(m, dt=dt, inputs={"r": r}, substeps=3)
    q, u = _loop_twin(J, B, dt, r, limit=5.0, q_res=2 * math.pi / 2**16, delay=delay, **gains)
    assert np.abs(u).max() == 5.0  # the limit was reached
    np.testing.assert_allclose(res.u[:, 0], u, atol=1e-9)
    np.testing.assert_allclose(res.q[:, 0], q, atol=1e-9)
    assert res.signal("motor.applied")[100] == res.u[100, 0]


def test_state_space_block_equals_dlsim():
    A = [[0.9, 0.05], [0.0, 0.8]]
    Bm = [[0.0], [1.0]]
    C = [[1.0, 0.5]]
    D = [[0.2]]
    m, _ = slider(None)
    m.add(StateSpace(outputs=("y",), inputs=("w",), A=A, B=Bm, C=C, D=D), Saturation("ys", "y", -0.3, 0.3))
    w = np.sin(np.linspace(0, 20, 400))
    res = simulate_machine(m, dt=1e-3, inputs={"w": w, "u": np.zeros(400)})
    _, y, _ = dlsim((np.array(A), np.array(Bm), np.array(C), np.array(D), 1e-3), w)
    np.testing.assert_allclose(res.signal("y"), y[:, 0], atol=1e-12)
    np.testing.assert_allclose(res.signal("ys"), np.clip(y[:, 0], -0.3, 0.3), atol=1e-12)


def test_friction_feedforward_block_evaluates_the_steady_state_map():
    law = fk.Directional(positive=fk.Stribeck(Fc=1.0, Fs=1.4, vs=2e-3, sigma2=3.0),
                         negative=fk.Stribeck(Fc=1.2, Fs=1.3, vs=1e-3, sigma2=2.0))
    gms = fk.GMS(law, k=[1e5, 1e6], xi=[0.3, 0.5], C=10.0)
    m, _ = slider(None)
    m.add(FrictionFeedforward("ff", "vref", law, scale=2.0), FrictionFeedforward("ffg", "vref", gms))
    v = np.linspace(-0.01, 0.01, 201)
    res = simulate_machine(m, dt=1e-3, inputs={"vref": v, "u": np.zeros(201)})
    np.testing.assert_allclose(res.signal("ff"), 2.0 * law.steady_state(v), rtol=1e-12)
    np.testing.assert_allclose(res.signal("ffg"), gms.steady_state(v), rtol=1e-12)


def test_nonfinite_state_ends_the_run_with_status_and_message():
    m, _ = slider(fk.CoulombViscous(Fc=1.0))
    u = np.r_[np.zeros(5), np.full(5, 1e308), np.zeros(10)]
    with pytest.warns(RuntimeWarning, match="non-finite state"):
        res = simulate_machine(m, dt=1.0, inputs={"u": u})
    assert res.status == 1 and "non-finite" in res.message
    assert np.isnan(res.q[-1, 0])
    assert "status 1" in res.summary()


# --------------------------------------------------------------------------- normal loads
def _pressed_slider(law, p, dt):
    """Slider x on a site whose normal load is the force of the spring "press" = 1000 (y - p).

    y is a 1e9 kg block, so the spring force is 1000 (-p) to 1e-9 relative."""
    m = Machine("pressed")
    x = m.dof("x", inertia=1.0)
    y = m.dof("y", inertia=1e9)
    pm = m.motion("p")
    m.spring(y, pm, k=1000.0, name="press")
    m.friction("contact", x, law=law, load=fk.machines.NormalLoad(on="press", reference=10.0))
    m.actuator("u", x)
    return m


def test_coulomb_level_follows_a_linear_normal_load():
    """Load 10 -> 5 N over 1 s, Fc = 1 N at 10 N, u = 0.8 N: sticks until t = 0.4 s, then
    x'' = 0.5 t - 0.2, i.e. x = (t - 0.4)^3 / 12."""
    dt = 1e-3
    t = np.arange(1001) * dt
    p = -0.01 + 0.005 * t
    m = _pressed_slider(fk.CoulombViscous(Fc=1.0), p, dt)
    expected = np.where(t > 0.4, (t - 0.4) ** 3 / 12.0, 0.0)
    err = {}
    for ns in (4, 16):
        r = simulate_machine(m, dt=dt, inputs={"p": p, "u": np.full(t.size, 0.8)}, substeps=ns)
        assert np.abs(r.position("x")[t < 0.399]).max() == 0.0
        err[ns] = np.abs(r.position("x") - expected).max()
    # first order in the sub-step (the load is sampled at each sub-step's start); measured
    # 1.12e-5 m and 2.78e-6 m (of 0.018 m travel)
    assert err[4] < 1.5e-5 and err[16] < 4e-6
    assert 3.0 < err[4] / err[16] < 5.0


def test_lugre_force_falls_with_the_load_and_is_kept_when_it_rises():
    """Pre-sliding LuGre held at 0.5 N: halving the load halves the bristle force at once
    (contacts lose traction); doubling it back keeps the force (new contact area is unloaded)."""
    dt = 1e-5
    n = 60001
    t = np.arange(n) * dt
    p = np.where((t >= 0.2) & (t < 0.4), -0.005, -0.01)  # load 10 N, 5 N from 0.2 s, 10 N from 0.4 s
    law = fk.LuGre(fk.Stribeck(Fc=1.0, Fs=1.5, vs=1e-3), sigma0=1e5, sigma1=316.0)
    m = _pressed_slider(law, p, dt)
    r = simulate_machine(m, dt=dt, inputs={"p": p, "u": np.full(n, 0.5)}, substeps=2)
    F = r.force("contact")
    k1 = np.searchsorted(t, 0.2)
    k2 = np.searchsorted(t, 0.4)
    assert F[k1 - 1] == pytest.approx(0.5, rel=1e-3)
    # the step of p is linear over one sample: one sample later the load is 5 N
    assert F[k1 + 1] == pytest.approx(0.25, rel=2e-2)
    assert F[k2 - 1] == pytest.approx(0.5, rel=1e-3)  # settled again at the lower load
    assert F[k2 + 1] == pytest.approx(0.5, rel=2e-2)  # load doubled: force kept
    assert abs(F[k2 + 1] - F[k2 - 1]) < 0.1 * abs(F[k1 + 1] - F[k1 - 1])


def test_one_dof_fast_path_is_the_single_axis_kernel_and_agrees_with_the_general_loop():
    law = fk.LuGre(fk.Stribeck(Fc=1.0, Fs=1.5, vs=1e-3, sigma2=0.4), sigma0=1e5, sigma1=316.0)
    m, _ = slider(law)
    m.actuators[0] = m.actuators[0].__class__("u", m.coord("x"), 2.0, 3.0, 0, "u")  # gain 2, limit 3
    dt = 2.5e-4
    t = np.arange(8001) * dt
    u = 2.0 * np.sin(np.pi * t)
    fast = simulate_machine(m, dt=dt, inputs={"u": u})
    assert "fast path" in fast.message and fast.substeps == 0
    ref = fk.simulate(law, plant=fk.Mass(1.0), force=2.0 * np.clip(u, -3.0, 3.0), dt=dt)
    np.testing.assert_array_equal(fast.q[:, 0], ref.x)
    np.testing.assert_array_equal(fast.force("contact"), ref.friction)
    general = simulate_machine(m, dt=dt, inputs={"u": u}, fast_path=False)
    assert general.substeps == 10 and "fast path" not in general.message
    # measured 0.47 um over a 1.0 m run (the two paths against each other)
    assert np.abs(general.q[:, 0] - fast.q[:, 0]).max() < 1e-6


def test_a_sum_without_terms_is_a_constant():
    m, _ = slider(fk.CoulombViscous(Fc=1.0))
    m.actuators[0] = m.actuators[0].__class__("u", m.coord("x"), 1.0, math.inf, 0, "push")
    m.add(Sum("push", {}, bias=3.0))
    r = simulate_machine(m, dt=1e-3, n_samples=101)
    np.testing.assert_allclose(r.signal("push"), 3.0)
    np.testing.assert_allclose(r.q[:, 0], (3.0 - 1.0) * r.t**2 / 2.0, rtol=1e-9, atol=1e-15)


def test_actuator_delay_applies_to_open_loop_inputs():
    m, _ = slider(None)
    m.actuators[0] = m.actuators[0].__class__("u", m.coord("x"), 1.0, math.inf, 5, "u")
    u = np.ones(21)
    r = simulate_machine(m, dt=1e-3, inputs={"u": u})
    m0, _ = slider(None)
    r0 = simulate_machine(m0, dt=1e-3, inputs={"u": np.r_[np.zeros(5), u[:-5]]})
    np.testing.assert_array_equal(r.u[:5, 0], 0.0)
    # the delayed input is the shifted array (zero before it arrives), linear between samples
    np.testing.assert_array_equal(r.q[:5, 0], 0.0)
    np.testing.assert_allclose(r.q[:, 0], r0.q[:, 0], rtol=1e-12, atol=1e-18)


def test_kinematic_site_on_a_motion_is_the_motion_driven_law():
    """A friction site on a prescribed motion only: the motion-driven law, to the last sample."""
    law = fk.LuGre(fk.Stribeck(Fc=1.0, Fs=1.5, vs=1e-3, sigma2=0.4), sigma0=1e5, sigma1=316.0)
    m = Machine("belt")
    x = m.dof("x", inertia=1.0)
    m.spring(x, k=100.0)
    p = m.motion("belt")
    m.friction("contact", p, law=law)
    dt = 1e-3
    t = np.arange(501) * dt
    belt = 1e-3 * np.sin(2 * np.pi * t)
    r = simulate_machine(m, dt=dt, inputs={"belt": belt}, substeps=20)
    ref = fk.simulate(law, position=belt, dt=dt)
    # both are exact for piecewise-linear position (constant rate per sub-step, exponential
    # bristle update; the force at a sample uses the arriving rate): equal to round-off
    np.testing.assert_allclose(r.force("contact"), ref.friction, rtol=0, atol=1e-12)
    assert np.abs(r.q).max() == 0.0  # a kinematic site acts on nothing
