"""Seed 002 (SDSS telescope): the quick reproduction of each axis, run once per session."""

from __future__ import annotations

import pytest

from frictionkit.reproduce import sdss as rep


@pytest.fixture(scope="session")
def azimuth():
    return rep.run_azimuth(quick=True, seed=0)


@pytest.fixture(scope="session")
def altitude():
    return rep.run_altitude(quick=True, seed=0)


@pytest.fixture(scope="session")
def rotator():
    return rep.run_rotator(quick=True, seed=0)
