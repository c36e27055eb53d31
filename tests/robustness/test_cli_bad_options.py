"""Bad options and bad output paths: one line naming the option and the cause, before any work is done."""

from __future__ import annotations

import errno
import json
import os
import time

import pytest
from _robustness_helpers import PRESLIDING_ARGS, STATIC_ARGS, one_error_line

import frictionkit.data
import frictionkit.identify
from frictionkit.cli import app


@pytest.fixture
def no_work(monkeypatch):
    """Fail the test if a command gets as far as loading data or running a reproduction."""

    def forbidden(*a, **k):
        raise AssertionError("the command started work before rejecting its options")

    monkeypatch.setattr(frictionkit.data, "load_recording", forbidden)
    monkeypatch.setattr(frictionkit.data, "load_groups", forbidden)
    import frictionkit.reproduce.zhu_fujimoto as zf
    import frictionkit.report.demo as demo

    monkeypatch.setattr(zf, "run", forbidden)
    monkeypatch.setattr(demo, "run_demo", forbidden)


# --------------------------------------------------------------------------- scale and number options
@pytest.mark.parametrize("value, rule", [
    ("1e300", "1e-12 <= |factor| <= 1e+12"),
    ("-1e300", "1e-12 <= |factor| <= 1e+12"),
    ("1e-300", "1e-12 <= |factor| <= 1e+12"),
    ("0", "1e-12 <= |factor| <= 1e+12"),
    ("nan", "must be finite (not nan or inf)"),
    ("inf", "must be finite (not nan or inf)"),
])
@pytest.mark.parametrize("option", ["--force-scale", "--velocity-scale", "--position-scale"])
def test_static_scale_options(runner, staircase_csv, no_work, option, value, rule):
    res = runner.invoke(app, ["identify", "static", str(staircase_csv), *STATIC_ARGS, option, value])
    assert res.exit_code == 2
    err = one_error_line(res)
    assert err.startswith(f"error: {option} ") and rule in err
    assert "row" not in err  # not "repair row 0 of the file"


def test_negative_scale_flips_sign_and_is_accepted(runner, staircase_csv):
    res = runner.invoke(app, ["identify", "static", str(staircase_csv), *STATIC_ARGS, "--force-scale", "-1"])
    assert res.exit_code == 0, res.output


@pytest.mark.parametrize("verb, extra", [
    ("rigid-body", ["--time", "t", "--position", "x", "--force", "F"]),
    ("output-error", ["--time", "t", "--velocity", "v", "--force", "F", "--Fc", "1", "--mass", "1"]),
    ("presliding", ["--time", "t", "--position", "x", "--force", "F", "--elements", "3"]),
])
def test_every_identify_verb_checks_its_scales(runner, tmp_path, no_work, verb, extra):
    res = runner.invoke(app, ["identify", verb, str(tmp_path / "r.csv"), *extra, "--force-scale", "1e300"])
    assert res.exit_code == 2
    assert one_error_line(res).startswith("error: --force-scale 1e+300: a unit factor")


@pytest.mark.parametrize("mass", ["0", "-1", "nan", "inf"])
def test_mass_names_the_option(runner, tmp_path, no_work, mass):
    res = runner.invoke(app, ["identify", "output-error", str(tmp_path / "r.csv"), "--time", "t", "--position", "x",
                              "--force", "F", "--Fc", "1", "--mass", mass])
    assert res.exit_code == 2
    err = one_error_line(res)
    assert err.startswith("error: --mass ") and "pre-sliding" not in err


@pytest.mark.parametrize("option, value, needle", [
    ("--cutoff", "0", "--cutoff 0.0: must be > 0"),
    ("--decimate", "0", "--decimate 0: must be >= 1"),
    ("--skip", "-1", "--skip -1: must be >= 0"),
])
def test_rigid_body_numbers(runner, tmp_path, no_work, option, value, needle):
    res = runner.invoke(app, ["identify", "rigid-body", str(tmp_path / "r.csv"), "--time", "t", "--position", "x",
                              "--force", "F", option, value])
    assert res.exit_code == 2 and needle in one_error_line(res)


@pytest.mark.parametrize("option, value, needle", [
    ("--trim", "0.7", "--trim 0.7: must be >= 0 and < 0.5"),
    ("--trim", "nan", "--trim nan: must be finite"),
    ("--delta", "-2", "--delta -2.0: must be > 0"),
    ("--direction", "up", "--direction 'up': must be one of both, positive, negative"),
])
def test_static_numbers_and_choices(runner, staircase_csv, no_work, option, value, needle):
    res = runner.invoke(app, ["identify", "static", str(staircase_csv), *STATIC_ARGS, option, value])
    assert res.exit_code == 2 and needle in one_error_line(res)


