"""Issue 13 campaign, second round: the verbs and APIs that landed later (export, simulate_machine
options, identify rigid-body --law stribeck, the .tdms loader, reproduce zhang2023 --robustness,
fleet [layout] constants). One test per pattern found; each failed before its fix.

Expected behaviour comes from the campaign's rule (exit 0 with a sound result, or ONE ``error:``
line; no traceback, no silent wrong answer, no lost file), not from the code under test.
"""

from __future__ import annotations

import io
import logging

import numpy as np
import pytest
from _robustness_helpers import one_error_line, stderr_of, write_csv
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

import frictionkit as fk
import frictionkit.cli as _cli
from frictionkit.cli import app
from frictionkit.errors import FrictionKitError, ParameterError

_cli._register()  # simulate, export, models, fleet verbs (the entry point does this)
FUZZ = settings(deadline=None, derandomize=True, suppress_health_check=[HealthCheck.function_scoped_fixture])
LUGRE = fk.LuGre(fk.Stribeck(Fc=1.0, Fs=1.5, vs=1e-3, delta=2.0, sigma2=0.4), sigma0=1e5, sigma1=300.0)


@pytest.fixture(scope="module")
def lugre_json(tmp_path_factory):
    return fk.save_model(LUGRE, tmp_path_factory.mktemp("model") / "lugre.json")


# --------------------------------------------------------------------------- export
@settings(FUZZ, max_examples=25)
@given(v_max=st.one_of(st.floats(min_value=1e-320, max_value=1e308), st.sampled_from([1e308, 1e-320, 1e13, 1e-13])))
def test_export_csv_table_is_finite_and_uniform_or_refused(runner, lugre_json, tmp_path, v_max):
    """--v-max 1e308 wrote a table of nan/inf, 1e-320 a non-uniform grid, both with exit 0."""
    out = tmp_path / "t.csv"
    out.unlink(missing_ok=True)
    res = runner.invoke(app, ["export", str(lugre_json), "--format", "csv", "--out", str(out), "--points", "11",
                              "--v-max", repr(v_max)])
    if res.exit_code != 0:
        assert "--v-max" in one_error_line(res) or "v_max" in one_error_line(res)
        assert not out.exists()
        return
    v, F = np.loadtxt(out, delimiter=",", skiprows=1, unpack=True)
    assert np.all(np.isfinite(v)) and np.all(np.isfinite(F))
    step = np.diff(v)
    assert np.all(step > 0)
    np.testing.assert_allclose(step, 2 * v_max / 10, rtol=1e-6)  # uniform: 11 points over [-v_max, v_max]


@pytest.mark.filterwarnings("ignore:overflow encountered:RuntimeWarning")  # the overflow is the case under test
def test_export_overflowing_map_is_refused_naming_v_max():
    with pytest.raises(ParameterError, match="v_max.*not finite"):
        from frictionkit.export import lookup_table

        lookup_table(fk.CoulombViscous(Fc=1.0, sigma2=1e300), v_max=1e10, points=3)


def test_export_empty_name_is_refused_not_replaced_by_the_default(runner, lugre_json, tmp_path):
    out = tmp_path / "f.h"
    res = runner.invoke(app, ["export", str(lugre_json), "--format", "c", "--out", str(out), "--name", ""])
    assert res.exit_code == 2 and "name = ''" in one_error_line(res)
    assert not out.exists()


# --------------------------------------------------------------------------- simulate_machine
def _slider():
    m = fk.Machine("slider")
    x = m.dof("x", inertia=1.0)
    m.friction("site", x, law=fk.CoulombViscous(Fc=1.0))
    m.actuator("u", x)
    return m


@settings(FUZZ, max_examples=10)
@given(max_substeps=st.one_of(st.booleans(), st.floats(allow_nan=True), st.integers(-5, 0), st.text(max_size=3)))
def test_simulate_machine_bad_max_substeps_is_refused_without_atol(max_substeps):
    """max_substeps = True, 2.5 or -1 passed silently when atol was not given."""
    with pytest.raises(ParameterError, match="max_substeps"):
        fk.simulate_machine(_slider(), dt=1e-3, inputs={"u": np.zeros(11)}, max_substeps=max_substeps)


