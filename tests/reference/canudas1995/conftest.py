"""The Canudas de Wit et al. (IEEE TAC 1995) experiments live in ``examples/``; load them by path."""

from __future__ import annotations

import importlib.util
import sys
from pathlib import Path

import pytest

EXAMPLES = Path(__file__).resolve().parents[3] / "examples"


def _load(name: str):
    path = EXAMPLES / f"{name}.py"
    if not path.is_file():
        pytest.fail(f"example {path} is missing")
    key = f"_examples_{name}"
    if key not in sys.modules:
        spec = importlib.util.spec_from_file_location(key, path)
        mod = importlib.util.module_from_spec(spec)
        sys.modules[key] = mod
        spec.loader.exec_module(mod)
    return sys.modules[key]


@pytest.fixture(scope="session")
def example():
    """``example("canudas1995_stickslip")`` -> the example's module."""
    return _load
