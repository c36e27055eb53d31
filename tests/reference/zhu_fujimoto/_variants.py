"""Shared, cached robustness runs for the seed 001 reference tests (quick settings).

Two stages (``presets.zhu_fujimoto.STAGES``): ``"table1"`` (Table 1 inertias as printed) and
``"fig2"`` (the default: inertia calibrated to the measured response, eq. 1 / Fig. 2).
13 variants per stage and nut model (``"sliding"``, the original; ``"flank"``, the load
transfer between groove flanks; ``"hertz"``, the flank friction on a preloaded Hertzian ball
contact): noise seeds 0, 1, 2 on the preset plant, and every assumed stiffness of
``presets.zhu_fujimoto.ASSUMED_STIFFNESSES`` scaled by 0.7 and 1.3 (seed 0).

A claim that fails on a stage is a strict ``xfail(raises=AssertionError)``; the numbers its
reason states are checked first with :func:`numbers`, which fails the test outright (not an
``AssertionError``), so the xfail cannot hide a drift of those numbers.
"""

from __future__ import annotations

import functools

import pytest

from frictionkit.presets import zhu_fujimoto as zf
from frictionkit.reproduce import zhu_fujimoto as rep

NUT_MODELS = zf.NUT_MODELS
STAGES = zf.STAGES


#: Set by ``conftest.py`` under pytest-xdist: a directory shared by the workers of the session.
SHARED_DIR = None


def _compute(nut_model: str, stage: str) -> dict:
    return rep.robustness(quick=True, seeds=(0, 1, 2), factors=(0.7, 1.3), nut_model=nut_model, stage=stage)


@functools.lru_cache(maxsize=len(NUT_MODELS) * len(STAGES))
def summaries(nut_model: str = "sliding", stage: str = zf.STAGE) -> dict:
    if SHARED_DIR is None:
        return _compute(nut_model, stage)
    import fcntl
    import json

    path = SHARED_DIR / f"{nut_model}-{stage}.json"
    with open(SHARED_DIR / f"{nut_model}-{stage}.lock", "w") as lock:
        fcntl.flock(lock, fcntl.LOCK_EX)
        if path.exists():
            return json.loads(path.read_text())
        out = _compute(nut_model, stage)
        tmp = path.with_suffix(".tmp")
        tmp.write_text(json.dumps(out))
        tmp.replace(path)
        return out


def values(nut_model: str, stage: str, get) -> dict:
    """``label -> get(summary)`` over the 13 variants."""
    return {k: get(s) for k, s in summaries(nut_model, stage).items()}


def span(d: dict) -> tuple:
    """``(min, max)`` of the values of ``d``."""
    v = list(d.values())
    return min(v), max(v)


def numbers(ok: bool, what: str) -> None:
    """Guard of the numbers an xfail reason states: a plain test failure if they drifted."""
    if not ok:
        pytest.fail(f"the numbers this xfail documents changed: {what}", pytrace=False)


def scale_band(min_displacement: float) -> float:
    """Worst-case relative error of one ``l_d`` window from the linear scale: two readings,
    each off by one resolution step plus 3 noise sigmas, over ``min_displacement``."""
    return 2.0 * (zf.SCALE_RESOLUTION + 3.0 * zf.SCALE_NOISE) / min_displacement
