"""Seed 001 Fig. 5 and the deformation patterns of §3.2, from runs of both stages.

* Fig. 5(b) / §3.2: in a fast deceleration the drive force — and the control input the figure
  shows — "changed its direction before the velocity comes to zero-speed point" (Pattern II);
  Fig. 5(a): after a slow deceleration it "does not change its direction" (Pattern I).
* Fig. 5 / §2.3: with the conventional compensation (sinc, from the reverse point, Fig. 13) the
  performance "is remarkably degraded in fast reverse motion" (max error in
  ``ZERO_SPEED_WINDOW`` = [t0 - 40 ms, t0 + 45 ms]: the Fig. 10 references' acceleration
  corners, 50.7 ms from zero speed in the fast case, ring by ~2.5 µm in both cases and are left
  out).

Fig. 5(b) is checked on the §5 reversal (the paper's one stated fast reverse motion, the
Table 3 run with the sinc law); the slow/fast comparison on the Fig. 10 references (same
cruise speed 50 mm/s and re-acceleration, deceleration 1/20 of or equal to the §5 peak).
"Before zero speed" means at least :data:`MIN_LEAD_MS` before the zero-speed instant: a sign
change in the last sample or two is the zero-speed point itself.
"""

import pytest

from ._variants import NUT_MODELS, STAGES, numbers, span, values

nut_models = pytest.mark.parametrize("nut_model", NUT_MODELS)
stages = pytest.mark.parametrize("stage", STAGES)

#: A reversal counts as "before zero speed" from 5 ms (10 control periods) on.
MIN_LEAD_MS = 5.0

FIG5B_TABLE1 = pytest.mark.xfail(strict=True, raises=AssertionError, reason=(
    "table1 stage: in the §5 fast reversal the motor input keeps the direction of motion until "
    "zero speed (no sign change in 38 of 39 runs, 0.5 ms before zero speed in one hertz variant), "
    "although the drive force F_bn turns 16-17.5 ms before: with Table 1's 4.3e-3 kg·m² the "
    "braking torque at the reversal, J a / R = 2.2 N·m, stays below the 2.43 N·m of friction the "
    "motor must overcome until the stage stops. The fig2 stage (J = 0.01 of the measured "
    "response: 5.2 N·m) reverses 53-55 ms before zero speed."))


@pytest.mark.parametrize("stage", [pytest.param("table1", marks=FIG5B_TABLE1), "fig2"])
@nut_models
def test_fig5b_motor_input_reverses_before_zero_speed_in_the_fast_reversal(nut_model, stage):
    """fig2 stage: the motor current turns to braking 53-55.5 ms before zero speed (13 variants,
    every nut model; seed 0: 55 ms sliding/flank, 53.5 ms hertz); F_bn 16.5-17 ms before."""
    lead = values(nut_model, stage, lambda s: s["fig5b"]["motor_input_reverses_before_zero_ms"])
    fbn = values(nut_model, stage, lambda s: s["fig5b"]["drive_force_reverses_before_zero_ms"])
    numbers(all(v is not None and 15.0 < v < 19.0 for v in fbn.values()), f"F_bn leads {fbn}")
    if stage == "table1":
        numbers(all(v is None or v < 1.0 for v in lead.values()), f"motor-input leads {lead}")
    bad = {k: v for k, v in lead.items() if v is None or not v >= MIN_LEAD_MS}
    assert not bad, bad
    lo, hi = span(lead)
    assert 50.0 <= lo and hi <= 58.0, (lo, hi)


@stages
@nut_models
def test_fig5_pattern_i_slow_deceleration_keeps_input_and_drive_force_direction(nut_model, stage):
    """Fig. 5(a) / §3.2: after the slow deceleration neither the motor input nor F_bn changes
    direction before zero speed (Pattern I), in every variant of both stages."""
    got = values(nut_model, stage, lambda s: (s["fig5"]["slow_reverse"]["motor_input_reverses_before_zero_ms"],
                                              s["fig5"]["slow_reverse"]["drive_force_reverses_before_zero_ms"]))
    bad = {k: v for k, v in got.items() if v != (None, None)}
    assert not bad, bad


@stages
@nut_models
def test_fig5_pattern_ii_fast_deceleration_reverses_the_drive_force(nut_model, stage):
    """§3.2: after the fast deceleration F_bn changes direction before zero speed (Pattern II):
    10-18 ms before (table1), 16-17.5 ms (fig2)."""
    got = values(nut_model, stage, lambda s: s["fig5"]["fast_reverse"]["drive_force_reverses_before_zero_ms"])
    bad = {k: v for k, v in got.items() if v is None or not v >= MIN_LEAD_MS}
    assert not bad, bad


FIG5_DEGRADED_FIG2 = pytest.mark.xfail(strict=True, raises=AssertionError, reason=(
    "fig2 stage, every nut model: with the conventional sinc compensation the error at the fast "
    "reversal is *smaller* than at the slow one. Quick, seed 0: slow 3.10 / fast 2.38 µm; 13 "
    "variants: fast - slow -1.07 to -0.59 µm (slow 2.80-3.76, fast 2.11-2.88). The table1 stage "
    "shows the degradation (+1.09 to +1.70 µm)."))


@pytest.mark.parametrize("stage", ["table1", pytest.param("fig2", marks=FIG5_DEGRADED_FIG2)])
@nut_models
def test_fig5_conventional_compensation_degraded_in_the_fast_reversal(nut_model, stage):
    """table1 stage, every nut model: max error in [t0 - 40 ms, t0 + 45 ms] (the reversal, not
    the reference's acceleration corners 50.7 ms away) slow 1.12 / fast 2.58 µm at seed 0;
    13 variants: slow 1.02-1.60, fast 2.38-3.08, fast - slow +1.09 to +1.70 µm. A degradation
    needs fast > slow + 0.1 µm (one scale count) in every variant."""
    got = values(nut_model, stage, lambda s: (s["fig5"]["slow_reverse"]["max_error_um"],
                                              s["fig5"]["fast_reverse"]["max_error_um"]))
    diff = {k: f - s for k, (s, f) in got.items()}
    lo, hi = span(diff)
    if stage == "fig2":
        numbers(-1.15 < lo and hi < -0.5, f"fast - slow {lo:.2f} to {hi:.2f} µm")
    bad = {k: v for k, v in got.items() if not v[1] > v[0] + 0.1}
    assert not bad, bad
    assert 1.0 < lo and hi < 1.8, (lo, hi)
