"""Seed 001 Table 3: max tracking error during the fast reversal of 25(1 - cos 2 pi t) mm.

Paper: sigmoid 1.65 µm < sinc 4.24 µm < Coulomb 5.44 µm, and the sigmoid "can reduce the
tracking error before the reversal" (§5.3) because it lowers u_f *before* zero speed (§4,
Fig. 11). Checked on 13 variants (3 noise seeds, each assumed stiffness ±30 %) of both stages
(``table1``, ``fig2``) and every nut model (``sliding``, ``flank``, ``hertz``). Corrections
applied to the paper before running: sigma = 2 read as 2 µm; eq. 7 sign flipped to a
compensation; B_m read as 1.1772e-3.

The pre-zero reduction is tested against ``sigmoid_post_only``: the same law with u_f held at
the previous-direction F0 until the zero-speed instant, then the same sigmoid rise.
"""

import pytest


from ._variants import NUT_MODELS, STAGES, numbers, span, summaries

#: Seed 001 Table 3, "Maximum error [μm]" during the reverse motion (typed from the paper, not
#: taken from the code under test).
TABLE3_PAPER_UM = {"sinc": 4.24, "coulomb": 5.44, "sigmoid": 1.65}

nut_models = pytest.mark.parametrize("nut_model", NUT_MODELS)
stages = pytest.mark.parametrize("stage", STAGES)


def _errors(nut_model, stage):
    return {k: {law: v["table3"][law]["max_error_um"] for law in v["table3"]}
            for k, v in summaries(nut_model, stage).items()}


@stages
@nut_models
def test_table3_each_law_within_factor_3_of_paper(nut_model, stage):
    bad = {}
    for label, e in _errors(nut_model, stage).items():
        for law, paper in TABLE3_PAPER_UM.items():
            if not (paper / 3.0 <= e[law] <= 3.0 * paper):
                bad[(label, law)] = (e[law], paper)
    assert not bad, bad


@stages
@nut_models
def test_table3_sinc_below_coulomb(nut_model, stage):
    bad = {k: e for k, e in _errors(nut_model, stage).items() if not e["sinc"] < e["coulomb"]}
    assert not bad, bad


ORDER_TABLE1 = pytest.mark.xfail(strict=True, raises=AssertionError, reason=(
    "table1 stage, every nut model: the simulated sigmoid is between sinc and Coulomb, not best. "
    "Quick, seed 0: sinc 2.36, sigmoid 2.95, Coulomb 3.15 µm (paper 4.24 / 1.65 / 5.44); 13 "
    "variants: sinc 2.13-2.86 < sigmoid 2.65-3.38 <= Coulomb 2.95-3.45 µm, 0 of 13 in the paper's "
    "order (sigmoid 0.44-0.71 µm above sinc). The fig2 stage (inertia of the measured response) "
    "gives the paper's order."))


@pytest.mark.parametrize("stage", [pytest.param("table1", marks=ORDER_TABLE1), "fig2"])
@nut_models
def test_table3_sigmoid_below_sinc_below_coulomb(nut_model, stage):
    """fig2 stage, every nut model: sigmoid 1.98-2.65 < sinc 2.13-2.83 < Coulomb 2.65-2.92 µm
    (seed 0: 2.18 / 2.33-2.43 / 2.76), 13 of 13 variants — but the sigmoid wins by only
    0.01-0.25 µm, at most 2.5 counts of the 100 nm scale."""
    e = _errors(nut_model, stage)
    if stage == "table1":
        s0 = e["seed=0"]
        numbers(abs(s0["sinc"] - 2.36) < 0.02 and abs(s0["sigmoid"] - 2.95) < 0.02 and abs(s0["coulomb"] - 3.15) < 0.02,
                f"seed 0: {s0}")
        numbers(all(v["sinc"] < v["sigmoid"] for v in e.values()), "sinc < sigmoid in every variant")
    else:
        margin = span({k: v["sinc"] - v["sigmoid"] for k, v in e.items()})
        assert 0.0 < margin[0] and margin[1] < 0.3, margin
    bad = {k: v for k, v in e.items() if not v["sigmoid"] < v["sinc"] < v["coulomb"]}
    assert not bad, bad


@pytest.mark.xfail(strict=True, raises=AssertionError, reason=(
    "Not reproduced on either stage with any nut model: removing the sigmoid's reduction of u_f "
    "before zero speed (u_f = F0 until the reversal, then the same sigmoid rise) *lowers* the "
    "error in 78 of 78 runs. Quick, seed 0: table1 sigmoid 2.95 vs post-only 2.38 µm; fig2 "
    "2.18 vs 1.55 µm; 13 variants: the pre-zero reduction costs 0.47-0.80 µm (table1) and "
    "0.50-0.98 µm (fig2). The friction in the model keeps its direction until the stage stops, "
    "so u_f lowered before zero speed under-compensates it; the sigmoid's advantage on the fig2 "
    "stage comes from its fast rise after zero speed, not from the braking before it."))
@stages
@nut_models
def test_table3_sigmoid_pre_zero_reduction_lowers_the_error(nut_model, stage):
    """§4 / §5.3: the sigmoid lowers u_f from F0 to 0 before zero speed "to help brake the
    motion" and so "can reduce the tracking error before the reversal"."""
    e = _errors(nut_model, stage)
    cost = {k: v["sigmoid"] - v["sigmoid_post_only"] for k, v in e.items()}
    lo, hi = span(cost)
    numbers(0.4 < lo and hi < 1.05, f"pre-zero reduction costs {lo:.2f}-{hi:.2f} µm")
    s0 = e["seed=0"]
    numbers(abs(s0["sigmoid_post_only"] - {"table1": 2.38, "fig2": 1.55}[stage]) < 0.02, f"seed 0: {s0}")
    bad = {k: (v["sigmoid"], v["sigmoid_post_only"]) for k, v in e.items()
           if not v["sigmoid"] < v["sigmoid_post_only"]}
    assert not bad, bad


def test_code_carries_the_papers_table3():
    """The reproduction compares against the paper's numbers: the code's copy equals Table 3."""
    from frictionkit.presets import zhu_fujimoto as zf

    assert {k: zf.TABLE3_UM[k] for k in TABLE3_PAPER_UM} == TABLE3_PAPER_UM
