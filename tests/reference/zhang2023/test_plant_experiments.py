"""Seed 000 TDMS virtual experiments: sub-step convergence, feed-forward hook, and the extension
(ours) finding: TDMS vs single drive (CDFS) velocity ripple at 1-10 µm/s."""

import re

import numpy as np
import pytest

from frictionkit.presets import zhang2023 as z


@pytest.fixture(scope="module")
def crawl():
    return z.crawling_comparison((1e-6, 10e-6), duration=1.0, seed=0)


PRESLIDE = dict(stroke=5e-6, speed=10e-6, cycles=0, seed=3)   # co-speed screw pre-sliding, table still


def test_default_substeps_pass_the_substep_check(monkeypatch):
    """The preset's default of 3 sub-steps passes simulate_machine's sub-step check on the co-speed
    pre-sliding run (table still: ~148 nm range), both as run (the guide's GMS couples 0.022 per
    sub-step, below the 0.03 that triggers the check) and with the check forced (against 48
    sub-steps). The former default of 2 is flagged there: its table moves by 1.6 nm = 1.06 % of
    its range against 32 sub-steps (bound 1 %), below the 10 nm scale count but beyond the bound."""
    import frictionkit.machines.simulate as S

    assert z.Assumptions().substeps == 3
    two = z.presliding_reciprocation("screw", substeps=2, **PRESLIDE)
    assert two.status == 2 and "'guide' couples to its own motion by 0.0331" in two.message
    # the table's move against 32 sub-steps: 1.06-1.08 % of its range (1.57-1.59 nm, by the site solves'
    # tolerance and the quantised loop), just beyond the 1 % bound; read from the message, not matched digit by digit
    got = re.search(r"position of 'table' moves by ([0-9.e+-]+) \(([0-9.]+) %", two.message)
    assert got is not None, two.message
    assert 1.5e-9 <= float(got.group(1)) <= 1.7e-9 and 1.0 < float(got.group(2)) <= 1.15, two.message
    a = z.presliding_reciprocation("screw", **PRESLIDE)
    # no sub-step coupling check needed (coupling < 0.03); the loop screen's hunting check
    # (steepest Stribeck slope, issue 13) may add its converged-limit-cycle note
    assert a.status == 0, a.message
    assert "couples to its own motion" not in a.message, a.message
    assert a.message == "ok" or (a.message.startswith("ok; note: the closed loop can hunt")
                                 and "the run converges" in a.message), a.message
    monkeypatch.setattr(S, "GMS_COUPLING_CHECK", 1e-9)            # force the check at the default
    b = z.presliding_reciprocation("screw", **PRESLIDE)
    assert b.status == 0 and "at 48 sub-steps every trace within its bound" in b.message, b.message
    np.testing.assert_array_equal(a.x_t_true, b.x_t_true)        # the check only reads the run


def test_presliding_converged_in_substeps():
    """The virgin pre-sliding curve of the screw (WSIM step 2 data) at the default 3 sub-steps
    stays within 0.3 N RMS (0.3 % of T_S = 113.5 N, Table 3) of 16 sub-steps (measured against
    64 sub-steps: 2 -> 0.097 N RMS, 3 -> 0.082 N, 8 -> 0.062 N, 16 -> 0.054 N; the floor is the
    quantised feedback of the semi-closed loop: any change flips encoder counts)."""
    a = z.presliding_reciprocation("screw", **PRESLIDE)
    b = z.presliding_reciprocation("screw", substeps=16, **PRESLIDE)
    assert a.success and b.success
    assert np.sqrt(np.mean((a.force1 - b.force1) ** 2)) < 0.3


def test_feedforward_hook_reduces_screw_error():
    """A FeedForward of the truth's support steady state cuts the screw and worktable tracking
    std in a differential sinusoidal run from base 0 (the screw reverses): the hook reaches the
    motor. Measured (seed 2, 0.6 s): screw std 0.47 -> 0.27 µm, worktable 0.53 -> 0.26 µm."""
    ref = z.tracking_reference("different", 0.0, duration=0.6)
    tf = z.true_friction()
    v1, v2 = ref.speeds()
    ff = z.FeedForward(ff1=z.force_to_torque(tf.screw_support.steady_state(v1)),
                       ff2=z.force_to_torque(tf.nut_support.steady_state(v2)), name="truth supports")
    r0 = z.run_reference(ref, loop="full", seed=2)
    r1 = z.run_reference(ref, loop="full", seed=2, feedforward=lambda r: ff)
    e0, e1 = z.tracking_errors(r0), z.tracking_errors(r1)
    assert r0.success and r1.success
    assert e1.screw[1] < 0.8 * e0.screw[1]
    assert e1.worktable[1] < 0.8 * e0.worktable[1]


def test_nut_driving_sweep_moves_table_against_nut():
    rec = z.differential_sweep(2e-3, [1e-3], driving="nut", hold=0.4, seed=1)
    pm = rec.plateau_means()
    assert rec.success
    assert pm["v_t"][0] == pytest.approx(-1e-3, rel=0.02)         # nut faster: table runs the other way


