"""Seed 000 (Zhang et al. 2023) TDMS plant: paper tables, true friction, physics of the plant.

Paper values are typed here from the paper (Tables 3-4, §5.2.1) and cited, not read from
the code under test.
"""

import math

import numpy as np
import pytest

from frictionkit.errors import ParameterError
from frictionkit.presets import zhang2023 as z
from frictionkit.presets.zhang2023 import truth as zt

# Table 4 critical points, §5.2.1 (µm, N) and Table 3 T_S (N)
POINTS = {
    "screw+": [(2.391, 71.82), (6.832, 86.18), (10.290, 89.37)],
    "nut+": [(7.654, 57.45), (16.11, 64.24), (31.43, 67.03)],
    "nut-": [(11.59, 31.92), (17.72, 39.9), (30.01, 44.69)],
    "screw-": [(1.811, 73.41), (4.176, 80.2), (9.766, 86.18)],
}
T_S = {"screw+": 113.5, "nut+": 67.85, "screw-": 79.87, "nut-": 99.64}          # Table 3
XI_PRINTED = {"screw+": (0.565, 0.139, 0.0835), "nut+": (0.736, 0.191, 0.084),  # Table 4
              "screw-": (0.829, 0.150, 0.135), "nut-": (0.169, 0.162, 0.117)}


def test_table4_k_unit_is_N_per_um():
    """Slopes between the P-points (N/µm) give Table 4's screw+ k by the GMS rule
    k_i = slope_i - slope_{i+1}: the printed "N/mm" is N/µm; stored in SI as N/m."""
    x, F = zip(*[(0.0, 0.0)] + POINTS["screw+"])
    slope = np.diff(F) / np.diff(x)
    k = [slope[0] - slope[1], slope[1] - slope[2], slope[2]]
    assert np.allclose(k, [26.804, 2.312, 0.922], rtol=2e-3)                   # Table 4
    assert np.allclose(z.PAPER_TABLES["table4"]["screw+"]["k"], np.array([26.804, 2.312, 0.922]) * 1e6)


@pytest.mark.parametrize("col", ["screw+", "nut+", "screw-", "nut-"])
def test_table4_xi_from_eq19_with_T_S(col):
    """eq. 19 xi_i = k_i |P_i| / T_S on the virgin branch reproduces every printed xi (3 digits)."""
    k = np.array(z.PAPER_TABLES["table4"][col]["k"]) / 1e6          # N/µm
    d = np.array([abs(p[0]) for p in POINTS[col]])
    assert np.allclose(k * d / T_S[col], XI_PRINTED[col], rtol=1.5e-2, atol=2e-3)


def test_table3_units_and_directions():
    t3 = z.PAPER_TABLES["table3"]
    assert t3["screw+"]["vs"] == pytest.approx(0.2439e-3) and t3["screw+"]["v_sign"] == 1
    assert t3["nut+"]["v_sign"] == -1 and t3["nut-"]["v_sign"] == 1     # clockwise nut speed is negative
    assert t3["nut+"]["sigma2"] == pytest.approx(2297.0)               # N·s/mm read -> N·s/m
    assert z.force_to_torque(87.4) == pytest.approx(87.4 * 5e-3 / (2 * math.pi))


@pytest.mark.parametrize("shaft", ["screw", "nut"])
def test_truth_presliding_literals_rederive(shaft):
    d = zt._design_presliding(shaft)
    lit = zt._PRESLIDING[shaft]
    virgin = zt._virgin
    for s in "+-":
        Fs = T_S[f"{shaft}{s}"]
        x = np.geomspace(0.1, 100.0, 30)
        assert np.allclose(virgin(lit["k_N_per_um"], lit["xi"][s], Fs, x),
                           virgin(d["k_N_per_um"], d["xi"][s], Fs, x), atol=0.01 * Fs)


@pytest.mark.parametrize("col", ["screw+", "nut+", "nut-", "screw-"])
def test_truth_virgin_curve_near_paper_points(col):
    """The truth's virgin curve passes within 7 % of the paper's P-points (worst: nut- P1, +6.8 %,
    the price of one stiffness set for both directions); screw-: P2, P3 lie above its own T_S
    and cannot be reached with sum xi = 1 — checked to stay below T_S."""
    tf = z.true_friction()
    law = tf.screw_support if col.startswith("screw") else tf.nut_support
    sign = z.PAPER_TABLES["table3"][col]["v_sign"]
    g = law.positive if sign > 0 else law.negative
    assert g.xi.sum() == pytest.approx(1.0)
    x = np.array([abs(p[0]) for p in POINTS[col]]) * 1e-6
    F = np.array([np.sum(g.k * np.minimum(xx, g.xi * g.static.Fs / g.k)) for xx in x])
    paper = np.array([p[1] for p in POINTS[col]])
    if col == "screw-":
        assert abs(F[0] / paper[0] - 1) < 0.07 and np.all(F <= T_S[col] + 1e-9)
    else:
        assert np.all(np.abs(F / np.abs(paper) - 1) < 0.07), (F, paper)


