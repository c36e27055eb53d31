"""One figure convention for every ``frictionkit reproduce`` verb: ``--plot FILE``, a PNG beside ``--json``
by default, ``--no-plot`` for none; the old bare ``--plot`` flag (zhu-fujimoto, zhang2023) still works,
with a deprecation warning.

Before: ``zhu-fujimoto`` and ``zhang2023`` had a ``--plot/--no-plot`` flag (``--plot fig.svg`` was "unexpected
extra argument") while ``sdss --plot PNG`` took a path and wrote no figure without it (and had no
``--no-plot``). The reproductions themselves are replaced by stand-ins here: this is about the options.
"""

from __future__ import annotations

import json
from types import SimpleNamespace

import pytest
from typer.testing import CliRunner

import frictionkit.cli.reproduce  # noqa: F401  (registers the command group)
from frictionkit.cli import app

VERBS = ("zhu-fujimoto", "sdss", "zhang2023")


def _figure():
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    return plt.subplots()


@pytest.fixture
def stand_ins(monkeypatch):
    """Each reproduction returns at once a summary with the keys its verb prints, and a one-line figure."""
    import frictionkit.plotting.ballscrew as ballscrew
    import frictionkit.reproduce.sdss as sdss_rep
    import frictionkit.reproduce.zhang2023 as zr
    import frictionkit.reproduce.zhu_fujimoto as zf_rep

    one = {"max_error_um": 1.0, "stop_ms": 1.0, "kind": "k"}
    zf = {"table3": {}, "ld": {}, "fig5": {}, "fig5b": {"motor_input_reverses_before_zero_ms": None,
                                                          "drive_force_reverses_before_zero_ms": None},
          "selector": {"laws": [], "mixed_max_error_um": 1.0, "best_fixed_max_error_um": 1.0},
          "table2_fast_non_reverse": {"original": one, "redesigned": one}}
    sd = {"axes": {}, "sidereal_tracking_rms_arcsec": {"no_compensation": 1.0, "lugre_feedforward": 0.5}}
    zh = {"table7": [], "table8": [], "hysteresis_rms_force_N": {}, "crawling": []}

    def result(summary, plot):
        return lambda **kw: SimpleNamespace(to_dict=lambda: dict(summary), plot=plot)

    monkeypatch.setattr(zf_rep, "run", result(zf, None))
    monkeypatch.setattr(ballscrew, "reproduction_figure", lambda r: _figure())
    monkeypatch.setattr(sdss_rep, "run", result(sd, _figure))
    monkeypatch.setattr(zr, "run", result(zh, lambda: [_figure()[1]]))
    monkeypatch.setattr(zr, "findings", lambda summary: {})


def _run(args):
    res = CliRunner().invoke(app, ["reproduce", *args])
    try:
        err = res.stderr
    except ValueError:  # older click mixes the streams
        err = res.output
    return res, err


@pytest.mark.parametrize("verb", VERBS)
def test_plot_takes_a_file_in_every_reproduction(stand_ins, tmp_path, verb):
    out = tmp_path / "r.json"
    res, err = _run([verb, "--quick", "--json", str(out), "--plot", str(tmp_path / "figs" / "fig.svg")])
    assert res.exit_code == 0, res.output
    assert (tmp_path / "figs" / "fig.svg").read_bytes().startswith(b"<?xml")
    assert not (tmp_path / "r.png").exists()
    assert json.loads(out.read_text())["plot"] == "figs/fig.svg"  # relative to the JSON's folder
    assert "deprecated" not in err


@pytest.mark.parametrize("verb", VERBS)
def test_the_figure_goes_beside_the_json_by_default_and_no_plot_writes_none(stand_ins, tmp_path, verb):
    out = tmp_path / "r.json"
    res, _ = _run([verb, "--quick", "--json", str(out)])
    assert res.exit_code == 0, res.output
    assert (tmp_path / "r.png").read_bytes()[:4] == b"\x89PNG" and json.loads(out.read_text())["plot"] == "r.png"
    (tmp_path / "r.png").unlink()
    res, _ = _run([verb, "--quick", "--no-plot", "--json", str(out)])
    assert res.exit_code == 0, res.output
    assert not (tmp_path / "r.png").exists() and "plot" not in json.loads(out.read_text())


@pytest.mark.parametrize("verb", ("zhu-fujimoto", "zhang2023"))
@pytest.mark.parametrize("where", ("last", "before another option"))
def test_the_old_plot_flag_still_works_with_a_deprecation_warning(stand_ins, tmp_path, verb, where):
    out = tmp_path / "r.json"
    args = [verb, "--json", str(out), "--plot"] if where == "last" else [verb, "--plot", "--quick", "--json", str(out)]
    res, err = _run(args)
    assert res.exit_code == 0, res.output
    assert (tmp_path / "r.png").exists()
    assert "warning: --plot without a file is deprecated" in err and "--plot FILE" in err


@pytest.mark.parametrize("args, message", [
    (["sdss", "--plot", "f.png", "--no-plot"], "--plot 'f.png' and --no-plot: give one"),
    (["zhang2023", "--robustness", "--plot", "f.png"], "--plot 'f.png' goes with a single run"),
])
def test_contradicting_plot_options_are_refused_before_the_run(stand_ins, tmp_path, monkeypatch, args, message):
    monkeypatch.chdir(tmp_path)
    res, err = _run([*args, "--json", "r.json"])
    assert res.exit_code == 2 and message in err and not (tmp_path / "r.json").exists()
