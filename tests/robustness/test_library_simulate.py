"""Issue 13, library side of simulation: no silent wrong answer, every error names its argument.

* the adaptive kernels flag an error control that cannot meet its tolerance (status 3)
  instead of accepting unchecked sub-steps;
* a very small mass keeps its accuracy against the ``solve_ivp`` twin;
* booleans are not numbers for parameter objects and ``dt``;
* ``simulate_batch`` names its bad arguments (``models``, ``masses``, ``weight``);
* ``reference_force_driven`` reports a solver failure as ``SimulationError`` even when
  the solver fails before its first output point.
"""

from __future__ import annotations

import importlib
import warnings

import numpy as np
import pytest
from _robustness_helpers import LAW

import frictionkit as fk
from frictionkit.errors import DataError, ParameterError, SimulationError

DT = 2.5e-4
T = np.arange(401) * DT
U = 2.0 * np.sin(np.pi * T)  # N; the README's input, 0.1 s of it
LUGRE = fk.LuGre(LAW, sigma0=1e5, sigma1=63.2)
GMS = fk.GMS(LAW, k=[1e4, 1e5, 1e6], xi=[0.5, 0.3, 0.2], C=20.0)


def _quiet_simulate(*args, **kwargs):
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", RuntimeWarning)
        return fk.simulate(*args, **kwargs)


# ------------------------------------------------------------------ error control flag
def test_lugre_on_a_nanogram_is_flagged_not_silently_wrong():
    # The campaign's case: u = 2 N on Mass(1e-9) returned status 0 with a peak friction
    # of 9.1e4 N (the force never exceeds 2 N, so |F| <= ~2 N in any honest answer).
    with pytest.warns(RuntimeWarning, match="error control failed"):
        res = fk.simulate(LUGRE, plant=fk.Mass(1e-9), force=2.0 * np.sin(np.pi * np.arange(4001) * DT), dt=DT)
    assert res.status == 3 and not res.success
    assert "step-size underflow" in res.message
    assert res.failed_at is not None and np.isnan(res.x[res.failed_at + 1:]).all()
    # the samples before the failing interval are still plausible (|u| <= 2 N)
    assert np.abs(res.friction[: res.failed_at]).max() < 2.5


def test_status_3_is_in_the_kernel_contract():
    from frictionkit.kernels import gms as kg
    from frictionkit.kernels import lugre as kl

    assert kl.TOLERANCE == kg.TOLERANCE == 3
    assert kl.H_MIN == kg.H_MIN == 1e-7


@pytest.mark.parametrize("m", [1e-7, 1e-5])
def test_small_mass_matches_the_solve_ivp_twin(m):
    """Before the atol_v cap the LuGre on 1e-7 kg ended 1.1e-2 m (1 %) away from the twin."""
    from frictionkit.simulation.reference import reference_force_driven

    u = 2.0 * np.sin(np.pi * np.arange(1201) * DT)
    ref = reference_force_driven(LUGRE, m, u, DT, rtol=1e-8, atol=1e-11)
    res = _quiet_simulate(LUGRE, plant=fk.Mass(m), force=u, dt=DT)
    k = None
    if m == 1e-5:
        # flagged since the accuracy check bounds the friction at the error contract (core.CHECK_BOUND 5,
        # was 1000 for the friction; 2026-11-24): the unchecked run's friction is 8.9e-4 of its range off
        # the twin at sample 868 (89 rtol; the contract is 10), x within 2.1e-6
        assert res.status == 2 and res.failed_at >= 800, (res.status, res.failed_at)
        k = res.failed_at + 1
    else:
        assert res.status == 0
    err = np.abs(res.x[:k] - ref["x"][:k]).max()
    stroke = np.abs(ref["x"]).max()
    assert err < 1e-4 * stroke, (err, stroke)


# ------------------------------------------------------------------ booleans
@pytest.mark.parametrize(
    "make, name",
    [
        (lambda: fk.Stribeck(Fc=True, Fs=1.5, vs=1e-3), "Stribeck.Fc"),
        (lambda: fk.CoulombViscous(Fc=1.0, sigma2=False), "CoulombViscous.sigma2"),
        (lambda: fk.LuGre(LAW, sigma0=1e5, sigma1=True), "LuGre.sigma1"),
        (lambda: fk.GMS(LAW, k=[1e4, True], xi=[0.5, 0.5], C=20.0), "GMS.k"),
        (lambda: fk.Mass(True), "Mass.m"),
        (lambda: fk.SimOptions(max_substeps=True), "SimOptions.max_substeps"),
        (lambda: fk.simulate(LUGRE, dt=True, position=[0.0, 1e-6]), "simulate.dt"),
    ],
)
def test_booleans_are_not_numbers(make, name):
    with pytest.raises(ParameterError, match=name.replace(".", r"\.")):
        make()


