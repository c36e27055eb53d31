"""Runs that pass (status 0) must agree with the ``solve_ivp`` twin within the README's error contract
(issue 13, "0 silent wrong answers"): reproducers of passed-WRONG runs found by the random campaigns.

GMS cases: helper "gmsw" (2026-11-23/24). LuGre/Dahl cases: helpers "lugw" and "lugw2" (2026-11-24;
benchmarks/robustness_lugre.py is lugw2's campaign).
"""

from __future__ import annotations

import warnings

import numpy as np
import pytest

import frictionkit as fk
from frictionkit.simulation.reference import reference_force_driven


def _errors(res, tw) -> dict[str, float]:
    """Largest difference run - twin of x, v and the friction, each relative to the twin's range (over the
    samples a flagged run kept, up to ``failed_at``)."""
    j = None if res.failed_at is None else res.failed_at + 1
    return {name: float(np.max(np.abs(getattr(res, name)[:j] - tw[name][:j])) / np.ptp(tw[name]))
            for name in ("x", "v", "friction")}


def _gms_sine_run(law, m, dt, n, amp, hz):
    """A GMS on a mass under ``amp sin(2 pi hz t)`` for ``n`` samples: ``(result, errors against a twin
    whose steps are at most dt/8)``."""
    u = amp * np.sin(2 * np.pi * hz * np.arange(n) * dt)
    res = fk.simulate(law, dt=dt, plant=fk.Mass(m), force=u)
    tw = reference_force_driven(law, m, u, dt, rtol=1e-11, atol=1e-16, max_step=dt / 8)
    return res, _errors(res, tw)

# --------------------------------------------------------------------------- GMS

# Round 8's passed-WRONG GMS set (random extreme-but-legal parameters): omega dt = 5.28, damping ratio
# 0.0054, a contact ringing about once per sample with breakaways and reversals inside the samples.
GMS_R8 = fk.GMS(
    fk.Stribeck(Fc=0.15237922893111022, Fs=0.17382210982304852, vs=0.001323514769825055,
                sigma2=0.013521783298779528),
    k=[1198.61151917, 1374.67979258], xi=[0.46578928, 0.53421072], C=1.0033285051540421,
)
GMS_R8_M = 6.108607554557013e-4
GMS_R8_DT = 0.002570801747272288


def _gms_r8_force(n):
    t = np.arange(n) * GMS_R8_DT
    return 0.43015554969495007 * np.sin(2 * np.pi * 1.4446760123959934 * t)


@pytest.fixture(scope="module")
def gms_r8():
    # 150 samples: the first breakaway the kernel missed is inside interval 136 -> 137
    u = _gms_r8_force(150)
    res = fk.simulate(GMS_R8, dt=GMS_R8_DT, plant=fk.Mass(GMS_R8_M), force=u)
    # the twin with steps of at most dt/8, so that it does not step over a grazing switch itself
    # (its default steps missed 3 of 335 switches over 3 s of this run)
    tw = reference_force_driven(GMS_R8, GMS_R8_M, u, GMS_R8_DT, rtol=1e-11, atol=1e-15, max_step=GMS_R8_DT / 8)
    return res, tw


def test_gms_breakaway_inside_a_substep_is_not_missed(gms_r8):
    """The twin breaks both elements away at t = 136.165 dt, while the mass still moves at ~30 vs
    (threshold xi Fc), and the velocity reverses at 136.226 dt. The old kernel landed a sub-step
    just before that reversal, where |v| << vs and the threshold is xi Fs, tested the breakaway
    there only, and carried the sticking springs 4 % past xi Fc: from sample 137 on x, v and the
    friction were off by up to 0.15 %, 0.07 % and 1.7 % of their ranges (3 s: 0.69 %, 0.11 %,
    2.4 %) at status 0, "accuracy check passed"."""
    res, tw = gms_r8
    assert res.status == 0
    rtol = fk.SimOptions().rtol
    # the twin's own switches: two breakaways between samples 136 and 137, then the reversal
    ev = [(t / GMS_R8_DT, kind) for t, kind, _ in tw["event_log"] if 136 < t / GMS_R8_DT < 137]
    assert [kind for _, kind in ev] == ["breakaway", "breakaway", "reversal"], ev
    for name, err in _errors(res, tw).items():
        assert err <= 10 * rtol, f"{name} {err:.3g} of its range off the twin at status 0 (contract 10 rtol)"


