"""``frictionkit export``: lookup table, C header (compiled with the system gcc), IEC 61131-3 ST.

Tolerances. The C code evaluates the same formulas as the library in IEEE double with
glibc's ``exp``/``pow``; the two differ by rounding only, measured at 2.2e-16 N (steady
state) and 1.6e-15 N (LuGre update over 8,000 samples). The bounds below are
1e-12 x the largest level for the steady state and 1e-9 x Fs for the LuGre update
(the state carries rounding from sample to sample), far below any physical effect and
far above rounding. The ST is checked structurally (declared inputs and outputs) and
by translating its body, statement by statement, into Python and running it on the
same inputs.
"""

from __future__ import annotations

import json
import math
import re
import shutil
import subprocess
from pathlib import Path

import numpy as np
import pytest
from typer.testing import CliRunner

import frictionkit as fk
from frictionkit.cli import _register, app

_register()
runner = CliRunner()

ST_POS = fk.Stribeck(Fc=1.0, Fs=1.5, vs=1e-3, sigma2=0.4)
ST_NEG = fk.Stribeck(Fc=1.2, Fs=1.6, vs=2e-3, delta=1.3, sigma2=0.5, shape="lorentzian")
LAWS = {
    "stribeck": fk.Stribeck(Fc=2.0, Fs=3.0, vs=5e-3, delta=0.7, sigma2=20.0),
    "coulomb_viscous": fk.CoulombViscous(Fc=2.0, sigma2=10.0),
    "directional_static": fk.Directional(positive=ST_POS, negative=ST_NEG),
    "gms": fk.GMS(ST_POS, k=[1e4, 1e5, 1e6], xi=[0.5, 0.3, 0.1], C=20.0),
    "lugre": fk.LuGre(fk.Directional(positive=ST_POS, negative=ST_NEG), sigma0=1e5, sigma1=63.2),
    "dahl": fk.Dahl(Fc=1.0, sigma0=2e5, sigma2=0.3),
    "lugre_zero_fc": fk.LuGre(fk.Stribeck(Fc=0.0, Fs=1.0, vs=1e-3), sigma0=1e5, sigma1=10.0),
    "directional_lugre": fk.Directional(positive=fk.LuGre(ST_POS, sigma0=1e5, sigma1=63.2),
                                        negative=fk.LuGre(ST_NEG, sigma0=3e5, sigma1=20.0)),
}
DYNAMIC = ("lugre", "dahl", "lugre_zero_fc", "directional_lugre")

#: Velocities for the steady-state comparison: 0, tiny, around vs, large, both signs [m/s].
V_STATIC = np.concatenate([[0.0, 1e-12, -1e-12], np.geomspace(1e-7, 10.0, 60), -np.geomspace(1e-7, 10.0, 60)])

DT = 2.5e-4
T = np.arange(8001) * DT
#: A 20 µm pre-sliding wiggle on a 1 mm, 0.25 Hz sweep: reversals, sticking and sliding.
X = 20e-6 * np.sin(np.pi * T) + 1e-3 * np.sin(0.5 * np.pi * T)
#: Fast enough (0.16 m/s) that exp(-(v/vs)^2) underflows: the law with Fc = 0 reaches |s(v)| = 0, the floor.
X_FAST = 0.05 * np.sin(np.pi * T)


def _motion(name: str) -> tuple[np.ndarray, np.ndarray]:
    """Position and the velocity of each interval (as a drive computes it) for a law's run."""
    x = X_FAST if name == "lugre_zero_fc" else X
    return x, np.diff(x) / DT

_MAIN_C = r"""
#include <stdio.h>
#include "model.h"
int main(void)
{
    double dt, v;
    if (scanf("%lf", &dt) != 1) return 1;
#ifdef DYNAMIC
    fk_friction_state s;
    fk_friction_reset(&s);
#endif
    while (scanf("%lf", &v) == 1) {
#ifdef DYNAMIC
        printf("%.17g %.17g\n", fk_friction_steady(v), fk_friction_update(&s, v, dt));
#else
        printf("%.17g\n", fk_friction_steady(v));
#endif
    }
    return 0;
}
"""


def _save(tmp: Path, name: str) -> Path:
    return fk.save_model(LAWS[name], tmp / f"{name}.json", method="export test")


def _export(model: Path, fmt: str, out: Path, *extra: str) -> None:
    res = runner.invoke(app, ["export", str(model), "--format", fmt, "--out", str(out), *extra])
    assert res.exit_code == 0, res.output
    assert f"wrote {out}" in res.stdout


