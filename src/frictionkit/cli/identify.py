"""``frictionkit identify ...``: static maps, rigid-body, dynamic (output-error) and GMS pre-sliding fits.

Thin wrappers: parse options, load with :mod:`frictionkit.data`, call
:func:`frictionkit.identify.fit_static_map` / :func:`~frictionkit.identify.fit_rigid_body` /
:func:`frictionkit.identify.output_error.fit_output_error` /
:func:`frictionkit.identify.presliding.fit_presliding`,
print a plain-text table and write JSON / plots on request. Options are checked
before any work (unit factors, masses, counts, output paths: writable folder, not an
input, a plot format matplotlib knows); errors go through the one error path of
:mod:`frictionkit.cli._errors` (one ``error:`` line, exit status 2 for bad input).
"""

from __future__ import annotations

from pathlib import Path
from typing import Optional

import typer

from . import app
from . import _common as chk

identify_app = typer.Typer(
    name="identify",
    help="Identify friction models from recordings (CSV, .mat, HDF5, Parquet).",
    no_args_is_help=True,
    add_completion=False,
    pretty_exceptions_enable=False,
    rich_markup_mode=None,
)
app.add_typer(identify_app, name="identify")


def _parse_where(items: list[str] | None) -> dict[str, str]:
    from ..errors import DataError

    out = {}
    for it in items or []:
        if "=" not in it:
            raise DataError(f"--where {it!r}: expected COLUMN=VALUE")
        k, v = it.split("=", 1)
        out[k.strip()] = v.strip()
    return out


def _write(res, json_out: Optional[Path], plot: Optional[Path], *, include_data: bool = True) -> None:
    """The result files, each written atomically (a failed write keeps the previous file)."""
    if json_out is not None:
        res.save_json(json_out, include_data=include_data)
    if plot is not None:
        chk.save_plot(res, plot)


@identify_app.command("rigid-body")
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
    plot: Optional[Path] = typer.Option(None, "--plot", help="Write measured vs predicted force as a plot "
                                        "(format from the extension: .png, .pdf, .svg ...)."),
) -> None:
    """Rigid-body IDIM-LS: F = M a + Fv v + Fc sgn(v) + offset (EMPS benchmark procedure)."""
    scales = {"force": chk.scale(force_scale, "--force-scale"), "position": chk.scale(position_scale, "--position-scale")}
    cutoff = chk.positive(cutoff, "--cutoff")
    decimation = chk.integer(decimation, "--decimate", lo=1)
    skip = chk.integer(skip, "--skip", lo=0)
    chk.outputs([recording], files={"--json": json_out}, plots={"--plot": plot})

    from ..data import load_recording
    from ..identify import fit_rigid_body

    rec = load_recording(recording, time=time, position=position, force=force, scales=scales)
    res = fit_rigid_body(rec, asymmetric=asymmetric, cutoff=cutoff, q=decimation, skip=skip)
    typer.echo(res.summary())
    typer.echo(f"condition number {res.diagnostics['condition_number']:.4g}")
    _write(res, json_out, plot, include_data=False)


