"""The vectorised fixed-step LuGre batch kernel (``frictionkit.kernels.batch``).

The twin is the project's scalar adaptive kernel ``lugre.lugre_force_batch_sse``
run with tolerances so loose (1e300) that every error test passes: it then takes
exactly one ROS2 step per sample interval. Feeding it the input resampled at
``dt / n_sub`` (exact: the input is linear inside each interval) with zero weight
on the inserted samples gives, set by set and with plain scalar code, the same
scheme the batch kernel runs in SIMD lanes.
"""

from __future__ import annotations

import math

import numpy as np
import pytest

import frictionkit as fk
from frictionkit.errors import ParameterError
from frictionkit.kernels import batch as kb
from frictionkit.kernels import lugre as kl
from frictionkit.models.pack import pack_lugre
from frictionkit.simulation.inputs import stick_slip_force

# one worker: the parallel (prange, simd) fixed-step kernel otherwise compiles on both xdist
# workers at once (~80 s each in a clean clone)
pytestmark = pytest.mark.xdist_group("batch_kernel")

DT = 2.5e-4
LOOSE = 1e300


def _law(**kw):
    base = dict(Fc=1.0, Fs=1.5, vs=1e-3, delta=2.0, sigma2=0.4)
    base.update(kw)
    return fk.Stribeck(**base)


def _mixed_models(rng, P):
    """P sets: the first CHUNK symmetric delta-2 (fast path), then a mixture of
    symmetric, directional, other exponents, Lorentzian shape and Dahl."""
    out = []
    for j in range(P):
        s0 = rng.uniform(5e4, 2e5)
        s1 = rng.uniform(20.0, 100.0)
        Fs = rng.uniform(1.2, 1.8)
        kind = 0 if j < kb.CHUNK else j % 5
        if kind == 0:
            out.append(fk.LuGre(_law(Fs=Fs), sigma0=s0, sigma1=s1))
        elif kind == 1:
            pos = fk.LuGre(_law(Fs=Fs), sigma0=s0, sigma1=s1)
            neg = fk.LuGre(_law(Fc=0.8, Fs=1.3, vs=2e-3), sigma0=0.7 * s0, sigma1=1.3 * s1)
            out.append(fk.Directional(positive=pos, negative=neg))
        elif kind == 2:
            out.append(fk.LuGre(_law(Fs=Fs, delta=rng.choice([1.0, 0.7, 1.6])), sigma0=s0, sigma1=s1))
        elif kind == 3:
            out.append(fk.LuGre(_law(Fs=Fs, shape="lorentzian"), sigma0=s0, sigma1=s1))
        else:
            out.append(fk.Dahl(Fc=1.0, sigma0=s0, sigma2=0.4))
    return out


def _pack(models):
    packs = [pack_lugre(m) for m in models]
    return np.stack([p.static for p in packs]), np.stack([p.dyn for p in packs])


def _twin(u, m, static, dyn, n_sub, target, which, weight):
    """Scalar per-set reference: one loose-tolerance adaptive step per sub-step."""
    N = u.size
    Nf = (N - 1) * n_sub + 1
    s = np.arange(Nf) / n_sub
    uf = np.interp(s, np.arange(N), u)
    tf = np.zeros(Nf)
    wf = np.zeros(Nf)
    tf[::n_sub] = target
    wf[::n_sub] = weight
    P = m.size
    sse = np.empty(P)
    st = np.empty(P, dtype=np.int64)
    kl.lugre_force_batch_sse(uf, DT / n_sub, m, static, dyn, LOOSE, LOOSE, LOOSE, 10, tf, which, wf, sse, st)
    return sse, st


def _fixed(u, m, static, dyn, n_sub, target, which, weight):
    P = m.size
    sse = np.empty(P)
    st = np.empty(P, dtype=np.int64)
    kb.lugre_fixed_batch_sse(u, DT, m, static, dyn, n_sub, target, which, weight,
                             kb.chunk_modes(static, dyn), sse, st)
    return sse, st


