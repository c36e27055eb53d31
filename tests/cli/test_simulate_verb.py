"""``frictionkit simulate MODEL.json --force|--position|--velocity FILE``."""

from __future__ import annotations

import json
import math

import numpy as np
import pytest
from typer.testing import CliRunner

import frictionkit as fk
from frictionkit.cli import _register, app

_register()
runner = CliRunner()

LAW = fk.LuGre(fk.Stribeck(Fc=1.0, Fs=1.5, vs=1e-3, sigma2=0.4), sigma0=1e5, sigma1=63.2)  # README example
DT = 1e-3
T = np.arange(1001) * DT


def _csv(path, header, *cols):
    np.savetxt(path, np.column_stack(cols), delimiter=",", header=header, comments="", fmt="%.17g")
    return path


def _traces(path):
    names = path.read_text().splitlines()[0].split(",")
    return dict(zip(names, np.loadtxt(path, delimiter=",", skiprows=1).T))


@pytest.fixture()
def model(tmp_path):
    return fk.save_model(LAW, tmp_path / "lugre.json", method="README example")


def test_position_ramp_settles_on_the_stribeck_curve(tmp_path, model):
    v0 = 2e-3  # m/s
    sig = _csv(tmp_path / "ramp.csv", "time,pos", T, v0 * T)
    out, png, js = tmp_path / "tr.csv", tmp_path / "loop.png", tmp_path / "sum.json"
    res = runner.invoke(app, ["simulate", str(model), "--position", str(sig), "--out", str(out), "--plot", str(png),
                              "--json", str(js)])
    assert res.exit_code == 0, res.output
    assert "LuGre position-driven, 1001 samples" in res.stdout and f"wrote {out}" in res.stdout
    tr = _traces(out)
    assert list(tr) == ["t [s]", "x [m]", "v [m/s]", "friction [N]", "z [m]"]
    # seed 002 eq. 8/9b by hand: F = Fc + (Fs - Fc) exp(-(v/vs)^2) + sigma2 v at v = 2 mm/s
    assert tr["friction [N]"][-1] == pytest.approx(1.0 + 0.5 * math.exp(-4.0) + 0.4 * v0, rel=1e-9)
    assert tr["z [m]"][-1] == pytest.approx((1.0 + 0.5 * math.exp(-4.0)) / 1e5, rel=1e-9)
    # the CLI is fk.simulate: same numbers (17 digits in the CSV)
    ref = fk.simulate(LAW, position=v0 * T, dt=DT)
    np.testing.assert_allclose(tr["friction [N]"], ref.friction, rtol=1e-12)  # dt from the file's time column: rounding
    assert png.stat().st_size > 5000
    doc = json.loads(js.read_text())
    assert doc["status"] == 0 and doc["samples"] == 1001 and doc["drive"] == "position"
    assert doc["columns"] == {"time": "time", "signal": "pos"}
    assert doc["peak_friction"] == pytest.approx(float(np.max(np.abs(ref.friction))))


def test_force_below_breakaway_rests_at_z_equal_u_over_sigma0(tmp_path, model):
    sig = _csv(tmp_path / "u.csv", "t,u", T, np.full(T.size, 0.5))
    res = runner.invoke(app, ["simulate", str(model), "--force", str(sig), "--mass", "1.0", "--out",
                              str(tmp_path / "tr.parquet"), "--json", "-"])
    assert res.exit_code == 0, res.output
    doc = json.loads(res.stdout)  # --json -: only the JSON on stdout
    # omega dt 0.32, damping ratio 0.1: a lightly damped ringing the accuracy check reruns (issue 13)
    assert doc["drive"] == "force" and doc["success"] is True
    assert doc["message"] == "ok" or doc["message"].startswith("ok; accuracy check passed"), doc["message"]
    import pandas as pd

    tr = pd.read_parquet(tmp_path / "tr.parquet")
    assert list(tr.columns) == ["t [s]", "x [m]", "v [m/s]", "friction [N]", "z [m]"]
    # at rest under 0.5 N < Fc the bristles carry the load: sigma0 z = u, v -> 0
    assert tr["z [m]"].iloc[-1] == pytest.approx(0.5 / 1e5, rel=1e-4)
    assert abs(tr["v [m/s]"].iloc[-1]) < 1e-7


