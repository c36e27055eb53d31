"""Seed 001 Table 3: max tracking error during the fast reversal of 25(1 - cos 2 pi t) mm.

Paper: sigmoid 1.65 µm < sinc 4.24 µm < Coulomb 5.44 µm. Checked on 13 variants (3 noise
seeds, each assumed stiffness ±30 %). Corrections applied to the paper before running:
sigma = 2 read as 2 µm; eq. 7 sign flipped to a compensation; B_m read as 1.1772e-3.
"""

import pytest

from frictionkit.reproduce.zhu_fujimoto import TABLE3_PAPER_UM

from ._variants import summaries


def _errors():
    return {k: {law: v["table3"][law]["max_error_um"] for law in TABLE3_PAPER_UM} for k, v in summaries().items()}


def test_table3_each_law_within_factor_3_of_paper():
    bad = {}
    for label, e in _errors().items():
        for law, paper in TABLE3_PAPER_UM.items():
            if not (paper / 3.0 <= e[law] <= 3.0 * paper):
                bad[(label, law)] = (e[law], paper)
    assert not bad, bad


def test_table3_sinc_below_coulomb():
    bad = {k: e for k, e in _errors().items() if not e["sinc"] < e["coulomb"]}
    assert not bad, bad


@pytest.mark.xfail(strict=True, reason=(
    "Not reproduced: the simulated sigmoid is between sinc and Coulomb, not best. Quick, seed 0: "
    "sinc 2.36, sigmoid 2.95, Coulomb 3.15 µm (paper 4.24 / 1.65 / 5.44); over all 13 variants "
    "sinc 2.13-2.86 < sigmoid 2.68-3.38 <= Coulomb 2.95-3.45 µm. In the model the nut/guide "
    "friction keeps its sign until the stage stops, so reducing u_f before zero speed "
    "under-compensates."))
def test_table3_sigmoid_below_sinc_below_coulomb():
    bad = {k: e for k, e in _errors().items() if not e["sigmoid"] < e["sinc"] < e["coulomb"]}
    assert not bad, bad
