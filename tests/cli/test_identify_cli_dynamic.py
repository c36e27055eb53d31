"""``frictionkit identify output-error`` and ``identify presliding`` through typer's CliRunner."""

from __future__ import annotations

import json

import numpy as np
import pytest
from typer.testing import CliRunner

import frictionkit as fk
import frictionkit.cli.identify  # noqa: F401  (registers the ``identify`` group)
from frictionkit.cli import app

runner = CliRunner()
DT = 1e-3
LAW = fk.Stribeck(Fc=1.0, Fs=1.5, vs=1e-3, delta=2.0, sigma2=0.4)
STATIC = ["--Fc", "1.0", "--Fs", "1.5", "--vs", "1e-3", "--sigma2", "0.4"]


def _stderr(res) -> str:
    try:
        return res.stderr
    except ValueError:  # older click mixes the streams
        return res.output


def _write(path, **cols):
    names = list(cols)
    arr = np.column_stack([cols[n] for n in names])
    np.savetxt(path, arr, delimiter=",", header=",".join(names), comments="", fmt="%.17g")
    return path


@pytest.fixture(scope="module")
def lugre_csv(tmp_path_factory):
    t = np.arange(8001) * DT
    u = np.where(t < 4.0, (2 / np.pi) * np.arcsin(np.sin(np.pi * t)), 2.0 * np.sin(np.pi * (t - 4.0)))
    sim = fk.simulate(fk.LuGre(LAW, sigma0=1e5, sigma1=63.2), plant=fk.Mass(1.0), force=u, dt=DT)
    # force logged in mN to exercise --force-scale; position in 10 nm counts
    return _write(tmp_path_factory.mktemp("oe") / "lugre.csv", t_s=t, x_m=np.round(sim.x / 1e-8) * 1e-8,
                  v_ms=sim.v, u_mN=1e3 * u)


@pytest.fixture(scope="module")
def gms_csv(tmp_path_factory):
    x = np.r_[np.linspace(0, 50e-6, 2501), np.linspace(50e-6, -50e-6, 5001)[1:]]
    t = np.arange(x.size) * DT
    F = fk.simulate(fk.GMS(LAW, k=[4e5, 1e5, 2e4], xi=[0.2, 0.3, 0.5], C=20.0), position=x, dt=DT).friction
    return _write(tmp_path_factory.mktemp("ps") / "gms.csv", t_s=t, x_m=x, F_N=F)


def test_output_error_lugre(lugre_csv, tmp_path):
    out, png = tmp_path / "oe.json", tmp_path / "oe.png"
    res = runner.invoke(app, ["identify", "output-error", str(lugre_csv), "--time", "t_s", "--position", "x_m",
                              "--velocity", "v_ms", "--force", "u_mN", "--force-scale", "1e-3", *STATIC,
                              "--mass", "1.0", "--json", str(out), "--plot", str(png)])
    assert res.exit_code == 0, res.output
    assert "initial guess: sigma0" in res.stdout
    d = json.loads(out.read_text(encoding="utf-8"))
    assert d["kind"] == "output_error"
    assert list(d["parameters"]) == ["sigma0", "sigma1"]
    assert abs(d["parameters"]["sigma0"]["value"] / 1e5 - 1) < 0.05
    assert abs(d["parameters"]["sigma1"]["value"] / 63.2 - 1) < 0.3
    assert d["parameters"]["sigma0"]["unit"] == "N/m"
    assert d["model"]["type"] == "LuGre"
    assert png.stat().st_size > 1000


def test_output_error_gms_needs_both_start_lists(lugre_csv):
    res = runner.invoke(app, ["identify", "output-error", str(lugre_csv), "--time", "t_s", "--velocity", "v_ms",
                              "--force", "u_mN", *STATIC, "--mass", "1", "--model", "gms", "--k", "1e5,1e4"])
    assert res.exit_code == 2
    err = _stderr(res).strip()
    assert err.startswith("error:") and "--k and --xi" in err and "\n" not in err


@pytest.mark.parametrize("model, extra, named", [
    ("lugre", ["--k", "a", "--xi", "nan"], "--k applies to --model gms only"),  # exited 0, ignored unread
    ("lugre", ["--C", "20"], "--C applies to --model gms only"),
    ("lugre", ["--elements", "5"], "--elements applies to --model gms only"),
    ("gms", ["--sigma0", "1e5"], "--sigma0 applies to --model lugre/dahl only"),
])
def test_output_error_refuses_options_of_another_model(lugre_csv, model, extra, named):
    res = runner.invoke(app, ["identify", "output-error", str(lugre_csv), "--time", "t_s", "--velocity", "v_ms",
                              "--force", "u_mN", *STATIC, "--mass", "1", "--model", model, *extra])
    assert res.exit_code == 2
    err = _stderr(res).strip()
    assert err.startswith("error:") and named in err and "\n" not in err


def test_output_error_without_static_map(lugre_csv):
    res = runner.invoke(app, ["identify", "output-error", str(lugre_csv), "--time", "t_s", "--velocity", "v_ms",
                              "--force", "u_mN", "--mass", "1"])
    assert res.exit_code == 2
    assert "--static-json" in _stderr(res) and _stderr(res).count("\n") == 1


def test_output_error_unknown_parameter(lugre_csv):
    res = runner.invoke(app, ["identify", "output-error", str(lugre_csv), "--time", "t_s", "--velocity", "v_ms",
                              "--force", "u_mN", "--force-scale", "1e-3", *STATIC, "--mass", "1",
                              "--sigma0", "1e5", "--free", "sigma0,bogus"])
    assert res.exit_code == 2
    assert "unknown parameter 'bogus'" in _stderr(res)


def test_presliding(gms_csv, tmp_path):
    out, png = tmp_path / "ps.json", tmp_path / "ps.png"
    res = runner.invoke(app, ["identify", "presliding", str(gms_csv), "--time", "t_s", "--position", "x_m",
                              "--force", "F_N", "--elements", "3", "--Fc", "1.0", "--Fs", "1.5",
                              "--json", str(out), "--plot", str(png)])
    assert res.exit_code == 0, res.output
    assert "total stiffness" in res.stdout
    d = json.loads(out.read_text(encoding="utf-8"))
    assert d["model"]["type"] == "GMS"
    ks = [d["parameters"][f"k{i}"]["value"] for i in (1, 2, 3)]
    assert abs(sum(ks) / 5.2e5 - 1) < 0.10
    assert png.stat().st_size > 1000


def test_presliding_bad_column(gms_csv):
    res = runner.invoke(app, ["identify", "presliding", str(gms_csv), "--time", "t_s", "--position", "nope",
                              "--force", "F_N", "--elements", "3"])
    assert res.exit_code == 2
    assert _stderr(res).startswith("error:") and "nope" in _stderr(res)


def test_existing_commands_still_listed():
    res = runner.invoke(app, ["identify", "--help"])
    assert res.exit_code == 0
    for cmd in ("rigid-body", "static", "output-error", "presliding"):
        assert cmd in res.stdout