@pytest.fixture(scope="module")
def run():
    u = stick_slip_force(duration=1.5, dt=DT, amplitude=2.0, frequency=1.0)
    rng = np.random.default_rng(7)
    P = kb.CHUNK + 13  # two chunks, the second one partial
    models = _mixed_models(rng, P)
    static, dyn = _pack(models)
    m = rng.uniform(0.5, 2.0, P)
    ref = fk.simulate(_mixed_models(np.random.default_rng(7), 1)[0], plant=fk.Mass(1.0), force=u, dt=DT)
    weight = rng.uniform(0.0, 2.0, u.size)
    weight[rng.random(u.size) < 0.2] = 0.0
    return dict(u=u, models=models, static=static, dyn=dyn, m=m, ref=ref, weight=weight)


def test_chunk_modes(run):
    modes = kb.chunk_modes(run["static"], run["dyn"])
    assert modes.tolist() == [kb.MODE_SYM, kb.MODE_GENERAL]
    d = [fk.Directional(positive=fk.LuGre(_law(), sigma0=1e5, sigma1=50.0),
                        negative=fk.LuGre(_law(Fc=0.9), sigma0=1e5, sigma1=50.0))]
    assert kb.chunk_modes(*_pack(d)).tolist() == [kb.MODE_DIR]


@pytest.mark.parametrize("n_sub", [1, 2, 3])
@pytest.mark.parametrize("compare", ["x", "v", "F"])
def test_equals_scalar_twin(run, n_sub, compare):
    which = {"x": 0, "v": 1, "F": 2}[compare]
    target = getattr(run["ref"], {"F": "friction"}.get(compare, compare))
    args = (run["u"], run["m"], run["static"], run["dyn"], n_sub, target, which, run["weight"])
    sse, st = _fixed(*args)
    sse_t, st_t = _twin(*args)
    assert (st == 0).all() and (st_t == 0).all()
    assert np.all(sse > 0.0)
    np.testing.assert_allclose(sse, sse_t, rtol=1e-10, atol=0.0)


def test_directional_fast_path_equals_twin(run):
    """Directional and symmetric delta-2 sets mixed in one chunk take MODE_DIR (vectorised selects)."""
    rng = np.random.default_rng(3)
    models = []
    for j in range(9):
        pos = fk.LuGre(_law(Fs=rng.uniform(1.2, 1.8)), sigma0=rng.uniform(5e4, 2e5), sigma1=rng.uniform(20, 100))
        neg = fk.LuGre(_law(Fc=0.8, Fs=1.3, vs=2e-3), sigma0=rng.uniform(5e4, 2e5), sigma1=rng.uniform(20, 100))
        models.append(pos if j % 3 == 0 else fk.Directional(positive=pos, negative=neg))
    static, dyn = _pack(models)
    assert kb.chunk_modes(static, dyn).tolist() == [kb.MODE_DIR]
    m = np.ones(9)
    args = (run["u"], m, static, dyn, 2, run["ref"].v, 1, run["weight"])
    np.testing.assert_allclose(_fixed(*args)[0], _twin(*args)[0], rtol=1e-10, atol=0.0)


@pytest.mark.parametrize("P", [1, kb.CHUNK, kb.CHUNK + 1])
def test_chunk_boundaries_do_not_matter(run, P):
    """Each set's result is independent of P and of its position in a chunk."""
    idx = np.arange(P) % run["m"].size
    sl = lambda a: np.ascontiguousarray(a[idx])  # noqa: E731
    args = (run["u"], sl(run["m"]), sl(run["static"]), sl(run["dyn"]), 2, run["ref"].x, 0, run["weight"])
    sse, st = _fixed(*args)
    full, _ = _fixed(run["u"], run["m"], run["static"], run["dyn"], 2, run["ref"].x, 0, run["weight"])
    assert (st == 0).all()
    np.testing.assert_array_equal(sse, full[idx])


def test_nonfinite_set_flagged_others_untouched(run):
    static = run["static"].copy()
    dyn = run["dyn"].copy()
    bad = [3, kb.CHUNK + 2]
    static[bad[0], :, 2] = 0.0  # vs = 0: 0 * inf at rest -> NaN
    static[bad[1], :, 1] = np.nan  # Fs = NaN: g is NaN at rest
    args = (run["u"], run["m"], static, dyn, 2, run["ref"].v, 1, run["weight"])
    sse, st = _fixed(*args)
    good, _ = _fixed(run["u"], run["m"], run["static"], run["dyn"], 2, run["ref"].v, 1, run["weight"])
    assert st[bad].tolist() == [kb.NONFINITE] * 2
    assert np.isinf(sse[bad]).all()
    keep = np.setdiff1d(np.arange(sse.size), bad)
    assert (st[keep] == 0).all()
    np.testing.assert_array_equal(sse[keep], good[keep])