@pytest.fixture(scope="module")
def compiled(tmp_path_factory):
    """name -> path of the compiled test program for every law (one gcc call each)."""
    gcc = shutil.which("gcc")
    if gcc is None:  # pragma: no cover - the CI image has gcc
        pytest.skip("no system gcc")
    tmp = tmp_path_factory.mktemp("export_c")
    out = {}
    for name in LAWS:
        d = tmp / name
        d.mkdir()
        _export(_save(d, name), "c", d / "model.h")
        (d / "main.c").write_text(_MAIN_C)
        flags = ["-DDYNAMIC"] if name in DYNAMIC else []
        subprocess.run([gcc, "-std=c99", "-O2", "-Wall", "-Wextra", "-pedantic", "-Werror", *flags, "-o",
                        str(d / "prog"), str(d / "main.c"), "-lm"], check=True, capture_output=True, text=True)
        out[name] = d / "prog"
    return out


def _run(prog: Path, v: np.ndarray, dt: float = DT) -> np.ndarray:
    text = f"{dt!r}\n" + "\n".join(repr(x) for x in v.tolist()) + "\n"
    out = subprocess.run([str(prog)], input=text, capture_output=True, text=True, check=True).stdout
    return np.array([[float(x) for x in line.split()] for line in out.splitlines()])


def _level(law) -> float:
    return float(np.max(np.abs(law.steady_state(np.array([1e-9, -1e-9, 1.0, -1.0])))))


@pytest.mark.parametrize("name", sorted(LAWS))
def test_c_steady_state_matches_the_model(compiled, name):
    law = LAWS[name]
    got = _run(compiled[name], V_STATIC)[:, 0]
    want = law.steady_state(V_STATIC)
    assert np.max(np.abs(got - want)) <= 1e-12 * _level(law)
    assert got[0] == 0.0  # v = 0: no steady sliding force


@pytest.mark.parametrize("name", DYNAMIC)
def test_c_lugre_update_matches_motion_driven_simulation(compiled, name):
    law = LAWS[name]
    x, v = _motion(name)
    got = _run(compiled[name], v)[:, 1]
    ref = fk.simulate(law, position=x, dt=DT)
    assert ref.success
    err = np.max(np.abs(got - ref.friction[1:]))
    assert err <= 1e-9 * _level(law), err
    # the run visits pre-sliding and sliding in both directions (Fc = 0: the force fades at speed)
    assert got.min() < -0.1 * _level(law) and got.max() > 0.1 * _level(law)


# --------------------------------------------------------------------------- structured text
def _st_python(src: str) -> tuple[dict, dict, str]:
    """Declared inputs/outputs/locals and the body translated into Python (one statement per line)."""
    src = re.sub(r"\(\*.*?\*\)", "", src, flags=re.S)
    m = re.search(r"FUNCTION_BLOCK\s+(\w+)(.*?)END_FUNCTION_BLOCK", src, re.S)
    assert m, "no FUNCTION_BLOCK ... END_FUNCTION_BLOCK"
    body = m.group(2)
    decls = {}
    for sect in ("VAR_INPUT", "VAR_OUTPUT", "VAR"):
        block = re.search(rf"\b{sect}\b(.*?)\bEND_VAR\b", body, re.S)
        decls[sect] = {}
        if block:
            for name, typ, init in re.findall(r"(\w+)\s*:\s*(\w+)\s*(?::=\s*([^;]+))?;", block.group(1)):
                decls[sect][name] = (typ, init or None)
    code = body[body.rindex("END_VAR") + len("END_VAR"):]
    lines, depth = [], 0
    for raw in code.splitlines():
        s = raw.strip()
        if not s:
            continue
        for st, py in (("EXPT(", "pow("), ("EXP(", "math.exp("), ("ABS(", "abs("), ("MAX(", "max(")):
            s = s.replace(st, py)
        if s.startswith("IF ") and s.endswith(" THEN"):
            lines.append("    " * depth + f"if {s[3:-5]}:")
            depth += 1
        elif s.startswith("ELSIF ") and s.endswith(" THEN"):
            lines.append("    " * (depth - 1) + f"elif {s[6:-5]}:")
        elif s == "ELSE":
            lines.append("    " * (depth - 1) + "else:")
        elif s == "END_IF;":
            depth -= 1
        else:
            assert re.fullmatch(r"\w+ := [^;]+;", s), f"unexpected ST statement: {s!r}"
            lines.append("    " * depth + s[:-1].replace(":=", "="))
    assert depth == 0
    return decls["VAR_INPUT"], decls["VAR_OUTPUT"], compile("\n".join(lines), "function_block.st", "exec")


