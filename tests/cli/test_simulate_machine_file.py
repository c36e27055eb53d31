"""``frictionkit simulate MACHINE.json --input NAME=FILE:COLUMN ...`` and ``compensate MACHINE.json``."""

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


def _csv(path, header, *cols):
    np.savetxt(path, np.column_stack(cols), delimiter=",", header=header, comments="", fmt="%.17g")
    return path


def _traces(path):
    names = path.read_text(encoding="utf-8").splitlines()[0].split(",")
    return dict(zip(names, np.loadtxt(path, delimiter=",", skiprows=1).T))


def _slider() -> fk.Machine:
    """1 kg on a Coulomb contact of 1 N, pushed by the open-loop force ``u`` [N]."""
    m = fk.Machine("slider")
    x = m.dof("x", inertia=1.0)
    m.friction("contact", x, law=fk.CoulombViscous(Fc=1.0))
    m.actuator("push", x, command="u")
    return m


@pytest.fixture(scope="module")
def emps(tmp_path_factory):
    from frictionkit.presets.emps import PUBLISHED, emps_machine

    d = tmp_path_factory.mktemp("emps")
    m = emps_machine(M=PUBLISHED["M"], friction=fk.CoulombViscous(Fc=PUBLISHED["Fc"], sigma2=PUBLISHED["Fv"]),
                     offset=PUBLISHED["offset"], encoder_resolution=5e-8)
    t = np.arange(1501) * 1e-3
    qg = 0.1 * np.sin(2 * np.pi * 0.2 * t)
    return m, fk.save_model(m, d / "emps.json", method="EMPS published"), _csv(d / "ref.csv", "t,qg", t, qg), qg


def test_machine_file_runs_as_the_library_does(tmp_path, emps):
    m, path, ref, qg = emps
    out, png, js = tmp_path / "tr.csv", tmp_path / "run.png", tmp_path / "run.json"
    res = runner.invoke(app, ["simulate", str(path), "--input", f"qg={ref}:qg", "--out", str(out),
                              "--plot", str(png), "--json", str(js)])
    assert res.exit_code == 0, res.output
    assert res.stdout.startswith("EMPS: 1501 samples") and f"wrote {out}" in res.stdout
    lib = fk.simulate_machine(m, dt=1e-3, inputs={"qg": qg})
    tr = _traces(out)
    assert list(tr)[:5] == ["t [s]", "x.q [m]", "v.q [m/s]", "force.friction [N]", "u.motor"]
    # the file's machine, the file's dt (from the time column) and 17 digits in the CSV: the library's numbers
    np.testing.assert_allclose(tr["x.q [m]"], lib.q[:, 0], rtol=1e-12, atol=1e-15)
    np.testing.assert_allclose(tr["nu"], lib.signal("nu"), rtol=1e-12, atol=1e-12)
    assert png.stat().st_size > 5000
    doc = json.loads(js.read_text())
    assert doc["kind"] == "machine" and doc["status"] == 0 and doc["samples"] == 1501 and doc["dt"] == pytest.approx(1e-3)
    assert doc["inputs"] == {"qg": f"{ref}:qg"} and doc["dofs"]["q"]["unit"] == "m"
    assert doc["dofs"]["q"]["final_x"] == pytest.approx(float(lib.q[-1, 0]), rel=1e-12)


def test_constant_inputs_dt_and_duration(tmp_path):
    path = fk.save_model(_slider(), tmp_path / "slider.json")
    res = runner.invoke(app, ["simulate", str(path), "--input", "u=3", "--dt", "1e-3", "--duration", "0.5",
                              "--json", "-", "--out", str(tmp_path / "tr.parquet")])
    assert res.exit_code == 0, res.output
    doc = json.loads(res.stdout)
    # Newton by hand: (3 N - 1 N) / 1 kg = 2 m/s², x(0.5 s) = 0.25 m, v = 1 m/s
    assert doc["samples"] == 501 and doc["dofs"]["x"]["final_x"] == pytest.approx(0.25, rel=1e-3)
    assert doc["dofs"]["x"]["peak_v"] == pytest.approx(1.0, rel=1e-6)
    # the sliding contact's 1 N with its unit (a translational site: newtons)
    assert doc["sites"]["contact"] == {"peak_force": pytest.approx(1.0, rel=1e-6), "unit": "N"}
    import pandas as pd

    tab = pd.read_parquet(tmp_path / "tr.parquet")
    assert tab["v.x [m/s]"].iloc[-1] == pytest.approx(1.0, rel=1e-6)
    # 0.5 N < Fc: it sticks
    res = runner.invoke(app, ["simulate", str(path), "--input", "u=0.5", "--dt", "1e-3", "--duration", "0.2",
                              "--json", "-"])
    assert res.exit_code == 0 and json.loads(res.stdout)["dofs"]["x"]["final_x"] == 0.0


