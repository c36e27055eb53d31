"""The one error path of the CLI: one ``error:`` line, exit status, ``--debug``, Ctrl-C, bugs, help texts."""

from __future__ import annotations

import subprocess
import sys

import pytest
from _robustness_helpers import STATIC_ARGS, one_error_line, stderr_of

import frictionkit.data
import frictionkit.identify
from frictionkit.cli import app


def test_bad_input_is_one_line_exit_2(runner, tmp_path):
    res = runner.invoke(app, ["identify", "static", str(tmp_path / "none.csv"), *STATIC_ARGS])
    assert res.exit_code == 2
    assert "none.csv" in one_error_line(res) and "not found" in one_error_line(res)


@pytest.mark.parametrize("where", ["front", "back", "env"])
def test_debug_shows_the_traceback(runner, tmp_path, where):
    args = ["identify", "static", str(tmp_path / "none.csv"), *STATIC_ARGS]
    env = {}
    if where == "front":
        args = ["--debug", *args]
    elif where == "back":
        args = [*args, "--debug"]
    else:
        env = {"FRICTIONKIT_DEBUG": "1"}
    res = runner.invoke(app, args, env=env)
    err = stderr_of(res)
    assert res.exit_code == 2
    assert err.startswith("Traceback (most recent call last):")
    assert "DataError" in err
    assert err.strip().splitlines()[-1].startswith("error: ") and "not found" in err.strip().splitlines()[-1]


def test_unexpected_exception_names_type_and_asks_for_debug(runner, staircase_csv, monkeypatch):
    def boom(*a, **k):
        return 1 / 0

    monkeypatch.setattr(frictionkit.identify, "fit_static_map", boom)
    res = runner.invoke(app, ["identify", "static", str(staircase_csv), *STATIC_ARGS])
    assert res.exit_code == 1
    err = one_error_line(res)
    assert "unexpected ZeroDivisionError: division by zero" in err and "--debug" in err
    res = runner.invoke(app, ["--debug", "identify", "static", str(staircase_csv), *STATIC_ARGS])
    assert "Traceback" in stderr_of(res) and "ZeroDivisionError" in stderr_of(res)


def test_ctrl_c_is_one_line_exit_130(runner, staircase_csv, monkeypatch):
    def interrupted(*a, **k):
        raise KeyboardInterrupt

    monkeypatch.setattr(frictionkit.data, "load_recording", interrupted)
    res = runner.invoke(app, ["identify", "static", str(staircase_csv), *STATIC_ARGS])
    assert res.exit_code == 130
    assert one_error_line(res) == "error: interrupted"


def test_computation_failure_exits_1(runner, staircase_csv, monkeypatch):
    from frictionkit.errors import IdentificationError

    def fails(*a, **k):
        raise IdentificationError("fit_static_map: the fit did not converge")

    monkeypatch.setattr(frictionkit.identify, "fit_static_map", fails)
    res = runner.invoke(app, ["identify", "static", str(staircase_csv), *STATIC_ARGS])
    assert res.exit_code == 1
    assert one_error_line(res) == "error: fit_static_map: the fit did not converge"


@pytest.mark.parametrize("args, needle", [
    (["identify", "static", "x.csv", "--time", "t", "--velocity", "v", "--force", "F", "--force-scale", "abc"],
     "'--force-scale'"),
    (["identify", "statc"], "No such command 'statc'"),
    (["reproduce", "zhu-fujimoto", "--seed", "x", "--json", "a.json"], "'--seed'"),
    (["demo", "--nope"], "--nope"),
])
def test_usage_errors_are_one_line(runner, args, needle):
    res = runner.invoke(app, args)
    assert res.exit_code == 2
    err = one_error_line(res)
    assert needle in err and "--help'" in err


def test_no_arguments_still_prints_help(runner):
    res = runner.invoke(app, ["identify"])
    assert "rigid-body" in res.output and "error:" not in res.output


def test_every_verb_runs_inside_the_error_path():
    """Each verb is reached through the top-level group that owns the error handling."""
    import typer.main

    from frictionkit.cli._errors import FrictionKitGroup

    root = typer.main.get_command(app)
    assert isinstance(root, FrictionKitGroup)
    assert {"demo", "identify", "reproduce"} <= set(root.commands)


