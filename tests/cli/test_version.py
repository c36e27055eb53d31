"""``frictionkit --version``."""

from __future__ import annotations

import os
import subprocess
import sys
from importlib.metadata import version
from pathlib import Path

from typer.testing import CliRunner

import frictionkit as fk
from frictionkit.cli import _register, app

_register()


def test_version_matches_the_installed_distribution():
    res = CliRunner().invoke(app, ["--version"])
    assert res.exit_code == 0
    assert res.stdout == f"frictionkit {version('frictionkit')}\n"
    assert fk.__version__ == version("frictionkit")


def test_version_through_the_console_script():
    """The launcher answers ``--version`` alone from the installed metadata (no frictionkit import)."""
    exe = Path(sys.executable).parent / "frictionkit"
    cmd = [str(exe)] if exe.exists() else [sys.executable, "-c", "from frictionkit.cli import main; main()"]
    out = subprocess.run([*cmd, "--version"], capture_output=True, text=True, timeout=120,
                         env={**os.environ, "FRICTIONKIT_DEBUG": ""})
    assert out.returncode == 0, out.stderr
    assert out.stdout.strip() == f"frictionkit {fk.__version__}"
    assert out.stderr == ""
