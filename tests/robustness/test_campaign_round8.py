"""Issue 13, round 7's leftovers and campaign round 8 (helper r13): one test per pattern fixed, each
built from the case that exposed it."""

from __future__ import annotations

import errno
import os
import tempfile

import pytest

from frictionkit.errors import DataError

_LAW_FILE = {"format": "frictionkit.model/1", "model": {"law": "Dahl", "Fc": 1.0, "sigma0": 1e5}}


@pytest.mark.skipif(not os.path.isfile("/proc/version"), reason="needs Linux /proc")
def test_a_folder_that_takes_no_new_files_is_named_as_such():
    """Was (round 7): `export --out /proc/version` said "folder '/proc' is not writable (No such file or
    directory)" — the system's text for ENOENT, read as if the folder were missing."""
    from frictionkit._io import check_output_file

    with pytest.raises(DataError) as exc:
        check_output_file("/proc/version", option="--out")
    msg = str(exc.value)
    assert msg.startswith("--out '/proc/version': folder '/proc' is not writable (it does not accept new files")
    assert "No such file" not in msg


def test_a_read_only_file_system_is_named(monkeypatch, tmp_path):
    from frictionkit import _io

    def refuse(*a, **k):
        raise OSError(errno.EROFS, os.strerror(errno.EROFS))

    monkeypatch.setattr(tempfile, "mkstemp", refuse)
    with pytest.raises(DataError, match=r"is not writable \(read-only file system\)"):
        _io.check_output_file(tmp_path / "r.json", option="--json")


@pytest.mark.parametrize("key,value", [("provenance", []), ("provenance", None), ("provenance", ""),
                                       ("units", []), ("units", None)])
def test_an_optional_key_of_the_wrong_type_is_refused_even_when_empty(key, value):
    """Was (round 7): `"provenance": []` (or null, "") in a law file was read as no provenance without a
    word, while the identification JSON refused it. One rule now: absent is none, present must be an object."""
    from frictionkit.models.files import ModelFile

    with pytest.raises(DataError, match=rf'^"{key}" is a JSON \w+ .*expected an object'):
        ModelFile.from_dict(dict(_LAW_FILE, **{key: value}))
    assert ModelFile.from_dict(dict(_LAW_FILE, **{key: {}})).model.Fc == 1.0  # empty, right type: fine


#: The hand-written minimal machine file of tests/unit/test_machine_files.py.
_MACHINE_FILE = {"format": "frictionkit.model/1", "kind": "machine",
                 "model": {"name": "slider", "dofs": [{"name": "x", "inertia": 2.0}],
                           "sites": [{"name": "c", "role": "friction", "at": {"x": 1.0},
                                      "law": {"law": "CoulombViscous", "Fc": 1.0}}],
                           "actuators": [{"name": "u", "at": {"x": 1.0}}]}}


def test_a_machine_file_takes_the_same_rule_for_its_optional_keys():
    """Was: "inputs": null, "provenance": [] and "units": null were read as absent in a machine file."""
    from frictionkit.models.files import ModelFile

    assert ModelFile.from_dict(dict(_MACHINE_FILE, inputs=["u"], units={}, provenance={})).model.input_names() == ["u"]
    for key, value, what in (("provenance", [], "an object"), ("units", None, "an object"),
                             ("inputs", None, "a list of names"), ("inputs", {}, "a list of names")):
        with pytest.raises(DataError, match=rf'^"{key}" is a JSON \w+ .*expected {what}'):
            ModelFile.from_dict(dict(_MACHINE_FILE, **{key: value}))


def test_a_two_direction_result_states_each_number_once_in_effect(static_json):
    """Was (round 7 leftover): the top-level model vs parts.<side>.model agreement was load_static_law's own
    check only, so `report`/`load_model` of a result edited in the top-level model AND its table (both 1 -> 5)
    showed 5 while its parts said 1. Now IdentificationResult.from_dict checks it for every reader, and
    load_static_law uses that one check (same message)."""
    import json

    from frictionkit.identify.result import IdentificationResult
    from frictionkit.identify.start_values import load_static_law

    doc = json.loads(static_json.read_text(encoding="utf-8"))
    fc = doc["parts"]["positive"]["model"]["Fc"]
    doc["model"]["positive"]["Fc"] = 5.0 * fc
    doc["parameters"]["Fc_pos"]["value"] = 5.0 * fc
    want = (rf'the top-level "model" \(positive.Fc = {5 * fc:g}\) disagrees with parts.positive.model '
            rf"\(Fc = {fc:g}\); the file was edited in one place only")
    with pytest.raises(DataError, match=want):
        IdentificationResult.from_dict(doc)
    p = static_json.parent / "r8_edited.json"
    p.write_text(json.dumps(doc), encoding="utf-8")
    with pytest.raises(DataError, match=want):
        load_static_law(p)
    del doc["model"]  # without a top-level model the table is held against the parts
    with pytest.raises(DataError, match=rf"parameters.Fc_pos.value = {5 * fc:g} disagrees with parts.positive.model "):
        IdentificationResult.from_dict(doc)
    for key in ("parts", "data"):  # optional keys: the same rule as model files
        with pytest.raises(DataError, match=rf'"{key}" is \[\], expected an object'):
            IdentificationResult.from_dict(dict(json.loads(static_json.read_text(encoding="utf-8")), **{key: []}))
