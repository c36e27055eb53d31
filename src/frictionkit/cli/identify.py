"""``frictionkit identify ...``: static maps and rigid-body parameters from recorded files.

Thin wrappers: parse options, load with :mod:`frictionkit.data`, call
:func:`frictionkit.identify.fit_static_map` / :func:`~frictionkit.identify.fit_rigid_body`,
print a plain-text table and write JSON / PNG on request. Errors print one line on
stderr and exit with status 1.
"""

from __future__ import annotations

import functools
from pathlib import Path
from typing import Any, Callable, Optional

import typer

from . import app

identify_app = typer.Typer(
    name="identify",
    help="Identify friction models from recordings (CSV, .mat, HDF5, Parquet).",
    no_args_is_help=True,
    add_completion=False,
    pretty_exceptions_enable=False,
)
app.add_typer(identify_app, name="identify")


def _one_line_errors(fn: Callable[..., Any]) -> Callable[..., Any]:
    """Turn library and file errors into one line on stderr and exit status 1."""

    @functools.wraps(fn)
    def wrapper(*args: Any, **kwargs: Any) -> Any:
        from ..errors import FrictionKitError

        try:
            return fn(*args, **kwargs)
        except (FrictionKitError, OSError) as exc:
            msg = " ".join(str(exc).split())
            typer.echo(f"error: {msg}", err=True)
            raise typer.Exit(code=1) from None

    return wrapper


def _parse_where(items: list[str] | None) -> dict[str, str]:
    from ..errors import DataError

    out = {}
    for it in items or []:
        if "=" not in it:
            raise DataError(f"--where {it!r}: expected COLUMN=VALUE")
        k, v = it.split("=", 1)
        out[k.strip()] = v.strip()
    return out


def _save_plot(result, path: Path) -> None:
    import matplotlib

    matplotlib.use("Agg", force=False)
    import matplotlib.pyplot as plt

    ax = result.plot()
    ax.figure.tight_layout()
    ax.figure.savefig(path, dpi=120)
    plt.close(ax.figure)


@identify_app.command("rigid-body")
@_one_line_errors
def rigid_body(
    recording: Path = typer.Argument(..., help="Data file (.csv, .mat, .h5, .parquet)."),
    time: str = typer.Option(..., "--time", help="Time column [s]."),
    position: str = typer.Option(..., "--position", help="Position column [m]."),
    force: str = typer.Option(..., "--force", help="Force column (scaled by --force-scale to N)."),
    force_scale: float = typer.Option(1.0, "--force-scale", help="Factor to N, e.g. EMPS gtau 35.15065188248547 N/V."),
    position_scale: float = typer.Option(1.0, "--position-scale", help="Factor to m."),
    asymmetric: bool = typer.Option(False, "--asymmetric", help="Direction-dependent Fv, Fc (no offset)."),
    cutoff: float = typer.Option(100.0, "--cutoff", help="Butterworth cut-off of the position filter [Hz]."),
    decimation: int = typer.Option(10, "--decimate", help="Decimation factor."),
    skip: int = typer.Option(49, "--skip", help="Samples dropped at the start."),
    json_out: Optional[Path] = typer.Option(None, "--json", help="Write the result as JSON."),
    plot: Optional[Path] = typer.Option(None, "--plot", help="Write measured vs predicted force as PNG."),
) -> None:
    """Rigid-body IDIM-LS: F = M a + Fv v + Fc sgn(v) + offset (EMPS benchmark procedure)."""
    from ..data import load_recording
    from ..identify import fit_rigid_body

    rec = load_recording(recording, time=time, position=position, force=force,
                         scales={"force": force_scale, "position": position_scale})
    res = fit_rigid_body(rec, asymmetric=asymmetric, cutoff=cutoff, q=decimation, skip=skip)
    typer.echo(res.summary())
    typer.echo(f"condition number {res.diagnostics['condition_number']:.4g}")
    if json_out is not None:
        res.save_json(json_out, include_data=False)
    if plot is not None:
        _save_plot(res, plot)


@identify_app.command("static")
@_one_line_errors
def static(
    recording: Path = typer.Argument(..., help="Data file (.csv, .mat, .h5, .parquet)."),
    time: str = typer.Option(..., "--time", help="Time column [s]."),
    velocity: Optional[str] = typer.Option(None, "--velocity", help="Velocity column."),
    position: Optional[str] = typer.Option(None, "--position", help="Position column (velocity by differences)."),
    force: str = typer.Option(..., "--force", help="Force or torque column."),
    force_scale: float = typer.Option(1.0, "--force-scale", help="Factor to N (or N·m)."),
    velocity_scale: float = typer.Option(1.0, "--velocity-scale", help="Factor to m/s (or rad/s)."),
    position_scale: float = typer.Option(1.0, "--position-scale", help="Factor to m (or rad)."),
    force_unit: str = typer.Option("N", "--force-unit", help="Unit label after scaling (e.g. N·m)."),
    velocity_unit: str = typer.Option("m/s", "--velocity-unit", help="Unit label after scaling (e.g. rad/s)."),
    group: Optional[list[str]] = typer.Option(None, "--group", help="Column(s) naming steady-state records; each record is averaged."),
    where: Optional[list[str]] = typer.Option(None, "--where", help="Keep rows with COLUMN=VALUE (repeatable)."),
    trim: Optional[float] = typer.Option(None, "--trim", help="Fraction dropped at both ends of each segment."),
    direction: str = typer.Option("both", "--direction", help="both, positive or negative."),
    model: str = typer.Option("auto", "--model", help="auto, coulomb_viscous, exponential or lorentzian."),
    delta: Optional[float] = typer.Option(None, "--delta", help="Fix the Stribeck exponent."),
    loss: str = typer.Option("linear", "--loss", help="linear, soft_l1, huber, cauchy, arctan."),
    criterion: str = typer.Option("aic", "--criterion", help="aic or bic."),
    json_out: Optional[Path] = typer.Option(None, "--json", help="Write the result as JSON."),
    plot: Optional[Path] = typer.Option(None, "--plot", help="Write the fitted map over the points as PNG."),
) -> None:
    """Static friction map (Coulomb, viscous, Stribeck) per direction from steady-state data."""
    from ..data import load_groups, load_recording, steady_state_points
    from ..errors import DataError
    from ..identify import fit_static_map

    if velocity is None and position is None:
        raise DataError("give --velocity or --position")
    kw = dict(time=time, velocity=velocity, position=position, force=force,
              scales={"force": force_scale, "velocity": velocity_scale, "position": position_scale},
              units={"F": force_unit, "v": velocity_unit}, where=_parse_where(where))
    if group:
        recs = load_groups(recording, group=group, **kw)
        pts = steady_state_points(recs, trim=trim)
    else:
        rec = load_recording(recording, **kw)
        pts = steady_state_points(rec, trim=trim)
    res = fit_static_map(pts, model=model, direction=direction, delta=delta, loss=loss, criterion=criterion)
    typer.echo(f"{len(pts)} steady-state point(s)")
    typer.echo(res.summary())
    if json_out is not None:
        res.save_json(json_out)
    if plot is not None:
        _save_plot(res, plot)
