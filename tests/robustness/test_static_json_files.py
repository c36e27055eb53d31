"""Malformed ``--static-json`` files: one line naming the file and what is wrong, never a traceback."""

from __future__ import annotations

import copy
import json

import pytest
from _robustness_helpers import PRESLIDING_ARGS, one_error_line

from frictionkit.cli import app


def _doc(static_json):
    return json.loads(static_json.read_text(encoding="utf-8"))


def _edit(doc, path, value=None, *, delete=False):
    d = copy.deepcopy(doc)
    node = d
    for key in path[:-1]:
        node = node[key]
    if delete:
        del node[path[-1]]
    else:
        node[path[-1]] = value
    return d


def _run(runner, gms_csv, path, verb="presliding"):
    if verb == "presliding":
        args = ["identify", "presliding", str(gms_csv), *PRESLIDING_ARGS, "--static-json", str(path)]
    else:
        args = ["identify", "output-error", str(gms_csv), "--time", "t_s", "--position", "x_m", "--force", "F_N",
                "--mass", "1", "--static-json", str(path)]
    return runner.invoke(app, args)


# (label, bytes or a function of the valid document, expected part of the message)
RAW_CASES = [
    ("empty", b"", "not valid JSON (Expecting value at line 1, column 1)"),
    ("truncated", None, "not valid JSON"),
    ("binary", bytes(range(256)) * 4, "not UTF-8 text (byte 128)"),
    ("latin-1", "{\"format\": \"Größe\"}".encode("latin-1"), "not UTF-8 text"),
    ("list", b"[1, 2, 3]", "the top level is a JSON list, expected an object"),
    ("string", b"\"static\"", "the top level is a JSON str, expected an object"),
    ("number", b"42", "the top level is a JSON int, expected an object"),
    ("null", b"null", "the top level is a JSON NoneType, expected an object"),
    ("deep", b"[" * 100_000 + b"]" * 100_000, "JSON nested too deeply"),
    ("other json", b"{\"a\": 1}", "not a frictionkit identification result (\"format\" is None"),
]


@pytest.mark.parametrize("label, raw, needle", RAW_CASES, ids=[c[0] for c in RAW_CASES])
def test_raw_files(runner, gms_csv, static_json, tmp_path, label, raw, needle):
    p = tmp_path / "static.json"
    p.write_bytes(static_json.read_bytes()[:200] if raw is None else raw)
    res = _run(runner, gms_csv, p)
    assert res.exit_code == 2
    err = one_error_line(res)
    assert err.startswith(f"error: --static-json '{p}': ")
    assert needle in err