def test_boolean_signal_is_refused():
    with pytest.raises(DataError, match="force.*booleans"):
        fk.simulate(LUGRE, plant=fk.Mass(1.0), force=np.array([True, False, True]), dt=DT)


# ------------------------------------------------------------------ simulate_batch arguments
@pytest.mark.parametrize(
    "kwargs, exc, match",
    [
        (dict(models=None), ParameterError, "models = None"),
        (dict(models=LUGRE), ParameterError, "models = LuGre.*list"),
        (dict(models=[LUGRE, LAW]), ParameterError, r"models\[1\]"),
        (dict(masses=None), ParameterError, "masses = None"),
        (dict(masses=[1.0, 2.0, 3.0]), ParameterError, "masses has 3 entries for 2 models"),
        (dict(masses="heavy"), ParameterError, "masses"),
        (dict(masses=[1.0, -1.0]), ParameterError, r"masses\[1\]"),
        (dict(masses=True), ParameterError, "masses"),
        (dict(weight=np.zeros(U.size)), DataError, "every weight after sample 0 is 0"),
        (dict(weight=np.r_[1.0, -np.ones(U.size - 1)]), DataError, r"weight\[1\]"),
        (dict(weight=np.ones(3)), DataError, "weight has 3 samples"),
    ],
)
def test_simulate_batch_names_the_bad_argument(kwargs, exc, match):
    args = dict(models=[LUGRE, LUGRE], masses=1.0, force=U, dt=DT, target=np.zeros(U.size))
    args.update(kwargs)
    with pytest.raises(exc, match=match):
        fk.simulate_batch(**args)


def test_simulate_batch_reports_failed_sets():
    # one healthy set, one on a nanogram that the error control cannot follow
    u = 2.0 * np.sin(np.pi * np.arange(4001) * DT)
    res = fk.simulate_batch(
        [LUGRE, LUGRE], masses=[1.0, 1e-9], force=u, dt=DT, target=np.zeros(u.size), compare="v"
    )
    assert res.status.tolist() == [0, 3]
    assert np.isfinite(res.sse[0]) and res.sse[1] == np.inf
    assert "1 of 2 parameter sets failed" in res.message and "status 3" in res.message
    assert "set 0" in res.summary()


# ------------------------------------------------------------------ reference twin failure path
def test_reference_failure_before_first_output_is_a_simulation_error(monkeypatch):
    """scipy leaves ``sol.t`` a list when it fails before its first t_eval point; this used
    to raise AttributeError ('list' object has no attribute 'size') on the failure path."""
    from scipy.integrate._ivp.ivp import OdeResult

    ref = importlib.import_module("frictionkit.simulation.reference")  # fk.simulate is the function

    def failing(*args, **kwargs):
        return OdeResult(t=[], y=np.empty((3, 0)), status=-1, nfev=1,
                         message="Required step size is less than spacing between numbers.")

    monkeypatch.setattr(ref, "solve_ivp", failing)
    with pytest.raises(SimulationError, match="solve_ivp failed after t = 0 s: Required step size"):
        ref.reference_force_driven(LUGRE, 1.0, U, DT)


@pytest.mark.xdist_group("batch_kernel")  # method='fixed' compiles kernels.batch's parallel kernel: once, with test_batch.py
def test_fixed_batch_method_flags_steps_too_coarse_for_the_mass():
    """method='fixed' has no error control: on the README LuGre at 4 kHz with 2 sub-steps the
    RMS position error against the twin was 24 % of the stroke on 10 g (h*(sigma1+sigma2)/m =
    0.8) and 0.14 % on 30 g (0.27); sets beyond FIXED_STEP_LIMIT = 0.5 now carry status 4. (40 g, not
    30 g, below: 30 g is omega·h 0.23, beyond FIXED_RING_LIMITS_ABOVE's 0.2 at its damping ratio 0.58.)"""
    from importlib import import_module

    FIXED_STEP_LIMIT = import_module("frictionkit.simulation.core").FIXED_STEP_LIMIT
    assert FIXED_STEP_LIMIT == 0.5
    u = 2.0 * np.sin(np.pi * np.arange(1201) * DT)
    res = fk.simulate_batch([LUGRE] * 3, masses=[1.0, 0.04, 0.01], force=u, dt=DT, target=np.zeros(u.size),
                            method="fixed")
    assert res.status.tolist() == [0, 0, 4]
    assert np.isfinite(res.sse[:2]).all() and res.sse[2] == np.inf
    assert "status 4 (fixed step too coarse)" in res.message
