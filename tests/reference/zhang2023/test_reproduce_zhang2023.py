"""Seed 000 findings on the simulated TDMS (frictionkit.reproduce.zhang2023), issue 9 "Findings to test".

One reduced run (``TEST_DESIGN``: fewer plateaus, two base speeds, 1.5 s tracking, the memory
test at 10 µm/s, crawling at 1 µm/s only, no simulation refinement of the creep fits) is
computed once per module (~20 s). Where our physically consistent plant agrees with the paper
the finding is asserted; where it does not, a strict xfail first asserts what we measured and
then states the paper's claim. The numbers of the --quick and full runs are in the reproduce
module's docstring / the report; this file fixes the measured relations, not exact values.

Paper values cited: Table 7 (ACIM -> WSIM), Table 8 (LuGre -> GMS), §5.3 / Fig. 16.
"""

from __future__ import annotations

import json

import numpy as np
import pytest

from frictionkit.reproduce import zhang2023 as zr

TEST_DESIGN = zr.Design(cospeed_slow=(0.05e-3, 0.15e-3, 0.4e-3), cospeed_fast=(1e-3, 5e-3, 20e-3), hold_slow=1.5,
                        hold_fast=0.3, diff_bases=(0.0, 6e-3), diff_slow=(0.03e-3, 0.1e-3),
                        diff_fast=(0.3e-3, 1e-3, 2.5e-3, 5e-3), diff_hold_slow=1.0, tracking_duration=1.5,
                        memory_speed=10e-6, crawl_speeds=(1e-6,), crawl_duration=1.0, polish=False, m7_samples=120)
TIE = zr.TIE_UM

# the module's run costs ~20-30 s: keep its tests on one xdist worker so it runs once
# (`make test` runs pytest with --dist loadgroup; see tests/conftest.py for pytest 9)
pytestmark = pytest.mark.xdist_group("zhang2023_run")


@pytest.fixture(scope="module")
def result():
    return zr.run(quick=True, seed=0, design=TEST_DESIGN)


@pytest.fixture(scope="module")
def summary(result):
    return result.to_dict()


@pytest.fixture(scope="module")
def found(summary):
    return zr.findings(summary)


def _cell(summary, table, key, speeds, base, structure="worktable"):
    for r in summary[table]:
        if r.get("method", r.get("model")) == key and r["speeds"] == speeds and r["base_speed_mm_s"] == base \
                and r["structure"] == structure:
            return abs(r["mean_um"]), r["std_um"]
    raise KeyError((table, key, speeds, base, structure))


# --------------------------------------------------------------------------- JSON layout (issue)
def test_json_layout(summary):
    json.dumps(summary)                                           # plain JSON
    assert len(summary["table7"]) == 24 and len(summary["table8"]) == 24
    for r in summary["table7"]:
        assert {"speeds", "base_speed_mm_s", "structure", "method", "mean_um", "std_um"} <= set(r)
        assert r["speeds"] in ("same", "different") and r["base_speed_mm_s"] in (0, 6)
        assert r["method"] in ("ACIM", "WSIM") and r["structure"] in ("screw", "nut", "worktable")
    assert {r["model"] for r in summary["table8"]} == {"LuGre", "GMS"}
    assert set(summary["identified"]) == {"table3", "table4", "table5", "table6"}
    h = summary["hysteresis_rms_force_N"]
    assert set(h["reciprocating"]) >= {"LuGre", "GMS"} and set(h["unidirectional"]) >= {"LuGre", "GMS"}
    assert {"table_speed_um_s", "cdfs_ripple_percent", "tdms_ripple_percent"} <= set(summary["crawling"][0])
    # Table 7 paper values beside ours (Table 7, same speed 6 mm/s, worktable: -0.328 (0.102) -> -2.5 (0.532))
    r = next(r for r in summary["table7"] if r["speeds"] == "same" and r["base_speed_mm_s"] == 6
             and r["structure"] == "worktable" and r["method"] == "WSIM")
    assert (r["paper_mean_um"], r["paper_std_um"]) == (-2.5, 0.532)


