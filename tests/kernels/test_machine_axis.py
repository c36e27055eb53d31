"""The machine core's one-DOF fast path (issue 8): ``kernels/machine_axis.py``.

A rigid axis with one flat static friction site (Coulomb-viscous levels per direction) in a
closed loop runs on an exact step per sample. Checked here against the general loop
(``fast_path=False``, the reference), never against numbers copied from the fast path:

* the controller copy is the general kernel's: on a plant that cannot move (friction level
  far above every actuator force), every signal is equal within 1e-12 relative (the general
  loop's stick leaves ~1e-16 m of round-off in the state) and every actuator command bit for
  bit, for every block kind, sensor option (quantisation, noise, delay, velocity) and actuator
  option (saturation, delay, anti-windup);
* the plant step is the limit of the general loop's sub-steps: the fast path's distance from
  the general loop at 640 sub-steps is at most twice the general loop's own change from 320 to
  640 sub-steps (its error estimate: the scheme is first order), on the EMPS preset and on
  machines not used while writing the kernel;
* machines that do not qualify run on the general loop and say why (``MachineResult.path``).
"""

from __future__ import annotations

import dataclasses

import numpy as np
import pytest

import frictionkit as fk
from frictionkit.machines import PID, FrictionFeedforward, Machine, Saturation, StateSpace, Sum, simulate_machine
from frictionkit.machines import simulate as sim
from frictionkit.machines.stability import loop_stability

DT = 1e-3


def _both(m, inputs, **kw):
    fast = simulate_machine(m, dt=DT, inputs=inputs, **kw)
    gen = simulate_machine(m, dt=DT, inputs=inputs, fast_path=False, **kw)
    return fast, gen


# --------------------------------------------------------------------------- controller parity
def _every_block_machine(level: float) -> Machine:
    """One DOF with every block kind, sensor and actuator option the core has."""
    m = Machine("axis parity")
    x = m.dof("x", inertia=3.0, x0=0.0123)
    m.friction("slide", x, law=fk.CoulombViscous(Fc=level, sigma2=50.0))
    m.sensor("xm", x, resolution=1e-6, noise=2e-5, delay=2)
    m.sensor("vm", x, quantity="velocity", noise=1e-3, delay=1)
    tdms = fk.TDMSSC(Fc0=0.8, Fc1=0.5, Fs0=1.1, Fs1=0.5, vs=0.01, sigma2=0.4)
    m.add(Sum("e", {"xr": 1.0, "xm": -1.0}),
          PID("u_pid", "e", Kp=300.0, Ki=4000.0, Kd=2.0, tau_d=2e-3, antiwindup="motor"),
          StateSpace(outputs=("vf",), inputs=("vm",), A=[[0.8]], B=[[0.2]], C=[[1.0]], D=[[0.0]]),
          FrictionFeedforward("u_ff", "vr", tdms, scale=1.0, schedule="vf"),
          FrictionFeedforward("u_ff2", "vf", fk.Stribeck(Fc=0.3, Fs=0.5, vs=0.02, sigma2=0.1), scale=0.5),
          Sum("u_c", {"u_pid": 1.0, "u_ff": 1.0, "u_ff2": 1.0, "vf": -2.0}, bias=0.1),
          Saturation("u", "u_c", -6.0, 5.0))
    m.actuator("motor", x, gain=2.0, limit=4.0, delay=3, command="u")
    m.actuator("aux", -0.5 * x, gain=1.5, command="u_pid")
    return m


def _parity_inputs(n=1500):
    t = np.arange(n) * DT
    xr = 0.02 * np.sin(2 * np.pi * 3.0 * t) + 0.01 * (t > 0.4)
    return {"xr": xr, "vr": np.gradient(xr, DT)}


