"""Issue 13 campaign, third round: the surfaces that landed on 2026-11-23 (force-driven output error
over several records with rests/masks, ``initial=``, ``FitOptions``, the sdss constant-velocity
screen, ``study`` with the ball-screw preset, ``reproduce ... --robustness --out``). One test per
pattern found; each failed before its fix.

Expected behaviour comes from the campaign's rule (a result, a flagged result, or ONE error naming
its cause; no traceback, no misleading message, no silent wrong answer), not from the code under test.
"""

from __future__ import annotations

import math

import numpy as np
import pytest
from _robustness_helpers import one_error_line, write_csv
from hypothesis import given, settings
from hypothesis import strategies as st

import frictionkit as fk
import frictionkit.cli.identify  # noqa: F401  (registers the verbs)
import frictionkit.cli.reproduce  # noqa: F401
from frictionkit.cli import app
from frictionkit.errors import DataError, FrictionKitError, ParameterError
from frictionkit.identify import FitOptions, fit_output_error, fit_two_step, screen_constant_velocity
from frictionkit.study import StudySpec

DT = 1e-3
LAW = fk.Stribeck(Fc=1.0, Fs=1.5, vs=1e-3, delta=2.0, sigma2=0.4)
TRUE = fk.LuGre(LAW, sigma0=1e5, sigma1=63.2)
FUZZ = settings(deadline=None, derandomize=True, max_examples=60)
START = {"sigma0": 1e5, "sigma1": 63.2}


@pytest.fixture(scope="module")
def records():
    """Two force-driven records (2 N and 1.8 N sines from rest, above the 1.5 N breakaway)."""
    out = []
    for amp, n in ((2.0, 600), (1.8, 500)):
        u = amp * np.sin(np.pi * np.arange(n) * DT * 2 + 0.2)
        sim = fk.simulate(TRUE, plant=fk.Mass(1.0), force=u, dt=DT)
        out.append({"t": np.arange(n) * DT, "x": sim.x, "v": sim.v, "F": u})
    return out


@pytest.fixture(scope="module")
def force_csv(tmp_path_factory, records):
    """The records in one file with a 'rec' column and a 'disabled' column that is 0 everywhere."""
    cols = {k: np.concatenate([r[k] for r in records]) for k in ("t", "x", "v", "F")}
    rec = np.concatenate([np.full(r["t"].size, i + 1.0) for i, r in enumerate(records)])
    return write_csv(tmp_path_factory.mktemp("r3") / "force.csv", rec=rec, disabled=np.zeros(rec.size), **cols)


# --------------------------------------------------------------------------- force-driven output error
def test_a_fit_whose_simulation_runs_is_not_reported_as_a_failed_simulation(records):
    """--mass 1e300: every simulation succeeds (the mass barely moves), but the fit said "the
    simulation fails at the optimum" (a cost as large as the data's was taken for a failure)."""
    res = fit_output_error(records, "lugre", static=LAW, inertia=1e300, initial=START, free=["sigma0"])
    assert not res.success  # sigma0 cannot act on a motion of 1e-300 m
    assert "simulation fails" not in res.message
    assert "sigma0" in res.message  # the cause: no effect of sigma0 on the simulated motion


def test_a_mask_marking_every_sample_is_named_as_the_cause(runner, force_csv):
    """A mask column that is non-zero everywhere was reported as "force logged exactly 0 everywhere?"."""
    res = runner.invoke(app, ["identify", "output-error", str(force_csv), "--time", "t", "--position", "x",
                              "--velocity", "v", "--force", "F", "--Fc", "1", "--Fs", "1.5", "--vs", "1e-3",
                              "--sigma2", "0.4", "--mass", "1", "--group", "rec", "--sigma0", "1e5", "--sigma1",
                              "63.2", "--free", "sigma0", "--mask", "rec"])
    assert res.exit_code == 2
    assert "the rest mask marks every sample as at rest" in one_error_line(res)


def test_a_mask_leaving_only_standstill_is_refused_not_fitted(records):
    """--mask F (the force column as the mask: non-zero wherever the drive acts) left only the
    samples of zero force; the fit ran on them, exit 0, "relative error 1.181e+299 %"."""
    masks = [np.ones(r["t"].size, bool) for r in records]
    for m in masks:
        m[:3] = False  # the first three samples: the axis at rest (v = 0 there), the rest masked
    recs = [dict(r, v=np.where(np.arange(r["t"].size) < 3, 0.0, r["v"])) for r in records]
    with pytest.raises(DataError, match=r"velocity is exactly 0 on every sample the rest mask leaves \(4 samples\)"):
        fit_output_error(recs, "lugre", static=LAW, inertia=1.0, initial=START, free=["sigma0"], rests=masks)


