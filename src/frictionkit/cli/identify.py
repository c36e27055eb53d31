"""``frictionkit identify ...``: static maps, rigid-body, dynamic (output-error) and GMS pre-sliding fits.

Thin wrappers: parse options, load with :mod:`frictionkit.data`, call
:func:`frictionkit.identify.fit_static_map` / :func:`~frictionkit.identify.fit_rigid_body` /
:func:`frictionkit.identify.output_error.fit_output_error` (``--drive force``) /
:func:`frictionkit.identify.motion_error.fit_motion_error` (``--drive motion``) /
:func:`frictionkit.identify.presliding.fit_presliding` /
:func:`frictionkit.identify.reversal.fit_reversal` (``identify reversal``: compensator parameters),
print a plain-text table and write JSON / plots on request.

Every verb takes the same data options: ``--group COL`` (a file stacking several
records), ``--where COL=VALUE`` (keep some rows), the unit labels ``--rotary`` or
``--force-unit`` / ``--velocity-unit`` (into the JSON, tables and plot labels), and
``--validate FILE`` (the fitted model's error on another record, loaded with the same
column options, beside the training error). Options are checked
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
    help="Identify friction models from recordings (CSV, .mat, HDF5, Parquet, TDMS).",
    no_args_is_help=True,
    add_completion=False,
    pretty_exceptions_enable=False,
    rich_markup_mode=None,
)
app.add_typer(identify_app, name="identify")


def _parse_where(items: list[str] | None) -> dict[str, str]:
    return chk.where_items(items)


def _write(res, json_out: Optional[Path], plot: Optional[Path], *, include_data: bool = True) -> None:
    """The result files, each written atomically (a failed write keeps the previous file), each named
    on stdout like the other verbs' (identify printed nothing about them)."""
    if json_out is not None:
        res.save_json(json_out, include_data=include_data)
        typer.echo(f"wrote {json_out}")
    if plot is not None:
        chk.save_plot(res, plot)
        typer.echo(f"wrote {plot}")


def _load(path: Path, *, group: Optional[list[str]], where: Optional[list[str]], **kw):
    """One Recording, or ``{name: Recording}`` with ``--group`` (several records in one file)."""
    from ..data import load_groups, load_recording

    w = _parse_where(where)
    if group:
        return load_groups(path, group=group, where=w, **kw)
    return load_recording(path, where=w, **kw)


def _early(loader, path: Optional[Path]) -> None:
    """Load the ``--validate`` record before the fit (its columns, rows, --where): a wrong one
    fails in a second, not after the fit (issue 13 round 7). It is read again after the fit."""
    if path is not None:
        loader(path)


def _validation(res, path: Optional[Path], label: str, loader, how=None) -> object:
    """``res`` with the error on the validation record in its diagnostics; prints the comparison."""
    if path is None:
        return res
    from ..identify.validation import validate, with_validation

    rep = validate(res, loader(path), name=str(path), **(how(path) if how is not None else {}))
    unit = res.provenance.get("units", {})
    u = unit.get("F") if res.kind in ("static_map", "rigid_body", "presliding") or "static_rms" in rep else None
    u = u or unit.get(res.provenance.get("procedure", {}).get("compare", "F"), "")
    line = (f"validation on {path}: {label} RMS {rep['rms']:.6g} {u} ({rep['relative_error_percent']:.4g} %), "
            f"training {rep['training_rms']:.6g} {u} ({rep['training_relative_error_percent']:.4g} %)")
    if "static_rms" in rep:
        line += (f"; static map {rep['static_rms']:.6g} {u} on validation, "
                 f"{rep['training_static_rms']:.6g} {u} in training")
    typer.echo(line)
    return with_validation(res, rep)


_EX_RIGID_BODY = """\b
Examples:
  frictionkit identify rigid-body DATA_EMPS.csv --time t_s --position qm_m --force vir_V \\
      --force-scale 35.15065188248547 --json fit.json --plot fit.png
  frictionkit identify rigid-body DATA_EMPS.csv --time t_s --position qm_m --force vir_V \\
      --force-scale 35.15065188248547 --law stribeck --asymmetric --json stribeck.json
"""