def test_tables_3_to_6_identified(summary, result):
    t = summary["identified"]
    assert set(t["table3"]["identified"]) == {"screw +", "nut +", "screw -", "nut -"}
    assert t["table3"]["plant_truth"]["screw +"]["T_S_N"] == pytest.approx(113.5)   # Table 3, the plant's truth
    for col in ("screw +", "nut +", "screw -", "nut -"):
        assert len(t["table4"]["identified"][col]["P_points_um_N"]) >= 1
    assert {"nut +", "nut -", "screw +", "screw -"} <= set(t["table5"]["identified"])
    assert set(t["table6"]["identified"]) == {"positive", "negative"}
    assert result.wsim.status in (0, 1) and result.acim.status in (0, 1)


# --------------------------------------------------------------------------- Table 7
def test_table7_differential_base0_wsim_better(summary, found):
    am, as_ = _cell(summary, "table7", "ACIM", "different", 0)
    wm, ws_ = _cell(summary, "table7", "WSIM", "different", 0)
    assert wm < am - TIE and ws_ < as_ - TIE           # Table 7: -13.2 (12.7) -> 1.5 (8.5)
    assert found["t7_diff0_wsim_better"]["holds"]


@pytest.mark.xfail(strict=True, raises=AssertionError,
                   reason="differential 6 mm/s: with the screw support sliding at 6 mm/s the component sum "
                          "(ACIM) already matches the lumped torque; WSIM's nearest-base curves add no accuracy")
def test_table7_differential_base6_wsim_better(summary):
    am, as_ = _cell(summary, "table7", "ACIM", "different", 6)
    wm, ws_ = _cell(summary, "table7", "WSIM", "different", 6)
    # measured (seed 0): ACIM 0.0003 (0.037) µm, WSIM 0.004 (0.041) µm — tens of nm, the scale counts 10 nm
    assert ws_ > as_ and wm > am
    assert ws_ < 0.1 and as_ < 0.1
    assert wm < am - TIE and ws_ < as_ - TIE           # paper: -13.1 (12.7) -> 5.5 (5.7)


@pytest.mark.xfail(strict=True, raises=AssertionError,
                   reason="co-speed: the table stands still, its error is the scale's noise with either "
                          "feed-forward (base 6), and WSIM's per-shaft GMS is no worse at base 0")
@pytest.mark.parametrize("base", [0, 6])
def test_table7_cospeed_acim_better(summary, base):
    am, as_ = _cell(summary, "table7", "ACIM", "same", base)
    wm, ws_ = _cell(summary, "table7", "WSIM", "same", base)
    # measured (seed 0): base 6 ACIM 0.0007 (0.0085), WSIM 0.0007 (0.0085) µm — a tie;
    # base 0 ACIM 0.003 (0.045), WSIM 0.002 (0.037) µm
    assert ws_ <= as_ + TIE and wm <= am + TIE
    assert am < wm - TIE and as_ < ws_ - TIE           # paper: ACIM 86.9 % / 80.8 % better (base 6)


# --------------------------------------------------------------------------- Table 8
@pytest.mark.parametrize("speeds,base", [("same", 6), ("same", 0), ("different", 6)])
def test_table8_gms_not_worse(summary, speeds, base):
    lm, ls = _cell(summary, "table8", "LuGre", speeds, base)
    gm, gs = _cell(summary, "table8", "GMS", speeds, base)
    assert gm <= lm + TIE and gs <= ls + TIE          # Table 8: GMS no worse in all four cases


@pytest.mark.xfail(strict=True, raises=AssertionError,
                   reason="differential 0 mm/s: GMS halves the std but its |mean| is a few nm larger")
def test_table8_gms_not_worse_differential0(summary):
    lm, ls = _cell(summary, "table8", "LuGre", "different", 0)
    gm, gs = _cell(summary, "table8", "GMS", "different", 0)
    # measured (seed 0): LuGre 0.0004 (0.138), GMS 0.0027 (0.046) µm
    assert gs < 0.5 * ls
    assert gm > lm + TIE
    assert gm <= lm + TIE and gs <= ls + TIE           # paper: 1.3 (19.5) -> -0.444 (18.6)


# --------------------------------------------------------------------------- Fig. 16
def test_fig16_reciprocating_gms_closer(summary):
    h = summary["hysteresis_rms_force_N"]["reciprocating"]
    assert h["GMS"] < h["LuGre"]                        # §5.3: LuGre cannot describe non-local memory


@pytest.mark.xfail(strict=True, raises=AssertionError,
                   reason="unidirectional legs: the LuGre built on the same static map (sigma0 = sum k) "
                          "bends too early into sliding; GMS-3 is closer here as well")
