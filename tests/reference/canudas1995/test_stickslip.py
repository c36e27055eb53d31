"""Stick-slip (Canudas de Wit et al. 1995): unit mass, 2 N/m spring pulled at 0.1 m/s, 20 s.

Run as the issue runs it (``python examples/canudas1995_stickslip.py --json OUT``), then checked
for what the paper shows — periodic stick phases, break-away with the friction near Fs — and
against the solve_ivp twin of the same machine.
"""

from __future__ import annotations

import json
import subprocess
import sys

import numpy as np
import pytest

from frictionkit.machines.reference import reference_machine

from .conftest import EXAMPLES

# the module-scoped fixtures below are costly: keep this module on one xdist worker so they are
# built once (`make test` runs --dist loadgroup; see tests/conftest.py for pytest 9)
pytestmark = pytest.mark.xdist_group("canudas1995_stickslip_trace")

DT = 1e-3


@pytest.fixture(scope="module")
def trace(tmp_path_factory):
    out = tmp_path_factory.mktemp("canudas") / "stickslip.json"
    proc = subprocess.run([sys.executable, str(EXAMPLES / "canudas1995_stickslip.py"), "--json", str(out)],
                          capture_output=True, text=True, timeout=300)
    assert proc.returncode == 0, proc.stderr
    data = json.loads(out.read_text())
    assert set(data) == {"t", "x", "friction"}
    return {k: np.asarray(v, dtype=float) for k, v in data.items()}


def test_json_covers_20_s_at_the_sample_rate(trace):
    assert trace["t"].size == trace["x"].size == trace["friction"].size == 20001
    assert trace["t"][0] == 0.0 and trace["t"][-1] == pytest.approx(20.0)


def test_stick_phases_are_periodic_and_break_away_near_Fs(trace, example):
    ex = example("canudas1995_stickslip")
    t, x, F = trace["t"], trace["x"], trace["friction"]
    phases = ex.stick_phases(t, x, DT)
    # measured: 0.00-7.44 s, 10.26-13.80 s, 16.63-20.00 s
    assert len(phases) >= 3
    ends = np.array([b for _, b in phases[:-1]])  # break-away instants
    stops = np.array([a for a, _ in phases[1:]])  # the mass sticks again
    period = np.diff(ends)  # measured 6.36 s
    assert 5.0 < period.mean() < 8.0 and np.all(np.abs(period - period.mean()) <= 0.01 * period.mean())
    slips = stops - ends  # measured 2.82 s each
    assert np.all(slips > 1.0) and np.ptp(slips) <= 0.02 * slips.mean()
    # while stuck, the spring force builds up to the break-away force: friction near Fs
    Fs, Fc = ex.LAW.static.Fs, ex.LAW.static.Fc
    for b in ends:
        k = int(round(b / DT))
        peak = F[max(k - 200, 0):k + 200].max()
        assert 0.97 * Fs <= peak <= 1.0 * Fs, peak  # measured 1.477 N = 0.984 Fs
    # and slides below it: the mean friction over a slip lies between Fc and Fs
    for b, a in zip(ends, stops):
        k0, k1 = int(round(b / DT)), int(round(a / DT))
        assert 0.95 * Fc < F[k0 + 200:k1 - 200].mean() < Fs


def test_stickslip_agrees_with_the_twin(trace, example):
    ex = example("canudas1995_stickslip")
    ref = reference_machine(ex.machine(), dt=DT, inputs=ex.inputs(20.0, DT))
    # measured at the default 10 sub-steps: 0.53 um (of a 1.27 m run), 2.5e-4 N; bound 3x
    assert np.abs(trace["x"] - ref.position("x")).max() <= 1.6e-6
    assert np.abs(trace["friction"] - ref.force("friction")).max() <= 7.6e-4
