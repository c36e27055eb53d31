"""``frictionkit simulate MODEL.json --force|--position|--velocity FILE``: run a friction model on a signal;
``frictionkit simulate MACHINE.json --input NAME=FILE:COLUMN ...``: run a machine file.

Thin: the model file is read by :meth:`frictionkit.models.files.ModelFile.load` (a model
file, an identification result or a bare law JSON), the signal by
:func:`frictionkit.data.load_recording`, the run is :func:`frictionkit.simulate`, the
traces are written by :func:`frictionkit.simulation.traces.write_traces` and the plot by
the result's ``.plot()``. A machine file (``fk.save_model(machine, ...)``) runs with
:func:`frictionkit.simulate_machine` on the input arrays given by ``--input``; the input files
are read by :func:`frictionkit.data.read_table`.
"""

from __future__ import annotations

from pathlib import Path
from typing import Optional

import typer

from . import _common as chk
from . import app

_EPILOG = """\b
Examples:
  frictionkit simulate lugre.json --position motion.csv --out traces.csv --plot loop.png
  frictionkit simulate fit.json --force u.csv --mass 1.0 --json -
  frictionkit simulate lugre1.json --velocity start_stop_200rpm.csv --where drive_id=1 --time t_s
      --column motor_velocity_rad_per_s --velocity-integration held --out sim1.csv
  frictionkit simulate emps.json --input qg=ref.csv:qg --out traces.csv --plot run.png
  frictionkit simulate axis.json --input r=ref.csv:r --input ff=0 --substeps 20 --json -
\b
The signal file (.csv, .parquet, .mat, .h5) holds a time column [s] (default: the first
column) and the signal (default: the second column) in SI units, or scaled to SI by --scale.
\b
A machine file reads the input arrays its file lists under "inputs" (references,
feed-forwards, open-loop commands, prescribed motions), each --input NAME=FILE:COLUMN (SI,
time in the --time column, default the first; all on one uniform grid, which gives dt) or
NAME=VALUE (a constant). Without input files give --dt and --duration."""


def _signal(force: Optional[Path], position: Optional[Path], velocity: Optional[Path]) -> tuple[str, Path]:
    from ..errors import ParameterError

    given = [(k, p) for k, p in (("force", force), ("position", position), ("velocity", velocity)) if p is not None]
    if len(given) != 1:
        raise ParameterError(f"give exactly one of --force, --position, --velocity (got "
                             f"{', '.join('--' + k for k, _ in given) or 'none'})")
    return given[0]


def _columns(path: Path, time: Optional[str], column: Optional[str]) -> tuple[str, str]:
    """``--time`` and ``--column``, defaulting to the file's first and second columns."""
    if time is not None and column is not None:
        return time, column
    from ..data import read_table
    from ..errors import DataError

    names = list(read_table(path))
    if len(names) < 2:
        raise DataError(f"'{path}': {len(names)} column(s) ({', '.join(names)}); expected a time column and a "
                        "signal column (or name them with --time and --column)")
    return time or names[0], column or next(n for n in names if n != (time or names[0]))


