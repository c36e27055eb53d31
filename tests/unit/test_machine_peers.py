"""Smoke test of the EMPS peer of benchmarks/machine_peers.py (issue 8): the loop written without
frictionkit (numba controller, numbalsoda LSODA plant with located stops) simulates the same machine
as the EMPS preset. Skipped without numbalsoda (the ``bench`` extra)."""

from __future__ import annotations

import os
import sys

import numpy as np
import pytest

pytest.importorskip("numbalsoda")
sys.path.insert(0, os.path.join(os.path.dirname(__file__), "..", "..", "benchmarks"))
import machine_peers  # noqa: E402


def test_emps_peer_is_the_preset_machine():
    """A 1 mm step and a ramp back (0.6 s, stops and a reversal): the peer at rtol 1e-10 and the
    preset's run (one-DOF fast path) agree far below the 50 nm encoder count; a loose peer
    (rtol 1e-4) does not, so the comparison can fail."""
    t = np.arange(600) * 1e-3
    qg = np.where(t < 0.01, 0.0, 1e-3) - np.clip(t - 0.3, 0.0, None) * 5e-3
    core, peer = machine_peers.emps_setup(np.ascontiguousarray(qg))
    q_fk = core(40)().position("q")
    d_tight = np.abs(peer(1e-10)() - q_fk).max()
    d_loose = np.abs(peer(1e-4)() - q_fk).max()
    assert d_tight < 1e-10, d_tight
    assert d_loose > 10 * d_tight, (d_loose, d_tight)


def test_two_shaft_peer_is_the_machine(monkeypatch):
    """The two-shaft drive (benchmarks/machines.py: GMS-3 at four sites with Stribeck exponents
    1, 3, 1.5 and 2, two PIDs at 250 us), 0.25 s from rest with ideal sensors (both shafts break
    away and the nut ramps up): the peer at rtol 1e-10 agrees with frictionkit at 10 sub-steps to
    within frictionkit's own error there (7.8e-11 m against the peer at rtol 1e-11 over 10 s,
    benchmark), far below the 10 nm scale count (measured 7.6e-11 m); a loose peer (rtol 1e-3,
    measured 1.0e-9 m) and the peer with every exponent read as 2 (the switch tests this peer
    replaced; measured 1.6e-8 m) do not."""
    core, peer, _, pos = machine_peers.two_shaft_setup(0.25, sensors=False)
    x_fk = pos(core(10)())
    d_tight = np.abs(peer(1e-10)() - x_fk).max()
    d_loose = np.abs(peer(1e-3)() - x_fk).max()
    assert peer.switches[-1] > 0  # element breakaways were located
    assert d_tight < 2e-10, d_tight
    assert d_loose > 5 * d_tight, (d_loose, d_tight)
    block = machine_peers.gms_block

    def delta_2(law):
        b = block(law)
        b[3] = 2.0
        return b
    monkeypatch.setattr(machine_peers, "gms_block", delta_2)
    _, peer2, _, _ = machine_peers.two_shaft_setup(0.25, sensors=False)
    d_delta2 = np.abs(peer2(1e-10)() - x_fk).max()
    assert d_delta2 > 5 * d_tight, (d_delta2, d_tight)
