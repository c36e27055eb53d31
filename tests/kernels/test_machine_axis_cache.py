"""The machine core's pack cache (issue 8, part B): repeated runs of one machine skip the
packing and exact discretisation, and an edited machine never meets a stale pack.

Every expected result here is a run of the same machine with the cache emptied first (the
packing from scratch, as before the cache existed), compared bit for bit.
"""

from __future__ import annotations

import dataclasses

import numpy as np
import pytest

import frictionkit as fk
from frictionkit.machines import PID, FrictionFeedforward, Machine, Saturation, Sum, simulate_machine
from frictionkit.machines import simulate as sim

DT = 1e-3
N = 300


def _machine() -> Machine:
    """A one-DOF position loop with every piece of state the kernel updates in place: a LuGre
    site (site state), a PID (block state), a TDMSSC feed-forward scheduled on a signal (block
    parameters rewritten per sample)."""
    m = Machine("cache probe")
    x = m.dof("x", inertia=2.0)
    m.friction("contact", x, law=fk.LuGre(fk.Stribeck(Fc=1.0, Fs=1.4, vs=0.01, sigma2=0.5), sigma0=1e5,
                                          sigma1=300.0))
    m.sensor("xm", x, resolution=1e-7)
    tdms = fk.TDMSSC(Fc0=0.8, Fc1=0.5, Fs0=1.1, Fs1=0.5, vs=0.01, sigma2=0.4)
    m.add(Sum("e", {"xr": 1.0, "xm": -1.0}), PID("u_pid", "e", Kp=800.0, Ki=2000.0, Kd=40.0, tau_d=2e-3),
          FrictionFeedforward("u_ff", "vr", tdms, scale=1.0, schedule="sched"),
          Sum("u_c", {"u_pid": 1.0, "u_ff": 1.0}), Saturation("u", "u_c", -8.0, 8.0))
    m.actuator("motor", x, gain=1.0, limit=8.0, command="u")
    return m


def _inputs():
    t = np.arange(N) * DT
    xr = 0.01 * (1.0 - np.cos(2 * np.pi * 2.0 * t))
    return {"xr": xr, "vr": np.gradient(xr, DT), "sched": 0.2 * np.sin(2 * np.pi * t)}


def _run(m, **kw):
    return simulate_machine(m, dt=DT, inputs=_inputs(), substeps=kw.pop("substeps", 4), **kw)


def _fresh(m, **kw):
    sim._PACK_CACHE.clear()
    return _run(m, **kw)


def _same(a, b):
    for f in ("q", "v", "site_forces", "signals", "u"):
        np.testing.assert_array_equal(getattr(a, f), getattr(b, f), err_msg=f)
    assert a.signal_names == b.signal_names and a.status == b.status


def test_repeated_runs_reuse_the_pack_and_equal_a_fresh_run(monkeypatch):
    m = _machine()
    ref = _fresh(m)
    assert ref.success, ref.message
    calls = []
    real = sim._pack
    monkeypatch.setattr(sim, "_pack", lambda *a: calls.append(1) or real(*a))
    again = [_run(m) for _ in range(3)]
    assert calls == []  # served from the cache: no packing
    for r in again:  # the kernel's in-place state (X, site, block states, scheduled levels) is not carried over
        _same(r, ref)
    _run(m, substeps=8)  # another sub-step count is another pack
    assert calls == [1]


def _edits():
    """In-place edits of a machine after a run; each must change the result."""
    def law(m):
        s = m.sites[0]
        m.sites[0] = dataclasses.replace(s, law=fk.LuGre(fk.Stribeck(Fc=1.5, Fs=1.4, vs=0.01, sigma2=0.5),
                                                           sigma0=1e5, sigma1=300.0))

    def gain(m):
        m.actuators[0] = dataclasses.replace(m.actuators[0], gain=0.7)

    def block(m):
        m.blocks[1] = PID("u_pid", "e", Kp=400.0, Ki=2000.0, Kd=40.0, tau_d=2e-3)

    def start(m):
        m.dofs[0] = dataclasses.replace(m.dofs[0], x0=1e-3)

    def inertia(m):
        m.inertia(m.coord("x"), 1.0)

    return {"law": law, "gain": gain, "block": block, "start": start, "inertia": inertia}


@pytest.mark.parametrize("edit", sorted(_edits()))
def test_an_edited_machine_never_reuses_a_stale_pack(edit):
    m = _machine()
    before = _fresh(m)
    _run(m)  # the pack is cached now
    _edits()[edit](m)
    after = _run(m)
    assert not np.array_equal(after.q, before.q)  # the edit matters ...
    _same(after, _fresh(m))  # ... and the cached path equals packing from scratch


def test_machine_without_json_form_is_packed_every_run(monkeypatch):
    m = _machine()
    monkeypatch.setattr(Machine, "to_dict", lambda self: {"f": object()})  # not JSON-serialisable
    calls = []
    real = sim._pack
    monkeypatch.setattr(sim, "_pack", lambda *a: calls.append(1) or real(*a))
    r1, r2 = _run(m), _run(m)
    assert len(calls) >= 2
    _same(r1, r2)


def test_a_failed_run_is_nan_after_it_stops():
    """The outputs are no longer pre-filled with NaN: the samples after a failure are set to NaN
    after the kernel returns, those before it keep their values."""
    m = Machine("blow-up")
    x = m.dof("x", inertia=1.0)
    m.friction("c", x, law=fk.CoulombViscous(Fc=1.0))
    m.actuator("u", x)
    u = np.r_[np.zeros(5), np.full(5, 1e308), np.zeros(10)]
    with pytest.warns(RuntimeWarning, match="non-finite"):
        r = simulate_machine(m, dt=1.0, inputs={"u": u})
    assert r.status == 1
    k = int(np.argmax(np.isnan(r.q[:, 0])))
    assert 5 < k < 20
    for a in (r.q, r.v, r.site_forces, r.signals, r.u):
        assert np.all(np.isnan(a[k:])) and np.all(np.isfinite(a[:k]))