@identify_app.command("rigid-body", epilog=_EX_RIGID_BODY)
def rigid_body(
    recording: Path = typer.Argument(..., help="Data file (.csv, .mat, .h5, .parquet, .tdms)."),
    time: str = typer.Option(..., "--time", help="Time column [s]."),
    position: str = typer.Option(..., "--position", help="Position column [m]."),
    force: str = typer.Option(..., "--force", help="Force column (scaled by --force-scale to N)."),
    force_scale: float = typer.Option(1.0, "--force-scale", help="Factor to N, e.g. EMPS gtau 35.15065188248547 N/V."),
    position_scale: float = typer.Option(1.0, "--position-scale", help="Factor to m."),
    asymmetric: bool = typer.Option(False, "--asymmetric", help="Direction-dependent friction (no offset)."),
    law: str = typer.Option("coulomb-viscous", "--law", help="Static friction map: coulomb-viscous (linear IDIM-LS), "
                            "stribeck or lorentzian (nonlinear, started from IDIM-LS)."),
    delta: Optional[float] = typer.Option(None, "--delta", help="--law stribeck: the fixed exponent (default 2)."),
    no_profile: bool = typer.Option(False, "--no-profile", help="--law stribeck/lorentzian: log-scale Wald interval "
                                    "of vs instead of its likelihood profile (faster)."),
    cutoff: float = typer.Option(100.0, "--cutoff", help="Butterworth cut-off of the position filter [Hz]."),
    decimation: int = typer.Option(10, "--decimate", help="Decimation factor."),
    skip: int = typer.Option(49, "--skip", help="Samples dropped at the start."),
    group: Optional[list[str]] = typer.Option(None, "--group", help="Column(s) naming records; all are fitted jointly."),
    where: Optional[list[str]] = typer.Option(None, "--where", help="Keep rows with COLUMN=VALUE (repeatable)."),
    rotary: bool = typer.Option(False, "--rotary", help="Rotary axis: label units N·m, rad, rad/s."),
    force_unit: Optional[str] = typer.Option(None, "--force-unit", help="Force unit label after scaling (default N)."),
    velocity_unit: Optional[str] = typer.Option(None, "--velocity-unit", help="Velocity unit label (default m/s)."),
    validate: Optional[Path] = typer.Option(None, "--validate", help="Report the error on this other record "
                                            "(same column options) beside the training error."),
    json_out: Optional[Path] = typer.Option(None, "--json", help="Write the result as JSON."),
    plot: Optional[Path] = typer.Option(None, "--plot", help="Write measured vs predicted force as a plot "
                                        "(format from the extension: .png, .pdf, .svg ...)."),
) -> None:
    """Rigid body by inverse dynamics: F = M a + friction(v) + offset (EMPS benchmark procedure).

    --law coulomb-viscous: IDIM-LS of F = M a + Fv v + Fc sgn(v) + offset. --law stribeck
    (or lorentzian): a Stribeck map (per direction with --asymmetric) fitted by nonlinear
    least squares on the same signals, with standard errors and intervals.
    """
    from ..errors import ParameterError

    law_name = chk.choice(law.replace("_", "-"), "--law", ("coulomb-viscous", "stribeck", "lorentzian")).replace("-", "_")
    delta = chk.optional(chk.positive, delta, "--delta", sized=True)
    if delta is not None and law_name != "stribeck":
        raise ParameterError(f"--delta applies to --law stribeck only (got --law {law})")
    if no_profile and law_name == "coulomb_viscous":
        raise ParameterError("--no-profile applies to --law stribeck or lorentzian only")
    scales = {"force": chk.scale(force_scale, "--force-scale"), "position": chk.scale(position_scale, "--position-scale")}
    cutoff = chk.positive(cutoff, "--cutoff", sized=True)
    decimation = chk.integer(decimation, "--decimate", lo=1)
    skip = chk.integer(skip, "--skip", lo=0)
    units = chk.units(rotary, force_unit, velocity_unit)
    chk.where_items(where)
    chk.outputs({"RECORDING": recording, "--validate": validate}, files={"--json": json_out}, plots={"--plot": plot})

    from ..identify import fit_rigid_body

    def loader(path):
        return _load(path, group=group, where=where, time=time, position=position, force=force, scales=scales,
                     units=units)

    _early(loader, validate)
    res = fit_rigid_body(loader(recording), law=law_name, asymmetric=asymmetric, delta=delta, cutoff=cutoff,
                         q=decimation, skip=skip, profile=not no_profile)
    typer.echo(res.summary())
    typer.echo(f"condition number {res.diagnostics['condition_number']:.4g}")
    if law_name != "coulomb_viscous":
        lin = res.diagnostics["linear"]
        typer.echo(f"relative force error {res.relative_error_percent:.4g} % against "
                   f"{lin['relative_error_percent']:.4g} % for the Coulomb-viscous start (IDIM-LS); "
                   f"{res.diagnostics['nfev']} evaluations, {'converged' if res.success else 'NOT converged'}")
        if res.flagged:
            typer.echo("not identifiable: " + (", ".join(res.diagnostics["identifiability"]["not_identifiable"])
                                               or "see warnings"))
    res = _validation(res, validate, "force", loader)
    _write(res, json_out, plot, include_data=True)


_EX_STATIC = """\b
Examples:
  frictionkit identify static steady_state_records.csv --time t_s \\
      --velocity motor_velocity_rad_per_s --force motor_torque_N_m --group source_file \\
      --where drive_id=1 --rotary --json static1.json
"""