# A stiff contact (gmsw campaign, 2026-11-24, seed 1013 of its /tmp script): sum k = 2.9e8 N/m (above the
# contract's 1e8) on 1.87 kg, omega dt = 3.73. Every element slips from sample 17 to the reversal at 122.53
# dt at |v| < vs; the slip forces' small errors integrate to a velocity error of -2.5e-9 m/s at the reversal,
# which the re-sticking 1.2e8 N/m element turns into 2.8e-5 N: 3.7e-4 of the friction range at sample 123.
# The old code passed it at status 0, "accuracy check passed": the check run at rtol / 10 agrees with the run
# within 0.05 rtol (the error does not fall with the tolerance until a decade further down). Now such a close
# agreement of a GMS run calls a third run at rtol / 100 (simulation/core.py CHECK_SAME), which differs by 28
# rtol of the friction range: flagged (status 2) from sample 122 on.
GMS_STIFF = fk.GMS(
    fk.Stribeck(Fc=0.02069749976324002, Fs=0.03461987149484603, vs=0.00022014332523584873,
                sigma2=30.737735057620274),
    k=[61640634.90713564, 120322898.6160256, 57472549.16046112, 47756660.338911526],
    xi=[0.020785486439100127, 0.7379212079911537, 0.10000359077242792, 0.14128971479731814],
    C=1.2679711249816048,
)


def test_gms_stiff_restick_after_slow_slip_is_flagged_or_keeps_the_contract():
    """Old kernel: status 0 with the friction 3.7e-4 of its range off the twin (37 rtol)."""
    with warnings.catch_warnings(record=True):
        warnings.simplefilter("always")
        res, errs = _gms_sine_run(GMS_STIFF, 1.8736176219710425, 0.0003013291405700899, 126,
                                  0.0690033639617832, 16.06541234172489)
    rtol = fk.SimOptions().rtol
    if res.status == 0:
        assert max(errs["x"], errs["friction"]) <= 10 * rtol, errs
        return
    assert res.status == 2 and "accuracy check" in res.message, res.message
    # the samples kept (up to failed_at) keep the contract: measured x 2.9e-6, friction 3.0e-6 of the ranges
    assert res.failed_at is not None and res.failed_at >= 100, res.failed_at
    assert max(errs["x"], errs["friction"]) <= 10 * rtol, errs


# Fast slip relaxation through the Stribeck range (gmsw campaign seed 1047), inside the contract's ranges
# (sum k 8e5 N/m, 5 kg, vs 5.2e-4 m/s) but with C = 479 N/s on Fc = 0.5 N (C dt / g ~ 0.3): every element
# slips through the Stribeck range (samples 30-120), where the friction falls with the speed faster than
# sigma2 damps it, so the local errors of ~100 sub-steps add up and grow. Two causes, both needed
# (measured, max over x, v, friction / their ranges): the slip forces' error estimate missed the moving
# target xi s(v) (a first-order term, |dT| a^2 / 12; the local slip-force error was 1-2.8 times its
# tolerance), and the tolerance per step is too loose for anti-damped sliding. Old kernel x 2.7e-4,
# friction 3.4e-4; with the moving-target term alone 2.4e-4 / 3.7e-4; with the tighter tolerance alone
# 1.3e-4 / 2.1e-4; with both 5.4e-5 / 8.2e-5.
GMS_FAST_SLIP = fk.GMS(
    fk.Stribeck(Fc=0.5013596726511216, Fs=0.666416422066796, vs=0.0005175606411482415, sigma2=29.70872732759385),
    k=[176161.534725023, 341154.26018553675, 60133.41749198814, 225984.10701970727],
    xi=[0.3444625383924662, 0.35618028865505524, 0.04795139941708407, 0.25140577353539456],
    C=478.976217640827,
)


def test_gms_fast_slip_relaxation_through_the_stribeck_range_keeps_the_contract():
    res, errs = _gms_sine_run(GMS_FAST_SLIP, 5.031449682254583, 0.00034727580691770824, 136,
                              0.8858957811421615, 12.744890273873612)
    assert res.status == 0, res.message
    # measured 2026-11-24 (136 samples): x 5.4e-5, v 3.5e-5, friction 8.2e-5 of their ranges (old: 2.7e-4,
    # 1.8e-4, 3.4e-4)
    assert max(errs["x"], errs["friction"]) <= 10 * fk.SimOptions().rtol, errs


