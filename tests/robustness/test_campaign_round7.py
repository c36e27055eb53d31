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


def test_every_input_path_is_checked_before_the_fit(runner, tmp_path, monkeypatch):
    """Was (round 6): `identify static rec.csv ... --validate 0.5` fitted first, then failed on '0.5'."""
    import frictionkit.cli.identify  # noqa: F401  (registers the verbs)
    import frictionkit.identify as fid
    from _robustness_helpers import STATIC_ARGS, one_error_line
    from frictionkit.cli import app

    def no_fit(*a, **k):
        raise AssertionError("the fit ran before the inputs were checked")

    monkeypatch.setattr(fid, "fit_static_map", no_fit)
    rec = tmp_path / "rec.csv"
    rec.write_text("t_s,v_ms,F_N\n0,1,1\n")
    (tmp_path / "folder").mkdir()
    for bad, why in ((tmp_path / "0.5", "no such file"), (tmp_path / "folder", "is a folder; give a data file")):
        res = runner.invoke(app, ["identify", "static", str(rec), *STATIC_ARGS, "--validate", str(bad)])
        assert res.exit_code == 2, res.output
        assert one_error_line(res) == f"error: --validate '{bad}'" + (": " if why[0] == "n" else " ") + why
    res = runner.invoke(app, ["identify", "static", str(tmp_path / "none.csv"), *STATIC_ARGS])
    assert one_error_line(res) == f"error: RECORDING '{tmp_path / 'none.csv'}': no such file"
