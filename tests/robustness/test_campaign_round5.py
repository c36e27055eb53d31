"""Issue 13, campaign round 5 (helper camp): one test per pattern fixed, each built from the case
that exposed it. Machine files and run inputs are checked at load: nothing here simulates."""

from __future__ import annotations

import json
import re
from pathlib import Path

import numpy as np
import pytest

import frictionkit as fk
from frictionkit.errors import DataError, ParameterError


@pytest.fixture(scope="module")
def machine_doc(tmp_path_factory) -> tuple[Path, dict]:
    """A saved one-mass machine with a P loop reading the reference input 'r'."""
    from frictionkit.presets.emps import PUBLISHED, emps_machine

    folder = tmp_path_factory.mktemp("machine")
    path = fk.save_model(emps_machine(M=PUBLISHED["M"], friction=fk.CoulombViscous(Fc=20.0, sigma2=200.0),
                                      offset=0.0), folder / "emps.json")
    return folder, json.loads(path.read_text())


def _write(folder: Path, name: str, doc: dict | str) -> Path:
    p = folder / name
    p.write_text(doc if isinstance(doc, str) else json.dumps(doc))
    return p


@pytest.mark.parametrize("where, value", [("inertia", "95"), ("Fc", "20"), ("term", "0.5")])
def test_a_number_written_as_a_string_is_refused(machine_doc, where, value):
    """Were read through float(): "95" ran as 95 kg with status 0 (float() also reads "1_000")."""
    folder, doc = machine_doc
    d = json.loads(json.dumps(doc))
    m = d["model"]
    target = {"inertia": m["dofs"][0], "Fc": m["sites"][0]["law"], "term": m["blocks"][0]["terms"]}[where]
    key = {"inertia": "inertia", "Fc": "Fc", "term": next(iter(target))}[where]
    target[key] = value
    with pytest.raises(DataError, match=re.escape(f"= '{value}': must be a real number, not a string")):
        fk.load_model(_write(folder, f"str_{where}.json", d))
    with pytest.raises(ParameterError, match="not a string"):
        fk.CoulombViscous(Fc="20", sigma2=1.0)


def test_an_edited_inputs_list_is_not_ignored(machine_doc):
    folder, doc = machine_doc
    need = doc["inputs"]
    for listed in (need + ["extra"], []):
        d = dict(doc, inputs=listed)
        with pytest.raises(DataError, match=re.escape(f'"inputs" lists {listed} but the machine reads {need}')):
            fk.load_model(_write(folder, "inputs.json", d))
    d = {k: v for k, v in doc.items() if k != "inputs"}  # leaving the list out is fine: it is derived
    assert fk.load_model(_write(folder, "no_inputs.json", d)).input_names() == need


def test_a_huge_integer_names_the_file(machine_doc):
    """Was: "error: Exceeds the limit (4300 digits) for integer string conversion" naming no file."""
    folder, doc = machine_doc
    p = _write(folder, "huge.json", json.dumps(doc).replace('"x0": 0.0', '"x0": 1' + "0" * 5000, 1))
    with pytest.raises(DataError, match=re.escape(f"'{p}': not readable JSON")):
        fk.load_model(p)


def _grid(tmp_path, text: str, col: str = "r"):
    from frictionkit.data import read_table
    from frictionkit.data.loaders import _grid_input

    p = tmp_path / "in.csv"
    p.write_text(text)
    tab = read_table(p)
    return _grid_input(tab, p, next(iter(tab)), col, "--input r", None)


@pytest.mark.parametrize("text, cause", [
    ("t,r\n", "0 row(s); a run's input needs at least 2 samples"),
    ("t,r\n0,1\n", "1 row(s)"),
    ("t,r\n0,1\n-0.001,1\n-0.002,1\n", "does not increase at row 1 (0 -> -0.001 s)"),
    ("t,r\n0,1\n0.001,1\n0.003,1\n", "not uniformly sampled (steps 0.001 to 0.002 s)"),
])
def test_a_run_input_grid_names_its_real_cause(tmp_path, text, cause):
    """All four said "not uniformly sampled" (an empty file, a time running backwards)."""
    with pytest.raises(DataError, match=re.escape(cause)):
        _grid(tmp_path, text)


