"""TDMSSC, seed 000 eq. 21 with Table 5's nut columns: levels, shape, directions, validation, JSON.

Table 5 (differential-speed mode, screw driving), nut, as printed:

=========  =====================  =========
           positive               negative
=========  =====================  =========
T_C (N)    6.45 theta2_dot - 4.52  -48.34
T_S (N)    6.45 theta2_dot - 19.56 -62.26
v_s (mm/s) 0.065                  -0.169
delta      1.7                    0.9
sigma      -1.12 "N·s/m"          0.39
eps        5.852 "N·s²/m"         3.754
=========  =====================  =========

Corrections (see ``frictionkit.models.tdmssc``): theta2_dot is the nut's base speed as a
linear-equivalent speed in mm/s (Fig. 12: "Vbase = -4 mm/s"), so the slope 6.45 N/(mm/s) is
6450 N·s/m; sigma and eps are per mm/s (x 1e3, x 1e6 to SI: read in SI their terms would be
invisible and the curve could not "increase first and then reduce", §5.2.2); the printed v_s is
signed (we pass its magnitude); ``- eps v^2`` is taken as ``- eps v |v|`` (odd).
"""

from __future__ import annotations

import json
import math

import numpy as np
import pytest

import frictionkit as fk
from frictionkit.errors import ParameterError
from frictionkit.models import kernel_family, law_from_dict, law_to_dict

MM = 1e-3  # m per mm
# Table 5, nut, positive column, in SI (corrections in the module docstring)
NUT_POS = fk.TDMSSC(Fc0=-4.52, Fc1=6.45 / MM, Fs0=-19.56, Fs1=6.45 / MM, vs=0.065 * MM, delta=1.7,
                    sigma2=-1.12 / MM, eps=5.852 / MM**2)
# Table 5, nut, negative column: constant levels as printed (no base-speed function given), |v_s|
NUT_NEG = fk.TDMSSC(Fc0=-48.34, Fs0=-62.26, vs=0.169 * MM, delta=0.9, sigma2=0.39 / MM, eps=3.754 / MM**2)
NUT = fk.Directional(positive=NUT_POS, negative=NUT_NEG)


def test_levels_follow_eq21_at_the_fig12_base_speeds():
    # eq. 21: T_C = 6.45 (-4) - 4.52 = -30.32 N, T_S = 6.45 (-4) - 19.56 = -45.36 N at -4 mm/s
    assert NUT_POS.levels(schedule=-4 * MM) == pytest.approx((-30.32, -45.36), abs=1e-9)
    # at -0.1 mm/s: -0.645 - 4.52 = -5.165 N, -0.645 - 19.56 = -20.205 N
    assert NUT_POS.levels(schedule=-0.1 * MM) == pytest.approx((-5.165, -20.205), abs=1e-9)


def test_levels_cross_zero_where_the_paper_numbers_say():
    # T_C = 0 at 4.52 / 6.45 = 0.7008 mm/s, T_S = 0 at 19.56 / 6.45 = 3.0326 mm/s (seed000_facts §3)
    assert NUT_POS.levels(schedule=4.52 / 6.45 * MM)[0] == pytest.approx(0.0, abs=1e-9)
    assert NUT_POS.levels(schedule=19.56 / 6.45 * MM)[1] == pytest.approx(0.0, abs=1e-9)
    # T_S - T_C = -15.04 N at every base speed: the nut's curve rises with speed
    for s in (-6.0, -4.0, 0.0, 0.7, 6.0):
        Fc, Fs = NUT_POS.levels(schedule=s * MM)
        assert Fs - Fc == pytest.approx(-15.04, abs=1e-9)


def test_steady_state_at_breakaway_and_past_the_stribeck_range():
    s = -4 * MM
    # v -> 0+: the static level T_S(-4) = -45.36 N (the viscous and quadratic terms vanish)
    assert float(NUT_POS.steady_state(1e-12, schedule=s)) == pytest.approx(-45.36, abs=1e-6)
    # v = 1 mm/s, far past v_s = 0.065 mm/s (exp(-(1/0.065)^1.7) ~ e^-104):
    # T_C - 1.12 * 1 - 5.852 * 1^2 = -30.32 - 1.12 - 5.852 = -37.292 N
    assert float(NUT_POS.steady_state(1 * MM, schedule=s)) == pytest.approx(-37.292, abs=1e-9)