# --------------------------------------------------------------------------- presliding elements: bounded
@pytest.mark.parametrize("elements", ["100", "33", "0"])
def test_presliding_elements_bounded_with_reason(runner, gms_csv, elements):
    t0 = time.perf_counter()
    args = [a if a != "3" else elements for a in PRESLIDING_ARGS]
    res = runner.invoke(app, ["identify", "presliding", str(gms_csv), *args, "--Fc", "1", "--Fs", "1.5"])
    assert time.perf_counter() - t0 < 5
    assert res.exit_code == 2
    err = one_error_line(res)
    assert f"--elements {elements}: must be between 1 and 32" in err
    assert "the breakpoint search grows with M" in err


@pytest.mark.parametrize("starts, rule", [("0", "must be between 1 and 10000"), ("10001", "must be between 1 and 10000"),
                                          ("1000000", "1-2 ms each per 8,000 samples")])
def test_output_error_starts_bounded_with_reason(runner, tmp_path, no_work, starts, rule):
    res = runner.invoke(app, ["identify", "output-error", str(tmp_path / "r.csv"), "--time", "t", "--velocity", "v",
                              "--force", "F", "--Fc", "1", "--mass", "1", "--starts", starts])
    assert res.exit_code == 2
    err = one_error_line(res)
    assert err.startswith(f"error: --starts {starts}: ") and rule in err


def test_presliding_elements_help_states_the_maximum(runner):
    res = runner.invoke(app, ["identify", "presliding", "--help"])
    assert "1 to 32" in " ".join(res.output.split())


# --------------------------------------------------------------------------- reproduce and demo
@pytest.mark.parametrize("seed", ["-1", "4294967296"])
def test_reproduce_seed(runner, tmp_path, no_work, seed):
    res = runner.invoke(app, ["reproduce", "zhu-fujimoto", "--quick", "--seed", seed, "--json", str(tmp_path / "a.json")])
    assert res.exit_code == 2
    assert f"error: --seed {seed}: must be between 0 and 4294967295" == one_error_line(res)


def test_reproduce_unknown_nut_model_is_one_line(runner, tmp_path, no_work):
    res = runner.invoke(app, ["reproduce", "zhu-fujimoto", "--nut-model", "lost", "--json", str(tmp_path / "a.json")])
    assert res.exit_code == 2
    assert one_error_line(res).startswith("error: --nut-model 'lost': must be one of sliding")


def test_reproduce_json_into_a_folder_path(runner, tmp_path, no_work):
    res = runner.invoke(app, ["reproduce", "zhu-fujimoto", "--json", str(tmp_path)])
    assert res.exit_code == 2
    assert one_error_line(res) == f"error: --json '{tmp_path}' is a folder; give a file name"


def test_reproduce_json_under_a_file(runner, tmp_path, no_work):
    f = tmp_path / "file.txt"
    f.write_text("x")
    res = runner.invoke(app, ["reproduce", "zhu-fujimoto", "--json", str(f / "sub" / "a.json")])
    assert res.exit_code == 2
    assert f"'{f}' is a file, not a folder" in one_error_line(res)


def test_reproduce_json_with_png_suffix_would_collide_with_its_plot(runner, tmp_path, no_work):
    res = runner.invoke(app, ["reproduce", "zhu-fujimoto", "--json", str(tmp_path / "zf.png")])
    assert res.exit_code == 2
    assert "name the same file" in one_error_line(res)


def _read_only(monkeypatch, folder):
    """Make ``folder`` read-only; as root (who may write anyway) make os.access say so."""
    folder.chmod(0o555)
    if os.geteuid() == 0:
        real = os.access

        def access(path, mode, *a, **k):
            if os.path.realpath(path) == os.path.realpath(folder) and mode & os.W_OK:
                return False
            return real(path, mode, *a, **k)

        monkeypatch.setattr(os, "access", access)


def test_reproduce_json_into_read_only_folder(runner, tmp_path, no_work, monkeypatch):
    ro = tmp_path / "ro"
    ro.mkdir()
    _read_only(monkeypatch, ro)
    try:
        res = runner.invoke(app, ["reproduce", "zhu-fujimoto", "--quick", "--json", str(ro / "zf.json")])
    finally:
        ro.chmod(0o755)
    assert res.exit_code == 2
    assert one_error_line(res) == f"error: --json '{ro / 'zf.json'}': folder '{ro}' is not writable"


def test_demo_out_naming_an_existing_file(runner, tmp_path, no_work):
    f = tmp_path / "report.html"
    f.write_text("keep me")
    res = runner.invoke(app, ["demo", "--out", str(f)])
    assert res.exit_code == 2
    assert one_error_line(res) == f"error: --out '{f}' is an existing file, not a folder"
    assert f.read_text() == "keep me"


