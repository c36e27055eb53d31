"""Shared fixtures: the paper-like example parameters and the shared data folder."""

from __future__ import annotations

from pathlib import Path

import pytest

import frictionkit as fk

REPO = Path(__file__).resolve().parents[1]
SHARED_DATA = REPO.parent / "shared" / "data"


@pytest.fixture(scope="session")
def shared_data() -> Path:
    if not SHARED_DATA.is_dir():
        pytest.fail(f"real data folder not found at {SHARED_DATA}: CI must have ../shared beside the repo")
    return SHARED_DATA


@pytest.fixture(scope="session")
def law() -> fk.Stribeck:
    return fk.Stribeck(Fc=1.0, Fs=1.5, vs=1e-3, delta=2.0, sigma2=0.4)


@pytest.fixture(scope="session")
def lugre(law) -> fk.LuGre:
    return fk.LuGre(law, sigma0=1e5, sigma1=63.2)


@pytest.fixture(scope="session")
def gms(law) -> fk.GMS:
    return fk.GMS(law, k=[1e4, 1e5, 1e6], xi=[0.5, 0.3, 0.2], C=20.0)
