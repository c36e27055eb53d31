"""The machine core (``simulate_machine``) against its ``solve_ivp`` twin (issue 8, part 5).

Each case is run once by :func:`frictionkit.machines.reference.reference_machine` (LSODA,
rtol 1e-10, GMS switchings located as events) and compared with the compiled loop:

* at the default of 10 sub-steps — max |dq| and max |dF| over the record, bounded by
  3x the value measured when the test was written (stated next to each bound);
* at 2, 4 and 8 sub-steps (GMS slider: 10, 20, 40) — the error must fall as the sub-step is
  halved. The scheme is documented as first order; measured, the smooth cases (LuGre,
  compliances, and the stage whose GMS nut only rings) fall about 4x per halving, the GMS
  slider 2x. The check asks for at least 1.5x per halving.

The twin's own error (measured against rtol 1e-11/1e-12 runs) is stated where it matters:
it is far below the compiled loop's error at 2-8 sub-steps, and below it at 10 sub-steps
except for the Hertz stage's motor angle and guide force, whose bounds then carry it.

Case (e) puts a static Stribeck law at the site: the twin then sticks and slips by events.
Case (f) puts a TDMSSC there whose levels follow another DOF's velocity (a schedule input),
crossing zero while it slides.

Plus the closed form of the exact linear discretisation: a mass-spring-damper without sites
under a force ramp and under a spring/damper dragged by a prescribed ramp, 1e-9 relative.
"""

from __future__ import annotations

import math

import numpy as np
import pytest

import frictionkit as fk
from frictionkit.errors import ParameterError
from frictionkit.machines import PID, HertzContact, Machine, PiecewiseLinearSpring, SineLoad, simulate_machine
from frictionkit.machines.reference import reference_machine
from frictionkit.simulation.inputs import example_gms

PAPER = fk.Stribeck(Fc=1.0, Fs=1.5, vs=1e-3, sigma2=0.4)  # Canudas et al. 1995 / README example

# --------------------------------------------------------------------------- cases
J_MOTOR = 4.3e-3  # kg m^2, seed 001 Table 1 motor side
R_SCREW = 10e-3 / (2.0 * math.pi)  # m/rad, 10 mm lead
M_TABLE = 50.0  # kg
K_NUT = 1.5e8  # N/m


def _t(T: float, dt: float) -> np.ndarray:
    return np.arange(int(round(T / dt)) + 1) * dt


def lugre_slider():
    """(a) 1 kg on a LuGre contact (sigma1 = sqrt(1e5)), u = 2 sin(pi t) N: stick-slip both ways."""
    m = Machine("lugre slider")
    x = m.dof("x", inertia=1.0)
    m.friction("contact", x, law=fk.LuGre(PAPER, sigma0=1e5, sigma1=math.sqrt(1e5)))
    m.actuator("u", x)
    dt = 2.5e-4
    return m, dt, {"u": 2.0 * np.sin(np.pi * _t(2.5, dt))}


def gms_slider():
    """(b) 1 kg on a GMS-3 contact, u = 2 sin(pi t) N."""
    m = Machine("gms slider")
    x = m.dof("x", inertia=1.0)
    m.friction("contact", x, law=example_gms(3))
    m.actuator("u", x)
    dt = 2.5e-4
    return m, dt, {"u": 2.0 * np.sin(np.pi * _t(2.5, dt))}