@pytest.mark.parametrize("site", ["screw_support", "nut_support", "ball_preload", "guide"])
def test_truth_does_not_ratchet_under_reciprocation(site):
    """Passive pre-sliding: after a virgin stroke, +-2 µm cycles retrace one closed loop — the force
    at the same turning point is the same every cycle (one stiffness set for both directions)."""
    import frictionkit as fk

    law = z.true_friction().sites()[site]
    dt = 1e-3
    turns = [0.0, 2e-6] + [-2e-6, 2e-6] * 4
    x = np.concatenate([np.linspace(a, b, 400, endpoint=False) for a, b in zip(turns[:-1], turns[1:])] + [[2e-6]])
    F = fk.simulate(law, position=x, dt=dt).friction
    at_top = F[400::800]
    assert np.ptp(at_top[1:]) < 1e-3 * np.max(np.abs(F)), at_top


def test_paper_gms_sum_xi_decision():
    g = z.paper_gms("screw")
    assert g.positive.xi.sum() == pytest.approx(1.0) and g.negative.xi.sum() == pytest.approx(1.0)
    from frictionkit.models.gms import GMSWeightWarning

    with pytest.warns(GMSWeightWarning, match="0.448"):                      # Table 4 nut- sums to 0.448
        gp = z.paper_gms("nut", sum_xi="as_printed")
    assert gp.positive.xi.sum() == pytest.approx(0.169 + 0.162 + 0.117)         # nut- column: theta2' > 0
    assert gp.negative.static.Fs == pytest.approx(67.85)                        # nut+ column: theta2' < 0
    g6 = z.paper_gms("screw", table="table6", sum_xi="as_printed")
    assert g6.positive.xi.sum() == pytest.approx(1.37)


def test_assumptions_validate():
    with pytest.raises(ParameterError, match="table_mass"):
        z.Assumptions(table_mass=-1.0)
    with pytest.raises(ParameterError, match="substeps"):
        z.Assumptions(substeps=0)
    with pytest.raises(ParameterError, match="actuator_delay"):
        z.Assumptions(actuator_delay=-1)
    with pytest.raises(ParameterError, match="direction"):
        z.co_speed_sweep([1e-3], direction=2)
    assert z.Assumptions().scaled("guide_level", 1.2).guide_level == pytest.approx(7.2)


# --------------------------------------------------------------------------- physics of runs
@pytest.fixture(scope="module")
def co_speed():
    return z.co_speed_sweep([1e-3, 5e-3], hold=0.6, seed=1)


@pytest.fixture(scope="module")
def diff4():
    return z.differential_sweep(4e-3, [0.5e-3, 3e-3], hold=0.4, settle=2.5, seed=1)


def _site_balance(rec, sl):
    f = {k: float(np.mean(v[sl])) for k, v in rec.site_forces.items()}
    ball = f["ball_preload"] + f["ball_load"]
    F_ax = float(np.mean(rec.F_axial[sl]))
    return f, ball, F_ax


def test_co_speed_table_still_and_torques_balance(co_speed):
    rec = co_speed
    assert rec.success, rec.message
    assert np.ptp(rec.x_t_true) < 2e-6                              # table quasi-stationary (µm)
    for a, b, v in rec.segments:
        sl = slice(b - 1000, b)
        f, ball, F_ax = _site_balance(rec, sl)
        # steady speed: each motor balances its support, the ball pair and the axial force (both shafts)
        assert np.mean(rec.force1[sl]) == pytest.approx(f["screw_support"] + ball + F_ax, abs=0.3)
        assert np.mean(rec.force2[sl]) == pytest.approx(f["nut_support"] + ball + F_ax, abs=0.3)


def test_differential_kinematics_and_load_on_both_shafts(diff4):
    rec = diff4
    assert rec.success, rec.message
    pm = rec.plateau_means()
    assert np.allclose(pm["v_t"], pm["value"], rtol=0.01)           # x_t = R (theta1 + theta2)
    assert np.allclose(pm["v1"] + pm["v2"], pm["value"], rtol=0.01)
    for a, b, v in rec.segments:
        sl = slice(b - 800, b)
        f, ball, F_ax = _site_balance(rec, sl)
        assert F_ax > 3.0                                           # the guide pushes back on the ball pair
        # the table load and the ball friction reach BOTH shafts (eqs. 11-12 put T_dt on the screw only)
        assert np.mean(rec.force2[sl]) == pytest.approx(f["nut_support"] + ball + F_ax, abs=0.5)
        assert abs(np.mean(rec.force2[sl])) < abs(f["nut_support"]) - 3.0


def test_differential_plateaus_match_lumped_steady_state(diff4):
    """eq. 20 derived for our plant (module docstring): at a steady plateau the screw motor carries
    F_fs(b + v3) + F_b(v3) + F_ft(v3) and the nut motor F_fn(-b) + F_b(v3) + F_ft(v3), with the ball
    pair's load part at |F_ft| (the axial spring carries the guide friction). Within 1 N (~1 %),
    after the nut's support has relaxed (2.5 s at base speed: tau = T_S / C = 0.97 s, Table 4)."""
    a, tf = z.Assumptions(), z.true_friction()
    pm = diff4.plateau_means(fraction=0.4)
    v3 = pm["value"]
    g = tf.guide.steady_state(v3)
    ball = tf.ball_preload.steady_state(v3) + tf.ball_load.steady_state(v3) * np.abs(g) / a.ball_load_reference
    F1 = tf.screw_support.steady_state(4e-3 + v3) + ball + g
    F2 = tf.nut_support.steady_state(np.full_like(v3, -4e-3)) + ball + g
    assert np.allclose(pm["F1"], F1, atol=1.0), (pm["F1"], F1)
    assert np.allclose(pm["F2"], F2, atol=1.0), (pm["F2"], F2)
