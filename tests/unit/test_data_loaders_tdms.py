"""National Instruments ``.tdms`` files (issue 11 part 7): the loader family's mapping, scales and errors.

Every file is written here with npTDMS's own writer (``TdmsWriter``), so the tests need no
binary fixture; the bad files are real TDMS files with one thing wrong (or not TDMS at all).
"""

from __future__ import annotations

import hashlib
import warnings

import numpy as np
import pytest

from frictionkit.data import load_groups, load_recording, read_table
from frictionkit.errors import DataError

nptdms = pytest.importorskip("nptdms")
from nptdms import ChannelObject, TdmsWriter  # noqa: E402

N = 40
T = np.arange(N) * 1e-3
POS = np.sin(T)
VOLT = np.cos(T)
GTAU = 35.15065188248547  # EMPS drive gain [N/V], as in the CSV tests


def _sha(p):
    return hashlib.sha256(p.read_bytes()).hexdigest()


def _write(path, *segments):
    with TdmsWriter(str(path)) as w:
        for seg in segments:
            w.write_segment(seg)
    return path


@pytest.fixture
def tdms_file(tmp_path):
    return _write(tmp_path / "run.tdms", [
        ChannelObject("Axis", "time_s", T),
        ChannelObject("Axis", "pos_mm", POS * 1e3),
        ChannelObject("Axis", "u_V", VOLT),
        ChannelObject("Info", "operator", np.array(["me"] * N)),
    ])


def test_mapping_scales_and_untouched_file(tdms_file):
    before, mtime = _sha(tdms_file), tdms_file.stat().st_mtime_ns
    rec = load_recording(tdms_file, time="Axis/time_s", position="Axis/pos_mm", force="Axis/u_V",
                         scales={"position": 1e-3, "force": GTAU})
    assert np.allclose(rec.x, POS) and np.allclose(rec.F, VOLT * GTAU)
    assert np.array_equal(rec.t, T)
    assert rec.provenance["columns"] == {"t": "Axis/time_s", "x": "Axis/pos_mm", "F": "Axis/u_V"}
    assert rec.provenance["sha256"] == before
    assert _sha(tdms_file) == before and tdms_file.stat().st_mtime_ns == mtime
    assert sorted(p.name for p in tdms_file.parent.iterdir()) == ["run.tdms"]  # no index file written


def test_read_table_names_group_slash_channel(tdms_file):
    assert sorted(read_table(tdms_file)) == ["Axis/pos_mm", "Axis/time_s", "Axis/u_V", "Info/operator"]


def test_segments_are_concatenated(tmp_path):
    p = _write(tmp_path / "seg.tdms",
               [ChannelObject("A", "t", T[:25]), ChannelObject("A", "F", VOLT[:25])],
               [ChannelObject("A", "t", T[25:]), ChannelObject("A", "F", VOLT[25:])])
    rec = load_recording(p, time="A/t", force="A/F")
    assert np.array_equal(rec.t, T) and np.array_equal(rec.F, VOLT)


def test_waveform_time_track_and_timestamps(tmp_path):
    """A waveform channel gives "<group>/<channel>/time" = wf_start_offset + i * wf_increment."""
    stamps = np.datetime64("2026-11-23T01:00:00", "us") + (np.arange(N) * 2000).astype("timedelta64[us]")
    p = _write(tmp_path / "wf.tdms", [
        ChannelObject("DAQ", "velocity", VOLT, properties={"wf_increment": 2e-3, "wf_start_offset": 0.5}),
        ChannelObject("DAQ", "torque", POS),
        ChannelObject("DAQ", "stamp", stamps),
    ])
    rec = load_recording(p, time="DAQ/velocity/time", velocity="DAQ/velocity", force="DAQ/torque")
    assert rec.t[0] == 0.5 and rec.dt == pytest.approx(2e-3, rel=1e-12)
    rec2 = load_recording(p, time="DAQ/stamp", force="DAQ/torque")  # timestamps -> s since the first
    assert rec2.t[0] == 0.0 and rec2.t[-1] == pytest.approx((N - 1) * 2e-3, rel=1e-12)


