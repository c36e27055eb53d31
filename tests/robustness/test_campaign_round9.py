"""Issue 13, round 8's leftovers and campaign round 9 (helper r9): one test per pattern fixed, each built
from the case that exposed it."""

from __future__ import annotations

import os
import warnings

import numpy as np
import pytest

from _robustness_helpers import one_error_line

from frictionkit.errors import DataError, ParameterError


def test_a_machine_or_part_without_a_name_is_refused():
    """Was (round 8 leftover): a machine file with "name": "" loaded and printed as Machine('');
    a part named "  " was accepted (only "" was refused)."""
    from frictionkit.machines.machine import Machine
    from frictionkit.models.files import ModelFile

    doc = {"format": "frictionkit.model/1", "kind": "machine",
           "model": {"name": "", "dofs": [{"name": "x", "inertia": 2.0}],
                     "sites": [{"name": "c", "role": "friction", "at": {"x": 1.0},
                                "law": {"law": "CoulombViscous", "Fc": 1.0}}],
                     "actuators": [{"name": "u", "at": {"x": 1.0}}]}}
    with pytest.raises(ParameterError, match=r"^Machine name = '': must be a non-empty string$"):
        ModelFile.from_dict(doc)
    with pytest.raises(ParameterError, match=r"^Machine name = ' \\t': must be a non-empty string$"):
        Machine(" \t")
    with pytest.raises(ParameterError, match=r"^Machine.dof name = '  ': must be a non-empty string$"):
        Machine("m").dof("  ", inertia=1.0)
    doc["model"]["name"] = "slider"
    assert ModelFile.from_dict(doc).model.name == "slider"  # the same file with a name loads


def test_a_result_given_twice_to_report_is_refused(runner, tmp_path, static_json):
    """Was (round 8 leftover): `report FIT FIT -o DIR` built a page with two identical sections; also
    through a second name (a link) of the same file."""
    import frictionkit.cli.report  # noqa: F401  (registers the verb)
    from frictionkit.cli import app

    link = tmp_path / "again.json"
    link.symlink_to(static_json)
    res = runner.invoke(app, ["report", str(static_json), str(static_json), "-o", str(tmp_path / "r")])
    assert res.exit_code == 2
    assert one_error_line(res) == (f"error: result file '{static_json}' is given twice; each file makes one section "
                                   "of the page: give it once")
    res = runner.invoke(app, ["report", str(static_json), str(link), "-o", str(tmp_path / "r")])
    assert one_error_line(res).startswith(f"error: result file '{static_json}' (the same file as '{link}') is given twice")
    assert not (tmp_path / "r").exists()


def test_a_result_path_that_is_a_link_is_written_through_it(tmp_path):
    """Was (round 8 leftover): `--json LINK` renamed the new file over the link: a dangling link became a plain
    file, a link to an old result left that result stale. Now the write goes to the link's target (as the
    shell's '>'), atomically; a link whose target's folder is missing, or a loop, is refused up front."""
    from frictionkit._io import atomic_write_text, check_output_file

    (tmp_path / "res").mkdir()
    link = tmp_path / "fit.json"
    link.symlink_to(tmp_path / "res" / "fit.json")  # dangling
    check_output_file(link, option="--json")
    atomic_write_text(link, "one")
    assert os.path.islink(link) and (tmp_path / "res" / "fit.json").read_text() == "one"
    atomic_write_text(link, "two")  # a live link: the target is replaced, the link stays
    assert os.path.islink(link) and (tmp_path / "res" / "fit.json").read_text() == "two"
    assert sorted(os.listdir(tmp_path / "res")) == ["fit.json"]
    lost = tmp_path / "lost.json"
    lost.symlink_to(tmp_path / "nowhere" / "x.json")
    with pytest.raises(DataError, match=rf"^--json '{lost}' \(a link to '{tmp_path}/nowhere/x.json'\): folder "
                                        rf"'{tmp_path}/nowhere' does not exist$"):
        check_output_file(lost, option="--json")
    a, b = tmp_path / "a.json", tmp_path / "b.json"
    a.symlink_to(b)
    b.symlink_to(a)
    with pytest.raises(DataError, match=r"is a loop of symbolic links; give a file name$"):
        check_output_file(a, option="--out")
    with pytest.raises(OSError, match="a loop of symbolic links"):
        atomic_write_text(a, "x")


