"""fit_output_error on several recordings at once (seed 002 §3.1: σ0, σ1 from "sine and
triangle torques of different amplitudes"), each recording simulated from rest."""

from __future__ import annotations

import numpy as np
import pytest

import frictionkit as fk
from frictionkit.errors import DataError
from frictionkit.identify.output_error import fit_output_error

TRUE = fk.LuGre(fk.Stribeck(Fc=1.0, Fs=1.5, vs=1e-3, sigma2=0.4), sigma0=1e5, sigma1=63.2)
DT = 1e-3


def _run(u, t0=0.0, dt=DT):
    t = np.arange(u.size) * dt
    sim = fk.simulate(TRUE, plant=fk.Mass(1.0), force=u, dt=dt)
    return {"t": t + t0, "F": u, "v": sim.v}


@pytest.fixture(scope="module")
def runs():
    t = np.arange(2001) * DT
    ts = np.arange(1501) * DT                                    # ends while sliding (sin(1.5 pi) = -1)
    sine = _run(2.0 * np.sin(np.pi * ts))                                           # above breakaway
    tri = _run(1.0 * (2 / np.pi) * np.arcsin(np.sin(2 * np.pi * t)), t0=7.0)      # below, own time axis
    return sine, tri


def test_joint_fit_recovers_truth_and_restarts_each_record_from_rest(runs):
    sine, tri = runs
    start = fk.LuGre(TRUE.static, sigma0=3e4, sigma1=100.0)
    res = fit_output_error([sine, tri], start, inertia=1.0)
    assert res["sigma0"] == pytest.approx(1e5, rel=1e-3)
    assert res["sigma1"] == pytest.approx(63.2, rel=1e-2)
    # every sample but the first of each record counts
    assert res.n_obs == sine["t"].size - 1 + tri["t"].size - 1
    # the prediction of the second record starts from rest, not from the first record's end state
    y_pred = res.data["y_pred"]
    assert y_pred[sine["t"].size] == pytest.approx(0.0, abs=1e-12)
    assert abs(y_pred[sine["t"].size - 1]) > 1e-3


def test_joint_fit_checks_its_records(runs):
    sine, tri = runs
    start = fk.LuGre(TRUE.static, sigma0=3e4, sigma1=100.0)
    # a record at another sample period is simulated at its own period (issue 11: was refused)
    coarse = _run(2.0 * np.sin(np.pi * np.arange(751) * 2 * DT), dt=2 * DT)
    res = fit_output_error([tri, coarse], start, inertia=1.0)
    assert [s["dt"] for s in res.diagnostics["segments"].values()] == pytest.approx([DT, 2 * DT])
    assert res["sigma0"] == pytest.approx(1e5, rel=1e-3)
    with pytest.raises(DataError, match="2 recordings but 1 external_load"):
        fit_output_error([sine, tri], start, inertia=1.0, external_load=[np.zeros(sine["t"].size)])
