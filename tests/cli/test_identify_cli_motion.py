"""``identify output-error --drive motion`` and the data options every identify verb shares.

A simulated drive log (two drives stacked in one file, rotary units, rests where the
torque is logged exactly 0, an "enabled" column) goes through the CLI alone: grouped
and filtered records, resets at rests, units in the JSON, validation on another record,
and one-line errors for bad input.
"""

from __future__ import annotations

import json

import numpy as np
import pytest
from typer.testing import CliRunner

import frictionkit as fk
import frictionkit.cli.identify  # noqa: F401  (registers the ``identify`` group)
from frictionkit.cli import app
from frictionkit.identify import IdentificationResult

runner = CliRunner()
DT = 1e-3
LAW = fk.Stribeck(Fc=3e-3, Fs=4e-3, vs=2.0, delta=2.0, sigma2=5e-5)  # N·m, rad/s
TRUE = {1: fk.LuGre(LAW, sigma0=0.6, sigma1=2e-4), 2: fk.LuGre(LAW, sigma0=0.2, sigma1=2e-4)}
STATIC = ["--Fc", "3e-3", "--Fs", "4e-3", "--vs", "2.0", "--sigma2", "5e-5"]


def _stderr(res) -> str:
    try:
        return res.stderr
    except ValueError:  # older click mixes the streams
        return res.output


def _one_error(res) -> str:
    err = _stderr(res).strip()
    assert "Traceback" not in err and len(err.splitlines()) == 1, err
    assert err.startswith("error: "), err
    return err


def _log(drive: int, seed: int, speed: float = 1.0):
    """rest, +speed, rest, -speed, rest; torque logged 0 at rest; velocity as a drive logs it (held)."""
    n = 300
    prof = np.r_[np.zeros(n), speed * np.sin(np.linspace(0, np.pi, 2 * n)) ** 0.3, np.zeros(n),
                 -speed * np.sin(np.linspace(0, np.pi, 2 * n)) ** 0.3, np.zeros(n)]
    x = np.r_[0.0, np.cumsum(prof[1:] * DT)]
    moving = prof != 0
    F = np.zeros_like(x)
    rng = np.random.default_rng(seed)
    edges = np.flatnonzero(np.diff(moving.astype(int)))
    for a, b in zip(edges[::2], edges[1::2]):
        seg = fk.simulate(TRUE[drive], position=x[a:b + 1] - x[a], dt=DT).friction
        F[a + 1:b + 1] = seg[1:] + 2e-5 * rng.standard_normal(b - a)
    t = np.arange(x.size) * DT
    return {"t_s": t, "v_rad_s": np.r_[0.0, np.diff(x) / DT], "T_Nm": F, "enabled": moving.astype(float)}


def _write(path, blocks):
    cols = ["drive_id", "record", "t_s", "v_rad_s", "T_Nm", "disabled"]
    rows = []
    for (drive, record), d in blocks.items():
        rows.append(np.column_stack([np.full(d["t_s"].size, drive), np.full(d["t_s"].size, record), d["t_s"],
                                     d["v_rad_s"], d["T_Nm"], 1.0 - d["enabled"]]))
    np.savetxt(path, np.vstack(rows), delimiter=",", header=",".join(cols), comments="", fmt="%.17g")
    return path


@pytest.fixture(scope="module")
def logs(tmp_path_factory):
    folder = tmp_path_factory.mktemp("drive_logs")
    train = _write(folder / "train.csv", {(1, 1): _log(1, 0), (2, 1): _log(2, 1), (1, 2): _log(1, 2, speed=0.5)})
    held_out = _write(folder / "held_out.csv", {(1, 1): _log(1, 3, speed=0.3), (2, 1): _log(2, 4, speed=0.3)})
    return train, held_out


ARGS = ["--drive", "motion", "--time", "t_s", "--velocity", "v_rad_s", "--force", "T_Nm", "--rotary", *STATIC]


def test_motion_fit_of_one_drive_with_units_rests_and_validation(logs, tmp_path):
    train, held_out = logs
    out, png = tmp_path / "d1.json", tmp_path / "d1.png"
    res = runner.invoke(app, ["identify", "output-error", str(train), *ARGS, "--where", "drive_id=1",
                              "--where", "record=1", "--validate", str(held_out), "--json", str(out),
                              "--plot", str(png)])
    assert res.exit_code == 0, res.output
    assert "training torque RMS" in res.stdout and "for the static map alone" in res.stdout
    assert "validation on" in res.stdout
    fit = IdentificationResult.load_json(out)
    assert fit["sigma0"] == pytest.approx(0.6, rel=0.05)
    assert fit.units == ("N·m/rad", "N·m·s/rad")
    assert fit.provenance["units"] == {"F": "N·m", "v": "rad/s", "x": "rad"}
    seg = fit.diagnostics["segments"]
    assert len(next(iter(seg.values()))["segments"]) == 2  # reset at every rest
    val = fit.diagnostics["validation"]
    assert val["rms"] < 3e-5 and val["rms"] < val["static_rms"]  # the dynamic law beats the static map
    assert png.stat().st_size > 1000
    law = fit.model
    assert isinstance(law, fk.LuGre)
    assert np.isfinite(fk.simulate(law, velocity=np.linspace(0, 1, 50), dt=DT).friction).all()


