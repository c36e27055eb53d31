"""The README walk (issue 12 acceptance): every command of every ```sh / ```python block is run
as written — here (``tests/readme_walk.py``), by a named section test, or listed as left out with
the reason. A new block that nobody runs fails ``test_every_readme_command_is_accounted_for``.
"""

from __future__ import annotations

import ast
import json
import sys
from pathlib import Path

import numpy as np
import pytest

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))
import readme_walk as walk  # noqa: E402

REPO = walk.REPO


def test_every_readme_command_is_accounted_for():
    text = walk.README.read_text(encoding="utf-8")
    cmds = walk.commands(text)
    assert len(cmds) >= 35, len(cmds)  # the parser still finds the blocks (38 on 2026-11-23)
    kinds = {c: walk.classify(c, text) for c in cmds}
    # every rule still matches a command (a rule for a block that is gone is stale)
    used = {why for _, why in kinds.values()}
    for rules in (walk.SECTION_TESTS, walk.LEFT_OUT):
        stale = [r for r in rules if r[2] not in used]
        assert not stale, stale
    assert set(walk.NEEDS_LEFT_OUT) <= used
    # each named section test exists and reads the README
    for test in {why for kind, why in kinds.values() if kind == "section"}:
        path, _, name = test.partition("::")
        src = (REPO / path).read_text(encoding="utf-8")
        names = {n.name for n in ast.walk(ast.parse(src)) if isinstance(n, (ast.FunctionDef, ast.ClassDef))}
        assert name in names, test
        assert "README" in src, test
    # the walked ones: nothing the walk cannot run (templates, placeholders)
    for c, (kind, _) in kinds.items():
        if kind == "walk":
            assert "REC.csv" not in c.text and "<" not in c.text.split("#")[0], c


def test_walk_catches_an_unaccounted_block():
    text = walk.README.read_text(encoding="utf-8") + "\n## New section\n\n```sh\nfrictionkit frobnicate\n```\n"
    new = [c for c in walk.commands(text) if c.text == "frictionkit frobnicate"]
    assert new and walk.classify(new[0], text) == ("walk", "")  # so the walk runs it, and fails on it


@pytest.fixture(scope="module")
def walked(tmp_path_factory):
    """The walked commands, in README order, in one fresh folder whose ``../shared/data`` is the data."""
    root = tmp_path_factory.mktemp("readme_walk")
    (root / "work").mkdir()
    has_data = walk.DATA.is_dir()
    if has_data:
        (root / "shared").mkdir()
        (root / "shared" / "data").symlink_to(walk.DATA, target_is_directory=True)
    text = walk.README.read_text(encoding="utf-8")
    ran, skipped = {}, []
    for c in walk.commands(text):
        if walk.classify(c, text)[0] != "walk":
            continue
        if "../shared/data" in c.text and not has_data:
            skipped.append(c)
            continue
        ran[c] = walk.run(c, root / "work")
    return root / "work", ran, skipped


def test_walked_commands_run_as_written(walked):
    work, ran, skipped = walked
    assert len(ran) + len(skipped) >= 8
    # compensate MACHINE.json --test: the README's numbers are the real ones (the preset's table)
    doc = json.loads((work / "emps_comp.json").read_text(encoding="utf-8"))
    assert doc["format"] == "frictionkit.compensation/1" and doc["status"] == 0
    got = {k: f"{v['max_error'] * 1e6:.3f}" for k, v in doc["compensators"].items()}
    readme = walk.README.read_text(encoding="utf-8")
    assert f"none: max {got['none']} µm; coulomb {got['coulomb']} µm" in readme, got
    if not skipped:  # the identification commands on the shared data
        for f in ("fit.json", "drive1.json", "stribeck.json"):
            d = json.loads((work / f).read_text(encoding="utf-8"))
            assert d["format"] == "frictionkit.identification/1", f
        emps = json.loads((work / "fit.json").read_text(encoding="utf-8"))["parameters"]
        # the README's EMPS table ("frictionkit" column) is what the command as written gives
        for name, unit in (("M", "kg"), ("Fv", "N·s/m"), ("Fc", "N")):
            p = emps[name]
            val = np.format_float_positional(p["value"], precision=5, fractional=False, trim="k")
            err = f"{p['stderr']:.{len(val.partition('.')[2])}f}"  # as many decimals as the value
            assert f"| {name} [{unit}] | {val} ± {err} |" in readme, (name, val, err)