def test_controller_is_the_general_kernels_bit_for_bit():
    m = _every_block_machine(level=1e9)  # far above any actuator force: both plants stay put
    fast, gen = _both(m, _parity_inputs(), seed=7)
    assert fast.path.startswith("axis") and gen.path.startswith("general"), (fast.path, gen.path)
    assert fast.success and gen.success, (fast.message, gen.message)
    # the fast path picks its own steps: its summary must not claim "0 sub-steps/sample"
    assert "0 sub-steps" not in fast.summary() and f"{gen.substeps} sub-steps/sample" in gen.summary()
    # the premise: no motion (the general loop's stick leaves round-off: ~1e-16 m, 1e-20 m/s)
    assert np.all(fast.q == fast.q[0]) and np.max(np.abs(gen.q - gen.q[0])) <= 1e-13 * abs(gen.q[0, 0])
    assert fast.signal_names == gen.signal_names
    scale = np.max(np.abs(gen.signals), axis=0)
    worst = np.max(np.abs(fast.signals - gen.signals) / (np.abs(gen.signals) + scale))
    assert worst <= 1e-12, worst  # relative to each signal's value and range
    np.testing.assert_array_equal(fast.u, gen.u)
    # the test exercises what it claims: saturation, the anti-windup and the delays act
    assert np.any(np.abs(gen.u[:, 0]) == 4.0) and np.any(np.abs(gen.signal("u")) == 6.0)
    assert gen.signal("xm")[:2].tolist() == [0.0, 0.0] and gen.signal("xm")[2] != 0.0


# --------------------------------------------------------------------------- plant accuracy
def _emps(n):
    from frictionkit.presets.emps import PUBLISHED, emps_machine

    t = np.arange(n) * DT
    qg = 0.1 * np.sin(2 * np.pi * 0.5 * t) ** 3 + 0.02 * np.sin(2 * np.pi * 3 * t) * (t > 1.0)
    m = emps_machine(M=PUBLISHED["M"], friction=fk.CoulombViscous(Fc=PUBLISHED["Fc"], sigma2=PUBLISHED["Fv"]),
                     offset=PUBLISHED["offset"])
    return m, {"qg": qg}


def _directional_delayed(n):
    """A light axis, other gains, a Directional law, a two-sample sensor delay."""
    m = Machine("directional")
    x = m.dof("x", inertia=0.8)
    m.friction("f", x, law=fk.Directional(positive=fk.CoulombViscous(Fc=2.0, sigma2=3.0),
                                          negative=fk.CoulombViscous(Fc=3.5, sigma2=9.0)))
    m.sensor("xm", x, delay=2)
    m.add(Sum("e", {"xr": 1.0, "xm": -1.0}), PID("u", "e", Kp=400.0, Ki=500.0, Kd=12.0, tau_d=3e-3))
    m.actuator("motor", x, command="u")
    t = np.arange(n) * DT
    return m, {"xr": 0.01 * np.sign(np.sin(2 * np.pi * 1.3 * t)) + 0.004 * np.sin(2 * np.pi * 7 * t)}


def _saturating_quantised(n):
    """A rotary axis on a scaled, reversed coordinate (site at -2 theta), a saturating
    actuator, a quantised encoder, pure Coulomb friction (no viscous term)."""
    m = Machine("rotary")
    th = m.dof("th", inertia=0.02, kind="rotational")
    m.friction("f", -2.0 * th, law=fk.CoulombViscous(Fc=0.4, sigma2=0.0))
    m.sensor("thm", th, resolution=2 * np.pi / 4096)
    m.add(Sum("e", {"r": 1.0, "thm": -1.0}), PID("u_c", "e", Kp=30.0, Ki=40.0, Kd=0.6, tau_d=2e-3, antiwindup="motor"))
    m.actuator("motor", th, gain=0.5, limit=3.0, command="u_c")
    t = np.arange(n) * DT
    return m, {"r": 2.0 * (t > 0.05) - 2.5 * (t > 0.9)}


def _flat_stribeck_heavy(n):
    """A heavy slow axis, a flat Stribeck (Fs = Fc), velocity feedback from a noisy sensor."""
    m = Machine("heavy")
    x = m.dof("x", inertia=400.0)
    m.friction("f", x, law=fk.Stribeck(Fc=60.0, Fs=60.0, vs=0.01, sigma2=800.0))
    m.sensor("xm", x, noise=1e-7)
    m.sensor("vm", x, quantity="velocity")
    m.add(Sum("u", {"xr": 2e5, "xm": -2e5, "vm": -8e3}))
    m.actuator("motor", x, limit=2e3, command="u")
    t = np.arange(n) * DT
    return m, {"xr": 0.003 * np.sin(2 * np.pi * 0.7 * t)}