@app.command("simulate", epilog=_EPILOG)
def simulate(
    model: Path = typer.Argument(..., help="Model file: 'frictionkit.model/1' JSON (fk.save_model) of a law or "
                                 "a machine, an identification result (identify ... --json) or a law's JSON form."),
    force: Optional[Path] = typer.Option(None, "--force", help="Force-driven run on a mass: file with the applied "
                                         "force [N]."),
    position: Optional[Path] = typer.Option(None, "--position", help="Motion-driven run: file with the position [m]."),
    velocity: Optional[Path] = typer.Option(None, "--velocity", help="Motion-driven run: file with the velocity [m/s]."),
    time: Optional[str] = typer.Option(None, "--time", help="Time column [s] (default: the first column)."),
    column: Optional[str] = typer.Option(None, "--column", help="Signal column (default: the second column)."),
    where: Optional[list[str]] = typer.Option(None, "--where", help="Keep rows with COLUMN=VALUE (repeatable), e.g. "
                                              "drive_id=1 in a file of several drives."),
    scale: float = typer.Option(1.0, "--scale", help="Factor from the file's signal unit to SI (e.g. 1e-3 for mm)."),
    mass: Optional[float] = typer.Option(None, "--mass", help="Moving mass [kg] (inertia [kg·m²] for a rotary axis) "
                                         "of a force-driven run."),
    velocity_integration: str = typer.Option("trapezoidal", "--velocity-integration",
                                             help="How --velocity becomes a position: 'trapezoidal' (samples at "
                                                  "the instant) or 'held' (mean over the interval, drive logs)."),
    out: Optional[Path] = typer.Option(None, "--out", help="Write the traces (t, x, v, friction, states) as .csv or "
                                       ".parquet."),
    plot: Optional[Path] = typer.Option(None, "--plot", help="Write hysteresis and force over time as a plot "
                                        "(format from the extension: .png, .pdf, .svg ...)."),
    json_out: Optional[str] = typer.Option(None, "--json", help="Write a JSON summary to a file (- for stdout, "
                                           "instead of the text)."),
    inputs: Optional[list[str]] = typer.Option(None, "--input", help="Machine file: an input array as "
                                               "NAME=FILE:COLUMN or NAME=VALUE (constant); repeatable."),
    dt: Optional[float] = typer.Option(None, "--dt", help="Machine file: sample period [s] (default: from the "
                                       "input files' time column)."),
    duration: Optional[float] = typer.Option(None, "--duration", help="Machine file without input files: run "
                                             "length [s]."),
    substeps: int = typer.Option(10, "--substeps", help="Machine file: plant sub-steps per sample."),
    seed: int = typer.Option(0, "--seed", help="Machine file: sensor-noise seed."),
) -> None:
    """Simulate a dynamic friction model (LuGre, Dahl, GMS) driven by a force, position or velocity signal,
    or a machine file (with its controller) driven by its input arrays."""
    from ..errors import ParameterError
    from ..models.files import ModelFile

    mf = ModelFile.load(model, kind=None)
    if mf.kind == "machine":
        law_only = {"--force": force, "--position": position, "--velocity": velocity, "--column": column,
                    "--where": where, "--mass": mass, "--scale": None if scale == 1.0 else scale,
                    "--velocity-integration": None if velocity_integration == "trapezoidal" else velocity_integration}
        given = [k for k, v in law_only.items() if v]
        if given:
            need = ", ".join(mf.model.input_names()) or "none"
            raise ParameterError(f"{', '.join(given)}: for a friction-law file; machine '{model}' reads its inputs "
                                 f"from --input NAME=FILE:COLUMN (it needs: {need})")
        return _run_machine(model, mf, inputs or [], time, dt, duration, substeps, seed, out, plot, json_out)
    law_only = {"--input": inputs, "--dt": dt, "--duration": duration}
    given = [k for k, v in law_only.items() if v]
    given += [k for k, v in (("--substeps", substeps != 10), ("--seed", seed != 0)) if v]
    if given:
        raise ParameterError(f"{', '.join(given)}: for a machine file; '{model}' is a friction law "
                             "(give --force, --position or --velocity)")

    kind, signal = _signal(force, position, velocity)
    factor = chk.scale(scale, "--scale")
    rows = chk.where_items(where)
    chk.choice(velocity_integration, "--velocity-integration", ("trapezoidal", "held"))
    if kind == "force":
        if mass is None:
            raise ParameterError("--force needs --mass KG (the moving mass the force accelerates)")
        mass = chk.positive(mass, "--mass", sized=True)
    elif mass is not None:
        raise ParameterError(f"--mass is for a force-driven run; a --{kind} run has no plant")
    if out is not None:
        from ..simulation.traces import TRACE_FORMATS

        if out.suffix.lower() not in TRACE_FORMATS:
            raise ParameterError(f"--out '{out}': unknown suffix {out.suffix!r}; use one of {', '.join(TRACE_FORMATS)}")
    chk.outputs([model, signal], files={"--out": out, **({"--json": Path(json_out)} if json_out not in (None, "-")
                                                          else {})}, plots={"--plot": plot})

    import warnings

    import numpy as np

    from ..data import load_recording
    from ..data.recording import IrregularSamplingWarning
    from ..errors import DataError
    from ..models.base import kernel_family, law_entry

    if kernel_family(mf.model) == "static":
        raise ParameterError(f"model '{model}' is a static map ({law_entry(mf.model).name}): it has no state to "
                             "simulate; its force is the steady state F(v) (see 'frictionkit export --format csv')")
    tcol, scol = _columns(signal, time, column)
    role = {"force": "force", "position": "position", "velocity": "velocity"}[kind]
    with warnings.catch_warnings():  # irregular sampling is an error here, not a warning
        warnings.simplefilter("ignore", IrregularSamplingWarning)
        rec = load_recording(signal, time=tcol, **{role: scol}, scales={role: factor}, where=rows)
    if not rec.is_regular:
        raise DataError(f"'{signal}': irregular sampling (time column {tcol!r}); simulate needs a uniform step "
                        "(resample the log first, frictionkit.data.Recording.resample)")
    data = {"force": rec.F, "position": rec.x, "velocity": rec.v}[kind]

    import frictionkit as fk
    from rich.console import Console

    kw = {kind: data}
    if kind == "force":
        kw["plant"] = fk.Mass(mass)
    else:
        kw["velocity_integration"] = velocity_integration
    with Console(stderr=True).status(f"simulating {rec.n} samples ({law_entry(mf.model).name}; the first run "
                                     "compiles the kernels)"):
        res = fk.simulate(mf.model, dt=rec.dt, **kw)

    if out is not None:
        from ..simulation.traces import write_traces

        write_traces(res, out, units=mf.units)
    if plot is not None:
        _save_plot(res, plot, units=mf.units)  # a rotary law's plot in rad and N·m (read µm and N)

    def peak(a: np.ndarray) -> float | None:
        a = a[np.isfinite(a)]
        return float(np.max(np.abs(a))) if a.size else None

    u = mf.units
    from ..simulation.traces import RUN_FORMAT

    doc = {"format": RUN_FORMAT, "model": str(model), "law": law_entry(mf.model).name, "drive": kind, "signal": str(signal),
           "columns": {"time": tcol, "signal": scol}, "samples": rec.n, "dt": rec.dt,
           "status": res.status, "message": res.message, "success": res.success,
           "peak_friction": peak(res.friction), "peak_v": peak(res.v), "x_range": [float(np.nanmin(res.x)), float(np.nanmax(res.x))],
           "units": dict(u), "outputs": {k: str(p) for k, p in (("traces", out), ("plot", plot)) if p is not None}}
    text = (f"{doc['law']} {kind}-driven, {rec.n} samples at dt = {rec.dt:.6g} s: {res.message}\n"
            f"peak |friction| {doc['peak_friction']:.6g} {u['F']}, peak |v| {doc['peak_v']:.6g} {u['v']}, "
            f"x in [{doc['x_range'][0]:.6g}, {doc['x_range'][1]:.6g}] {u['x']}")
    text += "".join(f"\nwrote {p}" for p in doc["outputs"].values())
    chk.emit(doc, json_out, text)
    if not res.success:
        raise typer.Exit(code=1)


