"""Scheduling inputs in the machine core: a static site whose levels follow another coordinate
(TDMSSC, seed 000 eq. 21), signed levels in the Karnopp solve, the scheduled friction
feed-forward block, and the errors of the API.

Closed forms (no value from the code under test): a mass sliding one way on a law whose level
is a constant or an affine function of a prescribed ramp moves under a constant or linear net
force, so its position is a quadratic or a cubic in time.
"""

from __future__ import annotations

import numpy as np
import pytest

import frictionkit as fk
from frictionkit.errors import ParameterError
from frictionkit.machines import FrictionFeedforward, Sum

DT = 1e-3


def _t(T: float) -> np.ndarray:
    return np.arange(int(round(T / DT)) + 1) * DT


def slider(law, *, m=2.0, v0=0.0, schedule=None, extra=None):
    """A mass on a friction site, a constant-force actuator "u", optional prescribed motion "p"."""
    mach = fk.Machine("slider")
    x = mach.dof("x", inertia=m, v0=v0)
    p = mach.motion("p")
    sched = {None: None, "p.position": p.position, "p.velocity": p.velocity}[schedule]
    mach.friction("site", x, law=law, schedule=sched)
    mach.actuator("u", x)
    return mach


def test_a_negative_level_pushes_along_the_motion():
    """Levels -1 N both ways (the ball pair driving the nut, seed 000 §5.2.2): a 2 kg mass
    pushed by 0.2 N from rest accelerates at (0.2 + 1) / 2 = 0.6 m/s^2 (x = 0.3 t^2)."""
    law = fk.TDMSSC(Fc0=-1.0, Fs0=-1.0, vs=1e-3, Fc1=1.0)  # Fc1 acts on a schedule fixed at 0
    m = slider(law, schedule="p.position")
    t = _t(1.0)
    res = fk.simulate_machine(m, dt=DT, inputs={"u": np.full(t.size, 0.2), "p": np.zeros(t.size)})
    assert res.success and np.all(np.isfinite(res.q))
    np.testing.assert_allclose(res.position("x"), 0.3 * t**2, rtol=1e-9, atol=1e-12)
    np.testing.assert_allclose(res.force("site")[1:], -1.0, atol=1e-12)


def test_at_rest_with_an_empty_stick_band_and_no_push_it_stays():
    """Both static levels negative and nothing pushing: no direction is preferred (documented)."""
    law = fk.TDMSSC(Fc0=-1.0, Fs0=-1.0, vs=1e-3)
    m = slider(law, schedule="p.velocity")
    t = _t(0.2)
    res = fk.simulate_machine(m, dt=DT, inputs={"u": np.zeros(t.size), "p": np.zeros(t.size)})
    assert res.success
    assert np.all(res.position("x") == 0.0) and np.all(res.force("site") == 0.0)


def test_a_level_of_zero_gives_no_force_and_no_nan():
    """Fc(s) = Fs(s) = s: the schedule (a prescribed position held at 0) makes both levels 0:
    free flight at u / m = 0.5 / 2 (x = 0.125 t^2), in both directions."""
    law = fk.TDMSSC(Fc0=0.0, Fs0=0.0, Fc1=1.0, Fs1=1.0, vs=1e-3)
    for sign in (1.0, -1.0):
        m = slider(law, schedule="p.position")
        t = _t(0.5)
        res = fk.simulate_machine(m, dt=DT, inputs={"u": np.full(t.size, 0.5 * sign), "p": np.zeros(t.size)})
        assert res.success and np.all(np.isfinite(res.site_forces))
        np.testing.assert_allclose(res.position("x"), sign * 0.125 * t**2, rtol=1e-9, atol=1e-12)


@pytest.fixture(scope="module")
def ramp_runs():
    """Coulomb level Fc(s) = 1 + 2 s with s = p(t) = 0.5 t (a prescribed ramp, read as a
    position): a 2 kg mass sliding forward at v0 = 1 m/s under u = 3 N feels
    3 - 1 - t = 2 - t, so v = 1 + t - t^2/4 > 0 over 2 s and x = t + t^2/2 - t^3/12."""
    law = fk.TDMSSC(Fc0=1.0, Fs0=1.0, Fc1=2.0, Fs1=2.0, vs=1e-3)
    t = _t(2.0)
    exact = t + t**2 / 2 - t**3 / 12
    out = {}
    for sub in (2, 4, 8):
        m = slider(law, v0=1.0, schedule="p.position")
        res = fk.simulate_machine(m, dt=DT, inputs={"u": np.full(t.size, 3.0), "p": 0.5 * t}, substeps=sub)
        assert res.success
        out[sub] = float(np.abs(res.position("x") - exact).max())
    return out


