"""``identify rigid-body --law stribeck|lorentzian`` and TDMS input through typer's CliRunner (issue 11 parts 5, 7)."""

from __future__ import annotations

import json
import sys
from pathlib import Path

import numpy as np
import pytest
from typer.testing import CliRunner

import frictionkit.cli.identify  # noqa: F401  (registers the ``identify`` group)
from frictionkit.cli import app
from frictionkit.identify import IdentificationResult

sys.path.insert(0, str(Path(__file__).resolve().parents[1] / "unit"))
from test_identify_rigid_body_stribeck import TRUTH, _record  # noqa: E402

nptdms = pytest.importorskip("nptdms")
runner = CliRunner()
ARGS = ["--time", "Axis/t", "--position", "Axis/x_mm", "--force", "Axis/F", "--position-scale", "1e-3"]


def _stderr(res) -> str:
    try:
        return res.stderr
    except ValueError:  # older click mixes the streams
        return res.output


def _tdms(path, rec):
    from nptdms import ChannelObject, TdmsWriter

    with TdmsWriter(str(path)) as w:
        w.write_segment([ChannelObject("Axis", "t", rec.t), ChannelObject("Axis", "x_mm", rec.x * 1e3),
                         ChannelObject("Axis", "F", rec.F)])
    return path


@pytest.fixture(scope="module")
def files(tmp_path_factory):
    d = tmp_path_factory.mktemp("tdms")
    return _tdms(d / "train.tdms", _record(1)), _tdms(d / "other.tdms", _record(7)), d


def test_stribeck_asymmetric_from_tdms_with_validation(files):
    train, other, d = files
    out = d / "r.json"
    res = runner.invoke(app, ["identify", "rigid-body", str(train), *ARGS, "--law", "stribeck", "--asymmetric",
                              "--no-profile", "--validate", str(other), "--json", str(out), "--plot", str(d / "r.png")])
    assert res.exit_code == 0, res.output
    assert "rigid_body_stribeck_asymmetric" in res.stdout
    assert "for the Coulomb-viscous start (IDIM-LS)" in res.stdout and "validation on" in res.stdout
    back = IdentificationResult.load_json(out)
    for name, true in TRUTH.items():
        p = back.parameter(name)
        assert abs(p["value"] - true) < 5 * p["stderr"], (name, p)
    assert back.model.M == pytest.approx(back["M"]) and back.model.offset == 0.0
    assert back.diagnostics["validation"]["data"] == str(other)
    d = json.loads(out.read_text(encoding="utf-8"))
    assert d["provenance"]["columns"] == {"t": "Axis/t", "x": "Axis/x_mm", "F": "Axis/F"}
    assert (d_png := files[2] / "r.png").stat().st_size > 1000, d_png


@pytest.mark.parametrize("extra, message", [
    (["--law", "tanh"], "error: --law 'tanh': must be one of coulomb-viscous, stribeck, lorentzian"),
    (["--delta", "2"], "error: --delta applies to --law stribeck only"),
    (["--law", "lorentzian", "--delta", "2"], "error: --delta applies to --law stribeck only"),
    (["--law", "stribeck", "--delta", "-1"], "error: --delta -1.0: must be > 0"),
    (["--no-profile"], "error: --no-profile applies to --law stribeck or lorentzian only"),
])
def test_bad_options_are_one_line_errors(files, extra, message):
    train, _, _ = files
    res = runner.invoke(app, ["identify", "rigid-body", str(train), *ARGS, *extra])
    assert res.exit_code == 2, res.output
    err = _stderr(res).strip()
    assert len(err.splitlines()) == 1 and err.startswith(message), err


def test_missing_tdms_channel_is_one_line_error(files):
    train, _, _ = files
    res = runner.invoke(app, ["identify", "rigid-body", str(train), "--time", "Axis/t", "--position", "x",
                              "--force", "Axis/F", "--law", "stribeck"])
    assert res.exit_code == 2
    err = _stderr(res).strip()
    assert len(err.splitlines()) == 1
    assert "column 'x' (given for position) not found; available columns: Axis/t, Axis/x_mm, Axis/F" in err