def test_group_fits_several_records_jointly(logs, tmp_path):
    train, _ = logs
    out = tmp_path / "joint.json"
    res = runner.invoke(app, ["identify", "output-error", str(train), *ARGS, "--group", "record",
                              "--where", "drive_id=1", "--json", str(out)])
    assert res.exit_code == 0, res.output
    d = json.loads(out.read_text(encoding="utf-8"))
    assert len(d["diagnostics"]["segments"]) == 2  # records 1 and 2 of drive 1
    assert d["parameters"]["sigma0"]["value"] == pytest.approx(0.6, rel=0.05)


def test_mask_column_and_direction_dependent_parameters(logs, tmp_path):
    train, _ = logs
    out = tmp_path / "mask.json"
    res = runner.invoke(app, ["identify", "output-error", str(train), *ARGS, "--where", "drive_id=2",
                              "--where", "record=1", "--mask", "disabled", "--free", "sigma0_pos,sigma0_neg",
                              "--json", str(out)])
    assert res.exit_code == 0, res.output
    d = json.loads(out.read_text(encoding="utf-8"))
    assert d["provenance"]["procedure"]["rests"] == "mask"
    assert d["model"]["type"] == "Directional"
    for n in ("sigma0_pos", "sigma0_neg"):
        assert d["parameters"][n]["value"] == pytest.approx(0.2, rel=0.05)


def test_gms_and_dahl_from_the_cli(logs, tmp_path):
    train, _ = logs
    for model, names in (("gms", ["k1", "k2", "k3", "C", "J"]), ("dahl", ["sigma0"])):
        out = tmp_path / f"{model}.json"
        free = ["--free", "k,C,J"] if model == "gms" else []
        res = runner.invoke(app, ["identify", "output-error", str(train), *ARGS, "--where", "drive_id=1",
                                  "--where", "record=1", "--model", model, *free, "--json", str(out)])
        assert res.exit_code == 0, res.output
        d = json.loads(out.read_text(encoding="utf-8"))
        assert list(d["parameters"]) == names
        assert d["diagnostics"]["static_rms"] > 0


def test_static_rotary_units_and_validation(tmp_path):
    rng = np.random.default_rng(0)
    speeds = np.geomspace(0.5, 20.0, 8)
    v = np.concatenate([np.full(100, s) for s in np.r_[speeds, -speeds]])
    t = np.arange(v.size) * DT
    F = LAW.steady_state(v) + 1e-5 * rng.standard_normal(v.size)
    data = tmp_path / "stairs.csv"
    np.savetxt(data, np.column_stack([t, v, F]), delimiter=",", header="t,v,F", comments="")
    out = tmp_path / "s.json"
    res = runner.invoke(app, ["identify", "static", str(data), "--time", "t", "--velocity", "v", "--force", "F",
                              "--rotary", "--model", "coulomb_viscous", "--validate", str(data), "--json", str(out)])
    assert res.exit_code == 0, res.output
    d = json.loads(out.read_text(encoding="utf-8"))
    assert d["parameters"]["Fc_pos"]["unit"] == "N·m"
    assert d["parameters"]["sigma2_pos"]["unit"] == "N·m·s/rad"
    assert d["diagnostics"]["validation"]["rms"] == pytest.approx(d["rms"], rel=1e-6)


def test_rigid_body_group_where_and_validation(tmp_path):
    M, Fv, Fc = 2.0, 5.0, 1.0
    blocks = []
    for rec in (1, 2, 3):
        t = np.arange(4000) * DT
        x = 0.05 * np.sin(2 * np.pi * (0.5 + 0.2 * rec) * t)
        v = np.gradient(x, DT)
        a = np.gradient(v, DT)
        F = M * a + Fv * v + Fc * np.sign(v)
        blocks.append(np.column_stack([np.full(t.size, rec), t, x, F]))
    data = tmp_path / "rb.csv"
    np.savetxt(data, np.vstack(blocks), delimiter=",", header="rec,t,x,F", comments="")
    out = tmp_path / "rb.json"
    res = runner.invoke(app, ["identify", "rigid-body", str(data), "--time", "t", "--position", "x", "--force", "F",
                              "--group", "rec", "--where", "rec=1", "--where", "rec=1", "--validate", str(data),
                              "--json", str(out)])
    assert res.exit_code == 0, res.output
    joint = tmp_path / "joint.json"
    res = runner.invoke(app, ["identify", "rigid-body", str(data), "--time", "t", "--position", "x", "--force", "F",
                              "--group", "rec", "--json", str(joint)])
    assert res.exit_code == 0, res.output
    d = json.loads(joint.read_text(encoding="utf-8"))
    assert d["parameters"]["M"]["value"] == pytest.approx(M, rel=0.02)
    assert d["n_obs"] > 2 * json.loads(out.read_text(encoding="utf-8"))["n_obs"]
    assert "validation" in json.loads(out.read_text(encoding="utf-8"))["diagnostics"]


