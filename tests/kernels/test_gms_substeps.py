"""Force-driven GMS runs: sub-step economy at reversals, the spans' pure-sliding loop and the
result's one allocation (issue 15, gms15).

* a reversal while elements slip: a trial step across it that the error control rejects lands
  at the reversal instead of marching to it by x0.2 rejections (2 s of the peers benchmark:
  GMS-4 836 -> 817, GMS-16 2414 -> 2209 sub-steps, abc898a -> now, same run), and the run against
  the ``solve_ivp`` twin;
* the pure-sliding loop of a span (past the Stribeck range) against the twin across SPAN_MAX
  samples and a reversal;
* the traces, element forces and stick flags of a run are views of one allocation (three blocks
  outgrew glibc's trim threshold together and were page-faulted anew on every run).
"""

from __future__ import annotations

import numpy as np
import pytest

import frictionkit as fk
from frictionkit.kernels import gms as kg
from frictionkit.simulation.inputs import example_gms, stick_slip_force
from frictionkit.simulation.reference import reference_force_driven

DT = 2.5e-4


@pytest.fixture(scope="module")
def stick_slip_2s():
    return stick_slip_force(duration=2.0, dt=DT)


def test_stick_slip_substeps_and_twin(stick_slip_2s):
    """2 s of the peers benchmark (benchmarks/peers.py, 1 kg, 2 sin(pi t) N, one reversal while every
    element slips): sub-steps GMS-4 836 -> 817, GMS-16 2414 -> 2209 (abc898a -> now); GMS-4 against
    the twin (LSODA, rtol 1e-11) within the README's stated default accuracy for this run (max |dx|
    0.22 um, max |dF| 7e-5 N of Fs 1.5 N; a 1e-4 N bound: 1.4 of it). Measured now 0.145 um,
    7.1e-5 N (abc898a 0.171 um, 6.8e-5 N)."""
    u = stick_slip_2s
    m4 = example_gms(4)
    r4 = fk.simulate(m4, plant=fk.Mass(1.0), force=u, dt=DT)
    r16 = fk.simulate(example_gms(16), plant=fk.Mass(1.0), force=u, dt=DT)
    assert r4.status == 0 and r16.status == 0
    assert r4.substeps <= 825, r4.substeps
    assert r16.substeps <= 2300, r16.substeps
    ref = reference_force_driven(m4, 1.0, u, DT, method="LSODA", rtol=1e-11, atol=1e-13)
    assert np.abs(r4.x - ref["x"]).max() <= 0.22e-6
    assert np.abs(r4.friction - ref["friction"]).max() <= 1e-4


def test_pure_sliding_loop_against_twin():
    """From rest under 3 N (breakaway, then sliding past the Stribeck range for more than SPAN_MAX
    samples), then -3 N (deceleration, a reversal, sliding back): the spans' pure-sliding loop and the
    samples where it hands over to the general loop, against the twin within the README's error
    contract (10 rtol of the ranges of x and of the friction)."""
    n = 3 * kg.SPAN_MAX
    u = np.concatenate([np.full(n, 3.0), np.full(n, -3.0)])
    model = example_gms(4)
    res = fk.simulate(model, plant=fk.Mass(1.0), force=u, dt=DT)
    assert res.status == 0
    assert res.substeps < 0.05 * u.size  # spans, not sub-steps
    assert res.v.max() > 100 * model.static.vs and res.v[-1] < 0.0  # slid past the Stribeck range, reversed
    ref = reference_force_driven(model, 1.0, u, DT, method="LSODA", rtol=1e-11, atol=1e-13)
    rtol = fk.SimOptions().rtol
    assert np.abs(res.x - ref["x"]).max() <= 10 * rtol * np.ptp(ref["x"])
    assert np.abs(res.friction - ref["friction"]).max() <= 10 * rtol * np.ptp(ref["friction"])


def _root(a):
    while a.base is not None:
        a = a.base
    return a


def test_gms_result_arrays_share_one_allocation():
    """t, x, v, the friction, the element forces and the stick flags of a force-driven GMS run are views
    of ONE block (simulation.core._gms_block), and the stick flags start cleared (the kernel writes
    them only where an element sticks)."""
    u = 2.0 * np.sin(np.pi * np.arange(2001) * DT)
    res = fk.simulate(example_gms(4), plant=fk.Mass(1.0), force=u, dt=DT)
    arrays = (res.t, res.x, res.v, res.friction, res.states["F_elements"], res.states["stick"])
    roots = {id(_root(a)) for a in arrays}
    assert len(roots) == 1
    st = res.states["stick"]
    assert st.dtype == np.bool_ and st.shape == (u.size, 4)
    assert st[0].all() and not st.all() and (~st).any(axis=1).any()  # sticks at rest, slips later
