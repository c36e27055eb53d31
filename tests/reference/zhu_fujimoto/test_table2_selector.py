"""Seed 001 Table 2, both stages.

* The selector applies sinc after slow decelerations and the sigmoid before zero speed after
  fast ones, and should beat any single fixed compensator on a trajectory that mixes slow and
  fast reversals (max reversal error).
* Fast non-reverse: "redesign of trajectory reference is necessary". The redesign run here
  (``reproduce.zhu_fujimoto.redesigned_non_reverse_reference``): decelerate fast while eq. 2
  keeps the drive force in the direction of motion, then at half the guide friction's rate, so
  zero speed is reached in Pattern I (slow non-reverse, Pattern I -> I) — against the original
  fast stop (Pattern II -> I), both with the ``hold`` compensation.
"""

import pytest

from ._variants import NUT_MODELS, STAGES, numbers, span, summaries, values

nut_models = pytest.mark.parametrize("nut_model", NUT_MODELS)
stages = pytest.mark.parametrize("stage", STAGES)


@stages
@nut_models
def test_table2_selector_picks_sinc_for_slow_and_sigmoid_for_fast(nut_model, stage):
    for label, s in summaries(nut_model, stage).items():
        sel = s["selector"]
        assert sel["kinds"] == ["slow_reverse", "fast_reverse"], label
        assert sel["laws"] == ["sinc", "sigmoid"], label


@pytest.mark.xfail(strict=True, raises=AssertionError, reason=(
    "Not reproduced on either stage with any nut model. table1: the selector's sigmoid at the fast "
    "reversal is worse than sinc (Table 3 order not reproduced): seed 0 selector 3.12 vs best fixed "
    "(sinc) 2.80 µm; 13 variants 2.81-3.62 vs 2.80-3.05 µm, the selector wins in none. fig2: the "
    "mixed run's fast reversals are trapezoidal and there sinc stays better: seed 0 2.56 vs 2.46 µm; "
    "13 variants 2.36-3.06 vs 2.26-2.96 µm, the selector wins in 1 of 13."))
@stages
@nut_models
def test_table2_selector_beats_every_fixed_compensator(nut_model, stage):
    got = values(nut_model, stage, lambda s: (s["selector"]["mixed_max_error_um"],
                                              s["selector"]["best_fixed_max_error_um"]))
    wins = sum(a < b for a, b in got.values())
    numbers(wins <= 1, f"the selector wins in {wins} of 13")
    bad = {k: v for k, v in got.items() if not v[0] < v[1]}
    assert not bad, bad


@stages
@nut_models
def test_table2_fast_non_reverse_needs_the_redesigned_reference(nut_model, stage):
    """The original fast stop is fast non-reverse (F_bn turns 10-18 ms before zero speed:
    Pattern II -> I); the redesigned stop (126 ms instead of 51 ms) is slow non-reverse, F_bn
    never turns, and the max error around zero speed falls from 5.63-5.93 to 3.35 µm (table1)
    and from 4.02-5.11 to 2.52-3.25 µm (fig2): by 2.3-2.6 / 1.5-1.9 µm in every variant."""
    red = values(nut_model, stage, lambda s: s["table2_fast_non_reverse"])
    for label, r in red.items():
        o, n = r["original"], r["redesigned"]
        assert o["kind"] == "fast_non_reverse" and n["kind"] == "slow_non_reverse", label
        assert o["drive_force_reverses_before_zero_ms"] >= 5.0, (label, o)
        assert n["drive_force_reverses_before_zero_ms"] is None, (label, n)
        assert n["stop_ms"] == pytest.approx(125.5) and o["stop_ms"] == pytest.approx(50.5)
    gain = span({k: r["original"]["max_error_um"] - r["redesigned"]["max_error_um"] for k, r in red.items()})
    assert gain[0] > {"table1": 2.0, "fig2": 1.3}[stage], gain