def _open_loop_ramps(n):
    """Open loop: an input-array actuator (force linear over each sample) with a delay and a
    limit it crosses inside samples, beside a held controller output; a Directional law with
    no viscous term one way. Breakaways and stops fall inside samples."""
    m = Machine("ramps")
    x = m.dof("x", inertia=0.3)
    m.friction("f", x, law=fk.Directional(positive=fk.CoulombViscous(Fc=1.0, sigma2=0.0),
                                          negative=fk.CoulombViscous(Fc=1.4, sigma2=2.0)))
    m.add(Sum("bias", {"f_cmd": 0.0}, bias=0.15))
    m.actuator("push", x, gain=1.0, limit=1.8, delay=1, command="f_cmd")
    m.actuator("bias_force", x, command="bias")
    t = np.arange(n) * DT
    return m, {"f_cmd": 2.3 * np.sin(2 * np.pi * 1.7 * t) + 0.4 * np.sin(2 * np.pi * 23 * t)}


def _stribeck_directional(n):
    """Stribeck levels (Fs > Fc, no closed form: Runge-Kutta slides), per direction, a PID loop
    (short: the general loop's 640 sub-steps cost ~9 us per sample on a Stribeck site)."""
    m = Machine("stribeck")
    x = m.dof("x", inertia=1.5)
    m.friction("f", x, law=fk.Directional(positive=fk.Stribeck(Fc=1.0, Fs=1.6, vs=0.004, sigma2=4.0),
                                          negative=fk.Stribeck(Fc=1.2, Fs=1.5, vs=0.01, sigma2=6.0, delta=1.0)))
    m.sensor("xm", x, resolution=1e-7)
    m.add(Sum("e", {"xr": 1.0, "xm": -1.0}), PID("u", "e", Kp=900.0, Ki=3000.0, Kd=20.0, tau_d=2e-3))
    m.actuator("motor", x, command="u")
    t = np.arange(n) * DT
    return m, {"xr": 0.004 * (t > 0.02) - 0.007 * (t > 0.2) + 0.002 * np.sin(2 * np.pi * 6 * t) * (t > 0.35)}


CASES = {"emps": (_emps, 4000), "directional_delayed": (_directional_delayed, 2500),
         "saturating_quantised": (_saturating_quantised, 1500), "flat_stribeck_heavy": (_flat_stribeck_heavy, 2500),
         "open_loop_ramps": (_open_loop_ramps, 2000), "stribeck_directional": (_stribeck_directional, 500)}


@pytest.mark.parametrize("name", list(CASES))
def test_fast_path_is_the_limit_of_the_general_loop(name):
    build, n = CASES[name]
    m, inputs = build(n)
    fast = simulate_machine(m, dt=DT, inputs=inputs, seed=3)
    assert fast.path.startswith("axis") and fast.success, (fast.path, fast.message)
    g = {ns: simulate_machine(m, dt=DT, inputs=inputs, seed=3, substeps=ns, fast_path=False) for ns in (320, 640)}
    assert all(r.success and r.path.startswith("general") for r in g.values())
    for what in ("q", "v"):
        est = np.max(np.abs(getattr(g[320], what) - getattr(g[640], what)))  # the 640 run's own error, about
        d = np.max(np.abs(getattr(fast, what) - getattr(g[640], what)))
        scale = np.max(np.abs(getattr(g[640], what)))
        assert d <= 2.0 * est + 1e-12 * scale, (name, what, d, est)
    # the machine moves, stops and sticks (what the exact step must locate)
    v = fast.v[:, 0]
    assert np.ptp(fast.q) > 0 and np.sum(v == 0.0) > 5 and np.any(v > 0) and np.any(v < 0), name


