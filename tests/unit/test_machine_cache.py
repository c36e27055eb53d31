"""Caches of the machine core's Python side (issue 8): the machine fingerprint remembered on
the machine object, the ball-screw stage's machine and the PTC feed-forward.

The rule every test here checks: an edited machine (or plant, controller, reference) never
meets a stale cache. Each expected value is computed afresh from scratch (the JSON form the
fingerprint stood for before its memo, a machine built anew, a feed-forward from an emptied
cache), never copied from the code under test.
"""

from __future__ import annotations

import dataclasses

import numpy as np
import pytest

import frictionkit as fk
from frictionkit.machines import PID, FrictionFeedforward, Machine, Saturation, StateSpace, Sum
from frictionkit.machines import simulate as sim


def _machine() -> Machine:
    m = Machine("memo probe")
    x = m.dof("x", inertia=2.0)
    y = m.dof("y", inertia=1.0)
    m.spring(x - y, k=1e4, c=3.0, name="link")
    m.inertia(0.5 * (x + y), 0.3)
    m.friction("contact", x, law=fk.LuGre(fk.Stribeck(Fc=1.0, Fs=1.4, vs=0.01, sigma2=0.5), sigma0=1e5, sigma1=300.0))
    m.friction("ball", x, y, law=fk.GMS(fk.Stribeck(Fc=2.0, Fs=2.4, vs=0.01), k=[1e5, 2e5], xi=[0.5, 0.5], C=20.0))
    m.friction("nut", y, law=fk.TDMSSC(Fc0=0.8, Fc1=0.5, Fs0=1.1, Fs1=0.5, vs=0.01, sigma2=0.4), schedule=x.velocity)
    m.sensor("xm", x, resolution=1e-7)
    m.add(Sum("e", {"xr": 1.0, "xm": -1.0}), PID("u_pid", "e", Kp=800.0, Ki=2000.0, Kd=40.0, tau_d=2e-3),
          StateSpace(outputs=("u_ss",), inputs=("e",), A=[[0.5]], B=[[1.0]], C=[[2.0]], D=[[0.0]]),
          FrictionFeedforward("u_ff", "vr", fk.CoulombViscous(Fc=0.5, sigma2=0.1), scale=1.0),
          Sum("u_c", {"u_pid": 1.0, "u_ff": 1.0, "u_ss": 1.0}), Saturation("u", "u_c", -8.0, 8.0))
    m.actuator("motor", x, gain=1.0, limit=8.0, command="u")
    return m


def _edits():
    """In-place edits of a machine, through the API and around it; each changes its JSON form."""
    def replace_law(m):
        m.sites[0] = dataclasses.replace(m.sites[0], law=fk.Dahl(Fc=1.0, sigma0=1e5))

    def add_part(m):
        m.damper(m.coord("y"), c=2.0, name="extra")

    def remove_part(m):
        del m.sensors[0]

    def coord_coefficient(m):
        m.sites[1].at.dofs[1] = -2.0

    def sum_term(m):
        m.blocks[0].terms["xm"] = -2.0

    def array_entry(m):
        A = m.blocks[2].A
        A.setflags(write=True)
        A[0, 0] = 0.25

    def rename(m):
        m.name = "renamed"

    def new_list(m):
        m.blocks = m.blocks[:-1]

    def inertia_entry(m):
        m.inertias[0] = (m.inertias[0][0], 0.6)

    def schedule_coord(m):
        m.sites[2].schedule.at.dofs[0] = 3.0

    def dof_start(m):
        m.dofs[0] = dataclasses.replace(m.dofs[0], x0=1e-3)

    return {f.__name__: f for f in (replace_law, add_part, remove_part, coord_coefficient, sum_term, array_entry,
                                     rename, new_list, inertia_entry, schedule_coord, dof_start)}


def test_fingerprint_is_remembered_and_equals_the_json_form(monkeypatch):
    m = _machine()
    first = sim._fingerprint(m)
    assert first == sim._json_form(m)
    calls = []
    real = sim._json_form
    monkeypatch.setattr(sim, "_json_form", lambda mm: calls.append(1) or real(mm))
    assert [sim._fingerprint(m) for _ in range(3)] == [first] * 3
    assert calls == []  # from the memo
    other = _machine()  # an equal machine: its own memo, the same key (it shares the pack)
    assert sim._fingerprint(other) == first and calls == [1]


@pytest.mark.parametrize("edit", sorted(_edits()))
def test_an_edited_machine_never_meets_a_stale_fingerprint(edit):
    m = _machine()
    before = sim._fingerprint(m)
    _edits()[edit](m)
    fresh = sim._json_form(m)
    assert fresh != before  # the edit changes the machine's content ...
    assert sim._fingerprint(m) == fresh  # ... and the remembered key follows it


def test_a_machine_holding_an_unwatchable_part_is_fingerprinted_every_call(monkeypatch):
    @dataclasses.dataclass  # not frozen: its fields can change without the watch seeing it
    class Loose:
        v: float = 1.0

    m = _machine()
    m.note = Loose()
    calls = []
    monkeypatch.setattr(sim, "_json_form", lambda mm: calls.append(1) or "key")
    sim._fingerprint(m)
    sim._fingerprint(m)
    assert calls == [1, 1]


