"""Segmentation on synthetic trajectories with known plateau boundaries."""

from __future__ import annotations

import numpy as np
import pytest

from frictionkit.data import (
    Recording,
    Segment,
    find_cycles,
    find_plateaus,
    find_reversals,
    steady_state_points,
)
from frictionkit.errors import DataError

DT = 1e-3


def _profile(levels, hold=400, ramp=40):
    """Piecewise-linear velocity: ramps of ``ramp`` samples between holds of ``hold`` samples."""
    v, bounds, cur = [], [], 0.0
    for lv in levels:
        v.append(np.linspace(cur, lv, ramp, endpoint=False))
        start = sum(map(len, v))
        v.append(np.full(hold, lv))
        bounds.append((start, start + hold))
        cur = lv
    v.append(np.linspace(cur, 0.0, ramp))
    return np.concatenate(v), bounds


def test_plateaus_found_in_both_directions_with_trimming():
    levels = [0.05, 0.1, -0.05, -0.2]
    v, bounds = _profile(levels)
    v = v + 1e-5 * np.random.default_rng(0).standard_normal(v.size)
    found = find_plateaus(v, DT, trim=0.1)
    assert [s.direction for s in found] == [1, 1, -1, -1]
    for s, (a, b), lv in zip(found, bounds, levels):
        assert a <= s.start and s.stop <= b  # inside the true hold
        assert len(s) >= 0.7 * (b - a)  # trimming takes 10 % per side plus the window edge
        assert np.mean(v[s.slice]) == pytest.approx(lv, rel=1e-3)
    untrimmed = find_plateaus(v, DT, trim=0.0)
    assert all(len(u) > len(t) for u, t in zip(untrimmed, found))


def test_slow_ramp_is_not_a_plateau():
    v = np.linspace(0.01, 1.0, 5000)  # 0.2 %/sample change passes the window test but drifts
    found = find_plateaus(v, DT, trim=0.0)
    for s in found:
        assert np.ptp(v[s.slice]) <= 0.05 * np.max(np.abs(v[s.slice]))


def test_min_duration_and_min_speed_override():
    v, _ = _profile([0.05, 0.0003], hold=400)
    assert len(find_plateaus(v, DT)) == 1  # 0.0003 is below the default min_speed (1 % of max)
    assert len(find_plateaus(v, DT, min_speed=0.0)) == 2
    assert len(find_plateaus(v, DT, min_duration=1.0)) == 0


def test_reversals_with_deadband():
    v = np.array([1.0, 0.5, 0.01, -0.01, 0.01, -0.5, -1.0, 0.3])
    assert find_reversals(v).tolist() == [3, 4, 5, 7]
    assert find_reversals(v, deadband=0.05).tolist() == [5, 7]


def test_presliding_cycles_selected_by_amplitude():
    t = np.arange(0, 6.0, DT)
    amp = np.where(t < 3.0, 2e-6, 50e-6)  # small (pre-sliding) then large strokes
    x = amp * np.sin(2 * np.pi * 1.0 * t)
    cycles = find_cycles(x, DT, max_amplitude=1e-5)
    assert len(cycles) >= 2
    assert all(c.amplitude == pytest.approx(4e-6, rel=0.01) for c in cycles)
    assert all(c.stop <= 3.0 / DT + 1 for c in cycles)
    assert len(find_cycles(x, DT)) > len(cycles)


def test_steady_state_points_from_recording_and_override():
    v, bounds = _profile([0.1, -0.1])
    F = np.where(v > 0, 2.0, -3.0) + 0.5 * v
    rec = Recording(t=np.arange(v.size) * DT, v=v, F=F)
    pts = steady_state_points(rec)
    assert pts.v.tolist() == pytest.approx([0.1, -0.1])
    assert pts.F.tolist() == pytest.approx([2.05, -3.05])
    manual = steady_state_points(rec, plateaus=[Segment(start=bounds[1][0], stop=bounds[1][1], direction=-1)])
    assert manual.n.tolist() == [400]
    assert manual.F.tolist() == pytest.approx([-3.05])


def test_steady_state_points_from_records_are_whole_record_means():
    rng = np.random.default_rng(1)
    recs = {}
    expect = []
    for k, lv in enumerate([0.5, -0.7]):
        vv = lv + 0.01 * rng.standard_normal(100)
        FF = 3 * lv + 0.1 * rng.standard_normal(100)
        recs[f"r{k}"] = Recording(t=np.arange(100) * 0.01, v=vv, F=FF)
        expect.append((vv.sum() / 100, FF.sum() / 100, np.sqrt(((FF - FF.sum() / 100) ** 2).sum() / 99)))
    pts = steady_state_points(recs)
    assert pts.labels == ("r0", "r1")
    for i, (vm, fm, fs) in enumerate(expect):
        assert pts.v[i] == pytest.approx(vm, rel=1e-12)
        assert pts.F[i] == pytest.approx(fm, rel=1e-12)
        assert pts.F_std[i] == pytest.approx(fs, rel=1e-12)
    assert steady_state_points(recs, trim=0.1).n.tolist() == [80, 80]
    assert pts.select(-1).labels == ("r1",)


def test_no_plateau_is_a_clear_error():
    t = np.arange(500) * DT
    rec = Recording(t=t, v=np.sin(2 * np.pi * 3 * t), F=np.zeros(500))
    with pytest.raises(DataError, match=r"no constant-velocity segment found"):
        steady_state_points(rec, rel_tol=1e-6, abs_tol=1e-9)
    with pytest.raises(DataError, match=r"needs velocity v or position x"):
        steady_state_points(Recording(t=t, F=np.zeros(500)))
