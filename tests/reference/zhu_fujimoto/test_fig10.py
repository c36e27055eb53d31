"""Seed 001 Fig. 10: l_d = Δx_t/Δθ_m stays at R through a slow deceleration and drops before
zero speed in a fast one. T_p = 10 ms; windows with |R Δθ_m| < 10 µm are not evaluated (the
paper: in slow motion l_d "cannot be calculated correctly" near zero speed).
"""

import pytest

from frictionkit.presets import zhu_fujimoto as zf

from ._variants import NUT_MODELS, scale_band, summaries

#: Resolution band of a slow-case window (>= 10 µm of motion): 3.2 %.
SLOW_BAND = scale_band(10e-6)
#: Resolution band of a fast-case window: the last one before zero speed still spans
#: a T_p^2 / 2 = 49 µm at the fast deceleration: 0.65 %.
FAST_BAND = scale_band(0.5 * zf.LD_FAST_DECEL * zf.LD_WINDOW**2)


@pytest.mark.parametrize("nut_model", NUT_MODELS)
@pytest.mark.parametrize("case", ["slow_reverse", "slow_non_reverse"])
def test_fig10_slow_deceleration_stays_near_R(case, nut_model):
    bad = {}
    for label, s in summaries(nut_model).items():
        lo, hi = s["ld"][case]["min_ratio_before_zero"], s["ld"][case]["max_ratio_before_zero"]
        if not (1 - SLOW_BAND <= lo and hi <= 1 + SLOW_BAND):
            bad[label] = (lo, hi)
    assert not bad, bad


@pytest.mark.xfail(strict=True, reason=(
    "Not reproduced as a drop with any nut model: in the fast deceleration the simulated l_d/R "
    "*rises* before zero speed (the table overruns the motor as the drive force turns into "
    "braking; every deformation released then moves the table ahead of the motor): seed 0 quick, "
    "fast reverse min 0.9965 / max 1.0113 (sliding), 0.9968 / 1.0113 (flank), 0.9965 / 1.0111 "
    "(hertz); all 13 variants min 0.9965-0.9980, max 1.0078-1.0175 (sliding), min 0.9964-0.9980, "
    "max 1.0078-1.0180 (flank), min 0.9965-0.9979, max 1.008-1.017 (hertz: |F_bn| <= 1.2 kN in these cases, the "
    "Hertz contact stays within 0.5 % of k_nut, no flank unloads). "
    "A drop needs min < 1 - 0.0065 (scale resolution band)."))
@pytest.mark.parametrize("nut_model", NUT_MODELS)
@pytest.mark.parametrize("case", ["fast_reverse", "fast_non_reverse"])
def test_fig10_fast_deceleration_drops_before_zero_speed(case, nut_model):
    bad = {}
    for label, s in summaries(nut_model).items():
        lo = s["ld"][case]["min_ratio_before_zero"]
        if not lo < 1 - FAST_BAND:
            bad[label] = lo
    assert not bad, bad