def test_levels_follow_a_scheduled_position_and_converge_first_order(ramp_runs):
    # The levels are read at the start of each sub-step h, so they lag the ramp by h/2 on
    # average: a force error Fc1 * ds/dt * h/2 = 2 * 0.5 * h/2 = h/2 N, an acceleration error
    # h/4 m/s^2 and, at t = 2 s, a position error (h/4) t^2/2 = h/2 m — first order, known.
    for sub, err in ramp_runs.items():
        assert err == pytest.approx(0.5 * DT / sub, rel=0.02)


def test_schedule_on_another_dof_velocity_changes_the_breakaway():
    """The same 1.2 N push holds a block whose static level is 1 + 0.5 s while the base
    rests (s = 0: 1.2 > 1, it slips) ... and while the base runs at 1 m/s (Fs = 1.5: it sticks)."""
    law = fk.TDMSSC(Fc0=1.0, Fs0=1.0, Fc1=0.5, Fs1=0.5, vs=1e-3)
    moved = {}
    for vb in (0.0, 1.0):
        m = fk.Machine("two")
        b = m.dof("base", inertia=1.0, v0=vb)
        x = m.dof("x", inertia=1.0)
        m.friction("site", x, law=law, schedule=b.velocity)
        m.actuator("u", x)
        t = _t(0.2)
        res = fk.simulate_machine(m, dt=DT, inputs={"u": np.full(t.size, 1.2)})
        moved[vb] = float(res.position("x")[-1])
        if vb:  # base coasts at 1 m/s (nothing acts on it)
            np.testing.assert_allclose(res.velocity("base"), 1.0, rtol=1e-12)
    assert moved[1.0] == 0.0
    assert moved[0.0] == pytest.approx(0.5 * 0.2 * 0.2**2, rel=1e-9)  # (1.2 - 1.0) / 1 kg


def test_scheduled_feedforward_block_equals_the_law():
    """FrictionFeedforward(schedule=...) outputs scale * F(v; s) every sample (vs the NumPy law)."""
    nut = fk.Directional(
        positive=fk.TDMSSC(Fc0=-4.52, Fc1=6450.0, Fs0=-19.56, Fs1=6450.0, vs=6.5e-5, delta=1.7,
                           sigma2=-1120.0, eps=5.852e6),  # seed 000 Table 5 nut, SI
        negative=fk.TDMSSC(Fc0=-48.34, Fs0=-62.26, vs=1.69e-4, delta=0.9, sigma2=390.0, eps=3.754e6))
    m = fk.Machine("ff")
    x = m.dof("x", inertia=1.0)
    m.sensor("enc", x)
    m.add(FrictionFeedforward("ff", "vref", nut, scale=0.5, schedule="vbase"), Sum("zero", {"enc": 0.0}))
    t = _t(0.3)
    vref = 2e-3 * np.sin(2 * np.pi * 5 * t)
    vbase = -6e-3 + 4e-2 * t
    res = fk.simulate_machine(m, dt=DT, inputs={"vref": vref, "vbase": vbase})
    np.testing.assert_allclose(res.signal("ff"), 0.5 * nut.steady_state(vref, schedule=vbase), rtol=1e-12, atol=1e-9)


def test_api_errors_name_the_problem():
    law = fk.TDMSSC(Fc0=1.0, Fs0=1.5, Fc1=0.1, vs=1e-3)
    m = fk.Machine("m")
    x = m.dof("x", inertia=1.0)
    other = fk.Machine("other").dof("y", inertia=1.0)
    with pytest.raises(ParameterError, match=r"friction\('a'\).schedule = None: TDMSSC reads a scheduling"):
        m.friction("a", x, law=law)
    with pytest.raises(ParameterError, match=r"must be <coordinate>.velocity"):
        m.friction("b", x, law=law, schedule=x)
    with pytest.raises(ParameterError, match="not a coordinate of machine 'm'"):
        m.friction("c", x, law=law, schedule=other.velocity)
    with pytest.raises(ParameterError, match="Stribeck reads no scheduling variable"):
        m.friction("d", x, law=fk.Stribeck(Fc=1.0, Fs=1.5, vs=1e-3), schedule=x.velocity)
    with pytest.raises(ParameterError, match=r"FrictionFeedforward\('f'\).schedule = None"):
        FrictionFeedforward("f", "v", law)
    with pytest.raises(ParameterError, match="reads no scheduling variable"):
        FrictionFeedforward("f", "v", fk.Stribeck(Fc=1.0, Fs=1.5, vs=1e-3), schedule="s")
    assert repr(x.velocity) == "CoordSignal(Coord(x).velocity)"