def ballscrew():
    """(c) Motor inertia and table coupled by the screw (R theta - x) through the nut stiffness
    (1.5e8 N/m, 2 % damping: first mode 280 Hz), a GMS-4 at the nut across the same relative
    motion, a LuGre at the guide (table to ground); motor torque 0.15 sin(4 pi t) N m."""
    meff = 1.0 / (1.0 / M_TABLE + R_SCREW**2 / J_MOTOR)
    m = Machine("ball-screw stage")
    th = m.dof("motor", inertia=J_MOTOR, kind="rotational")
    x = m.dof("table", inertia=M_TABLE)
    m.spring(R_SCREW * th, x, k=K_NUT, c=2 * 0.02 * math.sqrt(K_NUT * meff), name="nut contact")
    m.friction("nut", R_SCREW * th, x,
               law=fk.GMS(fk.Stribeck(Fc=10.0, Fs=15.0, vs=1e-3), k=[5e6, 1.5e7, 5e7, 1.5e8],
                          xi=[0.4, 0.3, 0.2, 0.1], C=2000.0))
    m.friction("guide", x, law=fk.LuGre(fk.Stribeck(Fc=40.0, Fs=60.0, vs=2e-3, sigma2=100.0),
                                        sigma0=1e7, sigma1=2e4))
    m.actuator("torque", th)
    dt = 2.5e-4
    return m, dt, {"torque": 0.15 * np.sin(4.0 * np.pi * _t(0.5, dt))}


def hertz_stage():
    """(d1) The stage with a preloaded Hertzian nut (5 N preload: one ball set unloads beyond
    14 N) instead of the linear spring, LuGre guide."""
    m = Machine("hertz nut stage")
    th = m.dof("motor", inertia=J_MOTOR, kind="rotational")
    x = m.dof("table", inertia=M_TABLE)
    m.compliance("nut", R_SCREW * th, x, law=HertzContact(preload=5.0, stiffness=5e7), c=1500.0)
    m.friction("guide", x, law=fk.LuGre(fk.Stribeck(Fc=40.0, Fs=60.0, vs=2e-3, sigma2=100.0),
                                        sigma0=1e7, sigma1=2e4))
    m.actuator("torque", th)
    dt = 2.5e-4
    return m, dt, {"torque": 0.15 * np.sin(4.0 * np.pi * _t(0.5, dt))}


def harmonic_drive():
    """(d2) Motor and link through a 50:1 harmonic drive (piecewise-linear stiffness 1e4/2e4/3e4
    N m/rad, breaks at 1 and 3 N m), gravity imbalance 8 sin(theta) N m and a LuGre bearing on
    the link; motor torque 0.1 sin(2 pi t) N m."""
    m = Machine("harmonic drive")
    tm = m.dof("motor", inertia=1e-4, kind="rotational")
    tl = m.dof("link", inertia=5e-2, kind="rotational")
    m.compliance("flexspline", tm / 50.0, tl,
                 law=PiecewiseLinearSpring.from_torque_breaks((1e4, 2e4, 3e4), (1.0, 3.0)), c=5.0)
    m.load("gravity", tl, law=SineLoad(amplitude=8.0))
    m.friction("bearing", tl, law=fk.LuGre(fk.Stribeck(Fc=0.5, Fs=0.8, vs=0.01, sigma2=0.05),
                                           sigma0=1e4, sigma1=20.0))
    m.actuator("torque", tm)
    dt = 2.5e-4
    return m, dt, {"torque": 0.1 * np.sin(2.0 * np.pi * _t(1.0, dt))}


def static_stickslip():
    """(e) The stick-slip set-up of Canudas et al. 1995 (1 kg, 2 N/m spring pulled at 0.1 m/s)
    on a *static* Stribeck law: the twin sticks and slips by events (Karnopp, exact)."""
    m = Machine("static stick-slip")
    x = m.dof("x", inertia=1.0)
    pull = m.motion("pull")
    m.spring(x, pull, k=2.0)
    m.friction("contact", x, law=PAPER)
    dt = 1e-3
    return m, dt, {"pull": 0.1 * _t(20.0, dt)}