@pytest.mark.parametrize("extra, needle", [
    (["--drive", "sideways"], "--drive 'sideways': must be one of force, motion"),
    (["--drive", "motion", "--mass", "1"], "--mass applies to --drive force only"),
    (["--drive", "force"], "--drive force needs --mass"),
    (["--drive", "force", "--mass", "1", "--inertia", "1"], "--inertia applies to --drive motion only"),
    (["--drive", "motion", "--velocity-integration", "simpson"], "--velocity-integration 'simpson'"),
    (["--drive", "motion", "--rests", "sometimes"], "--rests 'sometimes'"),
    (["--drive", "motion", "--where", "drive_id"], "--where 'drive_id': expected COLUMN=VALUE"),
    (["--drive", "motion", "--force-unit", " "], "--force-unit ' ': must be a non-empty"),
    (["--drive", "motion", "--model", "maxwell"], "--model 'maxwell': must be one of lugre, gms, dahl"),
])
def test_bad_options_are_one_line(logs, extra, needle):
    train, _ = logs
    res = runner.invoke(app, ["identify", "output-error", str(train), "--time", "t_s", "--velocity", "v_rad_s",
                              "--force", "T_Nm", *STATIC, *extra])
    assert res.exit_code == 2
    assert needle in _one_error(res)


def test_motion_without_any_motion_is_one_line(tmp_path):
    p = tmp_path / "still.csv"
    np.savetxt(p, np.column_stack([np.arange(50) * DT, np.zeros(50), np.zeros(50)]), delimiter=",",
               header="t,v,F", comments="")
    res = runner.invoke(app, ["identify", "output-error", str(p), "--drive", "motion", "--time", "t", "--velocity",
                              "v", "--force", "F", *STATIC])
    assert res.exit_code == 2
    assert "no motion to fit" in _one_error(res)


def test_force_drive_and_presliding_take_where_units_and_validate(tmp_path):
    law = fk.Stribeck(Fc=1.0, Fs=1.5, vs=1e-3, delta=2.0, sigma2=0.4)
    t = np.arange(3001) * DT
    u = 2.0 * np.sin(np.pi * t)
    rows = []
    for axis, s0 in ((1, 1e5), (2, 3e5)):
        sim = fk.simulate(fk.LuGre(law, sigma0=s0, sigma1=63.2), plant=fk.Mass(1.0), force=u, dt=DT)
        rows.append(np.column_stack([np.full(t.size, axis), t, sim.x, sim.v, u]))
    data = tmp_path / "axes.csv"
    np.savetxt(data, np.vstack(rows), delimiter=",", header="axis,t,x,v,u", comments="", fmt="%.17g")
    out = tmp_path / "force.json"
    res = runner.invoke(app, ["identify", "output-error", str(data), "--time", "t", "--velocity", "v", "--force", "u",
                              "--Fc", "1", "--Fs", "1.5", "--vs", "1e-3", "--sigma2", "0.4", "--mass", "1",
                              "--sigma0", "5e4", "--sigma1", "63.2", "--free", "sigma0", "--where", "axis=1",
                              "--validate", str(data), "--json", str(out)])
    assert res.exit_code == 0, res.output
    d = json.loads(out.read_text(encoding="utf-8"))
    assert d["parameters"]["sigma0"]["value"] == pytest.approx(1e5, rel=0.02)
    assert d["diagnostics"]["validation"]["rms"] == pytest.approx(d["rms"], rel=0.05)  # the same record
    assert "validation on" in res.stdout and "velocity RMS" in res.stdout

    x = np.r_[np.linspace(0, 50e-6, 501), np.linspace(50e-6, -50e-6, 1001)[1:]]
    tp = np.arange(x.size) * DT
    F = fk.simulate(fk.GMS(law, k=[4e5, 1e5, 2e4], xi=[0.2, 0.3, 0.5], C=20.0), position=x, dt=DT).friction
    ps = tmp_path / "ps.csv"
    np.savetxt(ps, np.column_stack([np.ones(x.size), tp, x, F]), delimiter=",", header="axis,t,x,F", comments="",
               fmt="%.17g")
    out = tmp_path / "ps.json"
    res = runner.invoke(app, ["identify", "presliding", str(ps), "--time", "t", "--position", "x", "--force", "F",
                              "--elements", "3", "--Fc", "1", "--Fs", "1.5", "--where", "axis=1",
                              "--force-unit", "kN", "--validate", str(ps), "--json", str(out)])
    assert res.exit_code == 0, res.output
    d = json.loads(out.read_text(encoding="utf-8"))
    assert d["provenance"]["units"]["F"] == "kN" and d["parameters"]["k1"]["unit"].startswith("kN/")
    assert "validation" in d["diagnostics"]
