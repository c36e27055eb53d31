"""Seed 001 Fig. 10: l_d = Δx_t/Δθ_m through slow and fast decelerations, both stages.

T_p = 10 ms; windows with |R Δθ_m| < 10 µm are not evaluated (the paper: in slow motion l_d
"cannot be calculated correctly" near zero speed). The measured l_d uses the scale and the
encoder (as the paper); the "true" one the simulated positions (the model's privilege).

What the paper and the physics agree on, tested as such:

* slow deceleration: l_d stays at R ("the nominal value of l_d remains constant"; Pattern I
  does not change, so the chain's deflection does not change either);
* fast deceleration: l_d departs from R before zero speed (the deformation changes from
  Pattern I to II while the stage still moves). Its sign: the drive force turns into braking
  while the stage moves forward, so the chain's deflection ``δ = R θ_m - x_t`` falls and
  ``l_d = R - dδ/dθ_m`` *rises* — the table runs ahead of the motor, the "overrun of the
  stage" §4 names. That is what the runs show.

The paper's word for the fast case, "l_d gradually reduced", is the last test: a strict xfail.
"""

import pytest

from frictionkit.presets import zhu_fujimoto as zf

from ._variants import NUT_MODELS, STAGES, numbers, scale_band, span, values

nut_models = pytest.mark.parametrize("nut_model", NUT_MODELS)
stages = pytest.mark.parametrize("stage", STAGES)

#: Resolution band of a slow-case window (>= 10 µm of motion): 3.2 %.
SLOW_BAND = scale_band(10e-6)
#: Resolution band of a fast-case window: the last one before zero speed still spans
#: a T_p^2 / 2 = 49 µm at the fast deceleration: 0.65 %.
FAST_BAND = scale_band(0.5 * zf.LD_FAST_DECEL * zf.LD_WINDOW**2)


def _ld(nut_model, stage, case, key):
    return values(nut_model, stage, lambda s: s["ld"][case][key])


@stages
@nut_models
@pytest.mark.parametrize("case", ["slow_reverse", "slow_non_reverse"])
def test_fig10_slow_deceleration_stays_near_R(case, nut_model, stage):
    """Measured l_d/R within the resolution band (0.989-1.014, both stages); the true l_d/R
    within 0.4 % below and 0.8 % above R (checked with 0.5 % and 0.9 %)."""
    lo = _ld(nut_model, stage, case, "min_ratio_before_zero")
    hi = _ld(nut_model, stage, case, "max_ratio_before_zero")
    bad = {k: (lo[k], hi[k]) for k in lo if not (1 - SLOW_BAND <= lo[k] and hi[k] <= 1 + SLOW_BAND)}
    assert not bad, bad
    tlo = span(_ld(nut_model, stage, case, "true_min_ratio_before_zero"))
    thi = span(_ld(nut_model, stage, case, "true_max_ratio_before_zero"))
    assert 0.995 <= tlo[0] and thi[1] <= 1.009, (tlo, thi)


@stages
@nut_models
@pytest.mark.parametrize("case", ["fast_reverse", "fast_non_reverse"])
def test_fig10_fast_deceleration_l_d_rises_before_zero_speed(case, nut_model, stage):
    """l_d/R rises above R by more than the scale's resolution band before zero speed and does
    not fall below it: measured max 1.008-1.017 (table1) / 1.009-1.014 (fig2), min >= 0.9964;
    the true rise is 1.3-3.2x the slow case's in every variant."""
    hi = _ld(nut_model, stage, case, "max_ratio_before_zero")
    lo = _ld(nut_model, stage, case, "min_ratio_before_zero")
    bad = {k: (lo[k], hi[k]) for k in hi if not (hi[k] > 1 + FAST_BAND and lo[k] > 1 - FAST_BAND)}
    assert not bad, bad
    slow = _ld(nut_model, stage, case.replace("fast", "slow"), "true_max_ratio_before_zero")
    fast = _ld(nut_model, stage, case, "true_max_ratio_before_zero")
    ratio = {k: (fast[k] - 1) / (slow[k] - 1) for k in fast}
    assert span(ratio)[0] > 1.2, ratio


@pytest.mark.xfail(strict=True, raises=AssertionError, reason=(
    "Not reproduced as a drop on either stage with any nut model: in the fast deceleration the "
    "simulated l_d/R *rises* before zero speed (the table overruns the motor as the drive force "
    "turns into braking). Quick, 13 variants: table1 min 0.9964-0.9980, max 1.008-1.017; fig2 "
    "min 0.9971-0.9976, max 1.009-1.014 (seed 0 fast reverse: table1 0.9965 / 1.0113, fig2 "
    "0.9974 / 1.0122). A drop needs min < 1 - 0.0065 (scale resolution band)."))
@stages
@nut_models
@pytest.mark.parametrize("case", ["fast_reverse", "fast_non_reverse"])
def test_fig10_fast_deceleration_drops_before_zero_speed(case, nut_model, stage):
    lo = _ld(nut_model, stage, case, "min_ratio_before_zero")
    numbers(0.996 < span(lo)[0], f"min l_d/R {span(lo)}")
    bad = {k: v for k, v in lo.items() if not v < 1 - FAST_BAND}
    assert not bad, bad
