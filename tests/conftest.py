"""Shared fixtures: the paper-like example parameters and the shared data folder."""

from __future__ import annotations

import os
from pathlib import Path

import pytest

import frictionkit as fk

REPO = Path(__file__).resolve().parents[1]
SHARED_DATA = REPO.parent / "shared" / "data"


@pytest.hookimpl(wrapper=True)
def pytest_collection_modifyitems(config, items):
    """Make ``xdist_group`` work under pytest 9 (``make test`` runs ``--dist loadgroup``).

    On each worker pytest-xdist 3.8 tags a grouped item by writing ``<nodeid>@<group>``
    into ``item._nodeid``; pytest 9 builds ``item.nodeid`` from ``item._id`` and never
    reads ``_nodeid``, so the controller saw no group and spread a group's tests (and
    their session/module fixtures: solve_ivp twins, Dask clusters) over both workers.
    After every other implementation has run (this is a wrapper), copy the tag into
    ``_id``. A no-op without xdist, without ``--dist loadgroup`` and on pytest < 9.
    Test-only hook: remove once pytest-xdist supports pytest 9's node ids.
    """
    result = yield
    try:
        from _pytest.nodeid import NodeId
    except ImportError:  # pytest < 9 reads _nodeid itself
        return result
    for item in items:
        tagged = item.__dict__.get("_nodeid")
        if isinstance(tagged, str) and tagged != item.nodeid:
            try:
                item._id = NodeId.parse(tagged)
            except Exception:  # private API moved: lose the grouping (slower), never the run
                return result
    return result


def pytest_sessionstart(session):
    """xdist controller only: compile the kernels both workers need once, before they start.

    In a clean clone (CI) two workers reaching the same ``cache=True`` kernel together both
    compile it (measured: ``machine.run`` 51 + 54 s CPU, ``lugre_force`` 40 + 38 s). The jobs of
    tests/_warm_kernels.py run here in up to 2 processes; the workers then load the kernels from
    numba's cache. Runs before xdist starts the workers (xdist's own hook is ``trylast``).
    ``FRICTIONKIT_TEST_WARMUP=0`` skips it; a failing or stuck warm-up never fails the run.
    """
    config = session.config
    try:
        n = int(getattr(config.option, "numprocesses", 0) or 0)
    except (TypeError, ValueError):  # "auto"/"logical" not resolved yet
        n = 2
    if n < 2 or hasattr(config, "workerinput") or os.environ.get("FRICTIONKIT_TEST_WARMUP") == "0":
        return
    import importlib.util
    import subprocess
    import sys
    import time

    script = Path(__file__).with_name("_warm_kernels.py")
    spec = importlib.util.spec_from_file_location("_warm_kernels", script)
    warm = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(warm)
    t0 = time.perf_counter()
    procs = [subprocess.Popen([sys.executable, str(script), *jobs], stdout=subprocess.DEVNULL,
                              stderr=subprocess.PIPE, text=True) for jobs in warm.split(list(warm.WEIGHTS), min(n, 2))]
    lines = []
    for p in procs:
        try:
            lines += p.communicate(timeout=900)[1].splitlines()
        except subprocess.TimeoutExpired:
            p.kill()
            lines.append(f"warm-up process {p.args[2:]} stopped after 900 s (tests will compile the rest)")
    tw = config.get_terminal_writer()
    tw.line(f"numba warm-up (tests/_warm_kernels.py): {time.perf_counter() - t0:.0f} s; " + "; ".join(lines))


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