# The same cause inside the contract's ranges, 19x over it (gmsw2 campaign, benchmarks/robustness_gms.py seed
# 2016): sum k 1.1e5 N/m on 0.205 kg (omega dt 0.24, damping ratio 0.0013), vs 6.6e-5 m/s, C = 449 N/s on
# Fc = 0.014 N. Old kernel at status 0: x 1.9e-3, v 2.7e-3, friction 1.8e-3 of their ranges off the twin.
GMS_ANTIDAMPED = fk.GMS(
    fk.Stribeck(Fc=0.014132423941055933, Fs=0.025205984438893728, vs=6.572510751877277e-05,
                sigma2=0.38210413394297804),
    k=[5212.46178576, 5725.62629614, 84537.28129593, 13682.55839747],
    xi=[0.36821138, 0.20675892, 0.15654373, 0.26848597],
    C=448.77241230323756,
)


def test_gms_antidamped_slip_inside_the_contract_ranges_keeps_the_contract():
    m, dt, n = 0.20496039115048548, 0.0003243119799567451, 342
    res, errs = _gms_sine_run(GMS_ANTIDAMPED, m, dt, n, 0.009844879496607025, 1.6427567115076815 / (n * dt))
    assert res.status == 0, res.message
    # measured 2026-11-24: x 4.1e-5, v 6.4e-5, friction 4.1e-5 of their ranges
    assert max(errs["x"], errs["friction"]) <= 10 * fk.SimOptions().rtol, errs


# The kind of gmsw's seed 1068 (its parameters were lost): a fast contact whose run takes few sub-steps per
# sample, so the accuracy check (> SUBSTEP_RISK sub-steps per sample) did not look at it. gmsw2's campaign
# (benchmarks/robustness_gms.py) seed 109329: one element, sum k 6.2e6 N/m on 16.5 g, sigma2 = 0 (omega dt
# 16.9, undamped), Fs < Fc, a span ringing through its reversals at 0.63 sub-steps per sample. Old kernel at
# status 0: friction 8.1e-3 of its range off the twin (814 rtol); 8 of 8 such sets passed WRONG (friction
# 1.3e-4 ... 8.1e-3). Now every fast GMS run is checked: this one is flagged (status 2) and the samples it
# keeps (up to sample 169) are within 4.7e-6 (x) and 1.0e-5 (friction) of the twin's ranges.
GMS_FAST_FEW_SUBSTEPS = fk.GMS(
    fk.Stribeck(Fc=0.09318040124080203, Fs=0.05041612053266876, vs=4.498380272535193e-05, sigma2=0.0),
    k=[6185989.052915047], xi=[1.0], C=0.28287597308395046,
)


def test_gms_fast_contact_with_few_substeps_is_checked():
    m, dt, n = 0.016534569616476355, 0.000875161088844484, 282
    with warnings.catch_warnings(record=True):
        warnings.simplefilter("always")
        res, errs = _gms_sine_run(GMS_FAST_FEW_SUBSTEPS, m, dt, n, 0.19026802687960392,
                                  1.7908217391978307 / (n * dt))
    rtol = fk.SimOptions().rtol
    assert res.substeps / (n - 1) < 2, res.substeps  # below SUBSTEP_RISK: checked only as a fast GMS
    if res.status != 0:
        assert res.status == 2 and "accuracy check" in res.message, res.message
    assert max(errs["x"], errs["friction"]) <= 10 * rtol, errs


# --------------------------------------------------------------------------- LuGre / Dahl

# Passed-WRONG LuGre/Dahl sets of helper lugw's campaign (2026-11-24: 82 random extreme-but-legal sets,
# omega dt 0.1-100, damping ratio 1e-3-2, mass 1e-3-1e2 kg, sigma0 1e3-1e8 N/m, sine force 0.3-3 Fs,
# against LSODA twins at rtol 1e-12 with steps <= 1/16 of the ringing period). Unchecked-run errors against
# the twin, / range (x, v, friction), and what the old code said:
# * ring_068: omega dt 0.68, damping ratio 0.0012 -- 1.3e-4, 3.0e-4, 7.5e-5; status 0 without a check
#   (below FAST_LIMIT); now checked as a lightly damped ringing (core.py, RING_FAST / RING_ZETA).
# * lugre_125: omega dt 12.5, damping ratio 0.0054 -- 2.0e-5, 3.9e-5, 5.2e-4 (52 rtol in the friction);
#   "accuracy check passed" (the check bounded the friction at 1000 rtol; now CHECK_BOUND = 5).
# * dahl_121: omega dt 12.1, damping ratio 0.0055 -- 1.5e-6, 6.5e-6, 1.0e-4; "accuracy check passed".
LUGRE_DAHL_PASSED_WRONG = {
    "ring_068": (fk.LuGre(fk.Stribeck(Fc=1.9150443032247046, Fs=3.714424679211325, vs=1.2301379836262769e-05,
                                      sigma2=0.40132709577098596), sigma0=68047.59234705339, sigma1=0.267522812098899),
                 1.1202439996323021, 0.0027723806250730793, 1.7826492622316215, 2.5167709423257554, 334),
    "lugre_125": (fk.LuGre(fk.Stribeck(Fc=0.3583564261478927, Fs=0.7002847301839813, vs=0.00010502981071820879,
                                       sigma2=2.167584359529281), sigma0=18590839.117511354, sigma1=2.743179966588317),
                  0.01115391601363389, 0.0003060529320016637, 0.9516631719878674, 1.600754759253861, 199),
    "dahl_121": (fk.Dahl(Fc=0.10240737718118277, sigma0=8844553.216609133, sigma2=2.067653245149673),
                 0.003951278395129656, 0.00025534004626539267, 0.13053415467420956, 2.312168127559201, 297),
}


