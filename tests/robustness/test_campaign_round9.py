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
