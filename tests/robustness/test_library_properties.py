"""Property layer of issue 13 (library side): random inputs end in a result, a flagged result
or one of the package's own errors — never a foreign exception, never a silent wrong answer.

* random files into the .mat, HDF5 and Parquet loaders (random bytes, and well-formed
  files holding random columns);
* random JSON into ``IdentificationResult.from_dict`` / ``load_json`` and the law registry
  (``law_from_dict``), both free-form and as one-field edits of a valid document;
* random legal LuGre and GMS parameters into force-driven ``simulate``, checked against
  the ``solve_ivp`` twin: either status 0 and within tolerance, or status != 0.

Examples are derandomized (the suite's time stays put; the campaign explores wider).
"""

from __future__ import annotations

import copy
import json
import warnings

import h5py
import numpy as np
import pandas as pd
import pytest
import scipy.io
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

import frictionkit as fk
from frictionkit.data import Recording, load_recording
from frictionkit.errors import FrictionKitError
from frictionkit.identify import IdentificationResult, fit_static_map
from frictionkit.models import law_from_dict
from frictionkit.models.gms import GMSWeightWarning

PROPS = settings(deadline=None, derandomize=True, suppress_health_check=list(HealthCheck))
ROLES = dict(time="t", velocity="v", force="F")


def _loads_or_own_error(path) -> None:
    try:
        rec = load_recording(path, **ROLES)
    except FrictionKitError:
        return
    assert isinstance(rec, Recording)
    assert np.isfinite(rec.F).all() and np.isfinite(rec.v).all()


# ------------------------------------------------------------------ random columns
def _column(draw, n):
    kind = draw(st.sampled_from(["float", "int", "bool", "nan", "huge", "short", "text", "2d", "const"]))
    if kind == "float":
        return np.array(draw(st.lists(st.floats(-1e6, 1e6), min_size=n, max_size=n)), dtype=float)
    if kind == "int":
        return np.arange(n, dtype=np.int64) * draw(st.integers(-5, 5))
    if kind == "bool":
        return np.arange(n) % 2 == 0
    if kind == "nan":
        a = np.linspace(0.0, 1.0, n)
        a[draw(st.integers(0, n - 1))] = draw(st.sampled_from([np.nan, np.inf, -np.inf]))
        return a
    if kind == "huge":
        a = np.linspace(0.1, 1.0, n)
        a[draw(st.integers(0, n - 1))] = 1e300
        return a
    if kind == "short":
        return np.linspace(0.0, 1.0, max(n - draw(st.integers(1, 5)), 1))
    if kind == "text":
        return np.array([draw(st.text(max_size=3)) for _ in range(n)], dtype=object)
    if kind == "2d":
        return np.ones((n, 2))
    return np.full(n, draw(st.floats(-10, 10)))


@st.composite
def tables(draw):
    n = draw(st.integers(1, 40))
    cols = {}
    for name in draw(st.lists(st.sampled_from(["t", "v", "F", "x", "other"]), min_size=0, max_size=5, unique=True)):
        cols[name] = _column(draw, n)
    if "t" in cols and draw(st.booleans()):
        cols["t"] = np.arange(n) * 1e-3  # often a good time column, so the other checks are reached
    return cols


@settings(PROPS, max_examples=40)
@given(cols=tables(), raw=st.binary(max_size=300), use_raw=st.booleans())
def test_random_mat_files(tmp_path_factory, cols, raw, use_raw):
    p = tmp_path_factory.mktemp("mat") / "r.mat"
    if use_raw:
        p.write_bytes(b"MATLAB 5.0 MAT-file" + raw if raw[:1] == b"\x00" else raw)
    else:
        scipy.io.savemat(p, {k: (v.astype(str) if v.dtype == object else v) for k, v in cols.items()})
    _loads_or_own_error(p)


@settings(PROPS, max_examples=40)
@given(cols=tables(), raw=st.binary(max_size=300), use_raw=st.booleans())
def test_random_hdf5_files(tmp_path_factory, cols, raw, use_raw):
    p = tmp_path_factory.mktemp("h5") / "r.h5"
    if use_raw:
        p.write_bytes(b"\x89HDF\r\n\x1a\n" + raw if raw[:1] == b"\x00" else raw)
    else:
        with h5py.File(p, "w") as f:
            for k, v in cols.items():
                f.create_dataset(k, data=np.array([str(x).encode("utf-8") for x in v]) if v.dtype == object else v)
    _loads_or_own_error(p)


@settings(PROPS, max_examples=40)
@given(cols=tables(), raw=st.binary(max_size=300), use_raw=st.booleans())
def test_random_parquet_files(tmp_path_factory, cols, raw, use_raw):
    p = tmp_path_factory.mktemp("pq") / "r.parquet"
    if use_raw:
        p.write_bytes(b"PAR1" + raw + b"PAR1" if raw[:1] == b"\x00" else raw)
    else:
        n = max((len(v) for v in cols.values()), default=0)
        flat = {k: (v if v.ndim == 1 and len(v) == n else np.resize(v.ravel(), n)) for k, v in cols.items()}
        pd.DataFrame(flat).to_parquet(p)
    _loads_or_own_error(p)