def test_fig16_unidirectional_lugre_closer(summary):
    h = summary["hysteresis_rms_force_N"]["unidirectional"]
    # measured (TEST_DESIGN, seed 0): LuGre 18.4 N, GMS-3 5.3 N (linear-equivalent)
    assert h["GMS"] < h["LuGre"]
    assert h["LuGre"] < h["GMS"]                        # paper: LuGre smoother and closer (§5.3)


def test_fig16_has_m3_and_m7(result):
    assert {"LuGre", "GMS M=3", "GMS M=7", "GMS M=3 (one k set)"} <= set(result.fig16.rms)


def test_fig16_m7_one_stiffness_set_beats_m3(summary):
    """§5.3 citing ref. [30]: 6-7 elements describe non-local memory better than M = 3. Both fitted
    the same way (one stiffness set for both directions, joint simulation error on step 4's two
    records), M = 7 is closer on the nested reciprocating legs. (The per-direction GMS-7 of an
    earlier version scored 20.9 N against M = 3's 5.7 N: its directions' elements did not
    correspond; see fit_gms_one_stiffness.)"""
    h = summary["hysteresis_rms_force_N"]["reciprocating"]
    # measured (TEST_DESIGN, seed 0): M=7 0.96 N, M=3 one k set 2.17 N, M=3 per direction 6.4 N
    assert h["GMS_M7"] < 0.7 * h["GMS_M3_one_k_set"]
    assert h["GMS_M7"] < h["GMS"]


# --------------------------------------------------------------------------- WSIM recovery
#: Tolerance on the lumped per-mode friction (RMS error over the identification plateaus, relative
#: to the RMS level of the truth): 10 %. Why: the plateau means carry the drives' torque noise
#: (2 mN·m = 2.5 N linear, averaged) and the models are structurally simpler than the truth
#: (exponential Stribeck vs GMS-7 sites); 10 % of ~100 N is the 10 N that separates the co-speed
#: and differential levels of Tables 3 and 5 — a coarser recovery could not tell the modes apart.
RECOVERY_TOL = 0.10


@pytest.mark.parametrize("key", ["differential_screw_b0", "differential_screw_b6", "differential_nut_tdmssc",
                                 "differential_nut_b0", "cospeed_sum"])
def test_wsim_recovers_lumped_friction(summary, key):
    assert summary["wsim_recovery"][key]["relative"] < RECOVERY_TOL


@pytest.mark.xfail(strict=True, raises=AssertionError,
                   reason="co-speed per shaft: two position loops with integral action hold a history-dependent "
                          "internal force through the preloaded ball pair (statically indeterminate), so each "
                          "shaft's K_t i_q is its support friction +- ~10 N; only the sum is recovered")
def test_wsim_recovers_cospeed_per_shaft(summary):
    rec = summary["wsim_recovery"]
    # measured (seed 0): screw 10.5 %, nut 21.8 %, sum 8.4 %; the screw's logged torque itself is 10.7 % off
    assert rec["cospeed_logged_vs_truth_screw"]["relative"] > RECOVERY_TOL
    assert rec["cospeed_sum"]["relative"] < RECOVERY_TOL
    assert max(rec["cospeed_screw"]["relative"], rec["cospeed_nut"]["relative"]) < RECOVERY_TOL


# --------------------------------------------------------------------------- extension (ours)
@pytest.mark.xfail(strict=True, raises=AssertionError,
                   reason="crawling (ours): at 1 µm/s the TDMS's true table velocity ripples as much as the "
                          "single drive's in this plant (the table-mode jitter of the current noise dominates)")
def test_crawling_tdms_smoother(summary):
    r = summary["crawling"][0]
    # measured (seed 0): CDFS 1001 %, TDMS 960 % (std of the true velocity / 1 µm/s)
    assert r["table_speed_um_s"] == 1.0 and r["cdfs_ripple_percent"] > 100 and r["tdms_ripple_percent"] > 100
    assert r["tdms_ripple_percent"] < 0.5 * r["cdfs_ripple_percent"]


