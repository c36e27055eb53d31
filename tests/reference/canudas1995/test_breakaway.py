"""Break-away force rising with the force rate (Canudas de Wit et al. 1995)."""

from __future__ import annotations

import json

import numpy as np

from frictionkit.machines.reference import reference_machine


def test_breakaway_force_rises_with_the_rate(tmp_path, example):
    ex = example("canudas1995_breakaway")
    out = tmp_path / "breakaway.json"
    ex.main(["--json", str(out)])
    d = json.loads(out.read_text())
    rate, fb = np.array(d["rate"]), np.array(d["breakaway"])
    assert rate.tolist() == [0.1, 1.0, 3.0, 10.0, 30.0, 100.0]
    Fs = ex.LAW.static.Fs
    # measured: 1.4955, 1.4932, 1.5165, 1.6582, 2.1180, 3.4537 N
    assert abs(fb[0] - Fs) < 0.01 * Fs  # quasi-static: Fs
    assert np.all(np.diff(fb[1:]) > 0)  # from 1 N/s on it rises with the rate
    assert fb[-1] > 2.0 * Fs


def test_breakaway_agrees_with_the_twin(example):
    ex = example("canudas1995_breakaway")
    rate = 10.0
    samples = 8000
    dt = 4.0 * ex.LAW.static.Fs / rate / samples
    t = np.arange(samples + 1) * dt
    ref = reference_machine(ex.machine(), dt=dt, inputs={"u": rate * t})
    k = int(np.flatnonzero(ref.position("x") > ex.X_BREAK)[0])
    fb, _ = ex.breakaway(rate, samples)
    assert abs(fb - rate * t[k]) <= rate * dt  # the same sample (measured: identical)
