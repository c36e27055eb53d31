"""A small simulated fleet and a real two-worker Dask LocalCluster, shared by the fleet tests."""

from __future__ import annotations

import pytest

from frictionkit.fleet import identify_fleet, simulate_fleet


@pytest.fixture(scope="session")
def small_fleet(tmp_path_factory):
    """6 axes x 3 days, 4 broken files (truncated, NaN burst, missing column, empty)."""
    root = tmp_path_factory.mktemp("fleet") / "small"
    return simulate_fleet(root, axes=6, days=3, seed=1, broken=4)


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
