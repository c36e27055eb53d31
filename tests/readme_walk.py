"""A walk through the README: every ```sh and ```python block, in order, each command as written.

    python tests/readme_walk.py --list          # every command: walked here / run by a section test / left out, why
    python tests/readme_walk.py DIR [--all]     # run the walked commands (--all: the section tests' too) in DIR

``--all`` in a folder whose ``../shared/data`` is the data runs 27 commands in README order
(the tro2021 loop included): 120 s wall on 2 loaded cores (2026-11-23).

Commands run in-process in one folder, in README order: ``frictionkit ...`` through the CLI app
(typer's runner: the same code as the console script, without a 4 s interpreter start per
command), ``python -c "..."`` and ```python blocks by ``exec``, other shell lines (``printf ... >
file``) by ``bash -c``. Optional arguments shown in brackets (``[--plot fit.png]``) are left out.

``tests/cli/test_readme_walk.py`` calls this module: it checks that every README command is
classified (a new block that nobody runs fails it), that each section test named below exists
and reads its section, and runs the walked commands. The section tests keep their own checks
of the outputs; they are not run twice.
"""

from __future__ import annotations

import os
import re
import shlex
import subprocess
import sys
from dataclasses import dataclass
from pathlib import Path

REPO = Path(__file__).resolve().parents[1]
README = REPO / "README.md"
DATA = REPO.parent / "shared" / "data"


@dataclass(frozen=True)
class Command:
    line: int        # README line of the block's first line
    section: str     # the heading above it
    kind: str        # "sh" or "python"
    text: str        # one shell command (continuations joined) or a whole Python block


def commands(text: str | None = None) -> list[Command]:
    """Every command of every ```sh / ```python block, in README order."""
    text = README.read_text(encoding="utf-8") if text is None else text
    out = []
    for m in re.finditer(r"^```(sh|python)\n(.*?)^```", text, re.S | re.M):
        line = text[:m.start()].count("\n") + 1
        heads = re.findall(r"^(#{2,4} .*)$", text[:m.start()], re.M)
        section = heads[-1] if heads else ""
        if m.group(1) == "python":
            out.append(Command(line, section, "python", m.group(2)))
            continue
        body = m.group(2).replace("\\\n", " ")
        lines = [ln for ln in body.splitlines() if ln.strip()]
        i = 0
        while i < len(lines):
            ln = lines[i]
            if ln.lstrip().startswith("for "):  # a loop: up to its 'done', one command
                j = next(k for k in range(i, len(lines)) if lines[k].strip() == "done")
                out.append(Command(line, section, "sh", "\n".join(lines[i:j + 1])))
                i = j + 1
                continue
            out.append(Command(line, section, "sh", ln.strip()))
            i += 1
    return out


#: Commands run by a section test (as written, in a fresh folder, with its own checks of the
#: outputs): (README section heading or text marker, first words of the command) -> test.
SECTION_TESTS = [
    ("**Machine files.**", "python", "tests/cli/test_simulate_machine_file.py::"
                                     "test_readme_machine_files_example_runs_as_written"),
    ("**Machine files.**", "frictionkit simulate emps.json", "tests/cli/test_simulate_machine_file.py::"
                                                            "test_readme_machine_files_example_runs_as_written"),
    ("## A short example", "python", "tests/unit/test_readme.py::test_readme_example_runs"),
    ("## Machines: any friction law", "python:import numpy", "tests/unit/test_readme.py::test_readme_machine_example_runs"),
    ("## Command line", "frictionkit --version", "tests/cli/test_readme_cli.py::test_command_line_section_runs_as_written"),
    ("## Command line", "frictionkit models", "tests/cli/test_readme_cli.py::test_command_line_section_runs_as_written"),
    ("## Command line", "python -c \"import frictionkit as fk; fk.save_model(fk.LuGre",
     "tests/cli/test_readme_cli.py::test_command_line_section_runs_as_written"),
    ("## Command line", "python -c \"import numpy as np; t = np.arange(4001)",
     "tests/cli/test_readme_cli.py::test_command_line_section_runs_as_written"),
    ("## Command line", "frictionkit simulate lugre.json", "tests/cli/test_readme_cli.py::"
                                                          "test_command_line_section_runs_as_written"),
    ("## Command line", "frictionkit export lugre.json", "tests/cli/test_readme_cli.py::"
                                                        "test_command_line_section_runs_as_written"),
    ("## Command line", "frictionkit compensate ballscrew --quick --plot", "tests/cli/test_readme_cli.py::"
                                                                          "test_command_line_section_runs_as_written"),
    ("## Report", "", "tests/cli/test_report.py::readme_page"),
    ("### From a log file to a dynamic model", "D=", "tests/realdata/test_screw_drives_dynamic.py::fits"),
    ("### From a log file to a dynamic model", "for d in 1 2 3", "tests/realdata/test_screw_drives_dynamic.py::fits"),
    ("DuckDB", "python:import duckdb", "tests/fleet/test_readme_duckdb.py::test_readme_duckdb_query"),
]

#: Section-test commands that read what a left-out command writes: ``--all`` does not run them.
NEEDS_LEFT_OUT = {"tests/fleet/test_readme_duckdb.py::test_readme_duckdb_query":
                  "reads the fleet's results.parquet (the left-out fleet commands; its test builds a small fleet)"}

