"""``frictionkit simulate MODEL.json --force|--position|--velocity FILE``: run a friction model on a signal.

Thin: the model file is read by :meth:`frictionkit.models.files.ModelFile.load` (a model
file, an identification result or a bare law JSON), the signal by
:func:`frictionkit.data.load_recording`, the run is :func:`frictionkit.simulate`, the
traces are written by :func:`frictionkit.simulate.traces.write_traces` and the plot by
the result's ``.plot()``.
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
\b
The signal file (.csv, .parquet, .mat, .h5) holds a time column [s] (default: the first
column) and the signal (default: the second column) in SI units, or scaled to SI by --scale."""


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
    model: Path = typer.Argument(..., help="Model file: 'frictionkit.model/1' JSON (fk.save_model), an "
                                 "identification result (identify ... --json) or a law's JSON form."),
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
    out: Optional[Path] = typer.Option(None, "--out", help="Write the traces (t, x, v, F, states) as .csv or "
                                       ".parquet."),
    plot: Optional[Path] = typer.Option(None, "--plot", help="Write hysteresis and force over time as a plot "
                                        "(format from the extension: .png, .pdf, .svg ...)."),
    json_out: Optional[str] = typer.Option(None, "--json", help="Write a JSON summary to a file (- for stdout, "
                                           "instead of the text)."),
) -> None:
    """Simulate a dynamic friction model (LuGre, Dahl, GMS) driven by a force, position or velocity signal."""
    from ..errors import ParameterError

    kind, signal = _signal(force, position, velocity)
    factor = chk.scale(scale, "--scale")
    rows = chk.where_items(where)
    chk.choice(velocity_integration, "--velocity-integration", ("trapezoidal", "held"))
    if kind == "force":
        if mass is None:
            raise ParameterError("--force needs --mass KG (the moving mass the force accelerates)")
        mass = chk.positive(mass, "--mass")
    elif mass is not None:
        raise ParameterError(f"--mass is for a force-driven run; a --{kind} run has no plant")
    if out is not None:
        from ..simulate.traces import TRACE_FORMATS

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
    from ..models.files import ModelFile

    mf = ModelFile.load(model)
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
        from ..simulate.traces import write_traces

        write_traces(res, out, units=mf.units)
    if plot is not None:
        _save_plot(res, plot)

    def peak(a: np.ndarray) -> float | None:
        a = a[np.isfinite(a)]
        return float(np.max(np.abs(a))) if a.size else None

    u = mf.units
    doc = {"model": str(model), "law": law_entry(mf.model).name, "drive": kind, "signal": str(signal),
           "columns": {"time": tcol, "signal": scol}, "samples": rec.n, "dt": rec.dt,
           "status": res.status, "message": res.message, "success": res.success,
           "peak_F": peak(res.F), "peak_v": peak(res.v), "x_range": [float(np.nanmin(res.x)), float(np.nanmax(res.x))],
           "units": dict(u), "outputs": {k: str(p) for k, p in (("traces", out), ("plot", plot)) if p is not None}}
    text = (f"{doc['law']} {kind}-driven, {rec.n} samples at dt = {rec.dt:.6g} s: {res.message}\n"
            f"peak |F| {doc['peak_F']:.6g} {u['F']}, peak |v| {doc['peak_v']:.6g} {u['v']}, "
            f"x in [{doc['x_range'][0]:.6g}, {doc['x_range'][1]:.6g}] {u['x']}")
    text += "".join(f"\nwrote {p}" for p in doc["outputs"].values())
    chk.emit(doc, json_out, text)
    if not res.success:
        raise typer.Exit(code=1)


def _save_plot(res, path: Path) -> None:
    """The result's two-panel plot (hysteresis, force over time), written atomically."""
    import matplotlib

    matplotlib.use("Agg", force=False)
    import matplotlib.pyplot as plt

    axes = res.plot()
    fig = (axes[0] if hasattr(axes, "__len__") else axes).figure
    try:
        chk.save_figure(fig, path)
    finally:
        plt.close(fig)