@pytest.mark.parametrize("args, msg", [
    ([], r"reads inputs qg: missing --input for qg"),
    (["--input", "qg={ref}:qg", "--input", "r=1"], r"missing|r not read by the machine"),
    (["--input", "qg={ref}:nope"], r"column 'nope' \(given for --input qg\) not found; available columns: t, qg"),
    (["--input", "qg"], r"--input 'qg': expected NAME=FILE:COLUMN or NAME=VALUE"),
    (["--input", "qg={ref}:qg", "--input", "qg=0"], r"--input: qg given twice"),
    (["--input", "qg={ref}:qg", "--duration", "1"], r"--duration: the input files give the run length"),
    (["--input", "qg={ref}:qg", "--dt", "2e-3"], r"--dt 0.002: the input files are sampled at 0.001 s"),
    (["--input", "qg=0"], r"without input files give --dt and --duration"),
    (["--input", "qg={ref}:qg", "--mass", "1"], r"--mass: for a friction-law file; machine '.*' reads its inputs"),
    (["--position", "{ref}"], r"--position: for a friction-law file; .*it needs: qg"),
    (["--input", "qg={irregular}:qg"], r"time column 't' is not uniformly sampled"),
])
def test_bad_machine_runs_say_why(tmp_path, emps, args, msg):
    _, path, ref, _ = emps
    irregular = _csv(tmp_path / "irr.csv", "t,qg", np.array([0.0, 1e-3, 3e-3]), np.zeros(3))
    argv = ["simulate", str(path), *[a.format(ref=ref, irregular=irregular) for a in args]]
    res = runner.invoke(app, argv)
    assert res.exit_code == 2, res.output
    line = res.output.strip()
    assert "\n" not in line and line.startswith("error: ")
    assert __import__("re").search(msg, line), line


def test_law_files_refuse_machine_options(tmp_path):
    law = fk.save_model(fk.Dahl(Fc=1.0, sigma0=1e5), tmp_path / "dahl.json")
    res = runner.invoke(app, ["simulate", str(law), "--input", "u=1", "--dt", "1e-3"])
    assert res.exit_code == 2 and "--input, --dt: for a machine file; " in res.output and "is a friction law" in res.output


def test_compensate_refuses_a_machine_file_saying_what_is_missing(tmp_path):
    path = fk.save_model(_slider(), tmp_path / "slider.json")
    res = runner.invoke(app, ["compensate", str(path)])
    assert res.exit_code == 2
    line = res.output.strip()
    assert "\n" not in line and line.startswith(f"error: machine file '{path}' (slider) carries no compensation test")
    assert "test motion" in line and "coordinate whose error is scored" in line
    law = fk.save_model(fk.Dahl(Fc=1.0, sigma0=1e5), tmp_path / "dahl.json")
    res = runner.invoke(app, ["compensate", str(law)])
    assert res.exit_code == 2 and "is a friction law, not a machine: give it as --model" in res.output


def test_readme_machine_files_example_runs_as_written(tmp_path, monkeypatch):
    import re
    import shlex
    from pathlib import Path

    text = (Path(__file__).resolve().parents[2] / "README.md").read_text(encoding="utf-8")
    start = text.index("**Machine files.**")
    sec = text[start:text.index("\n### ", start)]
    py = re.search(r"```python\n(.*?)```", sec, re.S).group(1)
    sh = re.search(r"```sh\n(.*?)```", sec, re.S).group(1).strip()
    monkeypatch.chdir(tmp_path)
    ns: dict = {}
    exec(compile(py, "README.md", "exec"), ns)  # noqa: S102 - the README's own example
    assert ns["m2"].input_names() == ["qg"] and ns["m2"].to_dict() == ns["m"].to_dict()
    argv = shlex.split(sh)
    assert argv[0] == "frictionkit"
    res = runner.invoke(app, argv[1:])
    assert res.exit_code == 0, res.output
    doc = json.loads((tmp_path / "run.json").read_text())
    assert doc["status"] == 0 and doc["samples"] == 5001
    cols = (tmp_path / "traces.csv").read_text(encoding="utf-8").splitlines()[0].split(",")
    assert cols[:4] == ["t [s]", "x.q [m]", "v.q [m/s]", "force.friction [N]"]  # as the README says
    assert (tmp_path / "run.png").stat().st_size > 5000