# ------------------------------------------------------------------ random JSON
json_values = st.recursive(
    st.one_of(st.none(), st.booleans(), st.integers(-10**20, 10**20),
              st.floats(allow_nan=False, allow_infinity=False), st.text(max_size=8)),
    lambda inner: st.one_of(st.lists(inner, max_size=4), st.dictionaries(st.text(max_size=8), inner, max_size=4)),
    max_leaves=12,
)


@pytest.fixture(scope="module")
def valid_doc():
    v = np.r_[np.geomspace(1e-3, 0.2, 8), -np.geomspace(1e-3, 0.2, 8)]
    law = fk.Stribeck(Fc=1.0, Fs=1.5, vs=1e-2, delta=2.0, sigma2=0.4)
    return fit_static_map(v, law.steady_state(v), model="coulomb_viscous").to_dict(include_data=False)


def _paths(doc, prefix=()):
    yield prefix
    if isinstance(doc, dict):
        for k, v in doc.items():
            yield from _paths(v, (*prefix, k))
    elif isinstance(doc, list):
        for i, v in enumerate(doc[:3]):
            yield from _paths(v, (*prefix, i))


def _result_or_own_error(doc) -> None:
    try:
        res = IdentificationResult.from_dict(doc)
    except FrictionKitError:
        return
    res.summary()  # a result that loads also presents itself


@settings(PROPS, max_examples=60)
@given(doc=json_values)
def test_random_json_into_from_dict(doc):
    _result_or_own_error(doc)
    _result_or_own_error({"format": "frictionkit.identification/1", **(doc if isinstance(doc, dict) else {})})


@settings(PROPS, max_examples=80)
@given(data=st.data(), value=json_values, delete=st.booleans())
def test_valid_document_with_one_field_edited(valid_doc, data, value, delete):
    paths = [p for p in _paths(valid_doc) if p]
    path = data.draw(st.sampled_from(paths))
    doc = copy.deepcopy(valid_doc)
    node = doc
    for k in path[:-1]:
        node = node[k]
    if delete and isinstance(node, dict):
        del node[path[-1]]
    else:
        node[path[-1]] = value
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", GMSWeightWarning)
        _result_or_own_error(json.loads(json.dumps(doc)))


@settings(PROPS, max_examples=60)
@given(name=st.sampled_from(["Stribeck", "CoulombViscous", "LuGre", "GMS", "Dahl", "Directional", "Magic"]),
       fields=st.dictionaries(st.sampled_from(["Fc", "Fs", "vs", "delta", "sigma2", "sigma0", "sigma1", "k", "xi",
                                               "C", "static", "positive", "negative", "shape"]),
                              json_values, max_size=6))
def test_random_json_into_the_law_registry(name, fields):
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", GMSWeightWarning)
        try:
            law = law_from_dict({"law": name, **fields})
        except FrictionKitError:
            return
    law.steady_state(np.array([-1.0, 0.0, 1.0]))


# ------------------------------------------------------------------ simulate vs the solve_ivp twin
DT = 1e-3
N = 201


@st.composite
def lugre_or_gms(draw):
    Fc = draw(st.floats(0.1, 10.0))
    law = fk.Stribeck(Fc=Fc, Fs=Fc * draw(st.floats(1.0, 2.0)), vs=draw(st.floats(1e-3, 0.1)),
                      sigma2=draw(st.floats(0.0, 5.0)))
    if draw(st.booleans()):
        model = fk.LuGre(law, sigma0=draw(st.floats(1e3, 1e6)), sigma1=draw(st.floats(0.0, 100.0)))
    else:
        M = draw(st.integers(1, 3))
        w = np.array(draw(st.lists(st.floats(0.1, 1.0), min_size=M, max_size=M)))
        model = fk.GMS(law, k=sorted(draw(st.lists(st.floats(1e3, 1e6), min_size=M, max_size=M))),
                       xi=(w / w.sum()).tolist(), C=draw(st.floats(1.0, 100.0)))
    m = draw(st.floats(0.01, 10.0))
    amp = Fc * draw(st.floats(0.5, 3.0))
    freq = draw(st.floats(1.0, 20.0))
    return model, m, amp, freq


