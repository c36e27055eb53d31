"""The README's "Command line" section, every command run as written (in-process, in a fresh folder)."""

from __future__ import annotations

import re
import shlex
import shutil
import subprocess
from pathlib import Path

import numpy as np
import pytest
from typer.testing import CliRunner

from frictionkit.cli import _register, app

_register()
README = Path(__file__).resolve().parents[2] / "README.md"


def _section() -> str:
    text = README.read_text(encoding="utf-8")
    start = text.index("## Command line\n")
    end = text.index("\n## ", start + 10)
    return text[start:end]


def test_command_line_section_runs_as_written(tmp_path, monkeypatch):
    sec = _section()
    commands = re.search(r"```sh\n(.*?)```", sec, re.S).group(1).strip().splitlines()
    shown = re.search(r"```text\n(.*?)```", sec, re.S).group(1)
    monkeypatch.chdir(tmp_path)
    runner = CliRunner()
    outputs = {}
    for line in commands:
        argv = shlex.split(line)
        if argv[0] == "python":
            assert argv[1] == "-c" and len(argv) == 3, line
            exec(compile(argv[2], "README.md", "exec"), {})  # noqa: S102 - the README's own one-liner
            continue
        assert argv[0] == "frictionkit", line
        res = runner.invoke(app, argv[1:])
        assert res.exit_code == 0, f"{line}\n{res.output}"
        outputs[line] = res.stdout
    sim = next(out for line, out in outputs.items() if line.startswith("frictionkit simulate"))
    assert sim == shown  # the output shown in the README is the real one
    for f in ("models.json", "lugre.json", "traces.csv", "loop.png", "friction_table.csv", "friction.h", "friction.st"):
        assert (tmp_path / f).stat().st_size > 0, f
    assert np.loadtxt(tmp_path / "friction_table.csv", delimiter=",", skiprows=1).shape == (201, 2)

    snippet = re.search(r"```c\n(.*?)```", sec, re.S).group(1)
    include, body = snippet.split("\n", 1)
    assert include == '#include "friction.h"'
    gcc = shutil.which("gcc")
    if gcc is None:  # pragma: no cover
        pytest.skip("no system gcc for the C snippet")
    (tmp_path / "use.c").write_text(f"{include}\nint main(void)\n{{\n    double x = 1e-6, x_prev = 0.0;\n{body}"
                                    "    return u_ff > 0.0 ? 0 : 1;\n}\n")
    subprocess.run([gcc, "-std=c99", "-Wall", "-Wextra", "-pedantic", "-Werror", "-o", str(tmp_path / "use"),
                    str(tmp_path / "use.c"), "-lm"], check=True, capture_output=True, text=True)
    assert subprocess.run([str(tmp_path / "use")]).returncode == 0  # 1 mm/s from rest: friction opposes, > 0
