"""Datasets: Hive-style partitions, globs, lists of files, HDF5 logs, and the TOML configuration's checks."""

from __future__ import annotations

import shutil

import h5py
import pandas as pd
import pytest

from frictionkit.errors import DataError
from frictionkit.fleet import PARAM_COLUMNS, config_from_dict, discover, identify_fleet, load_config
from frictionkit.fleet.config import DEFAULT_PATTERNS


def _good(small_fleet, fmt):
    broken = {p for p, _ in small_fleet.broken}
    return [p for p in small_fleet.files if p.endswith(fmt) and p not in broken]


def test_hive_partitions_glob_and_hdf5_give_the_same_rows(small_fleet, single_run, tmp_path):
    src = _good(small_fleet, ".parquet")[:2]
    cfg = load_config(small_fleet.config)
    cfg = config_from_dict({**_doc(cfg), "layout": {"patterns": list(DEFAULT_PATTERNS)}})
    hive = tmp_path / "hive"
    for rel in src:
        axis, name = rel.split("/")
        d = hive / f"axis={axis}" / f"date={name.split('.')[0]}"
        d.mkdir(parents=True)
        shutil.copy(small_fleet.root / rel, d / "part-0.parquet")
    h5 = tmp_path / "h5"
    for rel in src:
        axis, name = rel.split("/")
        (h5 / axis).mkdir(parents=True, exist_ok=True)
        df = pd.read_parquet(small_fleet.root / rel)
        with h5py.File(h5 / axis / (name.split(".")[0] + ".h5"), "w") as f:
            for c in df.columns:
                f[c] = df[c].to_numpy()
    ref = single_run.table.set_index(["axis", "period"]).loc[[tuple(r.split("/")[0:1] + [r.split("/")[1][:10]])
                                                              for r in src], list(PARAM_COLUMNS)]
    for dataset in (hive, str(small_fleet.root / "*" / "*.parquet"), h5,
                    [small_fleet.root / r for r in src]):
        logs, _ = discover(dataset, cfg)
        if isinstance(dataset, str):  # the glob takes every Parquet log, broken ones too
            logs = [g for g in logs if g.file in src]
            assert len(logs) == 2
            dataset = [g.path for g in logs]
        run = identify_fleet(dataset, out=tmp_path / f"r{id(dataset)}.parquet", config=cfg, scheduler="none",
                             progress=False, monitor=False)
        got = run.table.set_index(["axis", "period"])[list(PARAM_COLUMNS)]
        pd.testing.assert_frame_equal(got, ref, check_exact=True)


def _doc(cfg):
    d = cfg.to_dict()
    units = {"time": "s", "position": "mm", "velocity": "mm/s", "force": "N"}
    return {"columns": d["columns"], "units": units, "schedule": d["schedule"], "segmentation": d["segmentation"],
            "fit": d["fit"], "dynamic": d["dynamic"]}


@pytest.mark.parametrize("doc, match", [
    ({"colums": {}}, "unknown section"),
    ({"columns": {"time": "t"}}, "force"),
    ({"columns": {"time": "t", "force": "F"}}, "velocity"),
    ({"columns": {"time": "t", "force": "F", "velocity": "v"}, "units": {"force": "furlong"}}, "unknown unit"),
    ({"columns": {"time": "t", "force": "F", "velocity": "v"}, "layout": {"pattern": "(?P<axis>x)"}}, "period"),
    ({"columns": {"time": "t", "force": "F", "velocity": "v"}, "layout": {"pattern": "(["}}, "regular expression"),
    ({"columns": {"time": "t", "force": "F", "velocity": "v"}, "fit": {"modle": "auto"}}, "unknown key"),
    ({"columns": {"time": "t", "force": "F", "velocity": "v"}, "dynamic": {"lugre": "yes"}}, "true or false"),
    ({"columns": {"time": "t", "force": "F", "velocity": "v"}, "scales": {"force": 0}}, "non-zero"),
    ({"columns": {"time": "t", "force": "F", "velocity": "v"}, "schedule": {"oil temp": "T"}}, "letters"),
])
def test_config_mistakes_are_named(doc, match):
    with pytest.raises(DataError, match=match):
        config_from_dict(doc, source="fleet.toml")


def test_config_file_errors(tmp_path):
    with pytest.raises(DataError, match="not found"):
        load_config(tmp_path / "none.toml")
    bad = tmp_path / "bad.toml"
    bad.write_text("[columns\n")
    with pytest.raises(DataError, match="not valid TOML"):
        load_config(bad)
    ok = tmp_path / "ok.toml"
    ok.write_text('[columns]\ntime = "t"\nforce = "T"\nvelocity = "w"\n[units]\nforce = "N·m"\nvelocity = "rpm"\n')
    cfg = load_config(ok)
    assert cfg.si_units == {"v": "rad/s", "F": "N·m"} and abs(cfg.scales["velocity"] - 0.10471975511965977) < 1e-15