def test_demo_out_in_read_only_folder(runner, tmp_path, no_work, monkeypatch):
    ro = tmp_path / "ro"
    ro.mkdir()
    _read_only(monkeypatch, ro)
    try:
        res = runner.invoke(app, ["demo", "--out", str(ro / "demo")])
    finally:
        ro.chmod(0o755)
    assert res.exit_code == 2
    assert f"folder '{ro}' is not writable" in one_error_line(res)


# --------------------------------------------------------------------------- identify output paths
@pytest.mark.parametrize("name", ["fit.xyz", "fit", "fit.json"])
def test_plot_extension_checked_before_work(runner, staircase_csv, tmp_path, no_work, name):
    res = runner.invoke(app, ["identify", "static", str(staircase_csv), *STATIC_ARGS, "--plot", str(tmp_path / name)])
    assert res.exit_code == 2
    err = one_error_line(res)
    assert err.startswith(f"error: --plot '{tmp_path / name}': ") and ".png" in err and ".pdf" in err
    assert not (tmp_path / name).exists()


@pytest.mark.parametrize("ext", ["png", "pdf", "svg"])
def test_plot_formats_from_the_extension(runner, staircase_csv, tmp_path, ext):
    out = tmp_path / f"fit.{ext}"
    res = runner.invoke(app, ["identify", "static", str(staircase_csv), *STATIC_ARGS, "--plot", str(out)])
    assert res.exit_code == 0, res.output
    head = out.read_bytes()[:8]
    assert {"png": b"\x89PNG", "pdf": b"%PDF", "svg": b"<?xml"}[ext] in head
    assert [p.name for p in tmp_path.iterdir()] == [out.name]  # no temporary file left


def test_json_naming_the_input_refuses_and_keeps_the_input(runner, staircase_csv, tmp_path):
    data = tmp_path / "run.csv"
    data.write_bytes(staircase_csv.read_bytes())
    before = data.read_bytes()
    for option in ("--json", "--plot"):
        res = runner.invoke(app, ["identify", "static", str(data), *STATIC_ARGS, option, str(data)])
        assert res.exit_code == 2
        err = one_error_line(res)
        assert f"{option} '{data}' is the input file '{data}'" in err or "not a plot format" in err
    res = runner.invoke(app, ["identify", "static", str(data), *STATIC_ARGS, "--json", str(tmp_path / "." / "run.csv")])
    assert "is the input file" in one_error_line(res)
    assert data.read_bytes() == before


def test_json_naming_the_static_json_input_refuses(runner, gms_csv, static_json, tmp_path):
    copy = tmp_path / "static.json"
    copy.write_bytes(static_json.read_bytes())
    res = runner.invoke(app, ["identify", "presliding", str(gms_csv), *PRESLIDING_ARGS, "--static-json", str(copy),
                              "--json", str(copy)])
    assert res.exit_code == 2
    assert f"--json '{copy}' is the input file '{copy}'" in one_error_line(res)
    assert copy.read_bytes() == static_json.read_bytes()


def test_json_into_missing_folder(runner, staircase_csv, tmp_path, no_work):
    out = tmp_path / "nope" / "fit.json"
    res = runner.invoke(app, ["identify", "static", str(staircase_csv), *STATIC_ARGS, "--json", str(out)])
    assert res.exit_code == 2
    assert one_error_line(res) == f"error: --json '{out}': folder '{out.parent}' does not exist"


def test_json_into_read_only_folder(runner, staircase_csv, tmp_path, no_work, monkeypatch):
    ro = tmp_path / "ro"
    ro.mkdir()
    _read_only(monkeypatch, ro)
    try:
        res = runner.invoke(app, ["identify", "static", str(staircase_csv), *STATIC_ARGS, "--json", str(ro / "f.json")])
    finally:
        ro.chmod(0o755)
    assert res.exit_code == 2
    assert one_error_line(res) == f"error: --json '{ro / 'f.json'}': folder '{ro}' is not writable"


def test_json_and_plot_on_the_same_path(runner, staircase_csv, tmp_path, no_work):
    out = tmp_path / "fit.png"
    res = runner.invoke(app, ["identify", "static", str(staircase_csv), *STATIC_ARGS, "--json", str(out),
                              "--plot", str(out)])
    assert res.exit_code == 2
    assert "name the same file" in one_error_line(res)


def test_disk_full_at_the_end_keeps_the_old_result(runner, staircase_csv, tmp_path, monkeypatch):
    out = tmp_path / "fit.json"
    out.write_text('{"old": true}\n')

    def enospc(fd):
        raise OSError(errno.ENOSPC, os.strerror(errno.ENOSPC))

    monkeypatch.setattr(os, "fsync", enospc)
    res = runner.invoke(app, ["identify", "static", str(staircase_csv), *STATIC_ARGS, "--json", str(out)])
    assert res.exit_code == 1
    assert one_error_line(res) == f"error: cannot write '{out}': No space left on device"
    assert json.loads(out.read_text()) == {"old": True}
    assert [p.name for p in tmp_path.iterdir()] == ["fit.json"]