def test_velocity_log_in_mm_per_s_held(tmp_path):
    gms = fk.GMS(fk.Stribeck(Fc=1.0, Fs=1.5, vs=1e-3), k=[1e4, 1e5], xi=[0.6, 0.4], C=20.0)
    from frictionkit.identify.result import IdentificationResult

    fit = IdentificationResult(kind="presliding", model_name="gms", model=gms, names=("k1",), values=np.array([1e4]),
                               stderr=np.array([1.0]), ci95=np.array([[0.9e4, 1.1e4]]), units=("N/m",),
                               correlation=np.eye(1), rms=0.0, relative_error_percent=0.0, n_obs=10, dof=9)
    path = fit.save_json(tmp_path / "fit.json")
    vel = np.where(T < 0.5, 3.0, -3.0)  # mm/s
    sig = _csv(tmp_path / "log.csv", "a,b,vel_mm_s", T, np.zeros_like(T), vel)
    out = tmp_path / "tr.csv"
    res = runner.invoke(app, ["simulate", str(path), "--velocity", str(sig), "--column", "vel_mm_s", "--scale", "1e-3",
                              "--velocity-integration", "held", "--out", str(out)])
    assert res.exit_code == 0, res.output
    tr = _traces(out)
    assert [c for c in tr if c.startswith(("friction_", "stick_"))] == ["friction_1 [N]", "friction_2 [N]", "stick_1", "stick_2"]
    # held: x_k = sum_{j=1..k} v_j dt; v_1..v_499 = +3 mm/s, v_500..v_1000 = -3 mm/s
    # (the trapezoidal rule would give 1.497 mm at k = 500 and -3 µm at the end)
    assert tr["x [m]"][500] == pytest.approx(498 * 3e-6, rel=1e-9)
    assert tr["x [m]"][-1] == pytest.approx((499 - 501) * 3e-6, rel=1e-9)
    # sliding at 3 mm/s: (sum xi) [Fc + (Fs - Fc) exp(-9)] (seed 000 eq. 4, delta = 2)
    assert tr["friction [N]"][499] == pytest.approx(1.0 + 0.5 * math.exp(-9.0), rel=1e-6)


BAD = {
    "static_model": ("static", ["--position", "{sig}"], "is a static map (Stribeck): it has no state to simulate"),
    "no_mass": ("lugre", ["--force", "{sig}"], "--force needs --mass KG"),
    "mass_motion": ("lugre", ["--position", "{sig}", "--mass", "2"], "--mass is for a force-driven run"),
    "bad_mass": ("lugre", ["--force", "{sig}", "--mass", "-1"], "--mass -1.0: must be > 0"),
    "two_drives": ("lugre", ["--position", "{sig}", "--velocity", "{sig}"],
                   "give exactly one of --force, --position, --velocity (got --position, --velocity)"),
    "no_drive": ("lugre", [], "give exactly one of --force, --position, --velocity (got none)"),
    "column": ("lugre", ["--position", "{sig}", "--column", "nope"], "nope"),
    "irregular": ("lugre", ["--position", "{irregular}"], "irregular sampling"),
    "suffix": ("lugre", ["--position", "{sig}", "--out", "{tmp}/t.xlsx"], "unknown suffix '.xlsx'"),
    "integration": ("lugre", ["--velocity", "{sig}", "--velocity-integration", "euler"],
                    "--velocity-integration 'euler': must be one of trapezoidal, held"),
    "scale": ("lugre", ["--position", "{sig}", "--scale", "0"], "--scale 0.0: a unit factor must satisfy"),
    "newer_file": ("newer", ["--position", "{sig}"], "written by a newer frictionkit"),
    "missing_file": ("missing", ["--position", "{sig}"], "no such file"),
}


@pytest.mark.parametrize("case", sorted(BAD))
def test_bad_input_is_one_line_error(tmp_path, case):
    which, args, why = BAD[case]
    models = {"static": fk.save_model(fk.Stribeck(Fc=1.0, Fs=1.5, vs=1e-3), tmp_path / "static.json"),
              "lugre": fk.save_model(LAW, tmp_path / "lugre.json"), "missing": tmp_path / "missing.json"}
    models["newer"] = tmp_path / "newer.json"
    models["newer"].write_text(json.dumps({"format": "frictionkit.model/2", "model": {"law": "LuGre"}}))
    sig = _csv(tmp_path / "s.csv", "t,x", T[:50], 1e-6 * T[:50])
    t_irr = np.concatenate([T[:25], T[25:50] + 0.5e-3])
    irregular = _csv(tmp_path / "irr.csv", "t,x", t_irr, 1e-6 * t_irr)
    fill = {"sig": str(sig), "irregular": str(irregular), "tmp": str(tmp_path)}
    res = runner.invoke(app, ["simulate", str(models[which]), *[a.format(**fill) for a in args]])
    assert res.exit_code == 2, res.output
    err = res.stderr.strip()
    assert err.startswith("error: ") and "\n" not in err and why in err, err


def test_help_has_examples_and_units():
    res = runner.invoke(app, ["simulate", "--help"])
    assert res.exit_code == 0
    assert "frictionkit simulate lugre.json --position motion.csv --out traces.csv --plot loop.png" in res.stdout
    assert "[N]" in res.stdout and "[m/s]" in res.stdout


def test_where_picks_one_drive_of_a_stacked_log(tmp_path, model):
    t = T[:200]
    drive = np.repeat([1.0, 2.0], t.size)
    sig = _csv(tmp_path / "drives.csv", "drive,t,x", drive, np.tile(t, 2),
               np.concatenate([1e-3 * t, -2e-3 * t]))
    out = tmp_path / "tr.csv"
    res = runner.invoke(app, ["simulate", str(model), "--position", str(sig), "--where", "drive=2", "--time", "t",
                              "--column", "x", "--out", str(out)])
    assert res.exit_code == 0, res.output
    tr = _traces(out)
    np.testing.assert_allclose(tr["x [m]"], -2e-3 * t, rtol=1e-15, atol=0)
    res = runner.invoke(app, ["simulate", str(model), "--position", str(sig), "--time", "t", "--column", "x"])
    assert res.exit_code == 2
    assert "time stamps must be strictly increasing" in res.stderr and res.stderr.count("\n") == 1
