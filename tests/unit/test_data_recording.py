"""Recording: validation at construction, with messages that name file, column and row."""

from __future__ import annotations

import warnings

import numpy as np
import pytest

from frictionkit.data import IrregularSamplingWarning, Recording
from frictionkit.errors import DataError


def _t(n=10, dt=1e-3):
    return np.arange(n) * dt


def test_valid_recording_keeps_signals_and_default_units():
    rec = Recording(t=_t(), v=np.ones(10), F=2 * np.ones(10), name="ok")
    assert rec.n == 10
    assert rec.dt == pytest.approx(1e-3)
    assert rec.fs == pytest.approx(1000.0)
    assert rec.signals == ("v", "F")
    assert rec.units["F"] == "N" and rec.units["t"] == "s"
    with pytest.raises(ValueError):  # read-only arrays
        rec.v[0] = 3.0


def test_nan_message_names_signal_and_row():
    v = np.ones(10)
    v[4] = np.nan
    with pytest.raises(DataError, match=r"signal 'v', row 4: value nan is not finite"):
        Recording(t=_t(), v=v)


def test_inf_message_names_file_and_column_from_provenance():
    F = np.ones(10)
    F[7] = np.inf
    prov = {"file": "run1.csv", "columns": {"F": "torque_Nm"}}
    with pytest.raises(DataError, match=r"file 'run1.csv', column 'torque_Nm', row 7: value inf"):
        Recording(t=_t(), F=F, provenance=prov)


def test_time_going_backwards():
    t = _t()
    t[5] = t[3]
    with pytest.raises(DataError, match=r"row 5: time .* goes backwards .*strictly increasing"):
        Recording(t=t)


def test_repeated_time_stamp():
    t = _t()
    t[6] = t[5]
    with pytest.raises(DataError, match=r"row 6: time .* repeats the previous time stamp"):
        Recording(t=t)


def test_too_few_samples():
    with pytest.raises(DataError, match=r"has 1 sample\(s\); a recording needs at least 2 samples"):
        Recording(t=[0.0])


def test_length_mismatch():
    with pytest.raises(DataError, match=r"signal 'x': has 9 samples but t has 10"):
        Recording(t=_t(), x=np.zeros(9))


def test_irregular_sampling_warns_and_resample_fixes_it():
    t = np.array([0.0, 1.0, 2.0, 3.5, 4.5, 5.5]) * 1e-3
    x = 2.0 * t
    with pytest.warns(IrregularSamplingWarning, match=r"irregular sampling, step at row 3 .*resample"):
        rec = Recording(t=t, x=x)
    assert not rec.is_regular
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        even = rec.resample(0.5e-3)
    assert even.is_regular
    assert np.allclose(np.diff(even.t), 0.5e-3)
    assert np.allclose(even.x, 2.0 * even.t)  # linear signal interpolates exactly
    assert even.provenance["resampled_dt"] == 0.5e-3


def test_tiny_jitter_is_not_irregular():
    rng = np.random.default_rng(0)
    t = _t(1000) + rng.uniform(-4e-8, 4e-8, 1000)  # EMPS-like jitter
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        Recording(t=t)


def test_force_from_current_and_missing_signal():
    rec = Recording(t=_t(), current=np.full(10, 2.0), current_gain=0.5)
    assert np.allclose(rec.force(), 1.0)
    with pytest.raises(DataError, match=r"missing signal\(s\) x"):
        rec.require("x")
    with pytest.raises(DataError, match=r"missing signal\(s\) F \(or current with current_gain\)"):
        Recording(t=_t(), v=np.ones(10)).force()


def test_segment_slices_every_signal():
    rec = Recording(t=_t(), v=np.arange(10.0), F=-np.arange(10.0))
    s = rec.segment(2, 5)
    assert s.t.tolist() == pytest.approx([0.002, 0.003, 0.004])
    assert s.v.tolist() == [2.0, 3.0, 4.0]
    assert s.F.tolist() == [-2.0, -3.0, -4.0]
    with pytest.raises(DataError, match="need 0 <= start < stop <= 10"):
        rec.segment(5, 11)