def test_a_csv_cut_inside_its_last_row_is_noted_even_when_only_an_unused_column_is_lost(tmp_path):
    """Was (round 8 leftover, met by the fleet fixture): a CSV cut inside its last row read without a word
    when the lost field was a column the load does not use. Now a ShortRowWarning names file, row and
    column(s); a used column lost there stays an error naming file, column and row."""
    from frictionkit.data import ShortRowWarning, load_recording

    body = "\n".join(f"{1e-3 * k:.3f},0.1,1.0,20.5" for k in range(30))
    cut = tmp_path / "cut.csv"
    cut.write_text("t_s,v_ms,F_N,temp_C\n" + body + "\n0.030,0.1,1.0")
    with pytest.warns(ShortRowWarning, match=rf"^file '{cut}': its last row \(row 30\) has 3 of 4 fields, a "
                                             r"truncated file\? column\(s\) 'temp_C' are empty there$"):
        rec = load_recording(cut, time="t_s", velocity="v_ms", force="F_N")
    assert rec.n == 31
    cut.write_text("t_s,v_ms,F_N,temp_C\n" + body + "\n0.030,0.1")
    with pytest.raises(DataError, match=r"column 'F_N', row 30: value nan is not finite"):
        load_recording(cut, time="t_s", velocity="v_ms", force="F_N")
    whole = tmp_path / "whole.csv"  # a complete file, with or without the final newline, says nothing
    for text in ("t_s,v_ms,F_N,temp_C\n" + body + "\n", "t_s,v_ms,F_N,temp_C\n" + body):
        whole.write_text(text)
        with warnings.catch_warnings():
            warnings.simplefilter("error")
            assert load_recording(whole, time="t_s", velocity="v_ms", force="F_N").n == 30


@pytest.mark.parametrize("argv,option", [(["fleet", "simulate", "--axes", "1", "--days", "1", "--out", ""], "--out"),
                                         (["fleet", "identify", " ", "--out", "r.parquet"], "DATASET"),
                                         (["demo", "--out", ""], "--out"),
                                         (["reproduce", "zhang2023", "--json", "z.json", "--robustness", "--out", ""],
                                          "--out")])
def test_an_empty_folder_option_is_refused_not_read_as_the_working_folder(runner, tmp_path, monkeypatch, argv,
                                                                           option):
    """Was (round 9): typer turns "" into Path("."): `fleet simulate --out ""` (an unset $DIR) wrote the fleet
    into the working folder without a word, `demo --out ""` ran the demo there."""
    import frictionkit.cli.fleet  # noqa: F401  (registers the verb)
    from frictionkit.cli import app

    monkeypatch.chdir(tmp_path)
    res = runner.invoke(app, argv)
    assert res.exit_code == 2
    assert one_error_line(res).startswith(f"error: {option} {argv[argv.index(option) + 1] if option != 'DATASET' else ' '!r}: "
                                          "give a folder (an empty value would mean the working folder")
    assert os.listdir(tmp_path) == []


def test_a_result_name_longer_than_the_file_system_takes_is_refused_up_front(tmp_path):
    """Was (round 9): `--json` with a 300-byte name failed with "File name too long" (exit 1) after the fit,
    and names of 242-255 bytes too: the writer's temporary file added 14 bytes to the name."""
    from frictionkit._io import atomic_write_text, check_output_file

    most = os.pathconf(tmp_path, "PC_NAME_MAX")
    ok = tmp_path / ("x" * (most - 5) + ".json")
    check_output_file(ok, option="--json")
    atomic_write_text(ok, "{}")
    assert ok.read_text() == "{}" and os.listdir(tmp_path) == [ok.name]
    long = tmp_path / ("x" * most + ".json")
    with pytest.raises(DataError, match=rf"^--json '.*': the file name is {most + 5} bytes; the file system takes "
                                        rf"at most {most}$"):
        check_output_file(long, option="--json")


def test_a_fixed_stribeck_exponent_that_overflows_the_fit_is_refused():
    """Was (round 9): `identify static --model exponential --delta 1e9` ended in scipy's "array must not
    contain infs or NaNs" (100 ran, 300 did not)."""
    from frictionkit.identify import fit_static_map
    from frictionkit.identify.static_map import MAX_FIXED_DELTA

    v = np.r_[np.geomspace(1e-4, 0.2, 12), -np.geomspace(1e-4, 0.2, 12)]
    F = np.sign(v) * (1.0 + 0.5 * np.exp(-np.abs(v / 1e-3) ** 2)) + 0.4 * v  # seed 002 eq. 9b, delta = 2
    res = fit_static_map(v, F, model="exponential", delta=MAX_FIXED_DELTA)  # the wrong exponent: a result, maybe flagged
    assert np.isfinite(res.values).all()
    with pytest.raises(ParameterError, match=r"^fit_static_map.delta = 1000000000.0: a fixed Stribeck exponent "
                                             r"must be <= 50 "):
        fit_static_map(v, F, model="exponential", delta=1e9)


