"""Property: random option values and random ``--static-json`` files end in a result or one ``error:`` line.

Never a traceback, never an exception escaping the CLI. About 15 s in all.
"""

from __future__ import annotations

import copy
import json

from _robustness_helpers import PRESLIDING_ARGS, STATIC_ARGS, stderr_of
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st
from typer.testing import CliRunner

from frictionkit.cli import app

runner = CliRunner()
FUZZ = settings(deadline=None, derandomize=True, suppress_health_check=[HealthCheck.function_scoped_fixture])
# derandomize: the same examples on every run (the suite's time stays put); the campaign explores wider


def _ends_cleanly(res) -> None:
    assert res.exception is None or isinstance(res.exception, SystemExit), repr(res.exception)
    if res.exit_code == 0:
        return
    err = stderr_of(res).strip()
    assert "Traceback" not in err, err
    assert len(err.splitlines()) == 1 and err.startswith("error: "), err
    assert res.exit_code in (1, 2), res.exit_code


numbers = st.one_of(
    st.floats(allow_nan=True, allow_infinity=True).map(repr),
    st.sampled_from(["0", "-0", "1e300", "-1e300", "1e-320", "nan", "-inf", "1e12", "1e-12", "35.15"]),
    st.integers(-10**30, 10**30).map(str),
    st.text(max_size=6),
)


@settings(FUZZ, max_examples=60)
@given(force=numbers, velocity=numbers, position=numbers, trim=st.one_of(st.none(), numbers))
def test_static_scale_options(staircase_csv, force, velocity, position, trim):
    args = ["identify", "static", str(staircase_csv), *STATIC_ARGS, "--force-scale", force,
            "--velocity-scale", velocity, "--position-scale", position]
    if trim is not None:
        args += ["--trim", trim]
    _ends_cleanly(runner.invoke(app, args))


def _json_values():
    leaves = st.one_of(st.none(), st.booleans(), st.integers(-10**20, 10**20),
                       st.floats(allow_nan=False, allow_infinity=False), st.text(max_size=8))
    return st.recursive(leaves, lambda inner: st.one_of(st.lists(inner, max_size=4),
                                                        st.dictionaries(st.text(max_size=6), inner, max_size=4)),
                        max_leaves=12)


def _paths(doc, prefix=()):
    yield prefix
    if isinstance(doc, dict):
        for k, v in doc.items():
            yield from _paths(v, (*prefix, k))
    elif isinstance(doc, list):
        for i, v in enumerate(doc):
            yield from _paths(v, (*prefix, i))


@st.composite
def static_files(draw, valid: bytes):
    kind = draw(st.sampled_from(["bytes", "json", "mutated", "truncated"]))
    if kind == "bytes":
        return draw(st.binary(max_size=300))
    if kind == "json":
        return json.dumps(draw(_json_values())).encode()
    if kind == "truncated":
        return valid[: draw(st.integers(0, len(valid)))]
    doc = json.loads(valid)
    doc.pop("data", None)
    paths = [p for p in _paths(doc) if p]
    for _ in range(draw(st.integers(1, 3))):
        path = draw(st.sampled_from(paths))
        node = doc
        try:
            for key in path[:-1]:
                node = node[key]
            if draw(st.booleans()):
                node[path[-1]] = draw(_json_values())
            elif isinstance(node, dict):
                del node[path[-1]]
        except (KeyError, IndexError, TypeError):
            pass
    return json.dumps(copy.deepcopy(doc)).encode()


@settings(FUZZ, max_examples=80)
@given(data=st.data())
def test_random_static_json(gms_csv, static_json, tmp_path_factory, data):
    raw = data.draw(static_files(static_json.read_bytes()))
    p = tmp_path_factory.mktemp("fuzz") / "static.json"
    p.write_bytes(raw)
    res = runner.invoke(app, ["identify", "presliding", str(gms_csv), *PRESLIDING_ARGS, "--no-refine",
                              "--static-json", str(p)])
    _ends_cleanly(res)