def test_subprocess_one_line_and_status():
    code = "import sys; sys.argv[0] = 'frictionkit'; from frictionkit.cli import main; main()"
    proc = subprocess.run([sys.executable, "-c", code, "identify", "static", "/nonexistent/run.csv", *STATIC_ARGS,
                           "--force-scale", "1e300"], capture_output=True, text=True, timeout=120)
    assert proc.returncode == 2
    assert proc.stdout == ""
    assert proc.stderr.strip().splitlines() == [
        "error: --force-scale 1e+300: a unit factor must satisfy 1e-12 <= |factor| <= 1e+12 (e.g. 1e-3 for mm -> m)"]


# --------------------------------------------------------------------------- help texts
def test_units_in_square_brackets_show_in_help(runner):
    res = runner.invoke(app, ["identify", "static", "--help"])
    assert res.exit_code == 0
    assert "Time column [s]." in res.output


def _commands(cmd, path=()):
    subs = getattr(cmd, "commands", None)
    if subs:
        for name, sub in subs.items():
            yield from _commands(sub, (*path, name))
    else:
        yield path, cmd


def test_every_bracketed_help_text_survives(runner):
    """Every '[...]' written in an option's help appears verbatim in that verb's --help."""
    import re

    import typer.main

    checked = 0
    for path, cmd in _commands(typer.main.get_command(app)):
        out = " ".join(runner.invoke(app, [*path, "--help"]).output.split())
        for p in cmd.params:
            for unit in re.findall(r"\[[^\]]+\]", getattr(p, "help", None) or ""):
                assert unit in out, f"{' '.join(path)} {p.name}: {unit} missing from --help"
                checked += 1
    assert checked >= 15


@pytest.mark.skipif(sys.platform == "win32", reason="SIGINT to a child process")
def test_ctrl_c_while_the_package_imports_is_one_line():
    """The console script's launcher catches an interrupt before frictionkit has finished importing."""
    import signal

    # the interrupt must land while frictionkit imports, whatever the machine's speed: the child
    # holds that import open (a sleep inside it) until the signal comes
    code = ("import sys, time, builtins; sys.argv = ['frictionkit', 'identify', '--help']\n"
            "import _frictionkit_main\n"
            "real = builtins.__import__\n"
            "def slow(name, *a, **k):\n"
            "    if name == 'frictionkit.cli':\n"
            "        print('ready', flush=True)\n"
            "        time.sleep(60)\n"
            "    return real(name, *a, **k)\n"
            "builtins.__import__ = slow\n"
            "_frictionkit_main.main()\n")
    proc = subprocess.Popen([sys.executable, "-c", code], stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True,
                            preexec_fn=lambda: signal.signal(signal.SIGINT, signal.SIG_DFL))
    try:
        assert proc.stdout.readline().strip() == "ready"
        proc.send_signal(signal.SIGINT)
        out, err = proc.communicate(timeout=60)
    finally:
        if proc.poll() is None:
            proc.kill()
    assert proc.returncode == 130
    assert err == "error: interrupted\n"
    assert "Usage" not in out


def test_console_script_points_at_the_launcher():
    import tomllib
    from pathlib import Path

    meta = tomllib.loads((Path(__file__).resolve().parents[2] / "pyproject.toml").read_text())
    assert meta["project"]["scripts"]["frictionkit"] == "_frictionkit_main:main"


def test_warnings_are_one_line_and_numpy_noise_is_dropped(runner, staircase_csv, monkeypatch):
    import warnings

    import numpy as np

    real = frictionkit.identify.fit_static_map

    def noisy(*a, **k):
        warnings.warn("simulation stopped at t = 1 s:\n  step size too small", RuntimeWarning)
        np.square(np.array([1e300]))  # numpy: "overflow encountered in square"
        return real(*a, **k)

    monkeypatch.setattr(frictionkit.identify, "fit_static_map", noisy)
    res = runner.invoke(app, ["identify", "static", str(staircase_csv), *STATIC_ARGS])
    assert res.exit_code == 0, res.output
    assert stderr_of(res).strip().splitlines() == ["warning: simulation stopped at t = 1 s: step size too small"]