def test_simulate_batch_fixed_and_accuracy(run, lugre):
    """Through the public API; the fixed scheme converges in second order to a tight adaptive run."""
    u = run["u"]
    tight = fk.SimOptions(rtol=1e-9, atol_v=1e-12, atol_F=1e-10)
    ref = fk.simulate(lugre, plant=fk.Mass(1.0), force=u, dt=DT, options=tight)
    out = {}
    for n in (1, 2, 4):
        br = fk.simulate_batch([lugre], masses=1.0, force=u, dt=DT, target=ref.x, compare="x",
                               method="fixed", options=fk.SimOptions(batch_substeps=n))
        assert br.status.tolist() == [0]
        out[n] = float(br.rms[0])
    # measured: 5.2, 1.4, 0.36 µm rms
    assert out[1] < 1e-5
    assert out[1] / out[2] > 3.0 and out[2] / out[4] > 3.0
    own = fk.simulate(lugre, plant=fk.Mass(1.0), force=u, dt=DT)
    ad = fk.simulate_batch([lugre], masses=1.0, force=u, dt=DT, target=own.x, compare="x")
    assert ad.sse[0] == 0.0  # the default (adaptive) batch is simulate() itself


def test_vexp_within_2_ulp():
    x = np.concatenate([-np.random.default_rng(0).uniform(0.0, 708.0, 20000), -np.linspace(0.0, 2.0, 20001)])
    got = np.array([kb._vexp(v) for v in x])  # jitted scalar call path, every value built above
    ref = np.exp(x)
    assert np.all(np.abs(got - ref) <= 2 * np.spacing(ref))
    assert kb._vexp(0.0) == 1.0
    assert math.isclose(kb._vexp(-700.0), math.exp(-700.0), rel_tol=1e-15)


def test_bad_inputs_raise(run, lugre, gms):
    u = run["u"]
    y = np.zeros(u.size)
    with pytest.raises(ParameterError, match="method"):
        fk.simulate_batch([lugre], masses=1.0, force=u, dt=DT, target=y, method="rk4")
    with pytest.raises(ParameterError, match="LuGre and Dahl only"):
        fk.simulate_batch([gms], masses=1.0, force=u, dt=DT, target=y, method="fixed")
    for bad in (0, -1, 2.5, True, 10_000):
        with pytest.raises(ParameterError, match="batch_substeps"):
            fk.SimOptions(batch_substeps=bad)
    with pytest.raises(ParameterError, match="masses"):
        fk.simulate_batch([lugre], masses=0.0, force=u, dt=DT, target=y, method="fixed")


def test_batch_of_stiff_bristles_keeps_each_set_as_simulate_runs_it():
    """One set with sigma0 = 1e300 made every set of the batch fail (tolerances shared over the
    sets); now each set runs with its own tolerances: the 1e5 set's SSE is simulate()'s, the
    stiff sets are flagged and the message names sigma0. (Moved from test_lugre_expo.py: its
    method="fixed" run compiles this module's parallel kernel, 54 s CPU, which the other xdist
    worker compiled a second time.)"""
    dt = 1e-3
    u = 2.0 * np.sin(np.pi * np.arange(600) * dt)  # 0.6 s: breakaway at 0.27 s, peak speed at 0.5 s
    law = fk.Stribeck(Fc=1.0, Fs=1.5, vs=1e-3, delta=2.0, sigma2=0.4)
    models = [fk.LuGre(law, sigma0=s, sigma1=63.2) for s in (1e5, 1e30, 1e300)]
    target = np.zeros(u.size)
    res = fk.simulate_batch(models, masses=1.0, force=u, dt=dt, target=target, compare="x")
    alone = fk.simulate(models[0], plant=fk.Mass(1.0), force=u, dt=dt)
    assert res.status[0] == 0 and res.sse[0] == pytest.approx(float((alone.x[1:] ** 2).sum()), rel=1e-12)
    assert (res.status[1:] != 0).all() and np.isinf(res.sse[1:]).all()
    assert "sigma0 = 1e+30 N/m" in res.message
    fixed = fk.simulate_batch(models, masses=1.0, force=u, dt=dt, target=target, method="fixed")
    assert (fixed.status[1:] != 0).all()  # no error control there: flagged as too coarse (status 4)