def scheduled_static():
    """(f) A TDMSSC (seed 000 eq. 21) whose levels follow another DOF's velocity: a base
    (1 kg, 10 N s/m damper, pushed by 10 sin(pi t) N, so s swings over +-0.95 m/s) and a 1 kg
    block pulled through 20 N/m at 0.05 m/s on Fc(s) = 0.6 + 0.8 s, Fs(s) = 1.0 + 0.8 s,
    sigma2 = -0.2 N s/m (negative viscous slope), eps = 0.5 N s^2/m^2: it sticks, slips while
    its Coulomb level crosses zero (to -0.16 N), stops, slips back, stops."""
    m = Machine("scheduled static")
    b = m.dof("base", inertia=1.0)
    x = m.dof("x", inertia=1.0)
    m.damper(b, c=10.0)
    m.actuator("push", b)
    pull = m.motion("pull")
    m.spring(x, pull, k=20.0)
    m.friction("contact", x, law=fk.TDMSSC(Fc0=0.6, Fc1=0.8, Fs0=1.0, Fs1=0.8, vs=1e-2, delta=2.0,
                                           sigma2=-0.2, eps=0.5), schedule=b.velocity)
    dt = 1e-3
    t = _t(2.5, dt)
    return m, dt, {"push": 10.0 * np.sin(np.pi * t), "pull": 0.05 * t}


CASES = {f.__name__: f for f in (lugre_slider, gms_slider, ballscrew, hertz_stage, harmonic_drive, static_stickslip,
                                  scheduled_static)}

_TWINS: dict = {}

# the twins cost ~1 min of solve_ivp: keep this module's tests on one xdist worker so each
# twin runs once (`make test` runs pytest with --dist loadgroup)
pytestmark = pytest.mark.xdist_group("machine_twins")


def twin(name: str):
    """``(machine, dt, inputs, reference)`` of a case; the twin runs once per session."""
    if name not in _TWINS:
        m, dt, inputs = CASES[name]()
        ref = reference_machine(m, dt=dt, inputs=inputs, rtol=1e-10)
        assert ref.success
        _TWINS[name] = (m, dt, inputs, ref)
    return _TWINS[name]


def errors(name: str, substeps: int, *, window: float | None = None, **kw) -> dict:
    """max |dq| (per DOF), |dv| and |dF| (per site) of simulate_machine against the twin."""
    m, dt, inputs, ref = twin(name)
    res = simulate_machine(m, dt=dt, inputs=inputs, substeps=substeps, **kw)
    assert res.success, res.message
    k = slice(None) if window is None else slice(0, int(round(window / dt)) + 1)
    return {"dq": np.abs(res.q[k] - ref.q[k]).max(axis=0), "dv": np.abs(res.v[k] - ref.v[k]).max(axis=0),
            "dF": np.abs(res.site_forces[k] - ref.site_forces[k]).max(axis=0)}


# --------------------------------------------------------------------------- the runs are what they claim
def test_the_cases_exercise_what_they_are_for():
    m, dt, _, ref = twin("lugre_slider")
    v = ref.velocity("x")
    assert v.max() > 0.2 and v.min() < -0.2 and np.mean(np.abs(v) < 1e-3) > 0.05  # slides both ways, sticks
    _, _, _, ref = twin("gms_slider")
    kinds = {k for _, k, _, _ in ref.event_log}
    assert kinds == {"breakaway", "reversal"} and ref.n_events >= 20
    _, _, _, ref = twin("ballscrew")
    broke = {i for _, k, j, i in ref.event_log if k == "breakaway"}
    assert broke >= {1, 2, 3} and ref.n_events > 50  # nut elements break away and re-stick as it rings
    assert ref.velocity("table").max() > 2e-3 and ref.velocity("table").min() < -2e-3  # guide slides both ways
    m, _, _, ref = twin("hertz_stage")
    hz = m.sites[0].law
    assert np.abs(ref.force("nut") + hz.stiffness * ref.position(m.sites[0].at)).max() > 2**1.5 * hz.preload
    m, _, _, ref = twin("harmonic_drive")
    d = ref.position(m.sites[0].at)
    assert np.abs(d).max() > m.sites[0].law.breaks[1]  # the flexspline runs through both breaks
    _, _, _, ref = twin("static_stickslip")
    # sticks until the spring holds Fs (7.5 s), slips, stops, sticks, slips again
    assert [k for _, k, _, _ in ref.event_log] == ["slip", "stop", "slip", "stop"]
    assert ref.event_log[0][0] == pytest.approx(1.5 / (2.0 * 0.1), rel=1e-9)
    m, _, _, ref = twin("scheduled_static")
    assert [k for _, k, _, _ in ref.event_log] == ["slip", "stop", "slip", "stop"]
    s = ref.velocity("base")
    sliding = np.abs(ref.velocity("x")) > 1e-6
    assert s.max() > 0.9 and s.min() < -0.9
    assert (0.6 + 0.8 * s[sliding]).min() < -0.1  # the Coulomb level is negative while it slides


