"""Issue 13 round 11, family T residuals: public entry points given a wrong type in one argument ended in
Python's or numpy's own TypeError/ValueError/AttributeError (or were accepted). Each must be the package's
ParameterError naming the argument."""

from __future__ import annotations

import numpy as np
import pytest

import frictionkit as fk
from frictionkit.data import Recording, load_groups, steady_state_points
from frictionkit.errors import ParameterError
from frictionkit.identify.presliding import fit_presliding
from frictionkit.identify.static_map import fit_static_map, fit_static_records

T = np.arange(5) * 1e-3
F = np.ones(5)


@pytest.mark.parametrize("kw, name", [
    ({"current_gain": "abc"}, "current_gain"), ({"current_gain": object()}, "current_gain"),
    ({"current_gain": [np.nan]}, "current_gain"), ({"units": "abc"}, "units"), ({"units": None}, "units"),
    ({"units": [np.nan]}, "units"), ({"name": None}, "name"), ({"name": object()}, "name"),
    ({"provenance": "abc"}, "provenance"), ({"provenance": None}, "provenance"),
])
def test_recording_fields_of_the_wrong_type_are_named(kw, name):
    with pytest.raises(ParameterError, match=rf"Recording\.{name} = "):
        Recording(t=T, F=F, **kw)


def test_recording_keeps_its_legal_fields():
    rec = Recording(t=T, F=F, current=F, current_gain=np.float64(2.0), units={"F": "kN"}, name="r",
                    provenance={"file": "a.csv"})
    assert rec.current_gain == 2.0 and rec.units["F"] == "kN" and rec.provenance["file"] == "a.csv"


def _branch():
    x = np.linspace(0.0, 20e-6, 201)
    return {"t": np.arange(x.size) * 1e-3, "x": x, "F": 1e5 * x}


@pytest.mark.parametrize("static", ["abc", object(), [np.nan]])
def test_fit_presliding_names_a_static_map_that_is_none(static):
    with pytest.raises(ParameterError, match=r"fit_presliding\.static = "):
        fit_presliding(_branch(), elements=2, static=static)


def test_fit_presliding_names_rests_that_are_no_masks():
    with pytest.raises(ParameterError, match=r"rests = "):
        fit_presliding(_branch(), elements=2, rests=object())


@pytest.mark.parametrize("sigma", ["abc", object()])
def test_fit_static_map_names_sigma(sigma):
    v = np.r_[np.linspace(-1, -0.1, 10), np.linspace(0.1, 1, 10)]
    with pytest.raises(fk.errors.DataError, match=r"fit_static_map\.sigma"):
        fit_static_map(v, np.sign(v) * (1 + 0.1 * np.abs(v)), sigma=sigma)


@pytest.mark.parametrize("records", ["abc", object(), [np.nan]])
def test_fit_static_records_names_records_that_are_no_mapping(records):
    with pytest.raises(ParameterError, match=r"records|source"):
        fit_static_records(records)


def test_steady_state_points_names_an_entry_that_is_no_recording():
    with pytest.raises(ParameterError, match=r"source\['b'\] = 3"):
        steady_state_points({"a": Recording(t=T, v=F, F=F), "b": 3})


@pytest.mark.parametrize("group", [None, object(), [1, 2]])
def test_load_groups_names_group(tmp_path, group):
    p = tmp_path / "g.csv"
    p.write_text("t,v,F,g\n0,1,1,a\n0.001,1,1,a\n0.002,1,1,a\n")
    with pytest.raises(ParameterError, match=r"load_groups\.group = "):
        load_groups(p, group=group, time="t", velocity="v", force="F")


def test_stribeck_shape_that_is_no_name():
    with pytest.raises(ParameterError, match=r"shape = \[nan\]"):
        fk.Stribeck(Fc=1.0, Fs=1.5, vs=1e-3, shape=[np.nan])


def test_simulate_batch_compare_that_is_no_name():
    law = fk.Dahl(Fc=1.0, sigma0=1e5)
    with pytest.raises(ParameterError, match=r"compare = \[nan\]"):
        fk.simulate_batch([law], masses=[1.0], force=np.zeros(10), dt=1e-3, target=np.zeros(10), compare=[np.nan])
