"""Round 11 of benchmarks/robustness_lugre.py (issue 13, lug13): passed-WRONG patterns, one test each.

Reference values from the LSODA twin (``reference_force_driven``), never from the kernel under test.
"""
from __future__ import annotations

import numpy as np

import frictionkit as fk
from frictionkit.kernels.lugre import lugre_force
from frictionkit.models.pack import pack_lugre
from frictionkit.simulation.reference import reference_force_driven

# part a seed 519: an overdamped LuGre (damping ratio 1.35, m/c 0.17 ms) sampled at dt = 36 ms
LAW = fk.LuGre(fk.Stribeck(Fc=0.263941938785639, Fs=0.3301994017176323, vs=7.420436535750385e-05,
                           sigma2=1.8636005858424185), sigma0=36307.415660004415, sigma1=43.101697995550886)
M, DT = 0.007618741701639506, 0.03577583199441593


def test_a_force_applied_at_once_from_rest_is_not_spanned():
    """A staircase whose first level is on at t = 0: the bristles settle within the first millisecond
    of the first sample and slip on the way. The spanning step, linearised at rest (dz/dt = v), saw a
    spring settling without slip, and its error estimate (the remainder at three nodes, all after the
    transient) passed it at every rtol: x[1] was 5.03e-6 m (no slip) against the twin's 8.56e-6 m,
    3e-5 of the run's range at rtol 1e-5 ... 1.3e-8 (2,360 rtol). Now an ROS2 interval covers it."""
    u = np.full(4, 0.18256890482897667)
    tw = reference_force_driven(LAW, M, u, DT, rtol=1e-12, atol=1e-16, max_step=1e-5)
    pk = pack_lugre(LAW)
    x, v, F, z = (np.zeros(u.size) for _ in range(4))
    rtol = 1e-6
    # v_floor given as simulate() gives it: an omitted default is another numba specialisation, compiled
    # afresh in every test worker (16 s CPU, 70 s wall in a loaded clean-clone run)
    st, _, _ = lugre_force(u, DT, M, pk.static, pk.dyn, 0.0, 0.0, 0.0, rtol, 1e-9, 1e-11, 100_000, x, v, F, z, 1.0)
    assert st == 0
    assert abs(x[1] - tw["x"][1]) <= 10 * rtol * abs(tw["x"][1])
    # simulate() with its default tolerances: right or flagged, never a wrong status 0
    res = fk.simulate(LAW, plant=fk.Mass(M), force=u, dt=DT, options=fk.SimOptions(rtol=rtol))
    assert res.status != 0 or abs(res.x[1] - tw["x"][1]) <= 10 * rtol * abs(tw["x"][1])


def test_a_run_from_rest_under_no_force_keeps_its_spanning_steps():
    """The guard takes only an unbalanced force at exact rest: the README's sine from u(0) = 0 spans
    as before (a handful of steps for 1,000 samples) and stays within 10 rtol of the twin."""
    law = fk.LuGre(fk.Stribeck(Fc=1.0, Fs=1.5, vs=1e-3, delta=2.0, sigma2=0.4), sigma0=1e5, sigma1=63.2)
    dt = 2.5e-4
    u = 2.0 * np.sin(np.pi * np.arange(1001) * dt)
    res = fk.simulate(law, plant=fk.Mass(1.0), force=u, dt=dt)
    tw = reference_force_driven(law, 1.0, u, dt, rtol=1e-11, atol=1e-16, max_step=dt / 4)
    assert res.status == 0 and res.substeps < 200
    assert np.max(np.abs(res.x - tw["x"])) <= 10 * 1e-5 * np.ptp(tw["x"])