@pytest.mark.parametrize("name", sorted(LAWS))
def test_structured_text_declarations_and_formulas(tmp_path, name):
    law = LAWS[name]
    out = tmp_path / "fb.st"
    _export(_save(tmp_path, name), "st", out, "--name", "Axis1_Friction")
    text = out.read_text(encoding="ascii")  # ASCII only, for PLC editors
    assert re.search(r"^FUNCTION_BLOCK Axis1_Friction$", text, re.M)
    inputs, outputs, body = _st_python(text)
    assert outputs == {"F": ("LREAL", None)}
    if name in DYNAMIC:
        assert inputs == {"v": ("LREAL", None), "dt": ("LREAL", None), "reset": ("BOOL", None)}
        ns = {"math": math, "z": 0.0, "reset": False, "dt": DT}
        got = []
        x, vel = _motion(name)
        for v in vel.tolist():
            ns["v"] = v
            exec(body, ns)  # noqa: S102 - the translated function block
            got.append(ns["F"])
        ref = fk.simulate(law, position=x, dt=DT)
        assert np.max(np.abs(np.array(got) - ref.friction[1:])) <= 1e-9 * _level(law)
        ns["reset"], ns["v"] = True, 0.0
        exec(body, ns)  # noqa: S102
        assert ns["z"] == 0.0 and ns["F"] == 0.0
    else:
        assert inputs == {"v": ("LREAL", None)}
        got = []
        for v in V_STATIC.tolist():
            ns = {"math": math, "v": v}
            exec(body, ns)  # noqa: S102
            got.append(ns["F"])
        assert np.max(np.abs(np.array(got) - law.steady_state(V_STATIC))) <= 1e-12 * _level(law)


# --------------------------------------------------------------------------- lookup table
def test_csv_lookup_table(tmp_path):
    law = LAWS["directional_static"]
    out = tmp_path / "table.csv"
    _export(_save(tmp_path, "directional_static"), "csv", out, "--v-max", "0.01", "--points", "2001")
    lines = out.read_text().splitlines()
    assert lines[0] == "v [m/s],friction [N]"
    data = np.array([[float(x) for x in ln.split(",")] for ln in lines[1:]])
    assert data.shape == (2001, 2)
    np.testing.assert_allclose(data[:, 0], np.linspace(-0.01, 0.01, 2001), rtol=0, atol=1e-18)
    assert data[1000, 0] == 0.0 and data[1000, 1] == 0.0
    # by hand, seed 002 eq. 9b at v = +1 mm/s: 1 + 0.5 exp(-1) + 0.4e-3; eq. 9a at v = -2 mm/s: -(1.2 + 0.4/2) - 1e-3
    i_pos = int(np.argmin(np.abs(data[:, 0] - 1e-3)))
    i_neg = int(np.argmin(np.abs(data[:, 0] + 2e-3)))
    assert data[i_pos, 1] == pytest.approx(1.0 + 0.5 * math.exp(-1.0) + 0.4e-3, rel=1e-12)
    assert data[i_neg, 1] == pytest.approx(-(1.2 + 0.4 / 2.0) - 0.5 * 2e-3, rel=1e-12)
    np.testing.assert_allclose(data[:, 1], law.steady_state(data[:, 0]), rtol=1e-15, atol=0)


def test_csv_default_grid_spans_ten_stribeck_velocities(tmp_path):
    out = tmp_path / "t.csv"
    _export(_save(tmp_path, "lugre"), "csv", out)
    v = np.loadtxt(out, delimiter=",", skiprows=1)[:, 0]
    assert v.size == 201 and v[0] == pytest.approx(-0.02) and v[-1] == pytest.approx(0.02)  # 10 x vs = 2 mm/s


# --------------------------------------------------------------------------- CLI contract
def test_json_summary(tmp_path):
    model = _save(tmp_path, "lugre")
    res = runner.invoke(app, ["export", str(model), "--format", "c", "--out", str(tmp_path / "f.h"), "--json", "-"])
    assert res.exit_code == 0, res.output
    doc = json.loads(res.stdout)
    assert doc["law"] == "LuGre" and doc["family"] == "lugre" and doc["format"] == "c"
    assert doc["contents"] == "steady-state map and discrete-time update with state"
    assert doc["bytes"] == (tmp_path / "f.h").stat().st_size


def test_exports_an_identification_result_and_records_its_provenance(tmp_path):
    from frictionkit.identify.result import IdentificationResult

    law = LAWS["lugre"]
    res = IdentificationResult(kind="output_error", model_name="lugre", model=law, names=("sigma0",),
                               values=np.array([1e5]), stderr=np.array([1e3]), ci95=np.array([[9.8e4, 1.02e5]]),
                               units=("N/m",), correlation=np.eye(1), rms=0.01, relative_error_percent=1.0,
                               n_obs=100, dof=99, provenance={"sha256": "cd" * 32})
    fit = res.save_json(tmp_path / "fit.json")
    _export(fit, "st", tmp_path / "f.st")
    text = (tmp_path / "f.st").read_text()
    assert f"data_sha256: {'cd' * 32}" in text and "identification: output_error (lugre)" in text


