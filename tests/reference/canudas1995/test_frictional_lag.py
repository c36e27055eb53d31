"""Frictional lag (Canudas de Wit et al. 1995): friction against velocity under velocity
oscillations of 1, 10 and 25 rad/s — a hysteresis loop that widens with the frequency."""

from __future__ import annotations

import json

import numpy as np

import frictionkit as fk


def test_loop_widens_with_frequency(tmp_path, example):
    ex = example("canudas1995_lag")
    out = tmp_path / "lag.json"
    ex.main(["--json", str(out)])
    d = json.loads(out.read_text())
    assert d["omega"] == [1.0, 10.0, 25.0]
    area, width = np.array(d["area"]), np.array(d["width"])
    # measured: areas 1.07e-5, 8.74e-5, 1.40e-4 N m/s; widest gaps 0.014, 0.105, 0.147 N
    assert np.all(np.diff(area) > 0) and np.all(np.diff(width) > 0)
    assert width[0] < 0.03 and width[-1] > 0.1
    for v, F in zip(d["v"], d["friction"]):
        v, F = np.asarray(v), np.asarray(F)
        assert v.min() > 0.0  # always sliding forward, through the Stribeck region
        assert np.all((F > 0.99 * ex.LAW.static.Fc) & (F < ex.LAW.static.Fs))
        # the period starts at the mean velocity, rising; half a period later it is falling:
        # friction is larger while the velocity rises (it lags behind the falling Stribeck curve)
        assert F[0] > F[F.size // 2]


def test_stiff_coupling_reproduces_the_prescribed_velocity_loop(example):
    """The slider follows the prescribed motion closely enough: its loop equals the one of the
    single-axis motion-driven kernel (friction on the prescribed position itself)."""
    ex = example("canudas1995_lag")
    w = 10.0
    lp = ex.loop(w)
    n, per = 6000, 2000
    dt = 2 * np.pi / w / per
    t = np.arange(n + 1) * dt
    s = fk.simulate(ex.LAW, position=ex.position(t, w), dt=dt)
    # measured 2.1e-6 N
    assert np.abs(lp["friction"] - s.friction[n - per:n + 1]).max() < 2e-5