# --------------------------------------------------------------------------- accuracy at the default
# (name, max |dq| per DOF, max |dF| per site) of the general loop at substeps = 10, measured
# on 2026-11-22 (gms_slider and ballscrew again on 2026-11-23 after the GMS breakaway on the
# site's linear-velocity path); the bound is 3x. Units: m or rad, N or N m.
DEFAULT_ERRORS = [
    # 2.5 s, 0.4 m of travel: 8.6 nm, 3.0e-5 N (the twin's own error: ~1.5 nm, 1e-6 N)
    ("lugre_slider", [8.61e-9], [3.02e-5]),
    # 20 um, 7.4e-3 N: GMS is first order in the general loop, 50x less accurate here than
    # the one-DOF fast path (single-axis kernel, 0.40 um) on the same run (twin: 2 nm)
    ("gms_slider", [2.02e-5], [7.37e-3]),
    # motor [rad], table [m]; nut, guide
    ("ballscrew", [1.62e-8, 2.63e-11], [3.07e-4, 1.79e-4]),
    # the motor's 2.2e-7 rad and the guide's 1.4e-3 N carry the twin's own error (against an
    # rtol 1e-12 twin the loop is off by 4.3e-8 rad and 1.1e-3 N)
    ("hertz_stage", [2.18e-7, 5.26e-10], [2.45e-3, 1.40e-3]),
    # the motor swings over 96 rad: 9.7e-7 rad (the twin's own error there: 2.3e-7 rad, from an
    # rtol 1e-11 run); flexspline, gravity, bearing
    ("harmonic_drive", [9.65e-7, 1.93e-8], [8.60e-5, 1.36e-7, 1.72e-5]),
    # static law, 20 s: 0.14 mm (first order, from the stop instants); the force error is the
    # friction jump at a stop (1.4 -> 0.77 N) landing in a different sample. Rerun 2026-11-23
    # after the twin's static-site fixes (test_twin_static_sites.py): 1.371e-4 m, 8.761e-2 N,
    # unchanged (this case's holding force rises monotonically: the twin never stepped over it)
    ("static_stickslip", [1.37e-4], [8.76e-2]),
    # scheduled static law, 2.5 s (2026-11-23): base 6.2e-9 m, block 10.8 um (first order, the
    # stop instants); 8.5e-4 N
    ("scheduled_static", [6.25e-9, 1.08e-5], [8.52e-4]),
]


@pytest.mark.parametrize("name, dq, dF", DEFAULT_ERRORS, ids=[c[0] for c in DEFAULT_ERRORS])
def test_default_substeps_agree_with_the_twin(name, dq, dF):
    e = errors(name, 10, fast_path=False)
    assert np.all(e["dq"] <= 3.0 * np.array(dq)), e["dq"]
    assert np.all(e["dF"] <= 3.0 * np.array(dF)), e["dF"]