@identify_app.command("static", epilog=_EX_STATIC)
def static(
    recording: Path = typer.Argument(..., help="Data file (.csv, .mat, .h5, .parquet, .tdms)."),
    time: str = typer.Option(..., "--time", help="Time column [s]."),
    velocity: Optional[str] = typer.Option(None, "--velocity", help="Velocity column."),
    position: Optional[str] = typer.Option(None, "--position", help="Position column (velocity by differences)."),
    force: str = typer.Option(..., "--force", help="Force or torque column."),
    force_scale: float = typer.Option(1.0, "--force-scale", help="Factor to N (or N·m)."),
    velocity_scale: float = typer.Option(1.0, "--velocity-scale", help="Factor to m/s (or rad/s)."),
    position_scale: float = typer.Option(1.0, "--position-scale", help="Factor to m (or rad)."),
    rotary: bool = typer.Option(False, "--rotary", help="Rotary axis: label units N·m, rad, rad/s."),
    force_unit: Optional[str] = typer.Option(None, "--force-unit", help="Unit label after scaling (default N; e.g. N·m)."),
    velocity_unit: Optional[str] = typer.Option(None, "--velocity-unit", help="Unit label after scaling (default m/s; e.g. rad/s)."),
    validate: Optional[Path] = typer.Option(None, "--validate", help="Report the error on this other file's "
                                            "steady-state points (same column options) beside the training error."),
    group: Optional[list[str]] = typer.Option(None, "--group", help="Column(s) naming steady-state records; each record is averaged."),
    where: Optional[list[str]] = typer.Option(None, "--where", help="Keep rows with COLUMN=VALUE (repeatable)."),
    trim: Optional[float] = typer.Option(None, "--trim", help="Fraction dropped at both ends of each segment."),
    min_speed: Optional[float] = typer.Option(None, "--min-speed", help="Plateaus slower than this are left out "
                                              "(after scaling; default 1 %% of the top speed; 0 keeps every one)."),
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
    if velocity is not None and position is not None:  # one was silently ignored (issue 13 round 5)
        raise DataError("give --velocity or --position, not both: the static map reads one speed column")
    scales = {"force": chk.scale(force_scale, "--force-scale"), "velocity": chk.scale(velocity_scale, "--velocity-scale"),
              "position": chk.scale(position_scale, "--position-scale")}
    trim = chk.optional(chk.fraction, trim, "--trim")
    min_speed = chk.optional(chk.nonnegative, min_speed, "--min-speed", sized=True)
    if delta is not None:
        from ..identify.static_map import MAX_FIXED_DELTA

        delta = chk.between(chk.positive(delta, "--delta", sized=True), "--delta", 0.0, MAX_FIXED_DELTA,
                            "a fixed Stribeck exponent; above the top (|v|/vs)**delta overflows within the fit's "
                            "vs range")
    chk.choice(direction, "--direction", ("both", "positive", "negative"))
    chk.choice(criterion, "--criterion", ("aic", "bic"))
    units = chk.units(rotary, force_unit, velocity_unit)
    chk.where_items(where)
    chk.outputs({"RECORDING": recording, "--validate": validate}, files={"--json": json_out}, plots={"--plot": plot})

    from ..data import steady_state_points
    from ..identify import fit_static_map

    def loader(path):
        return _load(path, group=group, where=where, time=time, velocity=velocity, position=position, force=force,
                     scales=scales, units=units)

    _early(loader, validate)
    pts = steady_state_points(loader(recording), trim=trim, **({} if min_speed is None else {"min_speed": min_speed}))
    res = fit_static_map(pts, model=model, direction=direction, delta=delta, loss=loss, criterion=criterion)
    typer.echo(f"{len(pts)} steady-state point(s)")
    typer.echo(res.summary())
    res = _validation(res, validate, "mean force", loader)
    _write(res, json_out, plot)


def _floats_list(text: Optional[str], what: str) -> Optional[list[float]]:
    from ..errors import ParameterError

    if text is None:
        return None
    try:
        return [float(s) for s in text.replace(";", ",").split(",") if s.strip()]
    except ValueError:
        raise ParameterError(f"{what} = {text!r}: expected comma-separated numbers") from None


def _static_law(static_json: Optional[Path], Fc: Optional[float], Fs: Optional[float], vs: Optional[float],
                delta: Optional[float], sigma2: Optional[float]):
    """Static map from a ``identify static`` JSON result or from --Fc/--Fs/--vs/--delta/--sigma2
    (defaults vs 1e-3 m/s, delta 2, sigma2 0); not both."""
    from ..errors import ParameterError
    from ..models import Stribeck

    if static_json is not None:
        # the map comes from the file: --Fc ... given beside it were ignored without a word (campaign round 8)
        given = [f"--{n}" for n, x in (("Fc", Fc), ("Fs", Fs), ("vs", vs), ("delta", delta), ("sigma2", sigma2))
                 if x is not None]
        if given:
            raise ParameterError(f"{', '.join(given)} and --static-json both give the static map; give one "
                                 "(--static-json STATIC.json, or --Fc with --Fs, --vs, --delta, --sigma2)")
        return chk.load_static_json(static_json)
    if Fc is None:
        given = [f"--{n}" for n, x in (("Fs", Fs), ("vs", vs), ("delta", delta), ("sigma2", sigma2)) if x is not None]
        if given:  # were dropped without a word: the map came from the data
            raise ParameterError(f"{', '.join(given)} without --Fc: the static map needs its Coulomb level --Fc "
                                 "(or give --static-json)")
        return None
    # named at the boundary: --Fs 1e308 was reported as "GMS.C = inf", --Fc -1 as "Stribeck.Fc" (round 10)
    Fc, Fs, sigma2, vs, delta = (chk.optional(check, x, opt, sized=True) for x, opt, check in (
        (Fc, "--Fc", chk.nonnegative), (Fs, "--Fs", chk.nonnegative), (sigma2, "--sigma2", chk.nonnegative),
        (vs, "--vs", chk.positive), (delta, "--delta", chk.positive)))
    return Stribeck(Fc=Fc, Fs=Fs if Fs is not None else Fc, vs=1e-3 if vs is None else vs,
                    delta=2.0 if delta is None else delta, sigma2=0.0 if sigma2 is None else sigma2)


_EX_OUTPUT_ERROR = """\b
Examples:
  frictionkit identify output-error REC.csv --time t --velocity v --force u --mass 1.0 \\
      --model lugre --static-json static.json --json lugre.json --plot lugre.png
  frictionkit identify output-error start_stop_200rpm.csv --drive motion --time t_s \\
      --velocity motor_velocity_rad_per_s --force motor_torque_N_m --where drive_id=1 \\
      --rotary --model lugre --static-json static1.json --free sigma0,sigma1,J \\
      --max-presliding 0.00614 --json lugre1.json
"""


@identify_app.command("output-error", epilog=_EX_OUTPUT_ERROR)
def output_error(
    recording: Path = typer.Argument(..., help="Data file (.csv, .mat, .h5, .parquet, .tdms)."),
    time: str = typer.Option(..., "--time", help="Time column [s]."),
    position: Optional[str] = typer.Option(None, "--position", help="Position column (force drive: compared with "
                                           "--compare x; motion drive: drives the model)."),
    velocity: Optional[str] = typer.Option(None, "--velocity", help="Velocity column (force drive: compared by "
                                           "default; motion drive without --position: drives the model)."),
    force: str = typer.Option(..., "--force", help="Force or torque column (force drive: the input; "
                              "motion drive: compared with the predicted friction)."),
    drive: str = typer.Option("force", "--drive", help="force: the measured force drives a mass, the motion is "
                              "compared; motion: the measured motion drives the law, the force is compared "
                              "(drive logs)."),
    force_scale: float = typer.Option(1.0, "--force-scale", help="Factor to N (or N·m)."),
    position_scale: float = typer.Option(1.0, "--position-scale", help="Factor to m (or rad)."),
    velocity_scale: float = typer.Option(1.0, "--velocity-scale", help="Factor to m/s (or rad/s)."),
    group: Optional[list[str]] = typer.Option(None, "--group", help="Column(s) naming records; all are fitted "
                                              "jointly, each from the unloaded state (both drives)."),
    where: Optional[list[str]] = typer.Option(None, "--where", help="Keep rows with COLUMN=VALUE (repeatable)."),
    rotary: bool = typer.Option(False, "--rotary", help="Rotary axis: label units N·m, rad, rad/s."),
    force_unit: Optional[str] = typer.Option(None, "--force-unit", help="Force unit label after scaling (default N)."),
    velocity_unit: Optional[str] = typer.Option(None, "--velocity-unit", help="Velocity unit label (default m/s)."),
    rests: str = typer.Option("auto", "--rests", help="auto (force logged exactly 0 over --min-rest "
                              "samples = drive disabled: state reset, not fitted; both drives) or none."),
    mask: Optional[str] = typer.Option(None, "--mask", help="Column that is non-zero where the drive is disabled "
                                       "(instead of --rests auto; both drives)."),
    min_rest: int = typer.Option(3, "--min-rest", help="Shortest run of zero force taken as a rest [samples]."),
    velocity_integration: str = typer.Option("held", "--velocity-integration", help="Motion drive from a velocity "
                                             "log: held (the log is the mean over the preceding sample, as drives "
                                             "log it) or trapezoidal (the log is the velocity at the sample)."),
    model: str = typer.Option("lugre", "--model", help="lugre, gms or dahl."),
    static_json: Optional[Path] = typer.Option(None, "--static-json", help="Static map: JSON of 'identify static'."),
    Fc: Optional[float] = typer.Option(None, "--Fc", help="Static map without --static-json: Coulomb level [N]."),
    Fs: Optional[float] = typer.Option(None, "--Fs", help="Breakaway level [N] (default Fc)."),
    vs: Optional[float] = typer.Option(None, "--vs", help="Stribeck velocity [m/s] (default 0.001)."),
    delta: Optional[float] = typer.Option(None, "--delta", help="Stribeck exponent (default 2)."),
    sigma2: Optional[float] = typer.Option(None, "--sigma2", help="Viscous coefficient [N·s/m] (default 0)."),
    mass: Optional[float] = typer.Option(None, "--mass", help="Force drive: moving mass [kg] (start value with "
                                         "--free m)."),
    inertia: Optional[float] = typer.Option(None, "--inertia", help="Motion drive: inertia J of the J·a term "
                                            "[kg or kg·m²] (start value with --free J; default 0, or a least-squares "
                                            "start with --free J)."),
    offset: float = typer.Option(0.0, "--offset", help="Constant force [N] (start value with --free offset)."),
    sigma0: Optional[float] = typer.Option(None, "--sigma0", help="LuGre start sigma0 [N/m] (force drive default: "
                                           "the library's initial='auto', slope of the sub-breakaway branches; "
                                           "motion drive: a bristle time constant of one sample)."),
    sigma1: Optional[float] = typer.Option(None, "--sigma1", help="LuGre start sigma1 [N·s/m] (default: critical "
                                           "damping; motion drive: 1 % of the friction level per unit speed)."),
    k: Optional[str] = typer.Option(None, "--k", help="GMS start stiffnesses, comma separated [N/m] "
                             "(default: from the data; give --xi too)."),
    xi: Optional[str] = typer.Option(None, "--xi", help="GMS start weights, comma separated."),
    C: Optional[float] = typer.Option(None, "--C", help="GMS attraction constant [N/s] (force drive default 20, "
                                      "fixed unless freed; "
                                      "motion drive: a slip time constant of one sample)."),
    elements: int = typer.Option(3, "--elements", help="GMS without --k/--xi: number of elements "
                                 f"(1 to {chk.MAX_PRESLIDING_ELEMENTS})."),
    free: str = typer.Option("", "--free", help="Comma-separated parameters to fit (default sigma0,sigma1 or k; "
                             "motion drive: sigma0,sigma1 / k,C / sigma0, plus J or offset if named; _pos/_neg "
                             "suffixes fit a direction alone)."),
    compare: Optional[str] = typer.Option(None, "--compare", help="Force drive: v or x (default: v if --velocity "
                                          "else x)."),
    starts: Optional[int] = typer.Option(None, "--starts", help="Number of start points (force drive: screened in "
                                         f"one batch, default 1; motion drive: default a grid of 7; 1 to "
                                         f"{chk.MAX_OUTPUT_ERROR_STARTS:,})."),
    max_presliding: Optional[float] = typer.Option(None, "--max-presliding", help="Motion drive: largest "
                                                   "pre-sliding displacement the axis can have [m or rad], e.g. one "
                                                   "encoder count; bounds sigma0 and k from below."),
    no_profile: bool = typer.Option(False, "--no-profile", help="Motion drive: skip the likelihood profiles "
                                    "(intervals then from the log-scale Jacobian only)."),
    jacobian: str = typer.Option("auto", "--jacobian", help="auto: exact Jacobians from forward sensitivities "
                                 "where the law has them (LuGre, Dahl; GMS with --drive motion); fd: forward "
                                 "differences; sensitivity: also GMS with --drive force (sensitivities along the "
                                 "simulated trajectory; opt-in: more CPU than differences in 7 of 8 measured sets, fits no lower on balance)."),
    validate: Optional[Path] = typer.Option(None, "--validate", help="Report the error on this other record "
                                            "(same column options) beside the training error."),
    json_out: Optional[Path] = typer.Option(None, "--json", help="Write the result as JSON."),
    plot: Optional[Path] = typer.Option(None, "--plot", help="Write measured vs simulated output as a plot "
                                        "(format from the extension: .png, .pdf, .svg ...)."),
) -> None:
    """Output-error fit of LuGre, GMS (or Dahl) parameters by simulation (seed 002 eq. 12).

    --drive force (default): the measured force drives mass + friction, the simulated
    velocity (or position) is compared; start values not given are computed by the
    library (sub-breakaway slope). --drive motion: the measured motion drives the
    friction law and the predicted force is compared — the direction that suits logs of
    position-controlled drives. Both: --group records fitted jointly, every run between
    rests simulated from the unloaded state.
    """
    from ..errors import DataError, ParameterError

    if position is None and velocity is None:
        raise DataError("give --position or --velocity")
    chk.choice(drive, "--drive", ("force", "motion"))
    scales = {"force": chk.scale(force_scale, "--force-scale"), "position": chk.scale(position_scale, "--position-scale"),
              "velocity": chk.scale(velocity_scale, "--velocity-scale")}
    units = chk.units(rotary, force_unit, velocity_unit)
    chk.where_items(where)
    if mass is not None:
        mass = chk.positive(mass, "--mass", sized=True)
    offset = chk.magnitude(offset, "--offset")
    inertia = chk.optional(chk.nonnegative, inertia, "--inertia", sized=True)
    max_presliding = chk.optional(chk.positive, max_presliding, "--max-presliding", sized=True)
    chk.choice(model, "--model", ("lugre", "gms", "dahl"))
    if compare is not None:
        chk.choice(compare, "--compare", ("v", "x"))
    if starts is not None:
        starts = chk.integer(starts, "--starts", lo=1, hi=chk.MAX_OUTPUT_ERROR_STARTS,
                             why="the screening simulates every start over the whole record, 1-2 ms each per "
                                 "8,000 samples")
    if C is not None:
        C = chk.positive(C, "--C", sized=True)
    chk.choice(rests, "--rests", ("auto", "none"))
    chk.choice(jacobian, "--jacobian", ("auto", "fd", "sensitivity"))
    chk.choice(velocity_integration, "--velocity-integration", ("held", "trapezoidal"))
    min_rest = chk.integer(min_rest, "--min-rest", lo=1)
    elements = chk.integer(elements, "--elements", lo=1, hi=chk.MAX_PRESLIDING_ELEMENTS)
    if model != "gms":  # GMS start options would be ignored unread (issue 13 round 4: --xi nan exited 0)
        for opt, val, default in (("--k", k, None), ("--xi", xi, None), ("--C", C, None), ("--elements", elements, 3)):
            if val != default:
                raise ParameterError(f"{opt} applies to --model gms only (this is --model {model})")
    if model == "dahl" and sigma1 is not None:
        raise ParameterError("--sigma1 applies to --model lugre only (Dahl has no bristle damping)")
    if model == "gms":
        for opt, val in (("--sigma0", sigma0), ("--sigma1", sigma1)):
            if val is not None:
                raise ParameterError(f"{opt} applies to --model lugre/dahl only (this is --model gms: its start "
                                     "is --k/--xi/--C or --elements)")
    if drive == "force":
        if mass is None:
            raise ParameterError("--drive force needs --mass (the moving mass the force accelerates)")
        for opt, val, default in (("--inertia", inertia, None), ("--no-profile", no_profile, False),
                                  ("--max-presliding", max_presliding, None)):
            if val != default:
                raise ParameterError(f"{opt} applies to --drive motion only")
    elif mass is not None or compare is not None:
        raise ParameterError(f"{'--mass' if mass is not None else '--compare'} applies to --drive force only "
                             "(--drive motion compares the force; give the inertia with --inertia)")
    chk.outputs({"RECORDING": recording, "--static-json": static_json, "--validate": validate},
                 files={"--json": json_out}, plots={"--plot": plot})

    law = _static_law(static_json, Fc, Fs, vs, delta, sigma2)
    if law is None:
        raise ParameterError("give the static map: --static-json STATIC.json or --Fc (with --Fs, --vs, --sigma2)")
    names = tuple(s.strip() for s in free.split(",") if s.strip())
    kw = dict(time=time, position=position, velocity=velocity, force=force, scales=scales, units=units)

    def loader(path):
        return _load(path, group=group, where=where, **kw)

    def mask_loader(path):
        return _load(path, group=group, where=where, time=time, force=mask)

    _early(loader, validate)
    if drive == "motion":
        res = _output_error_motion(loader(recording), law, model=model, names=names, position=position,
                                   rests=rests, mask=mask, min_rest=min_rest, integration=velocity_integration,
                                   inertia=inertia, offset=offset, sigma0=sigma0, sigma1=sigma1, k=k, xi=xi, C=C,
                                   elements=elements, starts=starts, profile=not no_profile,
                                   max_presliding=max_presliding, mask_loader=mask_loader, path=recording,
                                   jacobian=jacobian)
        d = res.diagnostics
        Fu = res.provenance["units"]["F"]
        typer.echo(res.summary())
        what = "torque" if "·m" in Fu else "force"
        typer.echo(f"training {what} RMS {res.rms:.6g} {Fu} (motion-driven {res.model_name}) against "
                   f"{d['static_rms']:.6g} {Fu} for the static map"
                   + (f" with the same J·a + offset ({d['map_only_rms']:.6g} {Fu} for the map alone)"
                      if any(n in res.names for n in ("J", "offset")) or res.diagnostics["J"] or res.diagnostics["offset"]
                      else " alone")
                   + f"; {res.n_obs} samples in {sum(len(s['segments']) for s in d['segments'].values())} "
                   f"segment(s), {sum(s['rest_samples'] for s in d['segments'].values())} rest samples")
        typer.echo(f"{d['nfev']} evaluations, {'converged' if res.success else 'NOT converged'}: {res.message}")
        if res.flagged:
            typer.echo("not identifiable: " + (", ".join(d["identifiability"]["not_identifiable"]) or "see warnings"))
        res = _validation(res, validate, what, loader,
                          how=lambda path: {"rests": _rest_option(rests, mask, mask_loader, path),
                                            "min_rest": min_rest})
        _write(res, json_out, plot, include_data=True)
        return

    res = _output_error_force(loader(recording), law, model=model, names=names, mass=mass, offset=offset,
                              compare=compare or ("v" if velocity is not None else "x"),
                              rest=_rest_option(rests, mask, mask_loader, recording), min_rest=min_rest,
                              sigma0=sigma0, sigma1=sigma1, k=k, xi=xi, C=C, elements=elements, starts=starts,
                              jacobian=jacobian)
    d = res.diagnostics
    ini = d.get("initial") or {}
    if "sigma0" in ini and "branches" in ini:
        typer.echo(f"initial guess: sigma0 {ini['sigma0']:.6g} {units['F']}/{units['x']}"
                   + (f", sigma1 {ini['sigma1']:.6g} {units['F']}·s/{units['x']}" if "sigma1" in ini else "")
                   + f" ({ini['branches']} branches)")
    elif "k_total" in ini:
        typer.echo(f"initial guess: total stiffness {ini['k_total']:.6g} {units['F']}/{units['x']} "
                   f"({ini['branches']} branches)")
    typer.echo(res.summary())
    seg = d["segments"]
    typer.echo(f"{res.n_obs} samples in {sum(len(s['segments']) for s in seg.values())} segment(s) of {len(seg)} "
               f"record(s), each simulated from rest; {sum(s['rest_samples'] for s in seg.values())} rest samples")
    typer.echo(f"{d['nfev']} evaluations, status {d['status']}, {'converged' if res.success else 'NOT converged'}: "
               f"{res.message}")
    res = _validation(res, validate, {"v": "velocity", "x": "position"}[res.provenance["procedure"]["compare"]],
                      loader, how=lambda path: {"rests": _rest_option(rests, mask, mask_loader, path),
                                                "min_rest": min_rest})
    _write(res, json_out, plot, include_data=True)


def _output_error_force(data, law, *, model, names, mass, offset, compare, rest, min_rest, sigma0, sigma1, k, xi,
                        C, elements, starts, jacobian="auto"):
    """The ``--drive force`` branch: the given start values, the rest computed by the library."""
    from rich.console import Console

    from ..errors import ParameterError
    from ..identify.output_error import fit_output_error

    given: dict = {}
    if model in ("lugre", "dahl"):
        given.update({n: v for n, v in (("sigma0", sigma0), ("sigma1", sigma1)) if v is not None})

    else:
        kk, xx = _floats_list(k, "--k"), _floats_list(xi, "--xi")
        if (kk is None) != (xx is None):
            raise ParameterError("--model gms: give both --k and --xi, or neither (then the library computes the "
                                 "start from the data: total stiffness of the sub-breakaway branches, --elements)")
        given.update({n: v for n, v in (("k", kk), ("xi", xx), ("C", C)) if v is not None})
    with Console(stderr=True).status("output-error fit: starting") as status:
        return fit_output_error(
            data, model, static=law, initial=given or "auto", free=names or None, inertia=mass, offset=offset,
            compare=compare, rests=rest, min_rest=min_rest, elements=elements, starts=starts or 1, jacobian=jacobian,
            progress=lambda nfev, nsim, cost: status.update(
                f"output-error fit: evaluation {nfev}, {nsim} simulations, cost {cost:.6g}"),
        )


def _rest_option(rests: str, mask: Optional[str], mask_loader, path: Path):
    """``rests=`` of the motion fit: "auto", None, or the mask column(s) (non-zero = drive disabled)."""
    import numpy as np

    from ..data import Recording

    if mask is None:
        return "auto" if rests == "auto" else None
    m = mask_loader(path)
    if isinstance(m, Recording):
        return np.asarray(m.F) != 0
    return {name: np.asarray(r.F) != 0 for name, r in m.items()}


def _output_error_motion(data, law, *, model, names, position, rests, mask, min_rest, integration, inertia, offset,
                         sigma0, sigma1, k, xi, C, elements, starts, profile, mask_loader, path,
                         max_presliding=None, jacobian="auto"):
    """The ``--drive motion`` branch: segments, the start model from the library (given values kept), fit."""
    from ..errors import ParameterError
    from ..identify.motion_error import fit_motion_error, motion_data

    rest = _rest_option(rests, mask, mask_loader, path)
    md = motion_data(data, drive="position" if position is not None else "velocity", integration=integration,
                     rests=rest, min_rest=min_rest)
    kk, xx = _floats_list(k, "--k"), _floats_list(xi, "--xi")
    if model == "gms" and (kk is None) != (xx is None):
        raise ParameterError("--model gms: give both --k and --xi, or neither (then --elements sets the start)")
    given = {n: v for n, v in {"lugre": (("sigma0", sigma0), ("sigma1", sigma1)),
                               "gms": (("k", kk), ("xi", xx), ("C", C)),
                               "dahl": (("sigma0", sigma0),)}[model] if v is not None}
    return fit_motion_error(md, model, static=law, initial=given or "auto", elements=elements, free=names or None,
                            inertia=inertia or 0.0, offset=offset, starts=starts if starts is not None else "auto",
                            profile=profile, max_presliding=max_presliding, jacobian=jacobian)


_EX_REVERSAL = """\b
Examples:
  frictionkit identify reversal REV.csv --time t --position x --force T --rotary \\
      --json rev.json --plot rev.png
"""


@identify_app.command("reversal", epilog=_EX_REVERSAL)
def reversal(
    recording: Path = typer.Argument(..., help="Data file (.csv, .mat, .h5, .parquet, .tdms)."),
    time: str = typer.Option(..., "--time", help="Time column [s]."),
    position: str = typer.Option(..., "--position", help="Position column (reversals are its turning points)."),
    force: str = typer.Option(..., "--force", help="Drive force or torque column (the friction at slow reversals)."),
    force_scale: float = typer.Option(1.0, "--force-scale", help="Factor to N (or N·m)."),
    position_scale: float = typer.Option(1.0, "--position-scale", help="Factor to m (or rad)."),
    window: Optional[float] = typer.Option(None, "--window", help="Largest displacement from a reversal used "
                                           "[m or rad, after scaling]; default: everything up to halfway to the next."),
    min_travel: Optional[float] = typer.Option(None, "--min-travel", help="Travel that confirms a turning point "
                                               "[m or rad]; default 5 % of the position range."),
    inertia: float = typer.Option(0.0, "--inertia", help="J of a J·a term removed from the force [kg or kg·m²]."),
    offset: float = typer.Option(0.0, "--offset", help="Constant force removed from the force [N or N·m]."),
    group: Optional[list[str]] = typer.Option(None, "--group", help="Column(s) naming records; all are fitted jointly."),
    where: Optional[list[str]] = typer.Option(None, "--where", help="Keep rows with COLUMN=VALUE (repeatable)."),
    rotary: bool = typer.Option(False, "--rotary", help="Rotary axis: label units N·m, rad, rad/s."),
    force_unit: Optional[str] = typer.Option(None, "--force-unit", help="Force unit label after scaling (default N)."),
    velocity_unit: Optional[str] = typer.Option(None, "--velocity-unit", help="Velocity unit label (default m/s)."),
    validate: Optional[Path] = typer.Option(None, "--validate", help="Report the error on this other record "
                                            "(same column options) beside the training error."),
    json_out: Optional[Path] = typer.Option(None, "--json", help="Write the result as JSON."),
    plot: Optional[Path] = typer.Option(None, "--plot", help="Write the friction against the displacement from the "
                                        "reversal with both laws (format from the extension: .png, .pdf, .svg ...)."),
) -> None:
    """Compensator parameters from a reversal record: F0 and the sinc xs, the sigmoid sigma (seed 001 eqs. 5-6)."""
    scales = {"force": chk.scale(force_scale, "--force-scale"), "position": chk.scale(position_scale, "--position-scale")}
    window = chk.optional(chk.positive, window, "--window", sized=True)
    min_travel = chk.optional(chk.positive, min_travel, "--min-travel", sized=True)
    inertia = chk.nonnegative(inertia, "--inertia", sized=True)
    offset = chk.magnitude(offset, "--offset")
    units = chk.units(rotary, force_unit, velocity_unit)
    chk.where_items(where)
    chk.outputs({"RECORDING": recording, "--validate": validate}, files={"--json": json_out}, plots={"--plot": plot})

    from ..identify.reversal import fit_reversal

    def loader(path):
        return _load(path, group=group, where=where, time=time, position=position, force=force, scales=scales,
                     units=units)

    _early(loader, validate)
    res = fit_reversal(loader(recording), window=window, min_travel=min_travel, inertia=inertia, offset=offset)
    typer.echo(res.summary())
    d = res.diagnostics
    typer.echo(f"{d['reversals']} reversal(s); RMS residual: sinc {d['sinc_rms']:.6g} {units['F']}, sigmoid (after "
               f"the reversal) {d['sigmoid_rms']:.6g} {units['F']}; {d['samples_inside_xs']} samples inside xs")
    if res.model is not None:
        c = res.model
        typer.echo(f"compensator: RollingCompensator(F0={c.F0:.6g}, xs={c.xs:.6g}, sigma={c.sigma:.6g})")
    res = _validation(res, validate, "friction", loader)
    _write(res, json_out, plot, include_data=True)


_EX_PRESLIDING = """\b
Examples:
  frictionkit identify presliding REC.csv --time t --position x --force F --elements 3 \\
      --json gms.json
"""


@identify_app.command("presliding", epilog=_EX_PRESLIDING)
def presliding(
    recording: Path = typer.Argument(..., help="Data file (.csv, .mat, .h5, .parquet, .tdms)."),
    time: str = typer.Option(..., "--time", help="Time column [s]."),
    position: str = typer.Option(..., "--position", help="Position column."),
    force: str = typer.Option(..., "--force", help="Friction force column."),
    force_scale: float = typer.Option(1.0, "--force-scale", help="Factor to N."),
    position_scale: float = typer.Option(1.0, "--position-scale", help="Factor to m."),
    elements: int = typer.Option(..., "--elements", help=f"Number M of GMS elements (1 to {chk.MAX_PRESLIDING_ELEMENTS}: "
                                 "32 take about 20 s on a 2,000-sample branch)."),
    static_json: Optional[Path] = typer.Option(None, "--static-json", help="Static map: JSON of 'identify static'."),
    Fc: Optional[float] = typer.Option(None, "--Fc", help="Static map without --static-json: Coulomb level [N]."),
    Fs: Optional[float] = typer.Option(None, "--Fs", help="Breakaway level [N] (default Fc)."),
    vs: Optional[float] = typer.Option(None, "--vs", help="Stribeck velocity [m/s] (default 0.001)."),
    delta: Optional[float] = typer.Option(None, "--delta", help="Stribeck exponent (default 2)."),
    sigma2: Optional[float] = typer.Option(None, "--sigma2", help="Viscous coefficient [N·s/m] (default 0)."),
    branch: str = typer.Option("auto", "--branch", help="auto, virgin or reversal."),
    C: Optional[float] = typer.Option(None, "--C", help="Fix the attraction constant [N/s]."),
    no_polish: bool = typer.Option(False, "--no-polish", "--no-refine", help="Skip the simulation-error polish "
                                   "(--no-refine: the former name)."),
    group: Optional[list[str]] = typer.Option(None, "--group", help="Column(s) naming records; all are fitted "
                                              "jointly, each from the unloaded state."),
    rests: str = typer.Option("auto", "--rests", help="auto (force logged exactly 0 over --min-rest samples = "
                              "drive disabled: state reset, not fitted) or none."),
    mask: Optional[str] = typer.Option(None, "--mask", help="Column that is non-zero where the drive is disabled "
                                       "(instead of --rests auto)."),
    min_rest: int = typer.Option(3, "--min-rest", help="Shortest run of zero force taken as a rest [samples]."),
    where: Optional[list[str]] = typer.Option(None, "--where", help="Keep rows with COLUMN=VALUE (repeatable)."),
    rotary: bool = typer.Option(False, "--rotary", help="Rotary axis: label units N·m, rad, rad/s."),
    force_unit: Optional[str] = typer.Option(None, "--force-unit", help="Force unit label after scaling (default N)."),
    velocity_unit: Optional[str] = typer.Option(None, "--velocity-unit", help="Velocity unit label (default m/s)."),
    validate: Optional[Path] = typer.Option(None, "--validate", help="Report the error on this other record "
                                            "(same column options) beside the training error."),
    json_out: Optional[Path] = typer.Option(None, "--json", help="Write the result as JSON."),
    plot: Optional[Path] = typer.Option(None, "--plot", help="Write measured vs simulated force over time and "
                                        "as the force-displacement loop, as a plot (format from the "
                                        "extension: .png, .pdf, .svg ...)."),
) -> None:
    """GMS pre-sliding k_i, xi_i from a force-displacement branch (seed 000 eq. 19)."""
    elements = chk.integer(elements, "--elements", lo=1, hi=chk.MAX_PRESLIDING_ELEMENTS,
                           why="the breakpoint search grows with M: 32 elements on a 2,000-sample branch "
                               "take about 20 s")
    scales = {"force": chk.scale(force_scale, "--force-scale"), "position": chk.scale(position_scale, "--position-scale")}
    chk.choice(branch, "--branch", ("auto", "virgin", "reversal"))
    C = chk.optional(chk.positive, C, "--C", sized=True)
    chk.choice(rests, "--rests", ("auto", "none"))
    min_rest = chk.integer(min_rest, "--min-rest", lo=1)
    units = chk.units(rotary, force_unit, velocity_unit)
    chk.where_items(where)
    chk.outputs({"RECORDING": recording, "--static-json": static_json, "--validate": validate},
                 files={"--json": json_out}, plots={"--plot": plot})

    from rich.console import Console

    from ..identify.presliding import fit_presliding

    def loader(path):
        return _load(path, group=group, where=where, time=time, position=position, force=force, scales=scales,
                     units=units)

    def mask_loader(path):
        return _load(path, group=group, where=where, time=time, force=mask)

    _early(loader, validate)
    law = _static_law(static_json, Fc, Fs, vs, delta, sigma2)
    data = loader(recording)
    with Console(stderr=True).status(f"pre-sliding fit: {elements} element(s)"
                                     + ("" if no_polish else ", then simulation-error polish")):
        res = fit_presliding(data, elements=elements, static=law, branch=branch, C=C, polish=not no_polish,
                             rests=_rest_option(rests, mask, mask_loader, recording), min_rest=min_rest)
    typer.echo(res.summary())
    d = res.diagnostics
    if res.model is None:  # nothing to report or write: the branch gave no GMS
        from ..errors import IdentificationError

        raise IdentificationError(f"fit_presliding: {res.message}")
    if not res.success:
        typer.echo(f"NOT identified: {res.message}")
    typer.echo(f"total stiffness {d['total_stiffness']:.6g} {units['F']}/{units['x']}, breakpoints "
               + ", ".join(f"{b:.4g}" for b in d["breakpoints"]) + f" {units['x']}, C {d['C']:.4g} {units['F']}/s")
    seg = d["segments"]
    if len(seg) > 1 or any(len(s["segments"]) > 1 for s in seg.values()):
        typer.echo(f"{res.n_obs} samples in {sum(len(s['segments']) for s in seg.values())} segment(s) of "
                   f"{len(seg)} record(s), each from the unloaded state; breakpoints from record "
                   f"'{res.provenance['recording']}'")
    res = _validation(res, validate, "force", loader,
                      how=lambda path: {"rests": _rest_option(rests, mask, mask_loader, path), "min_rest": min_rest})
    _write(res, json_out, plot, include_data=True)