@identify_app.command("static")
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
    plot: Optional[Path] = typer.Option(None, "--plot", help="Write the fitted map over the points as a plot "
                                        "(format from the extension: .png, .pdf, .svg ...)."),
) -> None:
    """Static friction map (Coulomb, viscous, Stribeck) per direction from steady-state data."""
    from ..errors import DataError

    if velocity is None and position is None:
        raise DataError("give --velocity or --position")
    scales = {"force": chk.scale(force_scale, "--force-scale"), "velocity": chk.scale(velocity_scale, "--velocity-scale"),
              "position": chk.scale(position_scale, "--position-scale")}
    trim = chk.optional(chk.fraction, trim, "--trim")
    delta = chk.optional(chk.positive, delta, "--delta")
    chk.choice(direction, "--direction", ("both", "positive", "negative"))
    chk.choice(criterion, "--criterion", ("aic", "bic"))
    chk.outputs([recording], files={"--json": json_out}, plots={"--plot": plot})

    from ..data import load_groups, load_recording, steady_state_points
    from ..identify import fit_static_map

    kw = dict(time=time, velocity=velocity, position=position, force=force, scales=scales,
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
    _write(res, json_out, plot)


def _floats_list(text: Optional[str], what: str) -> Optional[list[float]]:
    from ..errors import ParameterError

    if text is None:
        return None
    try:
        return [float(s) for s in text.replace(";", ",").split(",") if s.strip()]
    except ValueError:
        raise ParameterError(f"{what} = {text!r}: expected comma-separated numbers") from None


def _static_law(static_json: Optional[Path], Fc: Optional[float], Fs: Optional[float], vs: float,
                delta: float, sigma2: float):
    """Static map from a ``identify static`` JSON result or from --Fc/--Fs/--vs/--delta/--sigma2."""
    from ..models import Stribeck

    if static_json is not None:
        return chk.load_static_json(static_json)
    if Fc is None:
        return None
    return Stribeck(Fc=Fc, Fs=Fs if Fs is not None else Fc, vs=vs, delta=delta, sigma2=sigma2)


@identify_app.command("output-error")
def output_error(
    recording: Path = typer.Argument(..., help="Data file (.csv, .mat, .h5, .parquet)."),
    time: str = typer.Option(..., "--time", help="Time column [s]."),
    position: Optional[str] = typer.Option(None, "--position", help="Position column (compared with --compare x)."),
    velocity: Optional[str] = typer.Option(None, "--velocity", help="Velocity column (compared by default)."),
    force: str = typer.Option(..., "--force", help="Input force column."),
    force_scale: float = typer.Option(1.0, "--force-scale", help="Factor to N."),
    position_scale: float = typer.Option(1.0, "--position-scale", help="Factor to m."),
    velocity_scale: float = typer.Option(1.0, "--velocity-scale", help="Factor to m/s."),
    model: str = typer.Option("lugre", "--model", help="lugre or gms."),
    static_json: Optional[Path] = typer.Option(None, "--static-json", help="Static map: JSON of 'identify static'."),
    Fc: Optional[float] = typer.Option(None, "--Fc", help="Static map without --static-json: Coulomb level [N]."),
    Fs: Optional[float] = typer.Option(None, "--Fs", help="Breakaway level [N] (default Fc)."),
    vs: float = typer.Option(1e-3, "--vs", help="Stribeck velocity [m/s]."),
    delta: float = typer.Option(2.0, "--delta", help="Stribeck exponent."),
    sigma2: float = typer.Option(0.0, "--sigma2", help="Viscous coefficient [N·s/m]."),
    mass: float = typer.Option(..., "--mass", help="Moving mass [kg] (start value with --free m)."),
    sigma0: Optional[float] = typer.Option(None, "--sigma0", help="LuGre start sigma0 [N/m] (default: initial_guess_lugre on the position)."),
    sigma1: Optional[float] = typer.Option(None, "--sigma1", help="LuGre start sigma1 [N·s/m] (default: critical damping)."),
    k: Optional[str] = typer.Option(None, "--k", help="GMS start stiffnesses, comma separated [N/m]."),
    xi: Optional[str] = typer.Option(None, "--xi", help="GMS start weights, comma separated."),
    C: float = typer.Option(20.0, "--C", help="GMS attraction constant [N/s]."),
    free: str = typer.Option("", "--free", help="Comma-separated parameters to fit (default sigma0,sigma1 or k)."),
    compare: Optional[str] = typer.Option(None, "--compare", help="v or x (default: v if --velocity else x)."),
    starts: int = typer.Option(1, "--starts", help="Number of start points (screened in one batch; "
                               f"1 to {chk.MAX_OUTPUT_ERROR_STARTS:,})."),
    json_out: Optional[Path] = typer.Option(None, "--json", help="Write the result as JSON."),
    plot: Optional[Path] = typer.Option(None, "--plot", help="Write measured vs simulated output as a plot "
                                        "(format from the extension: .png, .pdf, .svg ...)."),
) -> None:
    """Output-error fit of LuGre or GMS parameters by simulation (seed 002 eq. 12)."""
    from ..errors import DataError, ParameterError

    if position is None and velocity is None:
        raise DataError("give --position or --velocity")
    scales = {"force": chk.scale(force_scale, "--force-scale"), "position": chk.scale(position_scale, "--position-scale"),
              "velocity": chk.scale(velocity_scale, "--velocity-scale")}
    mass = chk.positive(mass, "--mass")
    chk.choice(model, "--model", ("lugre", "gms"))
    if compare is not None:
        chk.choice(compare, "--compare", ("v", "x"))
    starts = chk.integer(starts, "--starts", lo=1, hi=chk.MAX_OUTPUT_ERROR_STARTS,
                         why="the screening simulates every start over the whole record, 1-2 ms each per 8,000 samples")
    C = chk.positive(C, "--C")
    chk.outputs([recording, static_json], files={"--json": json_out}, plots={"--plot": plot})

    from ..data import load_recording
    from ..identify.output_error import fit_output_error, initial_guess_lugre
    from ..models import GMS, LuGre

    compare = compare or ("v" if velocity is not None else "x")
    law = _static_law(static_json, Fc, Fs, vs, delta, sigma2)
    if law is None:
        raise ParameterError("give the static map: --static-json STATIC.json or --Fc (with --Fs, --vs, --sigma2)")
    rec = load_recording(recording, time=time, position=position, velocity=velocity, force=force, scales=scales)
    if model == "lugre":
        if sigma0 is None:
            if rec.x is None:
                raise DataError("--sigma0 is needed without --position (the initial guess uses the position)")
            g = initial_guess_lugre(rec, mass=mass, sigma2=float(law.static_rows()[:, 4].mean()))
            sigma0 = g["sigma0"]
            if sigma1 is None:
                sigma1 = g["sigma1"]
            typer.echo(f"initial guess: sigma0 {sigma0:.6g} N/m, sigma1 {sigma1:.6g} N·s/m ({g['branches']} branches)")
        mdl = LuGre(law, sigma0=sigma0, sigma1=sigma1 if sigma1 is not None else 0.0)
        names = tuple(s.strip() for s in free.split(",") if s.strip()) or ("sigma0", "sigma1")
    elif model == "gms":
        kk, xx = _floats_list(k, "--k"), _floats_list(xi, "--xi")
        if kk is None or xx is None:
            raise ParameterError("--model gms needs start values --k and --xi (e.g. from 'identify presliding')")
        mdl = GMS(law, k=kk, xi=xx, C=C)
        names = tuple(s.strip() for s in free.split(",") if s.strip()) or ("k",)
    else:
        raise ParameterError(f"--model {model!r}: must be lugre or gms")
    from rich.console import Console

    console = Console(stderr=True)
    with console.status("output-error fit: starting") as status:
        res = fit_output_error(
            rec, mdl, free=names, plant_mass=mass, compare=compare, starts=starts,
            progress=lambda nfev, nsim, cost: status.update(
                f"output-error fit: evaluation {nfev}, {nsim} simulations, cost {cost:.6g}"),
        )
    typer.echo(res.summary())
    typer.echo(f"{res.diagnostics['nfev']} evaluations, status {res.diagnostics['status']}: {res.message}")
    _write(res, json_out, plot, include_data=False)


@identify_app.command("presliding")
def presliding(
    recording: Path = typer.Argument(..., help="Data file (.csv, .mat, .h5, .parquet)."),
    time: str = typer.Option(..., "--time", help="Time column [s]."),
    position: str = typer.Option(..., "--position", help="Position column."),
    force: str = typer.Option(..., "--force", help="Friction force column."),
    force_scale: float = typer.Option(1.0, "--force-scale", help="Factor to N."),
    position_scale: float = typer.Option(1.0, "--position-scale", help="Factor to m."),
    elements: int = typer.Option(..., "--elements", help=f"Number M of GMS elements (1 to {chk.MAX_PRESLIDING_ELEMENTS}: "
                                 "the breakpoint search grows about as M^3)."),
    static_json: Optional[Path] = typer.Option(None, "--static-json", help="Static map: JSON of 'identify static'."),
    Fc: Optional[float] = typer.Option(None, "--Fc", help="Static map without --static-json: Coulomb level [N]."),
    Fs: Optional[float] = typer.Option(None, "--Fs", help="Breakaway level [N] (default Fc)."),
    vs: float = typer.Option(1e-3, "--vs", help="Stribeck velocity [m/s]."),
    delta: float = typer.Option(2.0, "--delta", help="Stribeck exponent."),
    sigma2: float = typer.Option(0.0, "--sigma2", help="Viscous coefficient [N·s/m]."),
    branch: str = typer.Option("auto", "--branch", help="auto, virgin or reversal."),
    C: Optional[float] = typer.Option(None, "--C", help="Fix the attraction constant [N/s]."),
    no_refine: bool = typer.Option(False, "--no-refine", help="Skip the simulation-error refinement."),
    json_out: Optional[Path] = typer.Option(None, "--json", help="Write the result as JSON."),
    plot: Optional[Path] = typer.Option(None, "--plot", help="Write measured vs simulated force as a plot "
                                        "(format from the extension: .png, .pdf, .svg ...)."),
) -> None:
    """GMS pre-sliding k_i, xi_i from a force-displacement branch (seed 000 eq. 19)."""
    elements = chk.integer(elements, "--elements", lo=1, hi=chk.MAX_PRESLIDING_ELEMENTS,
                           why="the breakpoint search grows about as M^3: 32 elements take about 30 s, "
                               "100 more than 20 min")
    scales = {"force": chk.scale(force_scale, "--force-scale"), "position": chk.scale(position_scale, "--position-scale")}
    chk.choice(branch, "--branch", ("auto", "virgin", "reversal"))
    C = chk.optional(chk.positive, C, "--C")
    chk.outputs([recording, static_json], files={"--json": json_out}, plots={"--plot": plot})

    from rich.console import Console

    from ..data import load_recording
    from ..identify.presliding import fit_presliding

    law = _static_law(static_json, Fc, Fs, vs, delta, sigma2)
    rec = load_recording(recording, time=time, position=position, force=force, scales=scales)
    with Console(stderr=True).status(f"pre-sliding fit: {elements} element(s)"
                                     + ("" if no_refine else ", then simulation-error refinement")):
        res = fit_presliding(rec, elements=elements, static=law, branch=branch, C=C, refine=not no_refine)
    typer.echo(res.summary())
    d = res.diagnostics
    typer.echo(f"total stiffness {d['total_stiffness']:.6g} N/m, breakpoints "
               + ", ".join(f"{b:.4g}" for b in d["breakpoints"]) + f" m, C {d['C']:.4g} N/s")
    _write(res, json_out, plot, include_data=False)
