"""Seed 002 (SDSS telescope): the quick reproduction of each axis, run once per session."""

from __future__ import annotations

from pathlib import Path

import pytest

from frictionkit.reproduce import sdss as rep

_HERE = Path(__file__).resolve().parent
_AXES = {"azimuth", "altitude", "rotator"}


@pytest.hookimpl(tryfirst=True)  # before xdist's own hook, which reads the group into the node id
def pytest_collection_modifyitems(config, items):
    """Tests using an axis run share one xdist worker (``make test``: ``--dist loadgroup``), so
    each session fixture below runs once, not once per worker."""
    for item in items:
        if _HERE in Path(str(item.path)).resolve().parents and _AXES & set(getattr(item, "fixturenames", ())):
            item.add_marker(pytest.mark.xdist_group("sdss_axes"))


@pytest.fixture(scope="session")
def azimuth():
    return rep.run_azimuth(quick=True, seed=0)


@pytest.fixture(scope="session")
def altitude():
    return rep.run_altitude(quick=True, seed=0)


@pytest.fixture(scope="session")
def rotator():
    return rep.run_rotator(quick=True, seed=0)
