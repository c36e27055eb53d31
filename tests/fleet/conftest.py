"""A small simulated fleet and a real two-worker Dask LocalCluster, shared by the fleet tests.

Every test of this folder is marked for the xdist group ``fleet`` (``make test`` runs
``pytest -n 2 --dist loadgroup``), so that the session fixtures below (the cluster, the
fleet and its two identification runs) are made once, not once per xdist worker. With
pytest 9.2 and pytest-xdist 3.8 the grouping needs the node-id hook in ``tests/conftest.py``
(xdist writes the group into ``item._nodeid``, which pytest 9 no longer reads).
"""

from __future__ import annotations

from pathlib import Path

import pytest

from frictionkit.fleet import identify_fleet, simulate_fleet


_HERE = Path(__file__).resolve().parent


@pytest.hookimpl(tryfirst=True)  # before xdist's own hook, which reads the group into the node id
def pytest_collection_modifyitems(config, items):
    for item in items:
        if _HERE in Path(str(item.path)).resolve().parents:
            item.add_marker(pytest.mark.xdist_group("fleet"))


@pytest.fixture(scope="session")
def small_fleet(tmp_path_factory):
    """4 axes x 3 days (2 drifting), 4 broken files (truncated, NaN burst, missing column, empty
    Parquet): 12 files, 8 good, CSV and Parquet axes."""
    root = tmp_path_factory.mktemp("fleet") / "small"
    return simulate_fleet(root, axes=4, days=3, seed=1, broken=4, drifting=0.5)


@pytest.fixture(scope="session")
def cluster():
    """A real LocalCluster: two single-threaded worker processes (no mocked scheduler)."""
    from dask.distributed import LocalCluster

    from frictionkit.fleet.identify import PIN_ENV

    import logging

    cl = LocalCluster(n_workers=2, threads_per_worker=1, processes=True, dashboard_address=":0",
                      silence_logs=logging.ERROR, env=dict(PIN_ENV))
    yield cl
    cl.close()


@pytest.fixture(scope="session")
def single_run(small_fleet, tmp_path_factory):
    out = tmp_path_factory.mktemp("single") / "results.parquet"
    return identify_fleet(small_fleet.root, out=out, scheduler="none", progress=False)


@pytest.fixture(scope="session")
def dask_run(small_fleet, cluster, tmp_path_factory):
    out = tmp_path_factory.mktemp("dask") / "results.parquet"
    return identify_fleet(small_fleet.root, out=out, scheduler=cluster.scheduler_address, progress=False)
