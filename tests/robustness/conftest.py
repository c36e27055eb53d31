"""Small recordings and a valid static-map JSON for the robustness tests (all written to tmp folders)."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest
from _robustness_helpers import DT, LAW, write_csv
from typer.testing import CliRunner

import frictionkit as fk
import frictionkit.cli.demo  # noqa: F401  (registers the verbs)
import frictionkit.cli.identify  # noqa: F401
import frictionkit.cli.reproduce  # noqa: F401


@pytest.fixture
def runner() -> CliRunner:
    return CliRunner()


@pytest.fixture(scope="session")
def staircase_csv(tmp_path_factory) -> Path:
    """Constant-velocity plateaus both ways, steady-state force of LAW plus a little noise."""
    rng = np.random.default_rng(0)
    speeds = np.geomspace(1e-3, 5e-2, 8)
    v = np.concatenate([np.full(150, s) for s in np.r_[speeds, -speeds]])
    F = LAW.steady_state(v) + 1e-3 * rng.standard_normal(v.size)
    t = np.arange(v.size) * DT
    return write_csv(tmp_path_factory.mktemp("stairs") / "stairs.csv", t_s=t, v_ms=v, F_N=F)


@pytest.fixture(scope="session")
def static_json(tmp_path_factory) -> Path:
    """A valid ``identify static --json`` file for LAW."""
    from frictionkit.identify import fit_static_map

    v = np.r_[np.geomspace(1e-4, 0.2, 12), -np.geomspace(1e-4, 0.2, 12)]
    res = fit_static_map(v, LAW.steady_state(v))
    return res.save_json(tmp_path_factory.mktemp("static") / "static.json")


@pytest.fixture(scope="session")
def gms_csv(tmp_path_factory) -> Path:
    x = np.r_[np.linspace(0, 50e-6, 501), np.linspace(50e-6, -50e-6, 1001)[1:]]
    t = np.arange(x.size) * DT
    F = fk.simulate(fk.GMS(LAW, k=[4e5, 1e5, 2e4], xi=[0.2, 0.3, 0.5], C=20.0), position=x, dt=DT).friction
    return write_csv(tmp_path_factory.mktemp("ps") / "gms.csv", t_s=t, x_m=x, F_N=F)