def test_sticks_exactly_below_breakaway_and_breaks_away_above():
    """Open loop through a controller signal: a constant force below Fc holds, above it the
    closed form v(t) = vinf (1 - exp(-beta t)) (vinf = (U - Fc) / sigma2, beta = sigma2 / M)."""
    for U, moves in ((0.99, False), (1.5, True)):
        m = Machine("push")
        x = m.dof("x", inertia=2.0)
        m.friction("f", x, law=fk.CoulombViscous(Fc=1.0, sigma2=0.5))
        m.add(Sum("u", {"cmd": U}))
        m.actuator("motor", x, command="u")
        r = simulate_machine(m, dt=DT, inputs={"cmd": np.ones(2001)})
        assert r.path.startswith("axis")
        if not moves:
            assert np.all(r.q == 0.0) and np.all(r.v == 0.0)
            np.testing.assert_allclose(r.site_forces[1:, 0], U, rtol=1e-15)  # the holding force
        else:
            t = r.t
            vinf, beta = (U - 1.0) / 0.5, 0.5 / 2.0
            np.testing.assert_allclose(r.v[1:, 0], vinf * (1 - np.exp(-beta * t[1:])), rtol=1e-12)


# --------------------------------------------------------------------------- dispatch
def _loop(law, *, two_dofs=False, scheduled=False):
    m = Machine("probe")
    x = m.dof("x", inertia=1.0)
    if two_dofs:
        y = m.dof("y", inertia=1.0)
        m.spring(x, y, k=1e3)
    m.friction("f", x, law=law, schedule=x.velocity if scheduled else None)
    m.sensor("xm", x)
    m.add(Sum("u", {"xr": 50.0, "xm": -50.0}))
    m.actuator("motor", x, command="u")
    return m


@pytest.mark.parametrize("kw, why", [
    (dict(law=fk.TDMSSC(Fc0=0.8, Fc1=0.5, Fs0=1.1, Fs1=0.5, vs=0.01, sigma2=0.4), scheduled=True), "schedule"),
    (dict(law=fk.LuGre(fk.Stribeck(Fc=1.0, Fs=1.0, vs=0.01), sigma0=1e4, sigma1=100.0)), "dynamic law"),
    (dict(law=fk.CoulombViscous(Fc=1.0), two_dofs=True), "2 degrees of freedom"),
])
def test_machines_that_do_not_qualify_run_on_the_general_loop_and_say_why(kw, why):
    m = _loop(**kw)
    r = simulate_machine(m, dt=DT, inputs={"xr": np.full(50, 0.01)})
    assert r.path.startswith("general loop (one-DOF axis kernel not taken") and why in r.path, r.path
    assert r.success and r.substeps == 10


def test_fast_path_false_forces_the_general_loop():
    m = _loop(fk.CoulombViscous(Fc=1.0))
    r = simulate_machine(m, dt=DT, inputs={"xr": np.full(50, 0.01)}, fast_path=False)
    assert r.path == "general loop (one-DOF axis kernel not taken: fast_path=False)"


def test_loop_screen_is_remembered_with_the_pack_and_an_edited_machine_is_screened_again():
    """The loop screen's eigenproblem is cached with the pack; a loop it finds unstable goes to
    the general loop (whose convergence check decides its status). An edit (here the gain, in
    place) is another machine and must be screened anew, both ways."""
    m = _loop(fk.CoulombViscous(Fc=0.01, sigma2=0.1))
    inputs = {"xr": np.full(300, 0.01)}
    r1 = simulate_machine(m, dt=DT, inputs=inputs)
    assert r1.path.startswith("axis") and not loop_stability(m, DT).unstable
    m.blocks[0] = dataclasses.replace(m.blocks[0], terms={"xr": 5e6, "xm": -5e6})  # k dt^2 / M = 5: unstable
    assert loop_stability(m, DT).unstable  # independent check of the premise
    r2 = simulate_machine(m, dt=DT, inputs=inputs)
    assert r2.path.startswith("general loop") and "unstable" in r2.path, r2.path
    assert "unstable" in r2.message, r2.message
    m.blocks[0] = dataclasses.replace(m.blocks[0], terms={"xr": 50.0, "xm": -50.0})
    r3 = simulate_machine(m, dt=DT, inputs=inputs)
    assert r3.path.startswith("axis") and "unstable" not in r3.message
    np.testing.assert_array_equal(r3.q, r1.q)
    sim._PACK_CACHE.clear()