#: Commands nobody runs, and why.
LEFT_OUT = [
    ("## Set-up", "make demo", "builds the whole demo (minutes); `make demo` is its own CI step"),
    ("## Set-up", "make test", "runs this suite: it cannot run inside itself"),
    ("## Identification", "frictionkit identify output-error REC.csv", "a template: REC.csv stands for your record"),
    ("## Identification", "frictionkit identify presliding REC.csv", "a template: REC.csv stands for your record"),
    ("### Compensator parameters from a reversal record", "frictionkit identify reversal REV.csv",
     "a template: REV.csv stands for your record"),
    ("## Fleets", "frictionkit fleet", "1,500 axis-days (50 axes x 30 days): minutes; the same verbs run on small "
                                       "fleets in tests/fleet and tests/cli"),
    ("dask-jobqueue", "python:from dask_jobqueue", "needs a SLURM batch system (dask_jobqueue.SLURMCluster)"),
]


def _match(rules, cmd: Command, text: str):
    start_of_block = len("\n".join(text.splitlines()[:cmd.line - 1]))
    before = text[:start_of_block]
    cut = max(before.rfind("\n## "), before.rfind("\n### "), before.rfind("\n#### "), 0)
    above = before[cut:]  # the block's own section, up to the block
    for marker, start, what in rules:
        ok = cmd.section.startswith(marker) if marker.startswith("#") else marker in above
        if not ok:
            continue
        if start == "python" or start.startswith("python:"):  # a ```python block ("python:FIRST WORDS")
            ok = cmd.kind == "python" and cmd.text.lstrip().startswith(start[7:])
        elif start:
            ok = cmd.kind == "sh" and cmd.text.lstrip().startswith(start)
        if ok:
            return what
    return None


def classify(cmd: Command, text: str | None = None) -> tuple[str, str]:
    """``("section", test)``, ``("left out", reason)`` or ``("walk", "")``."""
    text = README.read_text(encoding="utf-8") if text is None else text
    test = _match(SECTION_TESTS, cmd, text)
    if test:
        return "section", test
    why = _match(LEFT_OUT, cmd, text)
    if why:
        return "left out", why
    return "walk", ""


def _strip_optional(argv: list[str]) -> list[str]:
    """Drop ``[--opt value]`` groups (shown as optional in the README)."""
    out, depth = [], 0
    for a in argv:
        if a.startswith("["):
            depth += 1
        if depth == 0:
            out.append(a)
        if a.endswith("]"):
            depth -= 1
    return out


def run(cmd: Command, cwd: Path, *, runner=None, shell_vars: dict | None = None) -> str:
    """Run one command in ``cwd``; returns its output; raises AssertionError naming it on failure.

    ``shell_vars``: variables set by earlier ``NAME=value`` lines of the same block (updated here),
    passed to the shell commands after them."""
    where = f"README line {cmd.line} ({cmd.section}): {cmd.text[:120]}"
    old = Path.cwd()
    os.chdir(cwd)
    try:
        if cmd.kind == "python":
            exec(compile(cmd.text, f"README.md:{cmd.line}", "exec"), {"__name__": "__readme__"})  # noqa: S102
            return ""
        if re.fullmatch(r"[A-Za-z_]\w*=\S*", cmd.text.strip()):  # D=../shared/data/...: for the lines after it
            name, _, value = cmd.text.strip().partition("=")
            if shell_vars is not None:
                shell_vars[name] = value
            return ""
        argv = _strip_optional(shlex.split(cmd.text, comments=True))
        if argv[0] == "frictionkit":
            from frictionkit.cli import _register, app

            if runner is None:
                from typer.testing import CliRunner

                runner = CliRunner()
            _register()
            res = runner.invoke(app, argv[1:])
            assert res.exit_code == 0, f"{where}\nexit {res.exit_code}\n{res.output}"
            return res.output
        if argv[:2] == ["python", "-c"] and len(argv) == 3:
            exec(compile(argv[2], f"README.md:{cmd.line}", "exec"), {"__name__": "__readme__"})  # noqa: S102
            return ""
        env = {**os.environ, **(shell_vars or {})}
        proc = subprocess.run(["bash", "-ec", cmd.text], cwd=cwd, capture_output=True, text=True, timeout=3600,
                              env=env)
        assert proc.returncode == 0, f"{where}\nexit {proc.returncode}\n{proc.stdout}{proc.stderr}"
        return proc.stdout
    finally:
        os.chdir(old)


def walk(cwd: Path, *, everything: bool = False) -> dict[Command, str]:
    """Run the walked commands (``everything``: the section tests' too) in README order in ``cwd``."""
    text = README.read_text(encoding="utf-8")
    out, shell_vars, block = {}, {}, None
    for cmd in commands(text):
        if cmd.line != block:  # a new block: a fresh shell
            shell_vars, block = {}, cmd.line
        kind, why = classify(cmd, text)
        if kind == "walk" or (everything and kind == "section" and why not in NEEDS_LEFT_OUT):
            out[cmd] = run(cmd, cwd, shell_vars=shell_vars)
    return out


def main(argv: list[str]) -> int:
    text = README.read_text(encoding="utf-8")
    if argv[:1] == ["--list"]:
        for cmd in commands(text):
            kind, why = classify(cmd, text)
            first = cmd.text.strip().splitlines()[0][:70]
            print(f"L{cmd.line:<5} {kind:<9} {first:<72} {why}")
        return 0
    if not argv or argv[0].startswith("-"):
        print(__doc__)
        return 2
    d = Path(argv[0])
    d.mkdir(parents=True, exist_ok=True)
    for cmd, output in walk(d, everything="--all" in argv).items():
        print(f"$ {cmd.text.splitlines()[0][:100]}\n{output}", end="")
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
