"""Shared, cached robustness runs for the seed 001 reference tests (quick settings).

13 variants per nut model (``"sliding"``, the original; ``"flank"``, the load transfer
between groove flanks; ``"hertz"``, the flank friction on a preloaded Hertzian ball contact):
noise seeds 0, 1, 2 on the preset plant, and every
assumed stiffness of ``presets.zhu_fujimoto.ASSUMED_STIFFNESSES`` scaled by 0.7 and 1.3
(seed 0).
"""

from __future__ import annotations

import functools

from frictionkit.presets import zhu_fujimoto as zf
from frictionkit.reproduce import zhu_fujimoto as rep


NUT_MODELS = zf.NUT_MODELS


@functools.lru_cache(maxsize=len(NUT_MODELS))
def summaries(nut_model: str = "sliding") -> dict:
    return rep.robustness(quick=True, seeds=(0, 1, 2), factors=(0.7, 1.3), nut_model=nut_model)


def scale_band(min_displacement: float) -> float:
    """Worst-case relative error of one ``l_d`` window from the linear scale: two readings,
    each off by one resolution step plus 3 noise sigmas, over ``min_displacement``."""
    return 2.0 * (zf.SCALE_RESOLUTION + 3.0 * zf.SCALE_NOISE) / min_displacement