# --------------------------------------------------------------------------- convergence in the sub-step
# Halving the sub-step twice divides max |dv| and max |dF| (each DOF, each site) by at least
# 1.5 each time. Measured ratios per halving in the comments.
CONVERGENCE = [
    ("lugre_slider", (2, 4, 8), None),  # dv 2.8, 7.9; dF 2.7, 8.8
    # GMS: 10 -> 20 -> 40 over the first slide (t <= 1.15 s, before the first reversal): from
    # 1 to 8 sub-steps, and over the later stick phases (which ring), the error is erratic
    ("gms_slider", (10, 20, 40), 1.15),  # dv 2.0, 1.9; dF 2.0, 1.9
    ("ballscrew", (2, 4, 8), None),  # dv 5.7/3.9, 2.4/3.6; dF 3.8/3.8, 3.4/4.5
    ("hertz_stage", (2, 4, 8), None),  # dv 3.8/4.0, 3.3/4.0; dF 4.0/3.9, 3.9/3.6
    ("harmonic_drive", (2, 4, 8), None),  # dv 4.1/4.0, 3.9/4.0; dF 3.9/7.4/3.1, 4.1/2.9/4.6
    ("static_stickslip", (10, 20, 40), None),  # dv 2.1, 2.0; dF 1.8, 1.9 (rerun 2026-11-23: the same)
]


@pytest.mark.parametrize("name, substeps, window", CONVERGENCE, ids=[c[0] for c in CONVERGENCE])
def test_error_falls_with_the_substep(name, substeps, window):
    e = [errors(name, s, window=window, fast_path=False) for s in substeps]
    for key in ("dv", "dF"):
        for a, b in zip(e[:-1], e[1:]):
            assert np.all(b[key] <= a[key] / 1.5), (key, [x[key] for x in e])


def test_scheduled_static_error_falls_with_the_substep():
    """(f): the block's position and the site force converge (measured per halving 10 -> 20 -> 40:
    dq 2.8, 3.9; dF 2.0, 1.6). Its velocity error is set by the stop instants and the base's by
    the twin's own error (1.5e-8 m/s at every sub-step count), so they are not asked to fall."""
    e = [errors("scheduled_static", s) for s in (10, 20, 40)]
    for a, b in zip(e[:-1], e[1:]):
        assert b["dq"][1] <= a["dq"][1] / 1.5, [x["dq"] for x in e]
        assert np.all(b["dF"] <= a["dF"] / 1.5), [x["dF"] for x in e]


def test_one_dof_defaults_take_the_fast_path_and_agree_with_the_twin():
    """(a), (b) with default options run on the one-DOF fast path (adaptive single-axis kernels)."""
    # measured: LuGre 0.15 um / 9.9e-5 N, GMS 0.40 um / 2.4e-4 N; bound 3x
    for name, dq, dF in (("lugre_slider", 1.52e-7, 9.88e-5), ("gms_slider", 3.96e-7, 2.45e-4)):
        m, dt, inputs, ref = twin(name)
        res = simulate_machine(m, dt=dt, inputs=inputs)
        assert res.success and "fast path" in res.message, res.message
        assert np.abs(res.q - ref.q).max() <= 3.0 * dq
        assert np.abs(res.site_forces - ref.site_forces).max() <= 3.0 * dF


# --------------------------------------------------------------------------- the twin itself
def test_twin_matches_the_single_mass_twin():
    """Two independent solve_ivp twins (this one and simulate.reference) on the GMS slider."""
    from frictionkit.simulation.reference import reference_force_driven

    m, dt, inputs = gms_slider()
    u = inputs["u"][: int(round(0.4 / dt)) + 1]  # 13 breakaways and reversals
    ref = reference_machine(m, dt=dt, inputs={"u": u})
    one = reference_force_driven(example_gms(3), 1.0, u, dt, rtol=1e-10, atol=1e-13)
    assert np.abs(ref.q[:, 0] - one["x"]).max() < 1e-8
    assert np.abs(ref.site_forces[:, 0] - one["friction"]).max() < 1e-5
    assert [k for _, k, _, _ in ref.event_log] == [k for _, k, _ in one["event_log"]]


