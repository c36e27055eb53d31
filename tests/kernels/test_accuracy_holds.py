"""Accuracy that holds (issue 15): the default tolerance on random legal parameter sets.

The error contract (README "Simulation", ``SimOptions``): with the default options, the
force-driven kernels keep max |dx| within ``MULT * rtol`` of the run's range of x and
max |dF| within ``MULT * rtol`` of the run's range of F, against the ``solve_ivp`` twin
(``reference_force_driven``, LSODA at rtol 1e-10), for any legal parameter set: sigma0 (or
the GMS stiffness sum) 1e3-1e8 N/m, sigma1 0-2x critical damping ``2 sqrt(sigma0 m)``, vs
1e-5-1e-2 m/s, masses 0.01-100 kg, inputs below (0.3-0.9 Fs) and above (1.2-2.5 Fs)
breakaway. ``simulate_batch`` (adaptive, all sets of a kind in one batch, so the batch's
shared tolerances are exercised) holds the same bound on its RMS error.

Runs are short (0.1 s of a 10 Hz sine at dt = 250 µs: 400 samples) so that the twin's
Python right-hand side stays affordable; the sets are the first ones drawn from a fixed
seed (not picked).
"""

from __future__ import annotations

import warnings

import numpy as np
import pytest

import frictionkit as fk
from frictionkit.simulation.reference import reference_force_driven

# the module-scoped fixtures below are costly: keep this module on one xdist worker so they are
# built once (`make test` runs --dist loadgroup; see tests/conftest.py for pytest 9)
pytestmark = pytest.mark.xdist_group("accuracy_holds_twins")

DT = 2.5e-4
DUR = 0.1
FREQ = 10.0
RTOL = fk.SimOptions().rtol
#: The stated multiple of rtol (README error contract).
MULT = 10.0
SEED = 7


def _draw(rng, kind):
    """One legal parameter set: (model, mass, input amplitude, above breakaway?)."""
    s0 = 10 ** rng.uniform(3, 8)
    m = 10 ** rng.uniform(-2, 2)
    vs = 10 ** rng.uniform(-5, -2)
    s1 = rng.uniform(0, 2) * 2 * np.sqrt(s0 * m)
    Fs = rng.uniform(1.0, 2.0)
    law = fk.Stribeck(Fc=1.0, Fs=Fs, vs=vs, sigma2=rng.uniform(0, 1))
    above = bool(rng.integers(2))
    A = (rng.uniform(1.2, 2.5) if above else rng.uniform(0.3, 0.9)) * Fs
    if kind == "lugre":
        model = fk.LuGre(law, sigma0=s0, sigma1=s1)
    elif kind == "dahl":
        model = fk.Dahl(Fc=1.0, sigma0=s0, sigma2=law.sigma2)
        A /= Fs  # Dahl's breakaway level is Fc
    else:
        model = fk.GMS(law, k=list(s0 * np.array([0.05, 0.15, 0.3, 0.5])), xi=[0.4, 0.3, 0.2, 0.1],
                       C=rng.uniform(5, 50))
    return model, m, A, above


N_SETS = {"lugre": 4, "dahl": 3, "gms": 3}


def _cases(kind):
    rng = np.random.default_rng(SEED)
    return [_draw(rng, kind) for _ in range(N_SETS[kind])]


T = np.arange(int(round(DUR / DT)) + 1) * DT


def _u(A):
    return A * np.sin(2 * np.pi * FREQ * T)


@pytest.fixture(scope="module")
def runs():
    """Per kind: list of (model, m, A, above, twin)."""
    out = {}
    for kind in N_SETS:
        rows = []
        for model, m, A, above in _cases(kind):
            ref = reference_force_driven(model, m, _u(A), DT, method="LSODA", rtol=1e-10, atol=1e-16)
            rows.append((model, m, A, above, ref))
        out[kind] = rows
    return out


def _rel(res_x, res_F, ref):
    return (float(np.abs(res_x - ref["x"]).max() / np.ptp(ref["x"])),
            float(np.abs(res_F - ref["friction"]).max() / np.ptp(ref["friction"])))


def _single_errors(rows):
    errs = []
    for model, m, A, above, ref in rows:
        with warnings.catch_warnings():
            warnings.simplefilter("error")  # a failed run must not pass silently
            res = fk.simulate(model, plant=fk.Mass(m), force=_u(A), dt=DT)
        assert res.success, res.message
        errs.append(_rel(res.x, res.friction, ref))
    return np.array(errs)


def test_draws_cover_the_legal_ranges():
    """The drawn sets span stiff and soft contacts, light and heavy masses, both input levels."""
    sets = [c for kind in N_SETS for c in _cases(kind)]
    masses = np.array([m for _, m, _, _ in sets])
    assert masses.min() < 0.05 and masses.max() > 30.0
    assert {above for *_, above in sets} == {True, False}


@pytest.mark.parametrize("kind", ["lugre", "dahl", "gms"])
def test_single_run_error_within_contract(runs, kind):
    """Dahl's set 1 (sigma0 9.7e6 N/m, 0.74 kg, 0.6 N: undamped pre-sliding ringing at 7 samples a
    period, a reversal every few samples) was 10.1x / 6.7x rtol (x / F range) with the ROS2 intervals
    at the plain tolerance; kernels.lugre.RING_FAST tightens them there (measured 4.4x / 2.9x)."""
    errs = _single_errors(runs[kind]) / RTOL
    print(kind, "max|dx|/range(x)/rtol, max|dF|/range(F)/rtol per set:", np.round(errs, 2).tolist())
    assert errs.max() <= MULT, errs


@pytest.mark.parametrize("kind", ["lugre", "dahl", "gms"])
def test_batch_rms_error_within_contract(runs, kind):
    """``simulate_batch`` on all sets of a kind at once: each set's RMS position error against its
    twin within ``MULT * rtol`` of its range of x (the batch reports error norms only)."""
    rows = runs[kind]
    models = [r[0] for r in rows]
    masses = np.array([r[1] for r in rows])
    rel = []
    for j, (model, m, A, above, ref) in enumerate(rows):
        # one shared input per batch: run the batch on set j's input, score set j
        res = fk.simulate_batch(models, masses=masses, force=_u(A), dt=DT, target=ref["x"], compare="x")
        assert res.status[j] == 0, res.message
        rel.append(float(res.rms[j] / np.ptp(ref["x"])))
    rel = np.array(rel) / RTOL
    print(kind, "batch rms|dx|/range(x)/rtol:", np.round(rel, 2).tolist())
    assert rel.max() <= MULT, rel
