"""What the CLI prints where a README walk tripped (walk3): ``reproduce zhang2023``'s run status, ``compensate`` on a
mistyped machine file.

Before: a quick run of status 1 (WSIM's identifiability flags, ~4,000 characters in the JSON's
"message" and in the report's section) printed nothing of it, and a finding that a failed fit left
unevaluated (``holds`` None, shown "NOT EVALUATED" by ``summary()``) was printed "=no". The
reproduction is a stand-in here: this is about the text.
"""

from __future__ import annotations

from types import SimpleNamespace

import pytest
from typer.testing import CliRunner

import frictionkit.cli.compensate  # noqa: F401  (registers the verbs)
import frictionkit.cli.reproduce  # noqa: F401
from frictionkit.cli import app

#: A WSIM-style status message longer than the report's clip (400 characters), with a "[...]" that rich
#: would read as markup.
MESSAGE = "WSIM: table3: screw: positive: vs not identifiable [N·m]; " + "; ".join(
    f"item {i}: C is not determined by this record" for i in range(40))


def _plot():
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    return [plt.subplots()[1]]


@pytest.fixture
def stand_in(monkeypatch):
    import frictionkit.reproduce.zhang2023 as zr

    summary = {"table7": [], "table8": [], "hysteresis_rms_force_N": {}, "crawling": [], "status": 1,
               "message": MESSAGE}
    monkeypatch.setattr(zr, "run", lambda **kw: SimpleNamespace(to_dict=lambda: dict(summary), plot=_plot))
    monkeypatch.setattr(zr, "findings", lambda s: {"t7_diff0_wsim_better": {"holds": True},
                                                    "t7_diff6_wsim_better": {"holds": False},
                                                    "fig16_reciprocating_m7_better": {"holds": None}})


def test_zhang2023_prints_its_status_and_unevaluated_findings(stand_in, tmp_path):
    res = CliRunner().invoke(app, ["reproduce", "zhang2023", "--quick", "--json", str(tmp_path / "z.json"),
                                   "--no-plot"])
    assert res.exit_code == 0, res.output
    text = " ".join(res.stdout.split())  # rich wraps at the terminal width
    assert "t7_diff0_wsim_better=yes" in text and "t7_diff6_wsim_better=no" in text
    assert "fig16_reciprocating_m7_better=n/a (not evaluated)" in text
    assert "status 1: WSIM: table3: screw: positive: vs not identifiable [N·m]" in text
    assert "more characters: the JSON's \"message\"" in text   # clipped, and says where the rest is
    assert "item 39" not in text


@pytest.mark.parametrize("name, why", [("emps.jsn", "not found"), ("runs/emps.json", "not found"),
                                       (".", "a folder")])
def test_compensate_names_a_missing_machine_file_as_a_file(name, why, tmp_path, monkeypatch):
    """``compensate emps.jsn`` (a mistyped machine file) said "must be one of ballscrew, emps, sdss"."""
    monkeypatch.chdir(tmp_path)
    res = CliRunner().invoke(app, ["compensate", name])
    assert res.exit_code == 2
    assert f"PRESET '{name}': not a preset (ballscrew, emps, sdss), and as a machine model file: {why}" \
        in " ".join(res.output.split())


def test_compensate_points_to_the_readme_section_that_exists():
    """The help and the no-test error named a README section 'Compensation' that does not exist."""
    from pathlib import Path

    readme = (Path(__file__).parents[2] / "README.md").read_text(encoding="utf-8")
    assert "## Command line" in readme and "**Compensate**" in readme
    res = CliRunner().invoke(app, ["compensate", "--help"])
    assert 'README "Command line", "Compensate"' in res.output


def test_reproduce_lines_are_not_wrapped_in_a_log(stand_in, tmp_path):
    """Redirected to a file, rich wrapped every line at 80 columns (the status line above over several)."""
    res = CliRunner().invoke(app, ["reproduce", "zhang2023", "--quick", "--json", str(tmp_path / "z.json"),
                                   "--no-plot"])
    line = next(x for x in res.stdout.splitlines() if x.startswith("status 1:"))
    assert line.endswith("more characters: the JSON's \"message\")"), line
    assert any(x.startswith("findings: ") and x.endswith("=n/a (not evaluated)") for x in res.stdout.splitlines())


def test_sdss_prints_an_axis_status(monkeypatch, tmp_path):
    """An sdss axis of status != 0 said so only in the JSON and the report."""
    import frictionkit.reproduce.sdss as sdss_rep

    axis = {"identified": {}, "truth": {}, "status": 1, "message": "sigma1 [N·m·s/rad] not identifiable"}
    summary = {"axes": {"azimuth": axis, "rotator": {"identified": {}, "truth": {}}},
               "sidereal_tracking_rms_arcsec": {"no_compensation": 1.0, "lugre_feedforward": 0.5}}
    monkeypatch.setattr(sdss_rep, "run", lambda **kw: SimpleNamespace(to_dict=lambda: dict(summary)))
    res = CliRunner().invoke(app, ["reproduce", "sdss", "--quick", "--json", str(tmp_path / "s.json"), "--no-plot"])
    assert res.exit_code == 0, res.output
    assert "azimuth: status 1: sigma1 [N·m·s/rad] not identifiable" in res.stdout.splitlines()
    assert "rotator: status" not in res.stdout


def test_sdss_prints_the_runs_status(monkeypatch, tmp_path):
    """The run's top-level status (worst of its parts, e.g. the rotator's static maps) was only in the JSON."""
    import frictionkit.reproduce.sdss as sdss_rep

    summary = {"axes": {"rotator": {"identified": {}, "truth": {}}},
               "sidereal_tracking_rms_arcsec": {"no_compensation": 1.0, "lugre_feedforward": 0.5},
               "status": 1, "message": "rotator static map (positive): vs not identifiable"}
    monkeypatch.setattr(sdss_rep, "run", lambda **kw: SimpleNamespace(to_dict=lambda: dict(summary)))
    res = CliRunner().invoke(app, ["reproduce", "sdss", "--quick", "--json", str(tmp_path / "s.json"), "--no-plot"])
    assert res.exit_code == 0, res.output
    assert "status 1: rotator static map (positive): vs not identifiable" in res.stdout.splitlines()


def test_the_progress_bar_ends_on_done(stand_in, tmp_path):
    """The stage bar's last frame read "plot" (the last stage) after the run had ended."""
    res = CliRunner().invoke(app, ["reproduce", "zhang2023", "--quick", "--json", str(tmp_path / "z.json")])
    assert res.exit_code == 0, res.output
    try:
        err = res.stderr
    except ValueError:  # older click mixes the streams
        err = res.output
    assert "zhang2023: done" in err.strip().splitlines()[-1]