def _input_spec(spec: str):
    """``NAME=FILE:COLUMN`` -> ``(name, path, column)``; ``NAME=VALUE`` -> ``(name, None, value)``."""
    from ..errors import ParameterError

    name, eq, rest = spec.partition("=")
    if not eq or not name or not rest:
        raise ParameterError(f"--input {spec!r}: expected NAME=FILE:COLUMN or NAME=VALUE")
    try:
        value = float(rest)
    except ValueError:
        pass
    else:
        return name, None, chk.magnitude(value, f"--input {name}")  # an input file's samples have the bound too
    path, colon, col = rest.rpartition(":")
    if not colon or not path or not col:
        raise ParameterError(f"--input {spec!r}: expected NAME=FILE:COLUMN (the column of the input) or NAME=VALUE")
    return name, Path(path), col


#: Largest machine run from --duration/--dt [samples]: its traces (several float64 per DOF,
#: site and signal) must fit in memory; 1e8 samples of one DOF are already ~4 GB.
MAX_SAMPLES = 1e8


def _machine_inputs(parsed: list, time: Optional[str], dt: Optional[float], duration: Optional[float]):
    """The input arrays, ``dt`` and sample count of a machine run from parsed ``--input`` specs."""
    import numpy as np

    from ..data import read_table
    from ..data.loaders import _grid_input
    from ..errors import ParameterError

    names = [p[0] for p in parsed]
    dup = sorted({n for n in names if names.count(n) > 1})
    if dup:
        raise ParameterError(f"--input: {', '.join(dup)} given twice")
    arrays, grid, consts, tables = {}, None, {}, {}
    for name, path, col in parsed:
        if path is None:
            consts[name] = col
            continue
        if path not in tables:
            tables[path] = read_table(path)
        tab = tables[path]
        # the loaders' column check: missing, repeated, true/false or non-numeric columns named
        arrays[name], grid = _grid_input(tab, Path(path), time or next(iter(tab)), col, f"--input {name}", grid,
                                         "the time (--time)")
    if grid is not None:
        if duration is not None:
            raise ParameterError("--duration: the input files give the run length; drop it or the files")
        if dt is not None and abs(chk.positive(dt, "--dt") - grid[1]) > 1e-6 * grid[1]:
            raise ParameterError(f"--dt {dt:g}: the input files are sampled at {grid[1]:.9g} s")
        n, h = grid[0], grid[1]
    else:
        if dt is None or duration is None:
            raise ParameterError("without input files give --dt and --duration (the run's sample period and length)")
        h = chk.positive(dt, "--dt")
        steps = chk.positive(duration, "--duration") / h
        if not steps <= MAX_SAMPLES:
            raise ParameterError(f"--duration {duration:g} / --dt {h:g} = {steps:.3g} samples; at most "
                                 f"{MAX_SAMPLES:.0e} (a longer run does not fit in memory: split it)")
        n = int(round(steps)) + 1
        if n < 2:
            raise ParameterError(f"--duration {duration:g}: shorter than one sample (--dt {h:g})")
    for name, value in consts.items():
        arrays[name] = np.full(n, value)
    return arrays, h, n


