"""Under pytest-xdist the 13-variant runs of each (nut model, stage) are computed once per
session, not once per worker: the first worker that needs them writes them to the session's
shared temporary directory under a file lock, the others read them (see ``_variants``)."""

from __future__ import annotations

import os

import pytest

from . import _variants


@pytest.fixture(scope="session", autouse=True)
def _share_variant_runs_between_workers(tmp_path_factory):
    if os.environ.get("PYTEST_XDIST_WORKER"):
        _variants.SHARED_DIR = tmp_path_factory.getbasetemp().parent / "zhu_fujimoto_variants"
        _variants.SHARED_DIR.mkdir(exist_ok=True)
    yield
    _variants.SHARED_DIR = None