def test_where_and_groups(tmp_path):
    drive = np.repeat([1.0, 2.0], N // 2)
    run = np.tile(np.repeat(["a", "b"], N // 4), 2)
    t = np.tile(np.arange(N // 4) * 0.1, 4)
    p = _write(tmp_path / "stack.tdms", [ChannelObject("L", "drive", drive), ChannelObject("L", "run", run),
                                        ChannelObject("L", "t", t), ChannelObject("L", "F", drive * 3)])
    one = load_recording(p, time="L/t", force="L/F", where={"L/drive": 2, "L/run": "b"})
    assert one.F.tolist() == [6.0] * (N // 4)
    recs = load_groups(p, group="L/run", where={"L/drive": 1}, time="L/t", force="L/F")
    assert list(recs) == ["a", "b"] and recs["b"].provenance["group"] == {"L/run": "b"}


# ----------------------------------------------------------------------------- bad files
def test_missing_channel_lists_available(tdms_file):
    with pytest.raises(DataError, match=r"file '.*run.tdms': column 'Axis/vel' \(given for velocity\) not found; "
                                        r"available columns: Axis/time_s, Axis/pos_mm, Axis/u_V, Info/operator"):
        load_recording(tdms_file, time="Axis/time_s", velocity="Axis/vel")


def test_nan_names_file_channel_row(tmp_path):
    F = VOLT.copy()
    F[7] = np.nan
    p = _write(tmp_path / "nan.tdms", [ChannelObject("A", "t", T), ChannelObject("A", "F", F)])
    with pytest.raises(DataError, match=r"file '.*nan.tdms', column 'A/F', row 7: value nan is not finite"):
        load_recording(p, time="A/t", force="A/F")


def test_time_going_backwards_names_row(tmp_path):
    t = T.copy()
    t[[10, 11]] = t[[11, 10]]
    p = _write(tmp_path / "back.tdms", [ChannelObject("A", "t", t), ChannelObject("A", "F", VOLT)])
    with pytest.raises(DataError, match=r"column 'A/t', row 11: time .* goes backwards"):
        load_recording(p, time="A/t", force="A/F")


def test_channels_of_different_length(tmp_path):
    p = _write(tmp_path / "short.tdms", [ChannelObject("A", "t", T), ChannelObject("A", "F", VOLT[:30])])
    with pytest.raises(DataError, match=r"file '.*short.tdms', column 'A/F': has 30 samples but t has 40"):
        load_recording(p, time="A/t", force="A/F")
    with pytest.raises(DataError, match=r"column 'A/F' \(given for force\) has 30 rows but the row selection"):
        load_recording(p, time="A/t", force="A/F", where={"A/t": 0.0})


def test_text_channel_is_not_numeric(tdms_file):
    with pytest.raises(DataError, match=r"column 'Info/operator' \(given for force\) is not numeric"):
        load_recording(tdms_file, time="Axis/time_s", force="Info/operator")


def test_not_a_tdms_file(tmp_path):
    p = tmp_path / "fake.tdms"
    p.write_bytes(b"t,F\n0,1\n0.001,2\n")
    with pytest.raises(DataError, match=r"file '.*fake.tdms': cannot be read as TDMS \(it starts with b't,F"):
        load_recording(p, time="A/t")
    p.write_bytes(b"TDSm" + b"\xff" * 40)  # the right tag, nonsense after it
    with pytest.raises(DataError, match=r"file '.*fake.tdms': (cannot be read as TDMS|truncated TDMS|the TDMS)"):
        load_recording(p, time="A/t")


def test_empty_file(tmp_path):
    p = tmp_path / "empty.tdms"
    p.write_bytes(b"")
    with pytest.raises(DataError, match=r"file '.*empty.tdms': the TDMS file holds no channels"):
        load_recording(p, time="A/t")


def test_truncated_file_is_refused(tdms_file, tmp_path):
    raw = tdms_file.read_bytes()
    p = tmp_path / "cut.tdms"
    p.write_bytes(raw[: len(raw) - 100])
    with pytest.raises(DataError, match=r"file '.*cut.tdms': truncated TDMS file"):
        load_recording(p, time="Axis/time_s", force="Axis/u_V")


def test_damaged_files_give_one_data_error(tdms_file, tmp_path):
    """Random byte flips and cuts: the file loads, or fails with a DataError naming it — nothing else."""
    raw = tdms_file.read_bytes()
    rng = np.random.default_rng(11)
    refused = 0
    for k in range(80):
        b = bytearray(raw)
        for _ in range(int(rng.integers(1, 4))):
            b[int(rng.integers(0, len(b)))] = int(rng.integers(0, 256))
        if k % 3 == 0:
            b = b[: int(rng.integers(1, len(b)))]
        p = tmp_path / f"d{k}.tdms"
        p.write_bytes(bytes(b))
        try:
            with warnings.catch_warnings():
                warnings.simplefilter("ignore")  # flipped time stamps: irregular-sampling warnings
                load_recording(p, time="Axis/time_s", force="Axis/u_V")
        except DataError as exc:
            assert f"d{k}.tdms" in str(exc) and "\n" not in str(exc)
            refused += 1
    assert refused > 10  # the corruption does reach the reader
