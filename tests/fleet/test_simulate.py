"""The simulated fleet: layout, broken files, configuration, determinism."""

from __future__ import annotations

import hashlib

import numpy as np
import pandas as pd
import pytest

from frictionkit.errors import ParameterError
from frictionkit.fleet import daily_test_motion, load_config, simulate_fleet
from frictionkit.fleet.simulate import LEVELS


def _sha(p):
    return hashlib.sha256(p.read_bytes()).hexdigest()


def test_layout_and_broken_list(small_fleet):
    root = small_fleet.root
    assert len(small_fleet.files) == 12  # 4 axes x 3 days
    listed = (root / "broken.txt").read_text().split()
    assert listed == [p for p, _ in small_fleet.broken] and len(listed) == 4
    assert all((root / p).is_file() for p in listed)
    kinds = dict(small_fleet.broken)
    assert sorted(kinds.values()) == ["empty", "missing_column", "nan_burst", "truncated"]
    assert {p.rsplit(".", 1)[1] for p in small_fleet.files} == {"csv", "parquet"}
    good = next(p for p in small_fleet.files if p.endswith(".parquet") and p not in kinds)
    df = pd.read_parquet(root / good)
    assert list(df.columns) == ["t_s", "x_mm", "v_mm_s", "F_N", "temperature_C"]
    assert len(df) == 20_000 and df["t_s"].diff().iloc[1:].round(12).eq(1e-3).all()
    cfg = load_config(root / "fleet.toml")
    assert cfg.columns["force"] == "F_N" and cfg.scales["velocity"] == 1e-3 and "temperature" in cfg.schedule
    truth = pd.read_csv(root / "truth.csv")
    assert truth["drifting"].sum() == 2 and len(truth) == 4  # drifting=0.5 of 4 axes


def test_test_motion_covers_the_stribeck_region():
    t, v = daily_test_motion()
    assert t.size == 20_000 and abs(t[1] - t[0] - 1e-3) < 1e-15
    for level in LEVELS:  # every staircase level is held in both directions
        assert np.sum(np.abs(v - level) < 1e-9) > 500 and np.sum(np.abs(v + level) < 1e-9) > 500
    assert np.sum(np.diff(np.sign(v[-2000:])) != 0) >= 3  # reversals at the end


def test_same_seed_same_files_and_axes_independent_of_fleet_size(tmp_path):
    a = simulate_fleet(tmp_path / "a", axes=1, days=1, seed=5, broken=0)
    b = simulate_fleet(tmp_path / "b", axes=2, days=1, seed=5, broken=0)
    f = a.files[0]
    assert f in b.files and _sha(a.root / f) == _sha(b.root / f)


@pytest.mark.parametrize("kw, match", [
    ({"axes": 0, "days": 1}, "axes"),
    ({"axes": 1, "days": 1.5}, "days"),
    ({"axes": 1, "days": 1, "formats": ("xlsx",)}, "formats"),
    ({"axes": 1, "days": 1, "drifting": 2.0}, "drifting"),
    ({"axes": 1, "days": 1, "broken": 3}, "broken"),
    ({"axes": 1, "days": 1, "start": "Monday"}, "start"),
])
def test_bad_arguments(tmp_path, kw, match):
    with pytest.raises(ParameterError, match=match):
        simulate_fleet(tmp_path / "x", **kw)