@pytest.mark.parametrize("name", list(LUGRE_DAHL_PASSED_WRONG))
def test_lugre_dahl_runs_that_pass_keep_the_error_contract(name):
    import warnings

    law, m, dt, amp, cycles, n = LUGRE_DAHL_PASSED_WRONG[name]
    u = amp * np.sin(2 * np.pi * cycles * np.arange(n) / n)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", RuntimeWarning)
        res = fk.simulate(law, dt=dt, plant=fk.Mass(m), force=u)
    if res.status != 0:
        assert res.status == 2 and "accuracy check" in res.message, res.message
        return
    period = 2 * np.pi / np.sqrt(law.sigma0 / m)
    tw = reference_force_driven(law, m, u, dt, rtol=1e-12, atol=1e-16, max_step=min(dt / 4, period / 16))
    rtol = fk.SimOptions().rtol
    errs = _errors(res, tw)
    # README error contract: 10 rtol of the ranges of x and the friction; v: the check's 1000 rtol
    assert errs["x"] <= 10 * rtol and errs["friction"] <= 10 * rtol and errs["v"] <= 1000 * rtol, errs


def test_simulate_batch_checks_a_lightly_damped_ringing_set_too():
    """simulate_batch runs such a set alone, as it does a fast one: ring_068 (its unchecked run is 1.3e-4 of
    its position range off the twin, 13 rtol) gets status 2 and sse inf (was 0 and a finite sse)."""
    law, m, dt, amp, cycles, n = LUGRE_DAHL_PASSED_WRONG["ring_068"]
    u = amp * np.sin(2 * np.pi * cycles * np.arange(n) / n)
    b = fk.simulate_batch([law], masses=[m], force=u, dt=dt, target=np.zeros(n))
    assert b.status[0] == 2 and np.isinf(b.sse[0]), b.message


# Helper lugw2's campaign (2026-11-24, seed 40 of /tmp/lugw2_camp.py part a: random LuGre/Dahl sets with
# steps, ramps to stick, staircases, random-phase multisines, a force held at breakaway). A single-sample
# spanning step across a velocity peak: the remainder of dz/dt (~ (v - v0)^2) vanishes again at the
# sample's end, so the step's end-only error estimate read < 1 tolerance where the sample was ~30 off
# (4e-6 m/s at tol_v 1.3e-7); the velocity error then reached the next reversal, where the friction
# turns by 0.11 N per sample.
LUGRE_PEAK = fk.LuGre(fk.Stribeck(Fc=0.15547068824389326, Fs=0.20632574781031032, vs=0.00691856948193845,
                                  sigma2=1.0866966098958122), sigma0=4115.43049678189, sigma1=8.517007046606572)
LUGRE_PEAK_M, LUGRE_PEAK_DT = 0.06049088399503904, 0.001711839572895819


def test_lugre_single_sample_step_across_a_velocity_peak_keeps_the_contract():
    """Old code: x 1.9, v 3.7, friction 16.1 rtol of their ranges off the twin at status 0 (the same
    at rtol 1e-6 and 1e-7: not a tolerance error); now the peak's sample is measured by its own
    mid-sample remainder (kernels/lugre.py, _span) and the run is ~1 rtol off."""
    n = 163
    k = np.arange(n)
    f = [7.6687239580392665, 4.770023694461076, 7.114068422013351, 0.992626156376153]
    ph = [0.13208351305825458, 3.680271465012278, 2.601133315553272, 0.5918791004919921]
    u = 0.14984838003677642 * sum(np.sin(2 * np.pi * fi * k / n + p) for fi, p in zip(f, ph))
    res = fk.simulate(LUGRE_PEAK, dt=LUGRE_PEAK_DT, plant=fk.Mass(LUGRE_PEAK_M), force=u)
    assert res.status == 0, res.message
    period = 2 * np.pi / np.sqrt(LUGRE_PEAK.sigma0 / LUGRE_PEAK_M)
    tw = reference_force_driven(LUGRE_PEAK, LUGRE_PEAK_M, u, LUGRE_PEAK_DT, rtol=1e-12, atol=1e-16,
                                max_step=min(LUGRE_PEAK_DT / 4, period / 16))
    errs = _errors(res, tw)
    rtol = fk.SimOptions().rtol
    assert errs["x"] <= 10 * rtol and errs["friction"] <= 10 * rtol and errs["v"] <= 10 * rtol, errs


