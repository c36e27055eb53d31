"""``identify output-error --drive force`` and ``identify presliding`` over several records with rests.

The CLI is a thin client: no start values are given on the command line (the library's
``initial="auto"`` computes them), the records come from ``--group``, the rests from the
zero-force runs or ``--mask``.
"""

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
TRUE = fk.LuGre(LAW, sigma0=1e5, sigma1=63.2)
STATIC = ["--Fc", "1.0", "--Fs", "1.5", "--vs", "1e-3", "--sigma2", "0.4"]
REST = 5


def _one_error(res) -> str:
    try:
        err = res.stderr
    except ValueError:  # older click mixes the streams
        err = res.output
    err = err.strip()
    assert err.startswith("error:") and "\n" not in err, err
    return err


def _sim(u, seed):
    """Position in 10 nm counts, velocity with noise of 0.5 % of its peak."""
    sim = fk.simulate(TRUE, plant=fk.Mass(1.0), force=u, dt=DT)
    noise = 0.005 * np.abs(sim.v).max() * np.random.default_rng(seed).standard_normal(sim.v.size)
    return np.round(sim.x / 1e-8) * 1e-8, sim.v + noise


@pytest.fixture(scope="module")
def force_csv(tmp_path_factory):
    """Record 1: sub-breakaway triangle, a 2 N sine ending while sliding, a rest, a 2 N sine from rest.
    Record 2: a 1.8 N sine. Columns: rec, t, x, v, u (force), disabled (1 at rests)."""
    t1 = np.arange(3500) * DT
    u1 = np.where(t1 < 2.5, (2 / np.pi) * np.arcsin(np.sin(np.pi * t1 + 0.3)), 2.0 * np.sin(np.pi * (t1 - 2.5)))
    x1, v1 = _sim(u1, 1)
    u2 = 2.0 * np.sin(np.pi * np.arange(1500) * DT + 0.2)
    x2, v2 = _sim(np.r_[0.0, u2], 2)
    u_a = np.r_[u1, np.zeros(REST), u2]
    v_a = np.r_[v1, np.zeros(REST - 1), v2]
    x_a = np.r_[x1, np.full(REST - 1, x1[-1]), x1[-1] + x2]
    off = np.zeros(u_a.size)
    off[u1.size:u1.size + REST] = 1.0
    u_b = 1.8 * np.sin(1.2 * np.pi * np.arange(2000) * DT + 0.1)
    x_b, v_b = _sim(u_b, 3)
    rows = [np.column_stack([np.full(u_a.size, 1), np.arange(u_a.size) * DT, x_a, v_a, u_a, off]),
            np.column_stack([np.full(u_b.size, 2), np.arange(u_b.size) * DT, x_b, v_b, u_b, np.zeros(u_b.size)])]
    path = tmp_path_factory.mktemp("oe_records") / "force.csv"
    np.savetxt(path, np.vstack(rows), delimiter=",", header="rec,t,x,v,u,disabled", comments="", fmt="%.17g")
    return path


ARGS = ["--time", "t", "--position", "x", "--velocity", "v", "--force", "u", *STATIC, "--mass", "1"]


def test_force_drive_fits_groups_jointly_from_auto_start_values(force_csv, tmp_path):
    out = tmp_path / "oe.json"
    res = runner.invoke(app, ["identify", "output-error", str(force_csv), *ARGS, "--group", "rec",
                              "--json", str(out)])
    assert res.exit_code == 0, res.output
    assert "initial guess: sigma0" in res.stdout  # computed by the library: no --sigma0 given
    assert "3 segment(s) of 2 record(s), each simulated from rest" in res.stdout
    d = json.loads(out.read_text(encoding="utf-8"))
    assert d["success"] is True and d["provenance"]["procedure"]["initial"] == "auto"
    for name, truth in (("sigma0", 1e5), ("sigma1", 63.2)):
        lo, hi = d["parameters"][name]["ci95"]
        assert lo < truth < hi, (name, lo, hi)
    assert d["diagnostics"]["segments"]["1"]["rest_samples"] == REST
    model = fk.identify.IdentificationResult.load_json(out).model
    assert isinstance(model, fk.LuGre)


def test_mask_column_gives_the_same_cut_and_validate_reports(force_csv, tmp_path):
    outs = []
    for extra in (["--rests", "auto"], ["--mask", "disabled"]):
        out = tmp_path / f"{extra[1]}.json"
        res = runner.invoke(app, ["identify", "output-error", str(force_csv), *ARGS, "--group", "rec",
                                  "--sigma0", "1e5", "--sigma1", "63.2", "--free", "sigma0", *extra,
                                  "--validate", str(force_csv), "--json", str(out)])
        assert res.exit_code == 0, res.output
        assert "validation on" in res.stdout and "velocity RMS" in res.stdout
        outs.append(json.loads(out.read_text(encoding="utf-8")))
    assert outs[0]["n_obs"] == outs[1]["n_obs"]
    assert outs[1]["diagnostics"]["validation"]["rms"] == pytest.approx(outs[1]["rms"], rel=0.05)  # same data


@pytest.mark.parametrize("verb, extra, needle", [
    ("output-error", [*ARGS, "--mask", "nosuch"], "nosuch"),
    ("output-error", [*ARGS, "--min-rest", "0"], "--min-rest"),
    ("output-error", [*ARGS, "--model", "gms", "--xi", "0.5,0.5"], "give both --k and --xi"),
    ("presliding", ["--time", "t", "--position", "x", "--force", "u", "--elements", "2", "--rests", "sometimes"],
     "--rests 'sometimes'"),
])
def test_bad_input_is_one_line(force_csv, verb, extra, needle):
    res = runner.invoke(app, ["identify", verb, str(force_csv), *extra, "--group", "rec"])
    assert res.exit_code == 2
    assert needle in _one_error(res)


def test_presliding_fits_several_records(tmp_path):
    gms = fk.GMS(LAW, k=[4e5, 1e5, 2e4], xi=[0.2, 0.3, 0.5], C=20.0)
    x1 = np.r_[np.linspace(0, 50e-6, 1001), np.linspace(50e-6, -50e-6, 2001)[1:]]
    x2 = np.r_[np.linspace(0, -40e-6, 801), np.linspace(-40e-6, 40e-6, 1601)[1:]]
    rows = [np.column_stack([np.full(x.size, i), np.arange(x.size) * DT, x, fk.simulate(gms, position=x, dt=DT).friction])
            for i, x in ((1, x1), (2, x2))]
    path = tmp_path / "ps.csv"
    np.savetxt(path, np.vstack(rows), delimiter=",", header="rec,t,x,F", comments="", fmt="%.17g")
    out = tmp_path / "ps.json"
    res = runner.invoke(app, ["identify", "presliding", str(path), "--time", "t", "--position", "x", "--force", "F",
                              "--elements", "3", "--Fc", "1", "--Fs", "1.5", "--group", "rec", "--json", str(out)])
    assert res.exit_code == 0, res.output
    assert "2 segment(s) of 2 record(s)" in res.stdout
    d = json.loads(out.read_text(encoding="utf-8"))
    assert d["n_obs"] == x1.size + x2.size  # every sample of both records (no rests)
    ks = [d["parameters"][f"k{i}"]["value"] for i in (1, 2, 3)]
    assert abs(sum(ks) / 5.2e5 - 1) < 0.10