def _run_machine(model: Path, mf, specs: list[str], time, dt, duration, substeps: int, seed: int,
                 out: Optional[Path], plot: Optional[Path], json_out: Optional[str]) -> None:
    """``simulate MACHINE.json``: check the inputs against the machine, run, write, summarise."""
    import numpy as np
    from rich.console import Console

    import frictionkit as fk

    from ..errors import DataError, ParameterError

    chk.integer(substeps, "--substeps", lo=1, hi=10_000)
    chk.integer(seed, "--seed", lo=0)
    if out is not None:
        from ..simulation.traces import TRACE_FORMATS

        if out.suffix.lower() not in TRACE_FORMATS:
            raise ParameterError(f"--out '{out}': unknown suffix {out.suffix!r}; use one of {', '.join(TRACE_FORMATS)}")
    parsed = [_input_spec(s) for s in specs]
    chk.outputs([model, *(p for _, p, _ in parsed)],
                files={"--out": out, **({"--json": Path(json_out)} if json_out not in (None, "-") else {})},
                plots={"--plot": plot})
    machine = mf.model
    need = machine.input_names()
    missing = [k for k in need if k not in {p[0] for p in parsed}]
    unknown = [p[0] for p in parsed if p[0] not in need]
    if missing or unknown:
        parts = ([f"missing --input for {', '.join(missing)}"] if missing else []) + \
                ([f"{', '.join(unknown)} not read by the machine"] if unknown else [])
        raise DataError(f"machine '{model}' reads inputs {', '.join(need) or '(none)'}: {'; '.join(parts)}")
    arrays, h, n = _machine_inputs(parsed, time, dt, duration)
    with Console(stderr=True).status(f"simulating {machine.name!r}: {n} samples (the first run compiles the "
                                     "kernels)"):
        res = fk.simulate_machine(machine, dt=h, inputs=arrays, n_samples=n, substeps=substeps, seed=seed)
    if out is not None:
        from ..simulation.traces import write_traces

        write_traces(res, out)
    if plot is not None:
        _save_plot(res, plot)

    def peak(a) -> float | None:
        a = a[np.isfinite(a)]
        return float(np.max(np.abs(a))) if a.size else None

    from ..simulation.traces import RUN_FORMAT, site_units

    doc = {"format": RUN_FORMAT, "model": str(model), "kind": "machine", "machine": machine.name,
           "inputs": {name: (f"{p}:{c}" if p is not None else c) for name, p, c in parsed}, "samples": n, "dt": h,
           # the fast paths choose their own steps: "substeps": 0 read as a run without steps (README walk)
           "substeps": res.substeps or None, "kernel": res.path, "status": res.status, "message": res.message, "success": res.success,
           "dofs": {d.name: {"unit": d.unit, "final_x": float(res.q[-1, i]), "peak_v": peak(res.v[:, i])}
                    for i, d in enumerate(machine.dofs)},
           "sites": {s: {"peak_force": peak(res.site_forces[:, j]), "unit": u}
                     for j, (s, u) in enumerate(zip(res.site_names, site_units(res)))},
           "outputs": {k: str(p) for k, p in (("traces", out), ("plot", plot)) if p is not None}}
    text = res.summary() + "".join(f"\nwrote {p}" for p in doc["outputs"].values())
    chk.emit(doc, json_out, text)
    if not res.success:
        raise typer.Exit(code=1)


def _save_plot(res, path: Path, units=None) -> None:
    """The result's plot (a law's run: hysteresis and force over time, labelled in the model file's
    ``units``), written atomically."""
    import matplotlib

    matplotlib.use("Agg", force=False)
    import matplotlib.pyplot as plt

    from ..plotting.simulation import plot_result

    axes = res.plot() if units is None else plot_result(res, units=units)
    fig = (axes[0] if hasattr(axes, "__len__") else axes).figure
    try:
        chk.save_figure(fig, path)
    finally:
        plt.close(fig)
