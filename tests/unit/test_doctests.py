"""The docstring examples of every public module run in the suite (doctest): a wrong example fails CI.

Public = a module of ``src/frictionkit`` whose dotted name has no part starting with ``_``
(so ``_io``, ``_jit`` ... are out) outside ``kernels/`` (private numba kernels), found on
disk, not from a list: a new module's examples are run without editing this file. Only
modules whose source holds ``>>>`` are imported. Each runs in a fresh temporary folder (an
example may write a file) with ``ELLIPSIS`` and ``NORMALIZE_WHITESPACE``; an example that
must not run in the suite (a cluster, a long run, files that are not there) says
``# doctest: +SKIP`` next to it.
"""

from __future__ import annotations

import doctest
import importlib
import io
from pathlib import Path

import pytest

import frictionkit

ROOT = Path(frictionkit.__file__).resolve().parent


def _public_modules_with_examples() -> list[str]:
    names = []
    for path in sorted(ROOT.rglob("*.py")):
        rel = path.relative_to(ROOT).with_suffix("")
        parts = list(rel.parts)
        if parts[-1] == "__init__":
            parts = parts[:-1]
        if any(p.startswith("_") for p in parts) or (parts and parts[0] == "kernels"):
            continue
        if ">>>" not in path.read_text(encoding="utf-8"):
            continue
        names.append(".".join(["frictionkit", *parts]))
    return names


MODULES = _public_modules_with_examples()


def test_the_discovery_finds_the_documented_modules():
    # modules known to carry examples; a broken walk (wrong root, every file skipped) fails here
    for name in ("frictionkit", "frictionkit.models.lugre", "frictionkit.study", "frictionkit.control.trajectories"):
        assert name in MODULES, name
    assert not [m for m in MODULES if "._" in m or ".kernels" in m]
    assert len(MODULES) >= 40


@pytest.mark.parametrize("name", MODULES)
def test_docstring_examples(name, tmp_path, monkeypatch):
    import matplotlib

    matplotlib.use("Agg")
    monkeypatch.chdir(tmp_path)
    module = importlib.import_module(name)
    flags = doctest.ELLIPSIS | doctest.NORMALIZE_WHITESPACE
    out = io.StringIO()
    runner = doctest.DocTestRunner(optionflags=flags, verbose=False)
    tests = doctest.DocTestFinder(exclude_empty=True).find(module, name)
    for test in sorted(tests, key=lambda t: t.name):
        runner.run(test, out=out.write)
    result = runner.summarize(verbose=False)
    assert result.failed == 0, f"{result.failed} of {result.attempted} example(s) failed in {name}:\n{out.getvalue()}"


def test_py_typed_is_shipped():
    """PEP 561 marker in the package and in the wheel's package data (checked by building a wheel
    once by hand: ``frictionkit/py.typed`` is in it)."""
    import tomllib

    assert (ROOT / "py.typed").is_file()
    pyproject = tomllib.loads((ROOT.parents[1] / "pyproject.toml").read_text(encoding="utf-8"))
    assert "py.typed" in pyproject["tool"]["setuptools"]["package-data"]["frictionkit"]