BAD_CLI = {
    "format": (["--format", "xls"], "--format 'xls': must be one of csv, json, c, st"),
    "points_even": (["--format", "csv", "--points", "200"], "--points 200: must be odd"),
    "points_few": (["--format", "csv", "--points", "1"], "--points 1: must be between 3 and 1000001"),
    "v_max": (["--format", "csv", "--v-max", "-1"], "--v-max -1.0: must be > 0"),
    "name": (["--format", "c", "--name", "2fast"], "name = '2fast': must be an identifier"),
}


@pytest.mark.parametrize("case", sorted(BAD_CLI))
def test_bad_options_are_one_line_errors(tmp_path, case):
    args, why = BAD_CLI[case]
    model = _save(tmp_path, "lugre")
    res = runner.invoke(app, ["export", str(model), *args, "--out", str(tmp_path / "o.txt")])
    assert res.exit_code == 2
    err = res.stderr.strip()
    assert err.count("\n") == 0 and err.startswith("error: ") and why in err, err
    assert not (tmp_path / "o.txt").exists()


def test_bad_model_file_is_one_line_error(tmp_path):
    p = tmp_path / "m.json"
    p.write_text(json.dumps({"format": "frictionkit.model/9", "model": {}}))
    res = runner.invoke(app, ["export", str(p), "--format", "c", "--out", str(tmp_path / "o.h")])
    assert res.exit_code == 2
    assert res.stderr.strip() == (f"error: model file '{p}': format 'frictionkit.model/9' was written by a newer "
                                  f"frictionkit; this one ({fk.__version__}) reads 'frictionkit.model/1': upgrade "
                                  "frictionkit")


def test_help_has_an_example():
    res = runner.invoke(app, ["export", "--help"])
    assert res.exit_code == 0
    assert "frictionkit export fit.json --format csv --out friction_table.csv" in res.stdout
    assert "[m/s]" in res.stdout  # units in square brackets survive the help formatter


def test_never_writes_over_the_model_file(tmp_path):
    model = _save(tmp_path, "lugre")
    before = model.read_bytes()
    res = runner.invoke(app, ["export", str(model), "--format", "c", "--out", str(model)])
    assert res.exit_code == 2
    err = res.stderr.strip()
    assert err.startswith("error: --out") and "input" in err and "\n" not in err, err
    assert model.read_bytes() == before


def test_json_reduces_an_identification_result_to_a_model_file(tmp_path):
    from frictionkit.identify.result import IdentificationResult

    law = LAWS["directional_lugre"]
    res = IdentificationResult(kind="output_error", model_name="lugre", model=law, names=("sigma0",),
                               values=np.array([1e5]), stderr=np.array([1e3]), ci95=np.array([[9.8e4, 1.02e5]]),
                               units=("N·m/rad",), correlation=np.eye(1), rms=0.01, relative_error_percent=1.0,
                               n_obs=100, dof=99, data={"t": np.arange(1000.0)},
                               provenance={"sha256": "ef" * 32, "units": {"F": "N·m", "v": "rad/s", "x": "rad"}})
    fit = res.save_json(tmp_path / "fit.json")
    out = tmp_path / "model.json"
    _export(fit, "json", out)
    doc = json.loads(out.read_text(encoding="utf-8"))
    assert doc["format"] == "frictionkit.model/1" and "data" not in doc
    assert doc["units"]["v"] == "rad/s" and doc["units"]["parameters"]["positive.sigma0"] == "N·m/rad"
    prov = doc["provenance"]
    assert prov["data_sha256"] == "ef" * 32 and prov["frictionkit_version"] == fk.__version__
    assert prov["converted_from"] == {"file": str(fit), "format": "frictionkit.identification/1"}
    assert fk.load_model(out) == law


def test_a_scheduled_law_says_why_it_cannot_be_exported(tmp_path):
    if not hasattr(fk, "TDMSSC"):  # pragma: no cover - the scheduled law of seed 000
        pytest.skip("no scheduled law registered")
    model = fk.save_model(fk.TDMSSC(Fc0=1.0, Fs0=1.5, vs=1e-3, Fc1=10.0), tmp_path / "tdmssc.json")
    for fmt, why in (("c", "has no fixed static map"), ("st", "has no fixed static map"), ("csv", "schedule")):
        res = runner.invoke(app, ["export", str(model), "--format", fmt, "--out", str(tmp_path / f"o.{fmt}")])
        assert res.exit_code == 2, res.output
        err = res.stderr.strip()
        assert err.startswith("error: ") and "\n" not in err and why in err, err
