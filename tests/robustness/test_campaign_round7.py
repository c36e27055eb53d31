"""Issue 13, round 6's leftovers and campaign round 7 (helper r13): one test per pattern fixed, each
built from the case that exposed it."""

from __future__ import annotations

import copy
import json

import pytest

from frictionkit.errors import DataError

#: A hand-written identification result: two parameters, as ``identify static --json`` lays it out.
_FIT = {
    "format": "frictionkit.identification/1", "kind": "static_map", "model_name": "coulomb_viscous",
    "model": {"type": "Stribeck", "Fc": 1.0, "Fs": 1.0, "vs": 1e-3, "delta": 2.0, "sigma2": 0.4,
              "shape": "exponential"},
    "parameters": {"Fc": {"value": 1.0, "stderr": 0.01, "ci95": [0.98, 1.02], "unit": "N"},
                   "sigma2": {"value": 0.4, "stderr": None, "ci95": [None, None], "unit": "N·s/m"}},
    "correlation": [[1.0, 0.1], [0.1, 1.0]], "rms": 0.01, "relative_error_percent": 1.0,
    "n_obs": 20, "dof": 18, "success": True, "message": "ok",
}


def test_hand_edited_identification_table_names_every_bad_field():
    """Was (round 6): a value "1" read as 1.0 (numpy converts strings), a value null as NaN in an 'ok'
    fit, a stderr of -1 shown as is."""
    from frictionkit.identify.result import IdentificationResult

    assert IdentificationResult.from_dict(_FIT).params == {"Fc": 1.0, "sigma2": 0.4}  # null stderr/ci: fine
    doc = copy.deepcopy(_FIT)
    doc["parameters"]["Fc"]["value"] = "1"
    doc["parameters"]["sigma2"]["value"] = None
    doc["parameters"]["Fc"]["stderr"] = -1
    doc["parameters"]["sigma2"]["ci95"] = [2.0, 1.0]
    doc["correlation"][0][1] = 3.0
    doc["rms"] = -0.5
    doc["dof"] = 25
    with pytest.raises(DataError) as exc:
        IdentificationResult.from_dict(doc)
    msg = str(exc.value)
    for needle in ('parameters.Fc.value is "1", expected a finite number',
                   "parameters.sigma2.value is null, expected a finite number (null only in a failed fit's result)",
                   "parameters.Fc.stderr is -1, expected a number >= 0 or null",
                   "parameters.sigma2.ci95 is [2.0, 1.0]: the low end is above the high end",
                   "correlation[0][1] is 3.0, expected a number in [-1, 1] or null",
                   "rms is -0.5, expected a number >= 0 or null", "dof is 25, expected 0 ... n_obs = 20"):
        assert needle in msg, msg
    failed = dict(copy.deepcopy(_FIT), success=False)  # a failed fit's table may hold nulls
    failed["parameters"]["Fc"]["value"] = None
    assert IdentificationResult.from_dict(failed).success is False
    part = dict(copy.deepcopy(_FIT), parts={"positive": doc})
    with pytest.raises(DataError, match=r'^parts.positive: parameters.Fc.value is "1"'):
        IdentificationResult.from_dict(part)