@pytest.mark.parametrize("header, col, unit", [("t [ms],r", "r", "ms"), ("t,r [mm]", "r [mm]", "mm")])
def test_a_non_si_unit_in_an_input_header_is_refused(tmp_path, header, col, unit):
    """`simulate MACHINE.json --input qg=f.csv:'qg [mm]'` with `t [ms]` ran 1,000x too slow, status 0."""
    rows = "".join(f"{i},{0.1}\n" for i in range(5))
    with pytest.raises(DataError, match=re.escape(f"is in {unit}; this input is read in SI")):
        _grid(tmp_path, f"{header}\n{rows}", col)
    arr, grid = _grid(tmp_path, "t [s],r [m]\n" + "".join(f"{i * 1e-3},{0.1}\n" for i in range(5)), "r [m]")
    assert grid[:2] == (5, pytest.approx(1e-3)) and np.all(arr == 0.1)


def test_a_corrupt_sample_in_a_run_input_is_refused(tmp_path):
    """One 1e300 sample in an EMPS reference ran with status 0."""
    rows = "".join(f"{i * 1e-3},{1e300 if i == 5 else 0.0}\n" for i in range(50))
    with pytest.raises(DataError, match=r"= 1e\+300 at row 5: beyond 1e\+150"):
        _grid(tmp_path, "t,r\n" + rows)


def test_an_empty_study_spec_is_refused(tmp_path):
    """A zero-byte spec ran a 20-run default study and exited 0."""
    from frictionkit.study import load_study

    p = tmp_path / "s.toml"
    p.write_text("")
    with pytest.raises(DataError, match=re.escape(f"study '{p}': the file holds no table")):
        load_study(p)


def test_compensate_never_writes_over_a_file_its_test_names(tmp_path):
    """`compensate M.json --test T.toml --json ref.csv` replaced the test's input data."""
    from frictionkit.cli.compensate import _spec_files

    spec = tmp_path / "t.toml"
    spec.write_text('[inputs]\nqg = "ref.csv:qg"\nff = 0.0\n[compensators]\ncoulomb = "law.json"\n')
    assert _spec_files(spec) == [tmp_path / "ref.csv", tmp_path / "law.json"]
    spec.write_text("[[[")  # unreadable: left to the spec loader's own error
    assert _spec_files(spec) == []


def test_compensate_refuses_an_input_nothing_reads_and_an_output_over_its_data(machine_doc, runner):
    """A spec input read by neither the machine nor the score/compensation was loaded and ignored;
    `--json ref.csv` (the spec's own data) was overwritten. Both are refused before any run."""
    from frictionkit.cli import app

    folder, _ = machine_doc
    t = np.arange(11) * 1e-3
    np.savetxt(folder / "ref.csv", np.column_stack([t, 0 * t, 0 * t]), delimiter=",", header="t,qg,vref", comments="")
    body = ('[score]\nposition = "q"\nreference = "qg"\n[compensation]\nvelocity = "vref"\nsite = "friction"\n'
            '[inputs]\nqg = "ref.csv:qg"\nvref = "ref.csv:vref"\n')
    spec = _write(folder, "t.toml", body + 'qgg = "ref.csv:qg"\n')
    res = runner.invoke(app, ["compensate", str(folder / "emps.json"), "--test", str(spec)])
    assert res.exit_code == 2 and "[inputs] qgg: not read by machine 'EMPS'" in res.stderr, res.stderr
    spec = _write(folder, "t.toml", body)
    before = (folder / "ref.csv").read_bytes()
    res = runner.invoke(app, ["compensate", str(folder / "emps.json"), "--test", str(spec),
                              "--json", str(folder / "ref.csv")])
    assert res.exit_code == 2 and "is the input file" in res.stderr, res.stderr
    assert (folder / "ref.csv").read_bytes() == before


