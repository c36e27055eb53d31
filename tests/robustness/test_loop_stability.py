"""Issue 13: unstable closed loops must not come back as a silent status 0.

The session note's cases: the EMPS axis with M <= 10 kg under its nominal controller, and the
seed 001 ball screw with every inertia x1e-2 — the drive sits at its limit most of the time and
the traces do not converge with the sub-steps, yet the runs returned status 0. The screen
(:mod:`frictionkit.machines.stability`) linearises one controller sample and, only for an
unstable loop, checks the run against 16x the sub-steps.

Expected values are independent of the code under test: an analytic discrete loop, the
compiled kernel itself on linear machines (no friction, no limits), and convergence measured
here at 640 sub-steps.
"""

from __future__ import annotations

import math

import numpy as np
import pytest

import frictionkit as fk
from frictionkit.machines import Machine, Sum, simulate_machine
from frictionkit.machines.simulate import STATUS_TOLERANCE, _run_machine
from frictionkit.machines.stability import RHO_MARGIN, closed_loop_matrix, loop_stability
from frictionkit.presets.ballscrew import ballscrew_machine
from frictionkit.presets.emps import PUBLISHED, emps_machine
from frictionkit.reproduce.zhu_fujimoto import paper_controller, paper_plant, paper_sensors
from frictionkit.control.trajectories import cosine_reference


def velocity_loop(K: float, m: float = 2.0, dt: float = 1e-3) -> Machine:
    """Mass m, velocity sensor, u = -K v (no delay). With the force held over the sample,
    v_{k+1} = (1 - K dt / m) v_k exactly: unstable iff K dt / m > 2."""
    mach = Machine("velocity loop")
    x = mach.dof("x", inertia=m, v0=1e-3)
    mach.sensor("v", x, quantity="velocity")
    mach.add(Sum("u", {"v": -K}))
    mach.actuator("f", x, command="u")
    return mach


@pytest.mark.parametrize("kdt_m", [1.9, 2.1, 3.0])
def test_radius_of_an_analytic_loop(kdt_m):
    m, dt = 2.0, 1e-3
    st = loop_stability(velocity_loop(kdt_m * m / dt, m, dt), dt)
    expected = max(1.0, abs(1.0 - kdt_m))  # the free position is a marginal eigenvalue 1
    assert st.radius == pytest.approx(expected, rel=1e-9)
    assert st.unstable == (kdt_m > 2.0)
    if st.unstable:
        assert st.actuators == ("f",) and st.dof == "x"
        assert st.frequency_hz == pytest.approx(0.5 / dt)  # a negative real eigenvalue: Nyquist


def _linear(machine: Machine, v0: float) -> Machine:
    """The machine without friction sites, limits, quantisation, noise or constant biases."""
    d = machine.to_dict()
    d["sites"] = [s for s in d["sites"] if s["role"] != "friction"]
    for a in d["actuators"]:
        a["limit"] = math.inf
    for s in d["sensors"]:
        s["resolution"], s["noise"] = 0.0, 0.0
    for b in d["blocks"]:
        if b["type"] == "Sum":
            b["bias"] = 0.0
        if b["type"] == "Saturation":
            b["lo"], b["hi"] = -1e300, 1e300
    d["dofs"][0]["v0"] = v0
    return Machine.from_dict(d)


def _ballscrew(scale: float = 1.0):
    plant = paper_plant()
    plant = paper_plant(J_m=plant.J_m * scale, J_b=plant.J_b * scale, M_b=plant.M_b * scale, M_t=plant.M_t * scale)
    ctrl = paper_controller()
    return ballscrew_machine(plant, ctrl, paper_sensors()), ctrl


@pytest.mark.parametrize("which", ["emps_light", "ballscrew_light", "ballscrew"])
def test_linear_map_matches_the_kernel(which):
    """The one-sample map iterated from a kicked state equals the compiled loop on the same
    linear machine (delays, held signals, PID, the DOB StateSpace, ZOH actuators)."""
    if which == "emps_light":
        mach, dt = emps_machine(M=9.51, friction=fk.CoulombViscous(Fc=20.0, sigma2=200.0), offset=-3.0), 1e-3
    else:
        mach, ctrl = _ballscrew(1e-2 if which == "ballscrew_light" else 1.0)
        dt = ctrl.T
    lin = _linear(mach, 1e-3)
    N = 60
    res = simulate_machine(lin, dt=dt, n_samples=N, inputs={k: np.zeros(N) for k in lin.input_names()
                                                             if k not in {s.name for s in lin.sensors}})
    A = closed_loop_matrix(lin, dt)
    n = lin.n
    z = np.zeros(A.shape[0])
    z[n:2 * n] = [d.v0 for d in lin.dofs]
    pred = []
    for _ in range(N):
        pred.append(z[:n].copy())
        z = A @ z
    pred = np.array(pred)
    scale = np.max(np.abs(res.q))
    assert np.max(np.abs(pred - res.q)) <= 1e-9 * scale


def _emps_reference(dt=1e-3, duration=1.5):
    t = np.arange(int(round(duration / dt)) + 1) * dt
    s = np.clip(t - 0.1, 0.0, 0.5) / 0.5
    return {"qg": 0.05 * s * s * (3 - 2 * s)}


