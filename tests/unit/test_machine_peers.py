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