def test_a_corrupt_fleet_part_is_identified_again_not_a_dead_end(tmp_path):
    """An empty, truncated or foreign part in R.parquet.parts/ made every later `fleet identify`
    fail ("Parquet magic bytes not found") until deleted by hand; it now counts as not done."""
    import pyarrow as pa
    import pyarrow.parquet as pq

    from frictionkit.fleet.identify import _complete_part

    good = tmp_path / "good.parquet"
    pq.write_table(pa.table({"a": [1.0, 2.0]}), good)
    raw = good.read_bytes()
    cases = {"empty": b"", "truncated": raw[: len(raw) // 2], "foreign": b"t,F\n0,1\n" * 10}
    assert _complete_part(good)
    for name, data in cases.items():
        (tmp_path / f"{name}.parquet").write_bytes(data)
        assert not _complete_part(tmp_path / f"{name}.parquet"), name
    assert not _complete_part(tmp_path / "missing.parquet")


@pytest.mark.parametrize("name", ["END_FUNCTION_BLOCK", "var", "a__b"])
def test_structured_text_export_refuses_a_reserved_function_block_name(name):
    """`export --format st --name END_FUNCTION_BLOCK` wrote "FUNCTION_BLOCK END_FUNCTION_BLOCK", exit 0."""
    from frictionkit.export import export_model

    with pytest.raises(ParameterError, match=re.escape(f"name = {name!r}: a reserved word of IEC 61131-3")):
        export_model(fk.CoulombViscous(Fc=1.0, sigma2=0.1), "st", name=name)
    assert "FUNCTION_BLOCK FB_var\n" in export_model(fk.CoulombViscous(Fc=1.0, sigma2=0.1), "st", name="FB_var")


@pytest.mark.parametrize("rows", [[1], {}])
def test_report_names_a_hand_edited_compensation_table(rows):
    """A list read "malformed content (AttributeError: 'list' object has no attribute 'items')";
    an empty object gave a page with an empty table and exit 0."""
    from frictionkit.report.adapters import compensation_sections

    with pytest.raises(DataError, match=re.escape(f'"compensators" = {rows}: expected an object')):
        compensation_sections({"format": "frictionkit.compensation/1", "preset": "emps", "compensators": rows})


def test_a_delay_as_long_as_the_run_is_refused_naming_the_part():
    """An actuator delay of 10,000 samples spent 648 s in the loop screen; 10**9 grew to 7.6 GB
    (round 5): a delay the run can never see the end of is refused, naming the part."""
    m = fk.Machine("slider")
    x = m.dof("x", inertia=1.0)
    m.friction("contact", x, law=fk.CoulombViscous(Fc=1.0))
    m.actuator("u", x, delay=10**9)
    with pytest.raises(ParameterError, match=r"actuator 'u' delay = 1000000000 samples.*\(101 samples\)"):
        fk.simulate_machine(m, dt=1e-3, inputs={"u": np.full(101, 0.5)})


def test_the_loop_screen_skips_a_state_too_large_to_linearise_and_says_so():
    """A closed loop whose delay lines make the screen's state larger than SCREEN_MAX_DIM is run
    without the screen and the message says why (it was minutes of eigenvalue work)."""
    from frictionkit.machines import PID, Sum
    from frictionkit.machines.stability import SCREEN_MAX_DIM

    m = fk.Machine("slider")
    x = m.dof("x", inertia=1.0)
    m.friction("contact", x, law=fk.CoulombViscous(Fc=0.1, sigma2=1.0))
    m.sensor("xs", x)
    m.add(Sum("e", {"r": 1.0, "xs": -1.0}), PID("i", "e", Kp=10.0))
    m.actuator("a", x, command="i", delay=SCREEN_MAX_DIM)
    n = SCREEN_MAX_DIM + 50
    res = fk.simulate_machine(m, dt=1e-3, inputs={"r": np.full(n, 1e-3)}, substeps=1)
    assert res.status == 0
    assert "stability screen was skipped" in res.message and str(SCREEN_MAX_DIM) in res.message


def test_identify_static_refuses_velocity_and_position_together(tmp_path, runner):
    """`identify static --velocity v --position x` exited 0 and ignored --position (round 5)."""
    from frictionkit.cli import app

    t = np.arange(50) * 1e-2
    np.savetxt(tmp_path / "d.csv", np.column_stack([t, 0.01 * t, 0.01 + 0 * t, 1 + 0 * t]), delimiter=",",
               header="t,x,v,F", comments="")
    res = runner.invoke(app, ["identify", "static", str(tmp_path / "d.csv"), "--time", "t", "--velocity", "v",
                              "--position", "x", "--force", "F"])
    assert res.exit_code == 2 and "not both" in res.stderr, res.stderr
