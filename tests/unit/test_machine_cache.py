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
from frictionkit.machines import machine as mach
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