# --------------------------------------------------------------------------- ball-screw stage caches
def _stage_args():
    from frictionkit.reproduce.zhu_fujimoto import paper_controller, paper_plant, paper_sensors

    return paper_plant("sliding"), paper_controller(), paper_sensors()


def test_stage_machine_is_remembered_by_content_and_follows_every_edit():
    from frictionkit.presets import ballscrew as bsp

    plant, ctrl, sens = _stage_args()
    m1, _ = bsp._stage_machine(plant, ctrl, sens, None, None, None)
    again, _ = bsp._stage_machine(*_stage_args(), None, None, None)  # equal content, new objects
    assert again is m1
    gms = fk.GMS(fk.Stribeck(Fc=1270.0, Fs=1400.0, vs=1e-3), k=[5e7, 2e8], xi=[0.5, 0.5], C=20.0)
    edits = {
        "plant": (dataclasses.replace(plant, k_nut=0.9 * plant.k_nut), ctrl, sens, None),
        "controller": (plant, dataclasses.replace(ctrl, i_max=0.5 * ctrl.i_max), sens, None),
        "sensors": (plant, ctrl, dataclasses.replace(sens, scale_resolution=2e-7), None),
        "nut law": (plant, ctrl, sens, gms),
        "nut law edited": (plant, ctrl, sens, dataclasses.replace(gms, C=30.0)),
    }
    seen = {sim._json_form(m1)}
    for what, (p, c, s, law) in edits.items():
        m, beta = bsp._stage_machine(p, c, s, law, None, None)
        fresh = bsp.ballscrew_machine(p, c, s, nut_law=law)
        assert sim._json_form(m) == sim._json_form(fresh), what  # what a fresh build gives ...
        assert sim._json_form(m) not in seen, what  # ... and not an earlier entry
        seen.add(sim._json_form(m))
        assert beta == bsp.rayleigh_beta(p)


def test_feedforward_is_remembered_by_content_and_read_only():
    from frictionkit.control.trajectories import cosine_reference
    from frictionkit.presets import ballscrew as bsp

    _, ctrl, _ = _stage_args()
    ref = cosine_reference(duration=0.05)
    th, om = ref.x / ctrl.R, ref.v / ctrl.R
    u, d = bsp._feedforward(ctrl.ptc, th, om)
    u0, d0 = ctrl.ptc.feedforward(th, om)
    np.testing.assert_array_equal(u, u0)
    np.testing.assert_array_equal(d, d0)
    assert bsp._feedforward(ctrl.ptc, th.copy(), om.copy())[0] is u  # equal content: remembered
    with pytest.raises(ValueError):
        u[0] = 1.0  # the remembered arrays cannot be edited by a caller
    th2 = th.copy()
    th2[7] += 1e-9  # one sample of the reference edited
    np.testing.assert_array_equal(bsp._feedforward(ctrl.ptc, th2, om)[0], ctrl.ptc.feedforward(th2, om)[0])
    ptc2 = dataclasses.replace(ctrl.ptc, J=1.1 * ctrl.ptc.J)
    np.testing.assert_array_equal(bsp._feedforward(ptc2, th, om)[0], ptc2.feedforward(th, om)[0])
    assert not np.array_equal(bsp._feedforward(ptc2, th, om)[0], u)


def test_a_cached_stage_run_equals_a_run_from_scratch(monkeypatch):
    from frictionkit.control.trajectories import cosine_reference
    from frictionkit.presets import ballscrew as bsp
    from frictionkit.plants.ballscrew import RigidBallScrew

    _, ctrl, sens = _stage_args()
    ref = cosine_reference(duration=0.1)
    plant = RigidBallScrew()
    runs = [bsp.simulate_stage(plant, ctrl, ref, sensors=sens) for _ in range(2)]  # the second one cached
    monkeypatch.setattr(bsp, "_stage_machine", lambda p, c, s, n, g, f: (bsp.ballscrew_machine(p, c, s), 0.0))
    monkeypatch.setattr(bsp, "_feedforward", lambda ptc, a, b: ptc.feedforward(a, b))
    monkeypatch.setattr(sim, "_fingerprint", sim._json_form)
    sim._PACK_CACHE.clear()
    scratch = bsp.simulate_stage(plant, ctrl, ref, sensors=sens)
    for r in runs:
        for f in ("x_t", "theta_m", "x_t_meas", "theta_m_meas", "i", "friction"):
            np.testing.assert_array_equal(getattr(r, f), getattr(scratch, f), err_msg=f)


def test_result_time_axis_is_the_sample_index_times_dt():
    m = Machine("t")
    x = m.dof("x", inertia=1.0)
    m.friction("c", x, law=fk.CoulombViscous(Fc=1.0))
    m.actuator("u", x)
    dt = 0.1 + 1e-3  # not a power of two: every product is rounded
    r = fk.simulate_machine(m, dt=dt, inputs={"u": np.zeros(50_001)}, fast_path=False, substeps=1)
    assert np.array_equal(r.t, np.array([k * dt for k in range(50_001)]))