# Helper lugw2's campaign seed 49: an overdamped LuGre (sigma1 = 1.68x critical, omega dt 0.24) under a force
# step to 2.9 Fs. While it slides, dz/dt is a small difference of v and sigma0 |v| z / g, each held to rtol
# of itself, and sigma1 dz/dt is in the friction: the friction was 10 rtol of its range off the twin at the
# default tolerances (x 0.005 rtol) and 16 rtol at rtol = atol_F = 1e-7. Fixed by bounding the friction's own
# share of the local error (kernels/lugre.py, F_ERROR).
LUGRE_OVERDAMPED = fk.LuGre(fk.Stribeck(Fc=4.9763908616224, Fs=6.59647814782858, vs=0.000757796844416329,
                                        sigma2=0.6006642671596605), sigma0=24707.394388698078, sigma1=374.1876441128367)
LUGRE_OVERDAMPED_M, LUGRE_OVERDAMPED_DT = 0.5019979613023899, 0.0010628703796107734


@pytest.mark.parametrize("rtol", [1e-5, 1e-7])
def test_overdamped_lugre_friction_keeps_the_contract_while_it_slides(rtol):
    """Old code (these 120 samples): friction 9.99 rtol (rtol 1e-5: inside the contract by a hair) and 16.2
    rtol (1e-7: outside) of its range off the twin at status 0; now 1.27 and 1.35 rtol (x <= 0.02 rtol)."""
    u = np.where(np.arange(120) >= 68, -19.266368431066265, 0.0)
    opts = fk.SimOptions(rtol=rtol, atol_F=rtol)
    res = fk.simulate(LUGRE_OVERDAMPED, dt=LUGRE_OVERDAMPED_DT, plant=fk.Mass(LUGRE_OVERDAMPED_M), force=u,
                      options=opts)
    assert res.status == 0, res.message
    tw = reference_force_driven(LUGRE_OVERDAMPED, LUGRE_OVERDAMPED_M, u, LUGRE_OVERDAMPED_DT, rtol=1e-12, atol=1e-16,
                                max_step=LUGRE_OVERDAMPED_DT / 4)
    errs = _errors(res, tw)
    # the contract's 10 rtol, with the margin the fix gives (measured 1.3-1.4 rtol): 5 rtol
    assert errs["x"] <= 5 * rtol and errs["friction"] <= 5 * rtol, errs


def test_overdamped_lugre_at_tight_rtol_with_the_default_atol_F():
    """Campaign seeds 49 and 71 (rtol 1.2e-8 and 1.8e-7, atol_F left at its default): the friction's
    absolute tolerance was atol_F max(Fc, Fs) with atol_F fixed at 1e-5 of the level, far above 10 rtol of
    the friction's range, so the friction was 15, 36 and 60 rtol of its range off at rtol 1e-6, 1e-7, 1e-8
    (x within 0.06 rtol). The default atol_F now follows min(1e-5, rtol) (SimOptions, ATOL_F)."""
    u = np.where(np.arange(120) >= 68, -19.266368431066265, 0.0)
    rtol = 1e-8
    res = fk.simulate(LUGRE_OVERDAMPED, dt=LUGRE_OVERDAMPED_DT, plant=fk.Mass(LUGRE_OVERDAMPED_M), force=u,
                      options=fk.SimOptions(rtol=rtol))
    assert res.status == 0, res.message
    tw = reference_force_driven(LUGRE_OVERDAMPED, LUGRE_OVERDAMPED_M, u, LUGRE_OVERDAMPED_DT, rtol=1e-12, atol=1e-16,
                                max_step=LUGRE_OVERDAMPED_DT / 4)
    errs = _errors(res, tw)
    # with atol_F fixed at 1e-5 (2026-11-24): x 0.057, friction 59.9 rtol of their ranges
    assert fk.SimOptions(rtol=rtol).atol_F == rtol and fk.SimOptions().atol_F == 1e-5
    assert errs["x"] <= 10 * rtol and errs["friction"] <= 10 * rtol, errs