def test_negative_column_and_odd_quadratic_term():
    # v = -1 mm/s on the negative column: sgn(v) [T_C + (T_S - T_C) exp(-(1/0.169)^0.9)] + sigma v - eps v|v|
    # = 48.34 + 13.92 * exp(-4.953) - 0.39 + 3.754 = 48.34 + 0.0983 - 0.39 + 3.754 = 51.802 N
    assert float(NUT.steady_state(-1 * MM, schedule=0.0)) == pytest.approx(51.802, abs=2e-3)
    # symmetric parameters: the friction is odd in v (the quadratic term is -eps v|v|)
    v = np.linspace(-3, 3, 61) * MM
    F = NUT_POS.steady_state(v, schedule=2 * MM)
    np.testing.assert_allclose(F, -F[::-1], atol=1e-9)


def test_the_nut_curve_rises_first_then_falls():
    """§5.2.2: 'friction increases first and then reduces' with the speed difference (at a base
    speed where the levels are positive: 6 mm/s gives T_C = 34.18 N, T_S = 19.14 N)."""
    v = np.linspace(1e-6, 3.0, 3001) * MM
    F = NUT_POS.steady_state(v, schedule=6 * MM)
    assert F[0] == pytest.approx(19.14, abs=1e-3)
    k = int(np.argmax(F))
    assert 0.05 * MM < v[k] < 0.5 * MM  # it first rises by ~15 N past v_s ...
    assert F[k] > 33.0
    # ... then falls: 34.18 - 1.12 * 3 - 5.852 * 9 = -21.85 N at 3 mm/s
    assert F[-1] == pytest.approx(34.18 - 3.36 - 52.668, abs=1e-6)


def test_schedule_is_required_and_validated():
    with pytest.raises(ParameterError, match="schedule = None"):
        NUT_POS.steady_state(1e-3)
    with pytest.raises(ParameterError, match="schedule = None"):
        NUT.steady_state([1e-3, -1e-3])
    with pytest.raises(ParameterError, match="must be finite"):
        NUT_POS.steady_state(1e-3, schedule=math.nan)
    # broadcasting: one schedule value per velocity
    F = NUT_POS.steady_state([1e-3, 1e-3], schedule=[-4e-3, 6e-3])
    assert F[0] == pytest.approx(-37.292) and F[1] == pytest.approx(34.18 - 1.12 - 5.852)


@pytest.mark.parametrize("kw, msg", [
    ({"vs": 0.0}, r"TDMSSC.vs = 0.0: must be > 0"),
    ({"vs": -0.065e-3}, r"TDMSSC.vs = -6.5e-05: must be > 0"),
    ({"delta": 0.0}, r"TDMSSC.delta = 0.0: must be > 0"),
    ({"Fc0": math.nan}, r"TDMSSC.Fc0 = nan: must be finite"),
    ({"eps": math.inf}, r"TDMSSC.eps = inf: must be finite"),
    ({"Fs1": "a"}, r"TDMSSC.Fs1 = 'a': must be a real number"),
])
def test_validation_names_the_bad_value(kw, msg):
    base = dict(Fc0=1.0, Fs0=1.5, vs=1e-3)
    with pytest.raises(ParameterError, match=msg):
        fk.TDMSSC(**{**base, **kw})


def test_negative_levels_and_slopes_are_allowed_but_not_an_empty_law():
    fk.TDMSSC(Fc0=-1.0, Fs0=-2.0, vs=1e-3, sigma2=-5.0, eps=-1.0)
    fk.TDMSSC(Fc0=0.0, Fs0=0.0, Fc1=1.0, vs=1e-3)
    with pytest.raises(ParameterError, match="no friction level"):
        fk.TDMSSC(Fc0=0.0, Fs0=0.0, vs=1e-3)


def test_registry_family_and_json_round_trip():
    assert kernel_family(NUT_POS) == "static" and kernel_family(NUT) == "static"
    for law in (NUT_POS, NUT):
        text = json.dumps(law_to_dict(law))
        assert law_from_dict(json.loads(text)) == law
    assert law_to_dict(NUT_POS)["law"] == "TDMSSC"
    # a TDMSSC is not a static map for LuGre/GMS (its level needs the schedule)
    with pytest.raises(ParameterError, match="static"):
        fk.LuGre(NUT_POS, sigma0=1e5)