def test_twin_refuses_what_it_cannot_model():
    m = Machine("m")
    x = m.dof("x", inertia=1.0)
    y = m.dof("y", inertia=1.0)
    m.friction("f", x, law=fk.Stribeck(Fc=1.0, Fs=1.5, vs=1e-3))
    m.friction("g", y, law=fk.CoulombViscous(Fc=1.0))
    m.actuator("u", x)
    with pytest.raises(ParameterError, match="hold static laws"):
        reference_machine(m, dt=1e-3, inputs={"u": np.zeros(3)})
    m = Machine("m")
    x = m.dof("x", inertia=1.0)
    m.actuator("u", x, command="i")
    m.sensor("s", x)
    m.add(PID("i", "s", Kp=1.0))
    with pytest.raises(ParameterError, match="open-loop"):
        reference_machine(m, dt=1e-3, n_samples=3)


# --------------------------------------------------------------------------- exact linear chain
def _msd(a: float, b0: float, m: float, c: float, k: float, t: np.ndarray):
    """x, v of ``m x'' + c x' + k x = a t + b0`` from rest (underdamped)."""
    al = c / (2.0 * m)
    wd = math.sqrt(k / m - al * al)
    xp0 = b0 / k - a * c / k**2
    A = -xp0
    B = (al * A - a / k) / wd
    e, co, si = np.exp(-al * t), np.cos(wd * t), np.sin(wd * t)
    x = a / k * t + xp0 + e * (A * co + B * si)
    v = a / k + e * ((-al * A + wd * B) * co + (-al * B - wd * A) * si)
    return x, v


@pytest.mark.parametrize("substeps", [1, 7])
def test_linear_chain_is_exact_for_a_force_ramp(substeps):
    mass, c, k, a = 2.0, 4.0, 5e3, 3.0  # zeta = 0.02, 7.96 Hz
    m = Machine("msd")
    x = m.dof("x", inertia=mass)
    m.spring(x, k=k, c=c)
    m.actuator("u", x)
    dt = 1e-3
    t = _t(1.0, dt)
    res = simulate_machine(m, dt=dt, inputs={"u": a * t}, substeps=substeps)
    xe, ve = _msd(a, 0.0, mass, c, k, t)
    assert np.abs(res.q[:, 0] - xe).max() <= 1e-9 * np.abs(xe).max()
    assert np.abs(res.v[:, 0] - ve).max() <= 1e-9 * np.abs(ve).max()


def test_linear_chain_is_exact_for_a_dragged_spring():
    """Spring and damper to a prescribed motion p = b t: m x'' + c x' + k x = k b t + c b."""
    mass, c, k, b = 2.0, 4.0, 5e3, 0.1
    m = Machine("dragged")
    x = m.dof("x", inertia=mass)
    p = m.motion("p")
    m.spring(x, p, k=k, c=c)
    dt = 1e-3
    t = _t(1.0, dt)
    res = simulate_machine(m, dt=dt, inputs={"p": b * t}, substeps=3)
    xe, ve = _msd(k * b, c * b, mass, c, k, t)
    assert np.abs(res.q[:, 0] - xe).max() <= 1e-9 * np.abs(xe).max()
    assert np.abs(res.v[:, 0] - ve).max() <= 1e-9 * np.abs(ve).max()


# --------------------------------------------------------------------------- one kernel signature for every layout
def _recorded_kernel_types(monkeypatch, module: str, name: str, runs) -> list:
    """numba's argument types of every call of ``kernels.<module>.<name>`` made by ``runs()``, with
    the kernel replaced by a stub that records them, zeroes the outputs and returns "ok" (nothing
    is compiled or run)."""
    import importlib

    import numba

    km = importlib.import_module(f"frictionkit.kernels.{module}")
    calls = []

    def stub(*args, **kw):
        calls.append(tuple(numba.typeof(a) for a in args) + tuple((k, numba.typeof(kw[k])) for k in sorted(kw)))
        outs = args[-5:]  # q_out, v_out, F_out, sig_out, u_out: the last positional arguments of both kernels
        for o in outs:
            o[...] = 0.0
        n = outs[0].shape[0]
        return (0, n, 0, 0, 0) if name == "run" else (0, n, 0)

    monkeypatch.setattr(km, name, stub)
    runs()
    return calls