def _measured_crawl_numbers(crawl):
    rows = {r["table_speed_um_s"]: r for r in crawl.rows}
    assert crawl.status == 0, crawl.message
    # measured (seed 0, 1 s feed): true-velocity ripple CDFS 1001 % / TDMS 960 % at 1 µm/s and 115 / 123 %
    # at 10 µm/s (current-noise jitter of the table); 10 ms averages CDFS 120 / 23 %, TDMS 158 / 30 %
    for v in (1.0, 10.0):
        r = rows[v]
        ratio = r["tdms_ripple_percent"] / r["cdfs_ripple_percent"]
        assert 0.7 < ratio < 1.4, ratio
        assert r["tdms_ripple_10ms_percent"] > 0.8 * r["cdfs_ripple_10ms_percent"]
    assert 500 < rows[1.0]["cdfs_ripple_percent"] < 2000
    return rows


def test_extension_measured_numbers(crawl):
    """The numbers the strict xfail below rests on, outside the xfail (so a change shows)."""
    _measured_crawl_numbers(crawl)


@pytest.mark.xfail(strict=True, raises=AssertionError,
                   reason="physics of our plant: in full closed loop on the 10 nm scale the single drive "
                          "does not crawl — the slow GMS lag of Table 4 (C = 250 N/s, |s|/C ~ 0.45 s) lets the "
                          "PID follow the Stribeck drop, and the 2 mN·m current noise dithers both drives; "
                          "the TDMS carries two motors' noise, so its ripple is not smaller")
def test_extension_tdms_ripple_much_smaller_than_cdfs(crawl):
    rows = _measured_crawl_numbers(crawl)
    # the finding: TDMS ripple much smaller (< half) than the single drive's at every speed
    # (noise-free diagnostics, 2 s feed, 10 ms ripple at 1 µm/s, CDFS vs TDMS: truth 5.1 / 5.0 %;
    # support C x100 19.3 / 4.5 %; x1000 64.0 / 4.7 %; memoryless Stribeck support 80.8 / 4.6 %)
    for v in (1.0, 10.0):
        assert rows[v]["tdms_ripple_10ms_percent"] < 0.5 * rows[v]["cdfs_ripple_10ms_percent"]


def test_extension_mechanism_memoryless_support_noise_free():
    """The mechanism behind the paper's claim is in the plant: with the screw support's lag removed
    (its Stribeck map as a memoryless law) and no current noise, the single drive stick-slips
    (true-velocity ripple over 10 ms > 2x the TDMS's, at 1 and 10 µm/s; the TDMS keeps its shafts
    sliding at 6 mm/s)."""
    import dataclasses

    import frictionkit as fk

    a0 = z.Assumptions(torque_noise=0.0, scale_noise=0.0)
    tf = z.true_friction(a0)
    st = dataclasses.replace(tf, screw_support=fk.Directional(positive=tf.screw_support.positive.static,
                                                               negative=tf.screw_support.negative.static))
    c = z.crawling_comparison((1e-6, 10e-6), duration=1.0, truth=st, assumptions=a0)
    for r in c.rows:
        assert r["cdfs_ripple_10ms_percent"] > 2.0 * r["tdms_ripple_10ms_percent"], r
        assert r["cdfs_stuck_fraction"] > r["tdms_stuck_fraction"], r


def test_memory_and_cospeed_tracking_keep_table_still():
    """Co-speed commands (Fig. 14 at 3 µm/s; §5.4 sinusoid at base 0) turn both shafts together:
    the table stays within ~1 µm while the shafts move (the balls do not roll relative to the nut)."""
    mem = z.memory_test("same", amplitude=2e-6, seed=4)
    x, F = mem.hysteresis("screw")
    assert mem.success and np.ptp(x) > 3.5e-6
    assert np.ptp(mem.x_t_true) < 1e-6
    assert F.max() > 20.0 and F.min() < -20.0                      # the loop reverses the friction
    trk = z.sinusoidal_tracking("same", 0.0, duration=0.5, seed=4)
    assert trk.success and np.ptp(trk.theta1_true) * z.R > 100e-6
    assert np.ptp(trk.x_t_true) < 2e-6


def test_cdfs_is_single_drive():
    m = z.cdfs_machine()
    assert [d.name for d in m.dofs] == ["screw", "table"]
    assert {s.name for s in m.sites} == {"screw_support", "ball_preload", "ball_load", "guide"}
    ref = z.crawl_reference("cdfs", 20e-6, duration=0.8)
    rec = z.run_reference(ref, drive="cdfs", loop="full", seed=1)
    k = ref.eval_from
    assert rec.success
    assert np.mean(rec.v_t_true[k:]) == pytest.approx(20e-6, rel=0.05)
    assert np.all(rec.torque2 == 0.0)


def test_results_summarise_and_plot(crawl):
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    rec = crawl.recordings[(1e-6, "tdms")]
    assert "tdms crawl run" in rec.summary()
    assert "CDFS" in crawl.summary() and "TDMS" in crawl.summary()
    axes = [rec.plot(), rec.plot_hysteresis("screw"), crawl.plot(), z.tracking_errors(rec).plot()]
    assert all(hasattr(ax, "figure") for ax in axes)
    plt.close("all")
