"""``fleet identify``'s summary counts what it read (README walk, walk3): one file holding several axes
(``[layout] axis_column``, as ``examples/fleet/tro2021_steady_state.toml``) said "3 log file(s)" for one
file, and "1 rows" / "0 axis/axes flagged"."""

from __future__ import annotations

import csv

import numpy as np
from typer.testing import CliRunner

import frictionkit.cli.fleet  # noqa: F401  (registers the ``fleet`` group)
from frictionkit.cli import app

CONFIG = """[layout]
axis_column = "axis"
record_column = "rec"
period = "2026-01"
[columns]
time = "t"
velocity = "v"
force = "F"
[units]
time = "s"
velocity = "m/s"
force = "N"
"""


def _records(path, axes):
    """Constant-speed records (8 speeds per direction, 50 samples) of a Stribeck axis per name in ``axes``."""
    rng = np.random.default_rng(0)
    speeds = np.r_[np.geomspace(1e-3, 0.1, 8), -np.geomspace(1e-3, 0.1, 8)]
    with open(path, "w", newline="") as f:
        w = csv.writer(f)
        w.writerow(["axis", "rec", "t", "v", "F"])
        for ax, Fc in axes:
            for i, v in enumerate(speeds):
                F = np.sign(v) * (Fc + 0.5 * np.exp(-(abs(v) / 5e-3) ** 2)) + 3.0 * v
                for k in range(50):
                    w.writerow([ax, f"r{i}", k * 1e-3, v, F + 0.01 * rng.standard_normal()])


def _identify(tmp_path, axes):
    _records(tmp_path / "many.csv", axes)
    (tmp_path / "many.toml").write_text(CONFIG)
    res = CliRunner().invoke(app, ["fleet", "identify", str(tmp_path / "many.csv"), "--config",
                                   str(tmp_path / "many.toml"), "--out", str(tmp_path / "r.parquet"),
                                   "--workers", "0", "--no-progress"])
    assert res.exit_code == 0, res.output
    return res.stdout


def test_one_file_of_two_axes_is_counted_as_one_file(tmp_path):
    text = _identify(tmp_path, [("a", 1.0), ("b", 2.0)])
    assert "2 axis-period(s) from 1 file(s): 2 identified" in text
    assert "drift: 0 axes flagged" in text and "(2 rows;" in text


def test_one_row_is_one_row(tmp_path):
    text = _identify(tmp_path, [("a", 1.0)])
    assert "1 log file(s): 1 identified" in text and "(1 row;" in text