@settings(FUZZ)
@given(rests=st.one_of(st.integers(-3, 3), st.booleans(), st.floats(allow_nan=True), st.sampled_from(
    ["auto", "none", "", None, "nan-mask", "ones", "twos"])),
       min_rest=st.one_of(st.integers(-2, 5), st.booleans(), st.floats(-1, 4), st.none()))
def test_rests_and_min_rest_values_end_in_a_result_or_one_named_error(records, rests, min_rest):
    """rests=5 / True raised a bare TypeError; a NaN mask was taken as all rest; min_rest=True as 1."""
    n = [r["t"].size for r in records]
    mask = {"nan-mask": [np.full(k, np.nan) for k in n], "ones": [np.ones(k) for k in n],
            "twos": [np.full(k, 2.0) for k in n]}
    value = mask.get(rests, rests) if isinstance(rests, str) else rests
    try:
        res = fit_output_error(records, "lugre", static=LAW, inertia=1.0, initial=START, free=["sigma0"],
                               max_nfev=2, rests=value, min_rest=min_rest)
    except FrictionKitError as exc:
        text = str(exc)
        assert "\n" not in text
        assert any(w in text for w in ("rests", "min_rest", "rest mask")), text
        return
    assert rests in ("auto", None)  # only these are legal rests=
    assert not isinstance(min_rest, bool) and isinstance(min_rest, int) and min_rest >= 1
    assert res.n_obs > 0


@pytest.mark.parametrize("value, match", [(True, "initial.sigma0 = True: must be a real number, not a boolean"),
                                          ([1e5, 2.0], r"initial.sigma0 = \[100000.0, 2.0\]: must be a real"),
                                          (math.nan, "initial.sigma0 = nan: must be finite")])
def test_start_values_are_validated_naming_the_key(records, value, match):
    """initial={'sigma0': True} fitted from sigma0 = 1 N/m; a list raised a bare TypeError."""
    with pytest.raises(ParameterError, match=match):
        fit_output_error(records, "lugre", static=LAW, inertia=1.0, initial={"sigma0": value}, max_nfev=2)


_FIELD_VALUES = st.one_of(st.integers(-2, 5), st.booleans(), st.floats(allow_nan=True), st.none(),
                          st.sampled_from(["", "auto", "lm", "trf", "fd", "x", [1]]))


@settings(FUZZ, max_examples=150)
@given(field=st.sampled_from(["starts", "refine", "seed", "max_nfev", "ftol", "xtol", "optimiser",
                              "diff_step", "jacobian", "workers", "profile", "raise_on_failure"]),
       value=_FIELD_VALUES)
def test_fit_options_take_any_value_or_refuse_it_in_one_line(field, value):
    try:
        opts = FitOptions(**{field: value})
    except ParameterError as exc:
        assert field in str(exc) and "\n" not in str(exc)
        return
    got = getattr(opts, field)
    if field not in ("profile", "raise_on_failure"):
        assert not isinstance(got, bool)  # a flag is never a number of starts or a tolerance
    if isinstance(got, float):
        assert math.isfinite(got) and got > 0


# --------------------------------------------------------------------------- sdss constant-velocity screen
@pytest.mark.parametrize("value, match", [(True, "not a boolean"), ("a", "must be a real number"),
                                          (math.nan, "finite"), (0.0, "> 0")])
def test_max_ripple_percent_is_validated_up_front(value, match):
    """True was a 1 % threshold, 'a' a TypeError; fit_two_step ignored a bad value when the screen
    did not run."""
    steady = {"v": np.r_[np.linspace(0.1, 1, 6), -np.linspace(0.1, 1, 6)], "F": np.ones(12),
              "ripple_percent": np.ones(12)}
    with pytest.raises(ParameterError, match=f"screen_constant_velocity.max_ripple_percent.*{match}"):
        screen_constant_velocity(steady, max_ripple_percent=value)
    with pytest.raises(ParameterError, match=f"fit_two_step.max_ripple_percent.*{match}"):
        fit_two_step(inertia=1.0, triangle={}, steady={"v": [], "F": []}, max_ripple_percent=value)