def _not_converged(machine, dt, inputs, n=10, fine=640):
    """Independent of the check: positions > 1 % or velocities > 10 % of their range apart."""
    N = len(next(iter(inputs.values())))
    a = _run_machine(machine, dt, inputs, N, n, 0, False)
    b = _run_machine(machine, dt, inputs, N, fine, 0, False)
    dq = np.max(np.abs(a.q - b.q), axis=0) / np.ptp(b.q, axis=0)
    dv = np.max(np.abs(a.v - b.v), axis=0) / np.ptp(b.v, axis=0)
    return bool(np.any(dq > 0.01) or np.any(dv > 0.1)), float(np.max(dq)), float(np.max(dv))


def test_light_emps_is_flagged():
    m = emps_machine(M=0.0951, friction=fk.CoulombViscous(Fc=PUBLISHED["Fc"], sigma2=PUBLISHED["Fv"]),
                     offset=PUBLISHED["offset"])
    inp = _emps_reference()
    bad, dq, dv = _not_converged(m, 1e-3, inp)
    assert bad, (dq, dv)  # measured: velocities ~10x their bound apart at 640 sub-steps
    res = simulate_machine(m, dt=1e-3, inputs=inp)
    assert res.status == STATUS_TOLERANCE
    assert res.message.startswith("result not converged: the closed loop is unstable") and "'motor'" in res.message
    assert "at its limit" in res.message and "Lower that loop's gains" in res.message


def test_ballscrew_inertias_1e_2_flagged():
    mach, ctrl = _ballscrew(1e-2)
    ref = cosine_reference(duration=0.1)
    u_ff, th = ctrl.ptc.feedforward(ref.x / ctrl.R, ref.v / ctrl.R)
    inp = {"theta_d": th, "u_ff": u_ff, "u_f": np.zeros(len(ref))}
    st = loop_stability(mach, ctrl.T)
    assert st.unstable and st.actuators == ("motor",)
    bad, dq, dv = _not_converged(mach, ctrl.T, inp)
    assert bad, (dq, dv)
    res = simulate_machine(mach, dt=ctrl.T, inputs=inp)
    assert res.status == STATUS_TOLERANCE, res.message


@pytest.mark.parametrize("nut_model", ["sliding", "flank", "hertz"])
def test_ballscrew_preset_is_stable(nut_model):
    ctrl = paper_controller()
    st = loop_stability(ballscrew_machine(paper_plant(nut_model), ctrl, paper_sensors()), ctrl.T)
    assert not st.unstable and st.radius < 1.0


def test_emps_preset_is_stable_and_untouched():
    m = emps_machine(M=PUBLISHED["M"], friction=fk.CoulombViscous(Fc=PUBLISHED["Fc"], sigma2=PUBLISHED["Fv"]),
                     offset=PUBLISHED["offset"])
    st = loop_stability(m, 1e-3)
    assert st.radius < 1.0 - 1e-3
    res = simulate_machine(m, dt=1e-3, inputs=_emps_reference())
    assert res.status == 0 and "unstable" not in res.message


def test_open_loop_machine_is_not_screened():
    m = velocity_loop(1.0)
    d = m.to_dict()
    d["blocks"] = []
    d["actuators"][0]["command"] = "u_in"
    st = loop_stability(Machine.from_dict(d), 1e-3)
    assert not st.closed and not st.unstable and math.isnan(st.radius)


def test_rho_margin_keeps_a_free_body():
    """A free rigid body (double eigenvalue 1) under a pure velocity loop is not 'unstable'."""
    st = loop_stability(velocity_loop(100.0), 1e-3)
    assert st.radius <= 1.0 + RHO_MARGIN and not st.unstable


def test_a_failing_screen_never_breaks_a_finished_run(monkeypatch):
    import frictionkit.machines.stability as stab

    def boom(machine, dt):
        raise AttributeError("static_rows")

    monkeypatch.setattr(stab, "loop_stability", boom)
    res = simulate_machine(velocity_loop(1.0), dt=1e-3, n_samples=20)
    assert res.status == 0 and "screen was skipped (AttributeError: static_rows)" in res.message


@pytest.mark.parametrize("which", ["sdss_azimuth", "sdss_altitude", "sdss_rotator", "tdms_full", "tdms_semi", "cdfs",
                                   "ballscrew_rigid", "ballscrew_table1"])
def test_other_presets_are_stable(which):
    """No preset triggers the screen (measured radii 0.963-0.993)."""
    from frictionkit.plants.ballscrew import RigidBallScrew
    from frictionkit.presets import sdss
    from frictionkit.presets.zhang2023.plant import cdfs_machine, tdms_machine

    if which.startswith("sdss"):
        mach, dt = sdss.axis(which.split("_")[1]).machine(loop="position"), 1e-3
    elif which.startswith("tdms"):
        mach, dt = tdms_machine(loop=which.split("_")[1]), 250e-6
    elif which == "cdfs":
        mach, dt = cdfs_machine(), 250e-6
    else:
        ctrl = paper_controller()
        plant = RigidBallScrew() if which == "ballscrew_rigid" else paper_plant(stage="table1")
        mach, dt = ballscrew_machine(plant, ctrl), ctrl.T
    st = loop_stability(mach, dt)
    assert st.closed and st.radius < 1.0