# --------------------------------------------------------------------------- robustness (tiny form) and CLI
def test_robustness_aggregates_variants(monkeypatch, result, summary):
    calls = []

    class _Fake:
        def __init__(self, s):
            self._s = s

        def to_dict(self):
            return self._s

    def fake_run(*, quick, seed, assumptions, design, crawling):
        calls.append((seed, assumptions.guide_level))
        s = json.loads(json.dumps(summary))
        f = assumptions.guide_level / 6.0                 # scale the worktable errors with the guide level
        for r in s["table7"] + s["table8"]:
            r["std_um"] *= f
        return _Fake(s)

    monkeypatch.setattr(zr, "run", fake_run)
    out = zr.robustness(quick=True, seeds=(0, 1), factors=(0.8, 1.2), names=("guide_level", "table_mass"))
    assert len(calls) == 2 + 2 * 2
    assert set(out["holds_fraction"]) == set(zr.findings(summary))
    assert out["ranking"][0] == "guide_level" and out["sensitivity"]["table_mass"] == 0.0
    assert out["runtime_s"] >= 0.0
    assert out["not_evaluated"] == {} and set(out["evaluated"].values()) == {6}


def test_robustness_names_a_variant_whose_m7_fit_failed(monkeypatch, summary):
    """A variant whose GMS M = 7 fit fails (as table_mass x1.2 did in the full robustness run of
    2026-11-23) is named under not_evaluated with the reason, left out of that finding's fraction,
    and its summary line says NOT EVALUATED (it was dropped silently: 24/24 of 25)."""
    assert "GMS_M7" in summary["hysteresis_rms_force_N"]["reciprocating"]
    why = "GMS M=7: fit_gms_one_stiffness (M = 7): no eq. 19 start for the negative record: ..."

    class _Fake:
        def __init__(self, s):
            self._s = s

        def to_dict(self):
            return self._s

    def fake_run(*, quick, seed, assumptions, design, crawling):
        s = json.loads(json.dumps(summary))
        if assumptions.table_mass > 8.0:
            h = s["hysteresis_rms_force_N"]
            for part in ("reciprocating", "unidirectional"):
                h[part].pop("GMS_M7")
            h["detail"]["message"] = why
        return _Fake(s)

    monkeypatch.setattr(zr, "run", fake_run)
    out = zr.robustness(quick=True, seeds=(0,), factors=(0.8, 1.2), names=("table_mass",))
    key = "fig16_reciprocating_m7_better"
    assert out["not_evaluated"] == {key: {"table_massx1.2": why}}
    assert out["evaluated"][key] == 2 and out["evaluated"]["fig16_reciprocating_gms_better"] == 3
    assert out["holds_fraction"][key] in (0.0, 1.0)
    f = zr.findings(fake_run(quick=True, seed=0, assumptions=zr.Z.Assumptions(table_mass=9.6), design=None,
                             crawling=False).to_dict())
    assert f[key]["holds"] is None and f[key]["not_evaluated"] == why


def test_fit_gms_one_stiffness_starts_where_eq19_fails_at_m7():
    """Where eq. 19 at M = 7 finds no concave virgin branch in a record (the table_mass x1.2
    variant's negative record: slope -1.7 -> 43 N/m at breakpoint 2), the one-stiffness-set fit
    starts from WSIM's retries (fewer elements padded to M, named in notes) instead of failing.
    Here: a noise-free GMS-7 (truth chosen here) whose negative record defeats eq. 19 at M = 7
    at 91 virgin samples (measured: M = 3 is the first that fits there); 8 evaluations."""
    import frictionkit as fk
    from frictionkit.data.recording import Recording
    from frictionkit.errors import IdentificationError
    from frictionkit.identify.presliding import fit_presliding

    st = fk.Directional(positive=fk.Stribeck(Fc=1.0, Fs=1.2, vs=1e-3), negative=fk.Stribeck(Fc=1.1, Fs=1.3, vs=1e-3))
    k = [8e5, 4e5, 2e5, 1e5, 5e4, 2.5e4, 1.2e4]
    true = fk.Directional(positive=fk.GMS(st.positive, k=k, xi=[.1, .15, .15, .2, .15, .15, .1], C=20.0),
                          negative=fk.GMS(st.negative, k=k, xi=[.2, .2, .1, .1, .15, .15, .1], C=20.0))
    dt, A, nv = 2e-3, 60e-6, 91
    recs = {}
    for lab, s in (("positive", 1.0), ("negative", -1.0)):
        x = s * np.r_[np.linspace(0, A, nv), np.linspace(A, -A, 2 * nv - 1)[1:]]
        recs[lab] = Recording(t=np.arange(x.size) * dt, x=x, F=fk.simulate(true, position=x, dt=dt).friction)
    with pytest.raises(IdentificationError, match="not concave"):
        fit_presliding(recs["negative"], elements=7, static=st, branch="virgin", polish=False, raise_on_failure=True)
    notes = []
    g = zr.fit_gms_one_stiffness(recs, {"positive": st, "negative": st}, elements=7, max_nfev=8, notes=notes)
    assert len(g.positive.k) == 7 and list(g.positive.k) == list(g.negative.k)
    assert len(notes) == 1 and notes[0].startswith("negative: ") and "padded to M = 7" in notes[0]
    err = np.concatenate([fk.simulate(g, position=r.x, dt=dt).friction - r.F for r in recs.values()])
    assert np.sqrt(np.mean(err ** 2)) < 0.05 * 1.3          # measured 0.023 of Fs = 1.3