# --------------------------------------------------------------------------- study spec
@pytest.mark.parametrize("section, key, value, match", [
    ("reference", "dt", "x", "dt = 'x'"),  # was ValueError: could not convert string to float
    ("study", "seed", -1, "seed = -1"),
    ("study", "seed", True, "seed = True"),
    ("study", "seed", 1.5, "seed = 1.5"),
    ("study", "compensators", ["none", "none"], "each compensator once"),
    ("reference", "frequency", 1e300, "half the sample rate"),  # every run: "Reference.a[0] = inf"
    ("reference", "duration", 1e-300, "shorter than two samples"),  # every run: "has 1 samples"
    ("reference", "amplitude", 0.0, "amplitude = 0.0: must be > 0"),  # every run: cosine_reference
])
def test_ballscrew_study_spec_refuses_in_one_line(section, key, value, match):
    parts = {"machine": {"preset": "ballscrew"}, "reference": {}, "study": {}}
    parts[section][key] = value
    with pytest.raises(DataError, match=match):
        StudySpec(**parts)


def test_a_study_too_large_to_list_is_refused_before_listing_it():
    """draws = seeds = 100000 (each within its own limit): 4e10 runs listed in memory; the process was
    killed by the kernel's OOM killer."""
    with pytest.raises(DataError, match=r"draws x seeds x compensators = 40,000,000,000 runs; at most 1,000,000"):
        StudySpec(machine={"preset": "ballscrew"}, study={"draws": 100000, "seeds": 100000})


_ANY = st.one_of(st.floats(allow_nan=True), st.integers(-5, 10**6), st.booleans(), st.none(),
                 st.sampled_from(["", "x", "sliding", "fig2", [], ["none"], {}]))


@settings(FUZZ, max_examples=150)
@given(preset=st.sampled_from(["ballscrew", "emps", "custom"]),
       section=st.sampled_from(["machine", "reference", "study", "spread"]),
       key=st.sampled_from(["mass", "guide_friction", "nut_friction", "presliding_length", "nut_model", "stage",
                            "Fc", "amplitude", "frequency", "duration", "dt", "draws", "seeds", "seed",
                            "compensators"]),
       value=_ANY)
def test_any_study_spec_edit_builds_or_fails_with_data_error(preset, section, key, value):
    parts = {"machine": {"preset": preset}, "reference": {}, "study": {}, "spread": None}
    if section == "spread":
        parts["spread"] = {key: value}
    else:
        parts[section][key] = value
    try:
        spec = StudySpec(**parts)
    except DataError as exc:
        assert "\n" not in str(exc)
        return
    ref = spec.reference
    assert ref["frequency"] * ref["dt"] < 0.5 and ref["duration"] >= 2 * ref["dt"]
    s = spec.study["seed"]
    assert not isinstance(s, bool) and isinstance(s, int) and s >= 0
    total = spec.study["draws"] * spec.study["seeds"] * len(spec.study["compensators"])
    assert total <= 1_000_000  # 100000 x 100000 draws x seeds listed 1e10 runs: the process was killed
    if total <= 2000:
        labels = [r["run"] for r in spec.runs()]
        assert len(labels) == len(set(labels)) == total


# --------------------------------------------------------------------------- reproduce --robustness --out
@pytest.mark.parametrize("verb", ["zhu-fujimoto", "zhang2023"])
def test_robustness_out_under_a_file_is_refused_before_the_sweep(runner, tmp_path, verb):
    """--out FILE/sub failed after start-up with a bare "Not a directory" (no option named)."""
    f = tmp_path / "keep.txt"
    f.write_text("keep")
    res = runner.invoke(app, ["reproduce", verb, "--robustness", "--quick", "--workers", "0",
                              "--json", str(tmp_path / "r.json"), "--out", str(f / "sub")])
    assert res.exit_code == 2
    assert one_error_line(res) == f"error: --out '{f / 'sub'}': '{f}' is a file, not a folder"
    assert f.read_text() == "keep" and not (tmp_path / "r.json").exists()


# --------------------------------------------------------------------------- loaders: --group / --where
@pytest.mark.parametrize("option", [["--group", "rec"], ["--where", "rec=1"]])
def test_a_repeated_group_or_where_column_is_refused(runner, tmp_path, option):
    """A header 'rec,t,x,v,u,rec': --group rec / --where rec=1 used the first 'rec' silently (the
    signal columns were already refused)."""
    path = tmp_path / "dup.csv"
    t = np.arange(50) * DT
    path.write_text("rec,t,x,v,u,rec\n" + "".join(f"1,{a!r},0,0,1,2\n" for a in t), encoding="utf-8")
    res = runner.invoke(app, ["identify", "output-error", str(path), "--time", "t", "--position", "x", "--velocity",
                              "v", "--force", "u", "--Fc", "1", "--mass", "1", *option])
    assert res.exit_code == 2
    assert "column 'rec' (given for " in one_error_line(res) and "appears 2 times in the header (columns 1, 6)" \
        in one_error_line(res)