def test_one_unpartitioned_parquet_file_of_many_axes_and_dates(small_fleet, single_run, tmp_path):
    """Every good log of the small fleet stacked in one Parquet file with ``axis`` and ``date``
    columns: the dataset is that file; one task per (axis, date); the same parameters."""
    from dataclasses import replace

    broken = {p for p, _ in small_fleet.broken}
    good = [p for p in small_fleet.files if p not in broken][:5]
    frames = []
    for rel in good:
        f = small_fleet.root / rel
        df = pd.read_parquet(f) if rel.endswith(".parquet") else pd.read_csv(f)
        frames.append(df.assign(axis=rel.split("/")[0], date=pd.Timestamp(rel.split("/")[1][:10])))
    one = tmp_path / "fleet.parquet"
    pd.concat(frames[::-1], ignore_index=True).to_parquet(one)  # rows in any order of the keys
    cfg = replace(load_config(small_fleet.config), layout={"axis_column": "axis", "period_column": "date"},
                  patterns=DEFAULT_PATTERNS)  # no pattern of its own: the columns give axis and period
    logs, _ = discover(one, cfg)
    assert [(g.axis, g.period) for g in logs] == sorted((r.split("/")[0], r.split("/")[1][:10]) for r in good)
    assert all(g.select for g in logs) and len({g.fingerprint for g in logs}) == len(good)
    run = identify_fleet(one, out=tmp_path / "r.parquet", config=cfg, scheduler="none", progress=False, monitor=False)
    got = run.table.set_index(["axis", "period"])[list(PARAM_COLUMNS)]
    ref = single_run.table.set_index(["axis", "period"]).loc[got.index, list(PARAM_COLUMNS)]
    pd.testing.assert_frame_equal(got, ref, check_exact=True)
    assert run.table["n_samples"].eq(20_000).all() and run.table["file"].eq("fleet.parquet").all()
    again = identify_fleet(one, out=tmp_path / "r.parquet", config=cfg, scheduler="none", progress=False)
    assert (again.computed, again.skipped) == (0, len(good))


def test_layout_keys_are_checked():
    base = {"columns": {"time": "t", "force": "F", "velocity": "v"}}
    with pytest.raises(DataError, match="both axis and axis_column"):
        config_from_dict({**base, "layout": {"axis": "a", "axis_column": "ax"}})
    with pytest.raises(DataError, match="non-empty string"):
        config_from_dict({**base, "layout": {"record_column": 3}})
    with pytest.raises(DataError, match="unknown key"):
        config_from_dict({**base, "layout": {"axes_column": "a"}})
    cfg = config_from_dict({**base, "layout": {"axis": "a", "period_column": "day", "pattern": r"x\.csv$"}})
    assert cfg.match("x.csv") == ("a", None) and cfg.match("y.csv") is None
    assert config_from_dict(base).sha256 == config_from_dict({**base, "layout": {}}).sha256  # old parts stay valid


def test_simulated_fleets_side_files_are_not_recordings_and_unknown_files_are_still_reported(tmp_path):
    # `fleet identify` on a simulated fleet warned "4 data file(s) match no [layout] pattern" about the
    # simulator's own truth.csv, truth_days.csv, broken.csv, broken.txt; fleet.toml now names them
    from frictionkit.fleet.simulate import fleet_config_toml

    (tmp_path / "fleet.toml").write_text(fleet_config_toml())
    for rel in ("axis-0001/2026-01-05.csv", "truth.csv", "truth_days.csv", "broken.csv", "broken.txt", "notes.csv"):
        (tmp_path / rel).parent.mkdir(exist_ok=True)
        (tmp_path / rel).write_text("t_s\n0\n")
    cfg = load_config(tmp_path / "fleet.toml")
    logs, unmatched = discover(tmp_path, cfg)
    assert [g.file for g in logs] == ["axis-0001/2026-01-05.csv"]
    assert unmatched == ["notes.csv"]  # a file nobody named is still reported
    # the list is checked, and changes no result (the parts of a fleet stay valid)
    base = {"columns": {"time": "t", "force": "F", "velocity": "v"}}
    assert config_from_dict({**base, "layout": {"ignore": ["notes/*"]}}).sha256 == config_from_dict(base).sha256
    assert config_from_dict({**base, "layout": {"ignore": "notes/*"}}).ignores("notes/a/b.csv")
    with pytest.raises(DataError, match=r"\[layout\] ignore = 5: must be a list of file patterns"):
        config_from_dict({**base, "layout": {"ignore": 5}})