def test_cli_writes_json_and_plot(monkeypatch, tmp_path, result):
    from typer.testing import CliRunner

    from frictionkit.cli import _register, app

    _register()
    monkeypatch.setattr(zr, "run", lambda **kw: result)
    out = tmp_path / "z.json"
    res = CliRunner().invoke(app, ["reproduce", "zhang2023", "--quick", "--json", str(out)])
    assert res.exit_code == 0, res.output
    doc = json.loads(out.read_text())
    assert doc["plot"] == "z.png" and (tmp_path / "z.png").stat().st_size > 1000
    assert "findings" in doc and np.isfinite(doc["table7"][0]["mean_um"])
    res = CliRunner().invoke(app, ["reproduce", "zhang2023", "--seed", "-1", "--json", str(out)])
    assert res.exit_code != 0 and "--seed" in res.output


def test_fit_gms_one_stiffness_recovers_a_known_gms():
    """fit_gms_one_stiffness on noise-free records of a GMS with one stiffness set (the plant's
    structure): both directions' virgin strokes break every element, the fit recovers k and
    both weight sets. Truth chosen here (no paper values: a recovery check of the procedure)."""
    import frictionkit as fk
    from frictionkit.data.recording import Recording

    st = fk.Directional(positive=fk.Stribeck(Fc=1.0, Fs=1.2, vs=1e-3), negative=fk.Stribeck(Fc=1.1, Fs=1.3, vs=1e-3))
    k = [4e5, 1e5, 2e4]                                      # N/m; break-away strokes 0.9-26 µm
    true = fk.Directional(positive=fk.GMS(st.positive, k=k, xi=[0.3, 0.3, 0.4], C=20.0),
                          negative=fk.GMS(st.negative, k=k, xi=[0.5, 0.3, 0.2], C=20.0))
    dt, A = 2e-3, 60e-6
    recs = {}
    for lab, s in (("positive", 1.0), ("negative", -1.0)):
        x = s * np.r_[np.linspace(0, A, 301), np.linspace(A, -A, 601)[1:]]
        recs[lab] = Recording(t=np.arange(x.size) * dt, x=x, F=fk.simulate(true, position=x, dt=dt).friction)
    g = zr.fit_gms_one_stiffness(recs, {"positive": st, "negative": st}, elements=3)
    np.testing.assert_allclose(np.sort(g.positive.k)[::-1], k, rtol=0.05)
    np.testing.assert_array_equal(g.positive.k, g.negative.k)
    np.testing.assert_allclose(g.positive.xi, [0.3, 0.3, 0.4], atol=0.03)
    np.testing.assert_allclose(g.negative.xi, [0.5, 0.3, 0.2], atol=0.03)


def test_summary_text_lists_every_finding(result, found):
    """summary() is the findings as text: one line per finding, its verdict matching findings()."""
    text = result.summary()
    assert isinstance(text, str)
    for name, f in found.items():
        line = next(ln for ln in text.splitlines() if f" {name} " in ln + " ")
        assert ("DOES NOT HOLD" not in line) == f["holds"], line
    # the WSIM steps present themselves the same way: text per step, JSON-ready dict per step
    wtext = result.wsim.summary()
    assert all(step.name in wtext for step in result.wsim.steps.values())
    assert set(result.wsim.to_dict()) == {"status", "message", *result.wsim.steps}