def test_presliding_rests_that_cut_the_motion_too_finely_are_named():
    """Force logged 0 at every third sample with min_rest=1: every run between rests is 2-3 samples
    long; the error said "the position does not move" of a 100 µm stroke."""
    from frictionkit.identify import fit_presliding

    x = np.r_[np.linspace(0, 50e-6, 301), np.linspace(50e-6, -50e-6, 601)[1:]]
    F = fk.simulate(fk.GMS(LAW, k=[4e5, 1e5, 2e4], xi=[0.2, 0.3, 0.5], C=20.0), position=x, dt=DT).friction
    F[::3] = 0.0
    rec = {"t": np.arange(x.size) * DT, "x": x, "F": F}
    with pytest.raises(DataError, match=r"no pre-sliding branch of 4 samples in any of the \d+ runs between rests "
                                        r"\(longest 3 samples\).*raise min_rest \(now 1\)"):
        fit_presliding(rec, elements=3, static=LAW, min_rest=1)
    fit_presliding(rec, elements=3, static=LAW, rests=None)  # the same record without the cut fits


def test_a_force_of_zero_everywhere_is_refused_not_called_unidentifiable(records):
    """u = 0 on every fitted sample (a rest mask kept the cut off): exit 0 with "sigma0 unidentifiable"."""
    recs = [dict(r, F=np.zeros(r["t"].size)) for r in records]
    masks = [np.zeros(r["t"].size, bool) for r in records]
    with pytest.raises(DataError, match="the applied force is exactly 0 on every sample to fit"):
        fit_output_error(recs, "lugre", static=LAW, inertia=1.0, initial=START, free=["sigma0"], rests=masks)


@pytest.mark.parametrize("rows, expect", [
    ("0,1,\n1,2,\n", {"t": [0.0, 1.0], "x": [1.0, 2.0]}),  # a trailing delimiter: read without the shift
    ("0,1,7\n1,2,8\n", r"header names 2 column\(s\) but the data rows have 3 fields"),
    ("0,1,\n1,2,8\n", r"header names 2 column\(s\) but the data rows have 3 fields"),
])
def test_rows_with_more_fields_than_the_header_never_shift_the_columns(tmp_path, rows, expect):
    """Header 't,x' over rows '0,1,<extra>': pandas took the first field as the index and every name
    moved one column right — 't' read x, 'x' read the extra field (NaN) — silently."""
    from frictionkit.data import read_table

    path = tmp_path / "f.csv"
    path.write_text("t,x\n" + rows, encoding="utf-8")
    if isinstance(expect, str):
        with pytest.raises(DataError, match=expect):
            read_table(path)
        return
    got = read_table(path)
    assert list(got) == ["t", "x"]
    for k, v in expect.items():
        np.testing.assert_array_equal(got[k], v)


def test_irregular_sampling_names_the_step(records):
    """A dropped row: "irregular sampling; call Recording.resample() first" with no place."""
    r = records[0]
    keep = np.arange(r["t"].size) != 100
    rec = {k: v[keep] for k, v in r.items()}
    with pytest.warns(fk.data.recording.IrregularSamplingWarning), pytest.raises(
            DataError, match=r"the step at t = 0\.099 s \(sample 99\) is 0\.002 s against a median of 0\.001 s"):
        fit_output_error(rec, "lugre", static=LAW, inertia=1.0, initial=START)


def test_study_json_and_out_naming_one_file_say_so(runner, tmp_path):
    """--out S.parquet --json S.parquet: "--json ... is the input file" (the results file is an output)."""
    import frictionkit.cli as _cli

    _cli._register()
    spec = tmp_path / "s.toml"
    spec.write_text('[machine]\npreset = "ballscrew"\n[study]\ndraws = 1\ncompensators = ["none"]\n', encoding="utf-8")
    out = tmp_path / "s.parquet"
    res = runner.invoke(app, ["study", str(spec), "--out", str(out), "--json", str(out), "--workers", "0"])
    assert res.exit_code == 2
    assert one_error_line(res) == f"error: --json '{out}' and --out '{out}' name the same file"
    assert not out.exists()