@settings(PROPS, max_examples=12)
@given(case=lugre_or_gms())
def test_simulate_agrees_with_the_twin_or_says_it_failed(case):
    from importlib import import_module

    reference_force_driven = import_module("frictionkit.simulation.reference").reference_force_driven
    model, m, amp, freq = case
    u = amp * np.sin(2 * np.pi * freq * np.arange(N) * DT)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", RuntimeWarning)
        res = fk.simulate(model, plant=fk.Mass(m), force=u, dt=DT)
    if res.status != 0:
        assert res.message and np.isnan(res.x[res.failed_at + 1:]).all()
        return
    ref = reference_force_driven(model, m, u, DT, rtol=1e-9, atol=1e-13)
    stroke = float(np.max(np.abs(ref["x"])))
    # tolerance: the defaults keep ~1e-6 relative on the README runs (SimOptions docstring); the
    # campaign's silent errors were 1 % and more, so 1e-3 of the stroke (+ 1 nm) separates them
    err = float(np.max(np.abs(res.x - ref["x"])))
    assert err <= 1e-3 * stroke + 1e-9, (err, stroke, model, m, amp, freq)


def test_gms_breakaway_after_a_reversal_inside_one_substep_is_located():
    """Found by the property test above: a light, undamped pre-sliding oscillation whose velocity
    reverses and whose stiffest element then breaks away within one sub-step. The breakaway was
    applied at the step's end (late, past its threshold): 2.9e-8 m = 1.5 % of the stroke off the
    twin at dt = 1 ms, independent of rtol, while dt = 0.5 ms gave 3e-14 m. The twins (LSODA,
    Radau, DOP853) agree to 1e-15 m."""
    from importlib import import_module

    reference_force_driven = import_module("frictionkit.simulation.reference").reference_force_driven
    law = fk.Stribeck(Fc=1.0, Fs=1.098667154517215, vs=0.05518509236015709)  # drawn by hypothesis
    gms = fk.GMS(law, k=[1000.0, 175145.92429616, 746740.0], xi=[0.4691914, 0.37440991, 0.1563987], C=1.0)
    u = 0.5 * np.sin(2 * np.pi * 5.0 * np.arange(N) * DT)  # N on 0.5 kg: the whole stays below breakaway
    ref = reference_force_driven(gms, 0.5, u, DT, rtol=1e-10, atol=1e-14)
    res = fk.simulate(gms, plant=fk.Mass(0.5), force=u, dt=DT)
    stroke = float(np.max(np.abs(ref["x"])))
    assert stroke == pytest.approx(1.8855e-6, rel=1e-3)  # m (twin: 17 switching events)
    assert res.status == 0
    assert float(np.max(np.abs(res.x - ref["x"]))) <= 1e-6 * stroke


def test_gms_swing_inside_one_substep_does_not_hide_breakaways():
    """Found by the property layer: on 0.1 kg the exactly-solved sticking springs let one
    sub-step span a swing out and back, whose breakaways were tested at the ends only —
    1.4 % of the stroke off the twin at dt = 1 ms for every rtol (1e-5 … 1e-9), 7.5e-6 at
    dt = 0.5 ms. Now sub-steps near a switch are capped at 1/8 of the contact period."""
    from importlib import import_module

    reference_force_driven = import_module("frictionkit.simulation.reference").reference_force_driven
    law = fk.Stribeck(Fc=5.009027312833026, Fs=7.513540969249538, vs=0.07523076774846967,
                      sigma2=2.3947309866523843)  # drawn by hypothesis
    gms = fk.GMS(law, k=[224545.8362241, 358046.87450928, 619412.89662187],
                 xi=[0.25147087, 0.3650759, 0.38345323], C=20.3935)
    u = 11.579382568419478 * np.sin(2 * np.pi * 10.384086265298349 * np.arange(N) * DT)  # N
    ref = reference_force_driven(gms, 0.1, u, DT, rtol=1e-10, atol=1e-14)
    import warnings

    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        res = fk.simulate(gms, plant=fk.Mass(0.1), force=u, dt=DT)
    stroke = float(np.max(np.abs(ref["x"])))
    assert stroke == pytest.approx(1.206e-2, rel=1e-2)  # m
    # Since the accuracy check bounds the friction at 5 rtol (2026-11-24, issue 13) this run is flagged:
    # its friction is ~26 rtol of its range off the twin over the whole run (the contract is 10 rtol),
    # so it keeps the samples up to failed_at (51 of 201 measured), each within the contract.
    assert res.status in (0, 2), res.message
    kept = np.isfinite(res.x)
    if res.status == 2:
        assert "accuracy check" in res.message and kept.sum() >= 20, (kept.sum(), res.message)
        assert any(issubclass(w.category, RuntimeWarning) and "accuracy check" in str(w.message) for w in caught)
    assert float(np.max(np.abs(res.x[kept] - ref["x"][kept]))) <= 1e-4 * stroke  # measured 2.2e-5 of the stroke
    F_err = float(np.max(np.abs(res.friction[kept] - ref["friction"][kept])) / np.ptp(ref["friction"]))
    assert F_err <= 10 * fk.SimOptions().rtol, F_err  # measured 7.2e-5 at rtol 1e-5
