"""``frictionkit compensate PRESET|MACHINE.json``: friction compensators on a machine, the error table.

Thin: the runs and the errors are :func:`frictionkit.compensate.compensate`, the plot the
result's ``.plot()``, the model file is read by :class:`frictionkit.models.files.ModelFile`.
"""

from __future__ import annotations

from pathlib import Path
from typing import Optional

import typer

from . import _common as chk
from . import app

_EPILOG = """\b
Examples:
  frictionkit compensate ballscrew --quick
  frictionkit compensate emps --model fit.json --compensator none --compensator model --json -
  frictionkit compensate ballscrew --compensator none --compensator sinc --plot errors.png
  frictionkit compensate sdss --model azimuth_lugre.json --quick
  frictionkit compensate emps.json --test test.toml --model fit.json
\b
Presets and their compensators:
  ballscrew  seed 001 stage, reversal test (25 mm, 1 s cosine): none, coulomb, sinc, sigmoid, model
  emps       EMPS axis, 0.1 m 0.2 Hz sine: none, coulomb (the true friction), model
  sdss       SDSS azimuth, sidereal tracking from rest: none, lugre (the true friction), model
  MACHINE.json  a machine model file with --test SPEC.toml (inputs, scored position, reference
                velocity, site; README "Command line", "Compensate"): none, the spec's, model
Errors are of the true position, r - x [µm; arcsec on sdss]: max and RMS after the first
10 % of the run (sdss: the whole run), and the max within -50 ... +100 ms of each velocity
reversal."""


@app.command("compensate", epilog=_EPILOG)
def compensate(
    preset: str = typer.Argument(..., help="Machine preset (ballscrew, emps, sdss) or a machine model file "
                                 "(with --test)."),
    model: Optional[Path] = typer.Option(None, "--model", help="Identified model file (identify ... --json, "
                                         "fk.save_model) for the 'model' compensator: its static map as "
                                         "feed-forward on the reference velocity, table side [N] at [m/s] "
                                         "(sdss: axis [N·m] at [rad/s])."),
    compensator: Optional[list[str]] = typer.Option(None, "--compensator", help="Compensator (repeatable); "
                                                    "default: every one the preset supports ('model' if --model)."),
    test: Optional[Path] = typer.Option(None, "--test", help="Compensation test of a machine file (.toml or "
                                        ".json): inputs, scored position, reference velocity, site, compensators."),
    quick: bool = typer.Option(False, "--quick", help="A short motion (ballscrew: the first reversal only; "
                               "emps, sdss: half the run)."),
    seed: int = typer.Option(0, "--seed", help="Sensor-noise seed (the same for every compensator)."),
    plot: Optional[Path] = typer.Option(None, "--plot", help="Write the error traces as a plot (format from the "
                                        "extension: .png, .pdf, .svg ...)."),
    json_out: Optional[str] = typer.Option(None, "--json", help="Write a JSON summary to a file (- for stdout, "
                                           "instead of the table)."),
) -> None:
    """Run a machine preset (or a machine file with its --test) with friction compensators and print the
    tracking-error table."""
    from ..compensate import COMPENSATORS, PRESETS

    is_file = preset not in PRESETS and Path(preset).is_file()
    if is_file and test is None:  # a model file without a test: the library says what it lacks
        from ..compensate import compensate as run

        run(preset)
    if test is not None and not is_file:
        from ..errors import ParameterError

        raise ParameterError(f"--test: for a machine model file; preset {preset!r} has its own test motion"
                             if preset in PRESETS else f"PRESET '{preset}': no such file")
    # a folder was "no such file" (round 10): the one input check names folders, broken links, unreadable files
    chk.input_files({"--test": test, "--model": model})
    if not is_file:
        if preset not in PRESETS and (Path(preset).suffix or "/" in preset or Path(preset).exists()):
            # a mistyped machine file was "PRESET 'emps.jsn': must be one of ballscrew, emps, sdss" (README walk)
            from .._io import missing_reason
            from ..errors import ParameterError

            why = "a folder" if Path(preset).is_dir() else missing_reason(preset)
            raise ParameterError(f"PRESET '{preset}': not a preset ({', '.join(PRESETS)}), and as a machine "
                                 f"model file: {why}")
        chk.choice(preset, "PRESET", PRESETS)
        for c in compensator or []:
            chk.choice(c, "--compensator", COMPENSATORS[preset])
    twice = sorted({c for c in compensator or [] if compensator.count(c) > 1})
    if twice:  # ran each twice, one table row per run (round 10); the study refuses it too
        from ..errors import ParameterError

        raise ParameterError(f"--compensator {', '.join(twice)} given twice; each compensator runs once")
    chk.integer(seed, "--seed", lo=0)
    chk.outputs([model, test, *([Path(preset)] if is_file else []), *_spec_files(test)], plots={"--plot": plot},
                files={"--json": Path(json_out)} if json_out not in (None, "-") else {})

    from rich.console import Console

    from ..compensate import compensate as run

    err = Console(stderr=True)
    with err.status(f"{preset}: starting (the first run compiles the kernels)") as status:
        res = run(preset, compensator or None, model=model, test=test, quick=quick, seed=seed,
                  progress=lambda name: status.update(f"{preset}: running compensator '{name}'"))
    if plot is not None:
        chk.save_plot(res, plot)
    doc = res.to_dict()
    doc["outputs"] = {"plot": str(plot)} if plot is not None else {}
    if json_out == "-":
        chk.emit(doc, json_out, "")
    else:
        _table(res)
        chk.emit(doc, json_out, "" if plot is None else f"wrote {plot}")
    if not res.success:
        raise typer.Exit(code=1)


def _spec_files(test: Optional[Path]) -> list[Path]:
    """The files a compensation test names (input FILE:COLUMN, compensator law files), relative to it.

    They are inputs of the run too: ``--json ref.csv`` overwrote the spec's input data (campaign
    round 5). Best effort: a spec that does not parse is left to the loader's error.
    """
    if test is None:
        return []
    import json
    import tomllib

    from .._io import read_input_bytes

    try:
        raw = read_input_bytes(test, f"compensation test '{test}'")  # not a FIFO's endless wait (round 11)
        doc = json.loads(raw) if test.suffix.lower() == ".json" else tomllib.loads(raw.decode("utf-8-sig"))
    except (OSError, ValueError):
        return []
    out = []
    for section in ("inputs", "compensators"):
        part = doc.get(section) if isinstance(doc, dict) else None
        for val in (part.values() if isinstance(part, dict) else ()):
            if isinstance(val, str):
                name = val.rsplit(":", 1)[0] if section == "inputs" and ":" in val else val
                out.append(test.parent / name)
    return out


def _table(res) -> None:
    from rich.console import Console
    from rich.markup import escape
    from rich.table import Table

    label, k = res.shown

    def um(x):
        return "-" if x is None else f"{x * k:.3f}"

    s = res.to_dict()
    title = f"{res.preset}: error r - x [{label}] over {s['duration_s']:.2f} s, {len(res.reversals)} reversal(s)"
    tab = Table(title=escape(title), min_width=64)  # escaped: rich reads "[arcsec]" as markup
    for col in ("compensator", "max", "RMS", "at reversals", "status"):
        tab.add_column(col, justify="left" if col in ("compensator", "status") else "right")
    for name, r in res.rows.items():
        tab.add_row(name, um(r["max_error"]), um(r["rms_error"]), um(r["reversal_error"]),
                    "ok" if r["ok"] else r["message"])
    Console(width=100).print(tab, markup=False)