def test_an_input_that_is_a_broken_link_or_a_folder_is_named_as_such(runner, tmp_path, staircase_csv):
    """Was (round 9): a link loop or a dangling link as RECORDING said "not found" (naming the link, which is
    there); a recording of 2 rows said "v has 2 samples: need at least 3", naming no file."""
    from _robustness_helpers import STATIC_ARGS

    from frictionkit.cli import app
    from frictionkit.data import load_recording

    loop, dangling = tmp_path / "loop.csv", tmp_path / "dangling.csv"
    loop.symlink_to(loop)
    dangling.symlink_to(tmp_path / "gone.csv")
    for path, why in ((loop, "a loop of symbolic links"),
                      (dangling, f"a symbolic link to '{tmp_path}/gone.csv', which does not exist")):
        res = runner.invoke(app, ["identify", "static", str(path), *STATIC_ARGS])
        assert one_error_line(res) == f"error: RECORDING '{path}': {why}"
        with pytest.raises(DataError, match=rf"^file '{path}': {why}$"):
            load_recording(path, time="t_s")
    (tmp_path / "d.csv").mkdir()
    with pytest.raises(DataError, match=r"^file '.*d.csv' is a folder; give a data file$"):
        load_recording(tmp_path / "d.csv", time="t_s")
    two = tmp_path / "two.csv"
    two.write_text("\n".join(staircase_csv.read_text().splitlines()[:3]))
    res = runner.invoke(app, ["identify", "static", str(two), *STATIC_ARGS])
    assert one_error_line(res) == (f"error: recording 'two' (file '{two}'): 2 samples; finding constant-velocity "
                                   "segments needs at least 3")


def test_numbers_in_a_model_file_follow_one_rule_alone_or_in_a_list(tmp_path):
    """Was (round 9): a 400-digit integer for sigma0 was an "unexpected OverflowError"; "xi": ["0.5", "0.5"]
    ran (a string alone is refused); a null entry in "k" was reported as nan; an unknown top-level key of a
    law file (a misspelt "provenence") was ignored without a word (a machine file refused it)."""
    import json

    from frictionkit.models.files import ModelFile

    law = {"law": "Stribeck", "Fc": 1.0, "Fs": 1.5, "vs": 1e-3}
    gms = {"format": "frictionkit.model/1", "model": {"law": "GMS", "static": law, "k": [1e4, 1e5], "xi": [0.5, 0.5],
                                                       "C": 20.0}}
    assert ModelFile.from_dict(gms).model.M == 2
    p = tmp_path / "huge.json"
    p.write_text(json.dumps({"format": "frictionkit.model/1", "model": {"law": "Dahl", "Fc": 1.0, "sigma0": 7}})
                 .replace('"sigma0": 7', '"sigma0": ' + "9" * 400))
    with pytest.raises(DataError, match=rf"^model file '{p}': Dahl.sigma0 = 999999999999...\(400 characters\): "
                                        r"beyond the float range; must be finite$"):
        ModelFile.load(p)
    for key, value, want in (("xi", ["0.5", "0.5"], r"GMS.xi\[0\] = '0.5': must be a real number, not a string"),
                             ("k", [1e4, None], r"GMS.k\[1\] = None: must be a real number, not null \(None\)"),
                             ("k", [10 ** 400, 1.0], r"GMS.k = \[1000000000.*: an entry is beyond the float range")):
        doc = json.loads(json.dumps(gms))
        doc["model"][key] = value
        with pytest.raises(ParameterError, match=want):
            ModelFile.from_dict(doc)
    with pytest.raises(DataError, match=r"^law file: unknown key\(s\) \['provenence'\]; known: "):
        ModelFile.from_dict(dict(gms, provenence={"by": "me"}))


def test_a_machine_of_more_degrees_of_freedom_than_it_takes_is_refused_not_run_for_minutes():
    """Was (round 9): a machine file with 2,000 DOFs ran for minutes with no output (800 DOFs: > 300 s for 51
    samples). MAX_DOFS is the named bound."""
    from frictionkit.machines.machine import MAX_DOFS, Machine

    m = Machine("shaft")
    for i in range(MAX_DOFS):
        m.dof(f"d{i}", inertia=1.0)
    with pytest.raises(ParameterError, match=rf"^Machine.dof\('one more'\): machine 'shaft' already has {MAX_DOFS} "
                                             r"degrees of freedom, the most a machine takes"):
        m.dof("one more", inertia=1.0)
