"""Seed 001 Table 3: max tracking error during the fast reversal of 25(1 - cos 2 pi t) mm.

Paper: sigmoid 1.65 µm < sinc 4.24 µm < Coulomb 5.44 µm. Checked on 13 variants (3 noise
seeds, each assumed stiffness ±30 %). Corrections applied to the paper before running:
sigma = 2 read as 2 µm; eq. 7 sign flipped to a compensation; B_m read as 1.1772e-3.
Each test runs for every nut model (``sliding``, ``flank``, ``hertz``).
"""

import pytest

from frictionkit.reproduce.zhu_fujimoto import TABLE3_PAPER_UM

from ._variants import NUT_MODELS, summaries

nut_models = pytest.mark.parametrize("nut_model", NUT_MODELS)


def _errors(nut_model):
    return {k: {law: v["table3"][law]["max_error_um"] for law in TABLE3_PAPER_UM}
            for k, v in summaries(nut_model).items()}


@nut_models
def test_table3_each_law_within_factor_3_of_paper(nut_model):
    bad = {}
    for label, e in _errors(nut_model).items():
        for law, paper in TABLE3_PAPER_UM.items():
            if not (paper / 3.0 <= e[law] <= 3.0 * paper):
                bad[(label, law)] = (e[law], paper)
    assert not bad, bad


@nut_models
def test_table3_sinc_below_coulomb(nut_model):
    bad = {k: e for k, e in _errors(nut_model).items() if not e["sinc"] < e["coulomb"]}
    assert not bad, bad


@pytest.mark.xfail(strict=True, reason=(
    "Not reproduced with any nut model: the simulated sigmoid is between sinc and Coulomb, "
    "not best. Quick, seed 0, all three models: sinc 2.36, sigmoid 2.95, Coulomb 3.15 µm (paper "
    "4.24 / 1.65 / 5.44); over the 13 variants sliding: sinc 2.13-2.86 < sigmoid 2.68-3.38 <= "
    "Coulomb 2.95-3.45 µm; flank: sinc 2.13-2.86 < sigmoid 2.65-3.38 <= Coulomb 2.95-3.45 µm; "
    "hertz: sinc 2.13-2.76 < sigmoid 2.65-3.38 <= Coulomb 2.95-3.45 µm (0 of 13 in the paper's "
    "order). Hertz contact: the largest drive force on this reference is 1.7 kN, where its "
    "tangent stiffness is within 0.5 % of k_nut; a flank set unloads only at 2^1.5 P = 9.9 kN. "
    "The nut/guide friction keeps its sign until the stage stops, so reducing u_f before zero "
    "speed under-compensates. Flank model: F_bn reverses ~17 ms (~150 µm) before zero speed; "
    "at the catalogue preload both flanks stay loaded (|F_bn| < 2P = 7 kN), so the flank levels "
    "keep their sum, and the traction lost by the unloading flank is rebuilt by the forward "
    "rolling within ~10 µm: the nut friction at zero speed differs from the sliding model's by "
    "< 1 N."))
@nut_models
def test_table3_sigmoid_below_sinc_below_coulomb(nut_model):
    bad = {k: e for k, e in _errors(nut_model).items() if not e["sigmoid"] < e["sinc"] < e["coulomb"]}
    assert not bad, bad