def test_every_machine_layout_calls_the_one_compiled_kernel(monkeypatch):
    """A machine layout the numba cache never saw must not compile the kernel again (issue 8:
    ~30 s CPU for ``kernels.machine.run`` on a cold cache; loading it from the cache ~0.3 s): the
    wrapper packs every layout — sites of every kind, motions, loads, schedules, sensors with
    delay and noise, every block kind, actuators held or linear — into arguments of one numba type
    each (C-contiguous, writeable, fixed dtypes and ranks). Each layout below is only packed; the
    kernel is a stub."""
    from frictionkit.presets.ballscrew import simulate_stage
    from frictionkit.presets.emps import PUBLISHED, emps_machine
    from frictionkit.control.trajectories import cosine_reference
    from frictionkit.reproduce.zhu_fujimoto import paper_controller, paper_plant, paper_sensors

    def runs():
        for f in CASES.values():
            m, dt, inputs = f()
            n = 41
            simulate_machine(m, dt=dt, inputs={k: v[:n] for k, v in inputs.items()}, fast_path=False)
        # closed loop: PID, DOB (state-space block), feed-forward inputs, quantised noisy sensors
        simulate_stage(paper_plant(), paper_controller(), cosine_reference(duration=0.01), sensors=paper_sensors())
        m = emps_machine(M=PUBLISHED["M"], friction=fk.CoulombViscous(Fc=PUBLISHED["Fc"], sigma2=PUBLISHED["Fv"]))
        simulate_machine(m, dt=1e-3, inputs={"qg": np.full(40, 1e-3)}, fast_path=False)

    calls = _recorded_kernel_types(monkeypatch, "machine", "run", runs)
    assert len(calls) >= len(CASES) + 2
    assert len(set(calls)) == 1, [i for i, c in enumerate(calls) if c != calls[0]]
    for t in calls[0]:
        t = t[1] if isinstance(t, tuple) else t
        if hasattr(t, "layout"):
            assert t.layout == "C" and t.mutable, t


def test_every_axis_layout_calls_the_one_compiled_axis_kernel(monkeypatch):
    """The same for the one-DOF fast path (``kernels.machine_axis.run_axis``): flat and Stribeck
    levels, input-array and controller actuators, with and without sensors and blocks."""
    from frictionkit.presets.emps import PUBLISHED, emps_machine

    def runs():
        for law in (fk.CoulombViscous(Fc=PUBLISHED["Fc"], sigma2=PUBLISHED["Fv"]),
                    fk.Stribeck(Fc=20.0, Fs=30.0, vs=0.01, sigma2=PUBLISHED["Fv"])):
            m = emps_machine(M=PUBLISHED["M"], friction=law)
            r = simulate_machine(m, dt=1e-3, inputs={"qg": np.full(40, 1e-3)})
            assert r.path.startswith("axis"), r.path
        m = Machine("open-loop axis")
        x = m.dof("x", inertia=2.0)
        m.friction("contact", x, law=fk.CoulombViscous(Fc=1.0, sigma2=0.5))
        m.actuator("u", x)
        r = simulate_machine(m, dt=1e-3, inputs={"u": np.linspace(0.0, 3.0, 40)})
        assert r.path.startswith("axis"), r.path

    calls = _recorded_kernel_types(monkeypatch, "machine_axis", "run_axis", runs)
    assert len(calls) == 3
    assert len(set(calls)) == 1, [i for i, c in enumerate(calls) if c != calls[0]]