# --------------------------------------------------------------------------- error control (issue 8)
def _stickslip():
    """Canudas et al. 1995 set-up on a static Stribeck law: 1 kg, 2 N/m pulled at 0.1 m/s."""
    m = fk.Machine("stick-slip")
    x = m.dof("x", inertia=1.0)
    pull = m.motion("pull")
    m.spring(x, pull, k=2.0)
    m.friction("contact", x, law=fk.Stribeck(Fc=1.0, Fs=1.5, vs=1e-3, sigma2=0.4))
    return m, {"pull": 0.1 * _t(12.0)}


def test_atol_picks_the_substeps_and_flags_a_miss():
    m, inp = _stickslip()
    runs = {s: fk.simulate_machine(m, dt=DT, inputs=inp, substeps=s) for s in (2, 4, 8, 16)}
    change = {s: float(np.abs(runs[2 * s].q - runs[s].q).max()) for s in (2, 4, 8)}
    # a tolerance between the 4 -> 8 and the 2 -> 4 changes stops at 8 sub-steps, with that run
    tol = 0.5 * (change[2] + change[4])
    assert change[4] < tol < change[2]
    res = fk.simulate_machine(m, dt=DT, inputs=inp, substeps=2, atol=tol)
    assert res.success and res.substeps == 8 and "error estimate" in res.message
    np.testing.assert_array_equal(res.q, runs[8].q)
    # a tolerance the cap does not allow: status 2, the finest run, the estimate in the message
    miss = fk.simulate_machine(m, dt=DT, inputs=inp, substeps=2, atol=1e-3 * change[8], max_substeps=16)
    assert miss.status == 2 and not miss.success and miss.substeps == 16
    assert "not met within max_substeps = 16" in miss.message
    np.testing.assert_array_equal(miss.q, runs[16].q)
    with pytest.raises(ParameterError, match="max_substeps = 1"):
        fk.simulate_machine(m, dt=DT, inputs=inp, substeps=2, atol=1e-6, max_substeps=1)
    with pytest.raises(ParameterError, match="atol = -1.0"):
        fk.simulate_machine(m, dt=DT, inputs=inp, atol=-1.0)


def test_closed_loop_with_scheduled_sites_runs_and_is_screened():
    """A feedback loop over a scheduled (TDMSSC) friction site and feed-forward: the loop screen reads
    a scheduled law's sliding slope (it crashed with AttributeError 'static_rows' on TDMSSC)."""
    from frictionkit.machines.stability import loop_stability

    law = fk.TDMSSC(Fc0=1.0, Fs0=1.5, Fc1=0.5, Fs1=0.5, vs=1e-3, sigma2=3.0)
    m = fk.Machine("scheduled loop")
    b = m.dof("base", inertia=1.0, v0=0.5)  # coasts: the schedule is its velocity
    x = m.dof("x", inertia=2.0)
    m.friction("f", x, law=law, schedule=b.velocity)
    m.sensor("v", x, quantity="velocity")
    m.add(FrictionFeedforward("ff", "v", law, scale=1.0, schedule="p"), Sum("u", {"v": -100.0, "ff": 1.0}))
    m.actuator("a", x, command="u")
    st = loop_stability(m, DT)
    # force held over the sample on a mass with the friction slope sigma2 and the feed-forward's
    # slope: v_{k+1} = (1 - (100 + 3 - 3) dt / m) v_k exactly for the linearised loop
    assert st.radius == pytest.approx(1.0, rel=1e-9) and not st.unstable  # the free positions
    t = _t(0.2)
    res = fk.simulate_machine(m, dt=DT, inputs={"p": np.full(t.size, 0.5)})
    assert res.status == 0, res.message
