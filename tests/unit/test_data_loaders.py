"""Loaders: explicit column mapping, scale factors, four file formats, untouched inputs."""

from __future__ import annotations

import hashlib

import h5py
import numpy as np
import pandas as pd
import pytest
import scipy.io

from frictionkit.data import load_csv, load_groups, load_recording, read_table
from frictionkit.errors import DataError

N = 50
T = np.arange(N) * 1e-3
POS = np.sin(T)
VOLT = np.cos(T)


def _sha(p):
    return hashlib.sha256(p.read_bytes()).hexdigest()


@pytest.fixture
def csv_file(tmp_path):
    p = tmp_path / "run.csv"
    pd.DataFrame({"time_s": T, "pos_mm": POS * 1e3, "u_V": VOLT}).to_csv(p, index=False)
    return p


def test_csv_mapping_and_scales(csv_file):
    before = _sha(csv_file)
    mtime = csv_file.stat().st_mtime_ns
    rec = load_csv(csv_file, time="time_s", position="pos_mm", force="u_V",
                   scales={"position": 1e-3, "force": 35.15065188248547})
    assert np.allclose(rec.x, POS)
    assert np.allclose(rec.F, VOLT * 35.15065188248547)
    assert rec.provenance["columns"] == {"t": "time_s", "x": "pos_mm", "F": "u_V"}
    assert rec.provenance["sha256"] == before
    assert _sha(csv_file) == before and csv_file.stat().st_mtime_ns == mtime
    assert sorted(p.name for p in csv_file.parent.iterdir()) == ["run.csv"]


def test_missing_column_message(csv_file):
    with pytest.raises(DataError, match=r"column 'vel' \(given for velocity\) not found; available columns: time_s, pos_mm, u_V"):
        load_csv(csv_file, time="time_s", velocity="vel")


def test_nan_in_file_names_file_column_row(tmp_path):
    p = tmp_path / "bad.csv"
    p.write_text("t,F\n0.0,1.0\n0.001,\n0.002,3.0\n")
    with pytest.raises(DataError, match=r"file '.*bad.csv', column 'F', row 1: value nan is not finite"):
        load_csv(p, time="t", force="F")


def test_non_monotonic_time_in_file(tmp_path):
    p = tmp_path / "back.csv"
    p.write_text("t,F\n0.0,1\n0.002,1\n0.001,1\n")
    with pytest.raises(DataError, match=r"column 't', row 2: time 0.001 goes backwards"):
        load_csv(p, time="t", force="F")


def test_too_few_samples_in_file(tmp_path):
    p = tmp_path / "one.csv"
    p.write_text("t,F\n0.0,1\n")
    with pytest.raises(DataError, match=r"column 't': has 1 sample\(s\)"):
        load_csv(p, time="t", force="F")


def test_unknown_file_type(tmp_path):
    p = tmp_path / "run.xlsx"
    p.write_bytes(b"not really")
    with pytest.raises(DataError, match=r"unknown file type '.xlsx'; supported: .csv"):
        load_recording(p, time="t")


def test_missing_file(tmp_path):
    with pytest.raises(DataError, match=r"not found"):
        load_recording(tmp_path / "nope.csv", time="t")


def test_non_numeric_column(tmp_path):
    p = tmp_path / "s.csv"
    p.write_text("t,F\n0.0,a\n0.001,b\n")
    with pytest.raises(DataError, match=r"column 'F' \(given for force\) is not numeric"):
        load_csv(p, time="t", force="F")


def test_semicolon_csv_is_detected(tmp_path):
    p = tmp_path / "semi.csv"
    p.write_text("t;F\n0.0;1.5\n0.001;2.5\n")
    rec = load_csv(p, time="t", force="F")
    assert rec.F.tolist() == [1.5, 2.5]


def test_mat_v5(tmp_path):
    p = tmp_path / "d.mat"
    scipy.io.savemat(p, {"t": T[:, None], "qm": POS[:, None], "vir": VOLT[None, :], "gtau": 35.15})
    before = _sha(p)
    rec = load_recording(p, time="t", position="qm", force="vir", scales={"force": 2.0})
    assert np.allclose(rec.x, POS) and np.allclose(rec.F, 2 * VOLT)
    assert _sha(p) == before


def test_mat_v73_is_read_through_hdf5(tmp_path):
    p = tmp_path / "d73.mat"
    with h5py.File(p, "w", userblock_size=512) as f:
        f["t"] = T[None, :]  # MATLAB stores column vectors transposed
        f["qm"] = POS[None, :]
    with open(p, "r+b") as fh:
        fh.write(b"MATLAB 7.3 MAT-file, Platform: GLNXA64".ljust(116, b" "))
    rec = load_recording(p, time="t", position="qm")
    assert np.allclose(rec.t, T) and np.allclose(rec.x, POS)


def test_hdf5_dataset_paths(tmp_path):
    p = tmp_path / "d.h5"
    with h5py.File(p, "w") as f:
        f["axis/time"] = T
        f["axis/velocity"] = VOLT
    before = _sha(p)
    rec = load_recording(p, time="axis/time", velocity="axis/velocity")
    assert np.allclose(rec.v, VOLT)
    assert _sha(p) == before
    assert sorted(read_table(p)) == ["axis/time", "axis/velocity"]


def test_parquet(tmp_path):
    p = tmp_path / "d.parquet"
    pd.DataFrame({"t": T, "v_rpm": VOLT}).to_parquet(p)
    rec = load_recording(p, time="t", velocity="v_rpm", scales={"velocity": np.pi / 30})
    assert np.allclose(rec.v, VOLT * np.pi / 30)


def test_unknown_scale_key(csv_file):
    with pytest.raises(DataError, match=r"scales: unknown key\(s\) \['torque'\]"):
        load_csv(csv_file, time="time_s", force="u_V", scales={"torque": 2.0})


def test_groups_and_where(tmp_path):
    p = tmp_path / "stack.csv"
    rows = []
    for drive in (1, 2):
        for rec_name, level in (("a.csv", 1.0), ("b.csv", -2.0)):
            for k in range(4):
                rows.append({"drive": drive, "file": rec_name, "t": k * 0.1, "v": level, "F": level * drive})
    pd.DataFrame(rows).to_csv(p, index=False)
    recs = load_groups(p, group="file", where={"drive": 2}, time="t", velocity="v", force="F")
    assert list(recs) == ["a.csv", "b.csv"]
    assert recs["b.csv"].F.tolist() == [-4.0] * 4
    assert recs["a.csv"].provenance["group"] == {"file": "a.csv"}
    both = load_groups(p, group=["drive", "file"], time="t", force="F")
    assert list(both) == ["1/a.csv", "1/b.csv", "2/a.csv", "2/b.csv"]
    with pytest.raises(DataError, match=r"no row matches where=\{'drive': 3\}"):
        load_groups(p, group="file", where={"drive": 3}, time="t", force="F")
    with pytest.raises(DataError, match=r"column 'run' \(given for group\) not found"):
        load_groups(p, group="run", time="t", force="F")