EDITS = [
    ("wrong format", ["format"], "frictionkit.identification/0", "\"format\" is 'frictionkit.identification/0'"),
    ("wrong kind", ["kind"], "presliding", "not a static-map result (\"kind\" is 'presliding'"),
    ("no parameters", ["parameters"], None, "missing key 'parameters'"),
    ("no parts", ["parts"], None, "stribeck_model: needs a fit with direction='both'"),
    ("no positive part", ["parts", "positive"], None, "needs a fit with direction='both'"),
    ("no part model", ["parts", "positive", "model"], None, "a direction has no valid model"),
    ("parameters a list", ["parameters"], [1, 2], "malformed content"),
    ("value a string", ["parameters", "Fc_pos", "value"], "one", "parameters.Fc_pos.value is \"one\", expected a finite number"),
    ("value a dict", ["parameters", "Fc_pos", "value"], {"x": 1}, 'parameters.Fc_pos.value is {"x": 1}, expected a finite number'),
    ("rms a string", ["rms"], "abc", 'rms is "abc", expected a number >= 0 or null'),
    ("n_obs a list", ["n_obs"], [1], "malformed content (TypeError"),
    ("parts a list", ["parts"], [1], "malformed content"),
    ("part a string", ["parts", "positive"], "x", "malformed content"),
    ("model type unknown", ["parts", "positive", "model", "type"], "Magic", "model type 'Magic' unknown"),
    ("model field missing", ["parts", "positive", "model", "Fc"], None, "law 'Stribeck': field 'Fc' missing"),
    ("model field extra", ["parts", "positive", "model", "mu"], 0.3, "law 'Stribeck': unknown field 'mu'"),
    ("model field negative", ["parts", "positive", "model", "vs"], -1.0, "Stribeck.vs = -1.0: must be > 0"),
    ("model field string", ["parts", "positive", "model", "Fc"], "1.0",
     "parts.positive.model.Fc is \"1.0\", expected a number"),
    ("model field true", ["model", "negative", "sigma2"], True, "model.negative.sigma2 is true, expected a number"),
    ("part parameters edited", ["parts", "negative", "parameters", "Fc", "value"], 0.5,
     "parts.negative: parameters.Fc.value = 0.5 disagrees with model.Fc = 1; the file was edited in one place only"),
    ("correlation wrong shape", ["correlation"], [[1.0]], "correlation is [[1.0]], expected a"),
    ("top model edited", ["model", "positive", "Fc"], 2.0,
     "parameters.Fc_pos.value = 1 disagrees with model.positive.Fc = 2; the file was edited in one place only"),
    ("parameters edited", ["parameters", "Fs_neg", "value"], 3.0,
     "parameters.Fs_neg.value = 3 disagrees with model.negative.Fs = 1.5; the file was edited in one place only"),
    ("model nested deeply", ["model", "positive", "Fc"], None, "JSON nested too deeply"),
    ("top model one-sided", ["model"], {"type": "CoulombViscous", "Fc": 1.0, "sigma2": 0.4},
     "the top-level \"model\" (CoulombViscous) has no positive direction"),
]


@pytest.mark.parametrize("label, path, value, needle", EDITS, ids=[c[0] for c in EDITS])
def test_edited_files(runner, gms_csv, static_json, tmp_path, label, path, value, needle):
    if label == "model nested deeply":  # within json's limit, beyond any sane model
        value = {"type": "Stribeck"}
        for _ in range(600):
            value = {"type": "Directional", "positive": value}
    doc = _edit(_doc(static_json), path, value, delete=value is None)
    p = tmp_path / "static.json"
    p.write_text(json.dumps(doc), encoding="utf-8")
    res = _run(runner, gms_csv, p)
    assert res.exit_code == 2
    err = one_error_line(res)
    assert err.startswith(f"error: --static-json '{p}': ")
    assert needle in err


def test_missing_file_and_folder(runner, gms_csv, tmp_path):
    res = _run(runner, gms_csv, tmp_path / "none.json")
    assert res.exit_code == 2
    assert one_error_line(res) == f"error: --static-json '{tmp_path / 'none.json'}': not found"  # checked up front
    res = _run(runner, gms_csv, tmp_path)
    assert res.exit_code == 2
    assert one_error_line(res) == f"error: --static-json '{tmp_path}' is a folder; give a data file"


def test_valid_file_still_works_and_output_error_uses_the_same_loader(runner, gms_csv, static_json, tmp_path):
    res = _run(runner, gms_csv, static_json)
    assert res.exit_code == 0, res.output
    bad = tmp_path / "bad.json"
    bad.write_bytes(b"\xff\xfe garbage")
    res = _run(runner, gms_csv, bad, verb="output-error")
    assert res.exit_code == 2
    assert "not UTF-8 text" in one_error_line(res)


def test_top_level_model_edited_consistently_is_used(runner, gms_csv, static_json, tmp_path):
    """An edit made everywhere (model, parameters, parts) is accepted, not ignored."""
    doc = _doc(static_json)
    for node in (doc["model"]["positive"], doc["parts"]["positive"]["model"]):
        node["Fc"] = 1.1
    doc["parameters"]["Fc_pos"]["value"] = 1.1
    doc["parts"]["positive"]["parameters"]["Fc"]["value"] = 1.1
    p = tmp_path / "static.json"
    p.write_text(json.dumps(doc), encoding="utf-8")
    from frictionkit.cli._common import load_static_json

    law = load_static_json(p)
    assert law.positive.Fc == 1.1 and law.negative.Fc == doc["model"]["negative"]["Fc"]