# --------------------------------------------------------------------------- identify rigid-body --law stribeck
@pytest.fixture(scope="module")
def reversal_csv(tmp_path_factory):
    t = np.arange(2000) * 1e-3
    x = 1e-3 * np.sin(2 * np.pi * 2 * t)
    v = np.gradient(x, t)
    F = LUGRE.static.steady_state(v) + 0.01 * np.random.default_rng(0).standard_normal(t.size)
    return write_csv(tmp_path_factory.mktemp("rev") / "rev.csv", t_s=t, x_m=x, F_N=F)


@pytest.mark.parametrize("delta", ["100", "1e300"])
def test_rigid_body_stribeck_extreme_delta_ends_cleanly(runner, reversal_csv, delta):
    """--delta 100 ended in 'unexpected OverflowError' (exp of the solver's log vs step)."""
    res = runner.invoke(app, ["identify", "rigid-body", str(reversal_csv), "--time", "t_s", "--position", "x_m",
                              "--force", "F_N", "--law", "stribeck", "--asymmetric", "--decimate", "1", "--skip", "0",
                              "--delta", delta])
    assert res.exception is None or isinstance(res.exception, SystemExit), repr(res.exception)
    if res.exit_code != 0:
        assert "bug in frictionkit" not in one_error_line(res)


# --------------------------------------------------------------------------- .tdms loader
def test_truncated_tdms_prints_nothing_besides_the_error(tmp_path):
    """npTDMS's own console handler printed two '[nptdms.reader WARNING]' lines before the error."""
    from nptdms import ChannelObject, TdmsWriter

    from frictionkit.data.loaders import read_table

    p = tmp_path / "log.tdms"
    with TdmsWriter(p) as w:
        w.write_segment([ChannelObject("g", "t", np.arange(2000) * 1e-3), ChannelObject("g", "x", np.zeros(2000))])
    p.write_bytes(p.read_bytes()[:-5000])
    before = p.read_bytes()
    handlers = [h for n in ("nptdms.reader", "nptdms.tdms_segment") for h in logging.getLogger(n).handlers
                if isinstance(h, logging.StreamHandler)]
    buf = io.StringIO()
    old = [h.setStream(buf) for h in handlers]
    try:
        with pytest.raises(FrictionKitError, match="truncated TDMS"):
            read_table(p)
    finally:
        for h, s in zip(handlers, old):
            h.setStream(s)
    assert buf.getvalue() == ""
    assert p.read_bytes() == before
    assert all(logging.getLogger(n).handlers == [h] for n, h in
               zip(("nptdms.reader", "nptdms.tdms_segment"), handlers))  # npTDMS's handlers are back


# --------------------------------------------------------------------------- reproduce zhang2023 --robustness
def test_robustness_out_same_as_json_is_refused_before_the_sweep(runner, tmp_path):
    """--json X --out X ran the whole sweep, then failed writing --json into the folder."""
    same = tmp_path / "res"
    res = runner.invoke(app, ["reproduce", "zhang2023", "--robustness", "--workers", "0", "--json", str(same),
                              "--out", str(same)])
    assert res.exit_code == 2 and "name the same path" in one_error_line(res)
    assert not same.exists()


# --------------------------------------------------------------------------- fleet [layout] constants
def test_fleet_constants_over_several_files_warn(runner, tmp_path):
    """[layout] axis/period constants over a folder of 2 logs gave both one label, exit 0, no word."""
    fleet = tmp_path / "fleet"
    res = runner.invoke(app, ["fleet", "simulate", "--axes", "1", "--days", "2", "--out", str(fleet), "--broken", "0"])
    assert res.exit_code == 0, stderr_of(res)
    cfg = (fleet / "fleet.toml").read_text()
    lines = cfg.splitlines()
    i = next(k for k, line in enumerate(lines) if line.startswith("pattern"))
    lines[i] = "axis = 'a'\nperiod = 'p'"
    (tmp_path / "const.toml").write_text("\n".join(lines) + "\n")
    res = runner.invoke(app, ["fleet", "identify", str(fleet / "axis-0001"), "--out", str(tmp_path / "r.parquet"),
                              "--workers", "0", "--no-monitor", "--no-progress", "--config", str(tmp_path / "const.toml")])
    assert res.exit_code == 0, stderr_of(res)
    warn = [ln for ln in stderr_of(res).splitlines() if "more than one file" in ln]
    assert len(warn) == 1 and "axis a period p: 2 files" in warn[0], stderr_of(res)