# --------------------------------------------------------------------------- compensate sdss (item 3)
def test_compensate_sdss_sidereal_tracking(tmp_path):
    """The SDSS azimuth preset: sidereal tracking from rest without and with the LuGre map as
    current feed-forward. The two runs must agree with the reproduction's own implementation of
    the same experiment (:func:`frictionkit.reproduce.sdss.sidereal_tracking`, written apart),
    and the feed-forward must lower the RMS error (README: 0.109 -> 0.069 arcsec, quick)."""
    from frictionkit.compensate import compensate
    from frictionkit.presets import sdss
    from frictionkit.reproduce.sdss import sidereal_tracking

    law = sdss.AzimuthAxis().friction
    f = fk.save_model(law, tmp_path / "az.json", units={"F": "N·m", "v": "rad/s"}, method="the axis's own law")
    res = runner.invoke(app, ["compensate", "sdss", "--quick", "--model", str(f), "--json", "-"])
    assert res.exit_code == 0, res.output
    doc = json.loads(res.stdout)
    assert doc["units"] == {"error": "rad"} and doc["reversals_s"] == [] and doc["duration_s"] == 15.0
    rows = doc["compensators"]
    assert list(rows) == ["none", "lugre", "model"] and rows["none"]["reversal_error"] is None
    ref = sidereal_tracking(model=law, duration=15.0)  # [arcsec], RMS over the whole run
    arcsec = math.pi / 648000.0
    assert rows["none"]["rms_error"] / arcsec == pytest.approx(ref["no_compensation"], rel=1e-9)
    assert rows["lugre"]["rms_error"] / arcsec == pytest.approx(ref["lugre_feedforward"], rel=1e-9)
    assert rows["model"] == rows["lugre"]  # the file holds the same law
    assert rows["lugre"]["rms_error"] < 0.8 * rows["none"]["rms_error"]
    text = runner.invoke(app, ["compensate", "sdss", "--quick", "--compensator", "none"]).stdout
    assert "[arcsec]" in text  # the unit survives rich's markup
    lin = fk.save_model(law, tmp_path / "lin.json")
    with pytest.raises(fk.DataError, match=r"act on the axis \(force \[N·m\], velocity \[rad/s\]\)"):
        compensate("sdss", ["model"], model=lin, quick=True)


@pytest.mark.parametrize("content, args, message", [
    ("t,u\n0,true\n0.001,false\n0.002,true\n", [], "holds true/false values"),
    ("t,u,u\n0,1,2\n0.001,1,2\n0.002,1,2\n", [], "'u'"),
    ("t,u\n0,1\n0.001,nan\n0.002,1\n", [], "not finite at row 1"),
    (None, ["--input", "u=1", "--dt", "1e-3", "--duration", "1e300"], "--duration 1e+300 / --dt 0.001"),
    (None, ["--input", "u=1", "--dt", "1e-300", "--duration", "1"], "at most 1e+08"),
])
def test_bad_input_columns_and_run_lengths_are_named(tmp_path, content, args, message):
    """Issue 13 round 3: a true/false or repeated input column was read as 1/0 or the first
    copy (exit 0); --duration/--dt that make 1e303 samples ended in numpy's 'Maximum allowed
    dimension exceeded'."""
    path = fk.save_model(_slider(), tmp_path / "slider.json")
    if content is not None:
        (tmp_path / "in.csv").write_text(content)
        args = ["--input", f"u={tmp_path / 'in.csv'}:u"]
    res = runner.invoke(app, ["simulate", str(path), *args])
    assert res.exit_code == 2 and message in res.output, res.output
    assert len([ln for ln in res.output.splitlines() if ln.strip()]) == 1, res.output
