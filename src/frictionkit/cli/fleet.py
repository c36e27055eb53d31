"""``frictionkit fleet ...``: simulate a fleet, identify every log on Dask, monitor drift.

Thin wrappers around :mod:`frictionkit.fleet`. Options and output paths are checked
before any work; errors go through the one error path of :mod:`frictionkit.cli._errors`
(one ``error:`` line; exit 2 for bad input, 1 when a computation or a write fails).
``--json PATH`` writes a summary (``--json -`` prints it on stdout instead of the text).
"""

from __future__ import annotations

import json
import re
from pathlib import Path
from typing import Optional

import typer

from . import _common as chk
from . import app

fleet_app = typer.Typer(
    name="fleet",
    help="Fleets: simulate, identify every axis-day on Dask, monitor friction drift.",
    no_args_is_help=True,
    add_completion=False,
    pretty_exceptions_enable=False,
    rich_markup_mode=None,
)
app.add_typer(fleet_app, name="fleet")

#: Upper bounds of the simulate options (a day is a 20 s log of ~1 MB: 10^6 files is a terabyte).
MAX_AXES, MAX_DAYS = 100_000, 3_660
#: Upper bound of --workers on one machine.
MAX_WORKERS = 512

_ADDRESS = re.compile(r"^(?:(?:tcp|tls|inproc|ucx|ws|wss)://)?[^\s/:]+(?::\d{1,5})?/?$")


def dask_options(workers: Optional[int], scheduler: Optional[str]) -> Optional[int]:
    """Check --workers / --scheduler of a Dask verb; returns the validated worker count."""
    from ..errors import ParameterError

    if workers is not None:
        workers = chk.integer(workers, "--workers", lo=0, hi=MAX_WORKERS)
    if scheduler is not None and scheduler != "none":
        if not _ADDRESS.match(scheduler):
            raise ParameterError(f"--scheduler {scheduler!r}: expected a scheduler address such as "
                                 "tcp://10.0.0.5:8786, or 'none'")
        if workers is not None:
            raise ParameterError("--workers starts a local cluster; with --scheduler the cluster decides the "
                                 "workers (drop --workers)")
    return workers


def _summary(doc: dict, json_out: Optional[str], text: str) -> None:
    if json_out == "-":
        typer.echo(json.dumps(doc, indent=2, default=str))
        return
    typer.echo(text)
    if json_out is not None:
        chk.save_json(doc, Path(json_out))
        typer.echo(f"wrote {json_out}")


def _json_option(json_out: Optional[str], inputs: list, out: Optional[Path] = None) -> None:
    if json_out is not None and json_out != "-":
        from ..errors import ParameterError

        if out is not None and Path(json_out).resolve() == out.resolve():  # was "--json ... is the input file"
            raise ParameterError(f"--json '{json_out}' and --out '{out}' name the same file")
        chk.outputs(inputs, files={"--json": Path(json_out)}, make_parents=False)


@fleet_app.command("simulate", epilog="\b\nExample:\n  frictionkit fleet simulate --axes 50 --days 30 --out fleet/ --seed 1")
def simulate(
    axes: int = typer.Option(..., "--axes", help="Number of axes."),
    days: int = typer.Option(..., "--days", help="Number of days (one 20 s, 1 kHz log per axis and day)."),
    out: str = typer.Option(..., "--out", help="Folder to write the fleet into (created)."),
    seed: int = typer.Option(0, "--seed", help="Seed (0 to 2**32 - 1); the same seed gives the same files."),
    fmt: str = typer.Option("mixed", "--format", help="csv, parquet, or mixed (CSV and Parquet by axis)."),
    drifting: float = typer.Option(0.3, "--drifting", help="Fraction of axes with wear drift [0, 1]."),
    broken: Optional[int] = typer.Option(None, "--broken", help="Number of deliberately broken files "
                                         "(default min(5, max(1, files/100)))."),
    json_out: Optional[str] = typer.Option(None, "--json", help="Write a JSON summary (- for stdout)."),
) -> None:
    """Write a simulated fleet: logs with wear and temperature drift, noise, a few broken files, fleet.toml."""
    from .._io import check_output_dir
    from ..fleet import simulate_fleet

    axes = chk.integer(axes, "--axes", lo=1, hi=MAX_AXES)
    days = chk.integer(days, "--days", lo=1, hi=MAX_DAYS)
    seed = chk.integer(seed, "--seed", lo=0, hi=2**32 - 1)
    chk.choice(fmt, "--format", ("csv", "parquet", "mixed"))
    drifting = chk.fraction(drifting, "--drifting", below=1.0 + 1e-12)
    if broken is not None:
        broken = chk.integer(broken, "--broken", lo=0, hi=axes * days, why="at most one per file")
    out = chk.folder(out, "--out")
    check_output_dir(out, option="--out")
    _json_option(json_out, [])
    formats = ("csv", "parquet") if fmt == "mixed" else (fmt,)

    from rich.console import Console
    from rich.progress import BarColumn, MofNCompleteColumn, Progress, TextColumn, TimeElapsedColumn

    with Progress(TextColumn("simulate"), BarColumn(), MofNCompleteColumn(), TimeElapsedColumn(),
                  console=Console(stderr=True)) as bar:
        task = bar.add_task("simulate", total=axes * days)
        fleet = simulate_fleet(out, axes=axes, days=days, seed=seed, formats=formats, drifting=drifting,
                               broken=broken, progress=lambda done, total: bar.update(task, completed=done))
    doc = fleet.to_dict()
    text = (f"wrote {doc['files']} log file(s) of {doc['axes']} axes x {doc['days']} days to {out} "
            f"({len(doc['drifting_axes'])} drifting, {len(doc['broken'])} broken: see broken.txt"
            + (f"; resumed: {fleet.resumed} kept from the interrupted run" if fleet.resumed else "")
            + f"); configuration {fleet.config}")
    _summary(doc, json_out, text)


@fleet_app.command("identify", epilog="\b\nExamples:\n  frictionkit fleet identify fleet/ --out results.parquet --workers 2\n"
                   "  frictionkit fleet identify 'plant/*/2026-*.parquet' --config plant.toml --out r.parquet "
                   "--scheduler tcp://10.0.0.5:8786")
def identify(
    dataset: str = typer.Argument(..., help="Folder of logs, or a quoted glob."),
    out: Path = typer.Option(..., "--out", help="Results Parquet file (parts go to OUT.parts/ beside it)."),
    workers: Optional[int] = typer.Option(None, "--workers", help="Worker processes of the local Dask cluster "
                                          "(default: the cores); 0 runs in this process without Dask."),
    scheduler: Optional[str] = typer.Option(None, "--scheduler", help="Address of a running Dask scheduler "
                                            "(tcp://host:8786), or 'none' for no Dask."),
    config: Optional[Path] = typer.Option(None, "--config", help="Fleet configuration TOML "
                                          "(default DATASET/fleet.toml)."),
    monitor: bool = typer.Option(True, "--monitor/--no-monitor", help="Run drift monitoring on the table "
                                 "(adds drift_flag and the trend columns)."),
    progress: bool = typer.Option(True, "--progress/--no-progress", help="Progress bar on stderr."),
    batch: int = typer.Option(1, "--batch", help="Files per Dask task (more on large clusters: the scheduler "
                              "costs a few ms per task)."),
    json_out: Optional[str] = typer.Option(None, "--json", help="Write a JSON summary (- for stdout)."),
) -> None:
    """Identify every log (segmentation, static map with intervals and model choice); one row per axis-period.

    Exit 0 when at least one log was identified (a warning on stderr counts the failed ones),
    1 when every log failed (one line: how many and the first error; the table is still written)."""
    from ..errors import IdentificationError, ParameterError
    from ..fleet import identify_fleet
    from ..fleet.identify import resolve_config
    from ..fleet.report import axes_word

    chk.folder(dataset, "DATASET")
    workers = dask_options(workers, scheduler)
    batch = chk.integer(batch, "--batch", lo=1, hi=100_000)
    if config is not None and not config.is_file():
        raise ParameterError(f"--config '{config}': file not found")
    cfg = resolve_config(dataset, config)  # a bad configuration fails here, before any work
    chk.outputs([config], files={"--out": out}, make_parents=True)
    if out.suffix.lower() not in (".parquet", ".pq"):
        raise ParameterError(f"--out '{out}': the results are Parquet; use a .parquet file name")
    _json_option(json_out, [config], out)

    run = identify_fleet(dataset, out=out, config=cfg, scheduler=scheduler, workers=workers,
                         progress=progress, monitor=monitor, batch=batch)
    doc = run.to_dict()
    files = run.table["file"].nunique() if "file" in run.table else run.tasks
    # one file of many axes (examples/fleet/tro2021_steady_state.toml) said "3 log file(s)" for 1 file
    what = (f"{run.tasks} log file(s)" if files == run.tasks
            else f"{run.tasks} axis-period(s) from {files} file(s)")
    lines = [f"{what}: {run.computed} identified, {run.skipped} done before (skipped); "
             f"{run.ok} ok, {run.errors} with an error"]
    errs = run.table.loc[~run.table["ok"].astype(bool), ["axis", "period", "error"]]
    for _, r in errs.head(5).iterrows():
        lines.append(f"  {r['axis']} {r['period']}: {r['error']}")
    if len(errs) > 5:
        lines.append(f"  ... {len(errs) - 5} more (column 'error')")
    if run.monitored:
        flagged = doc.get("flagged_axes", [])
        lines.append(f"drift: {len(flagged)} {axes_word(len(flagged))} flagged" + (f" ({', '.join(flagged[:10])}"
                                                                    f"{' ...' if len(flagged) > 10 else ''})" if flagged else ""))
    lines.append(f"wrote {out} ({len(run.table)} row{'' if len(run.table) == 1 else 's'}; {run.elapsed:.1f} s)")
    if len(errs) and len(errs) == len(run.table):
        if json_out not in (None, "-"):
            chk.save_json(doc, Path(json_out))
        first = errs.iloc[0]
        raise IdentificationError(f"all {len(errs)} log file(s) failed (their rows, with the errors, are in {out}); "
                                  f"first: {first['axis']} {first['period']}: {first['error']}")
    if len(errs):
        typer.echo(f"warning: {len(errs)} of {len(run.table)} log file(s) failed; their rows carry the error "
                   "(column 'error')", err=True)
    if run.failed_tasks:
        typer.echo(f"warning: {run.failed_tasks} task(s) failed on the cluster; their rows carry the error "
                   "and a rerun retries them", err=True)
    if run.unmatched:
        typer.echo(f"warning: {len(run.unmatched)} data file(s) match no [layout] pattern and were not "
                   f"identified (e.g. {run.unmatched[0]}); name files that are not recordings under [layout] "
                   "ignore", err=True)
    if {"axis", "period", "file"} <= set(run.table.columns) and len(run.table):
        # e.g. [layout] axis/period constants over a folder of several logs: every file got the same
        # axis-period, so distinct logs would pass for repeated measurements of one axis on one day
        n_files = run.table.groupby(["axis", "period"], sort=True)["file"].nunique()
        shared = n_files[n_files > 1]
        if len(shared):
            (ax, per), n = shared.index[0], int(shared.iloc[0])
            typer.echo(f"warning: {len(shared)} axis-period(s) come from more than one file (e.g. axis {ax} "
                       f"period {per}: {n} files); each file is one row of that axis-period — check the "
                       "[layout] pattern/constants", err=True)
    _summary(doc, json_out, "\n".join(lines))


@fleet_app.command("monitor", epilog="\b\nExample:\n  frictionkit fleet monitor results.parquet --out monitored.parquet --alpha 0.01")
def monitor_cmd(
    results: Path = typer.Argument(..., help="Results Parquet file of 'fleet identify'."),
    out: Optional[Path] = typer.Option(None, "--out", help="Where to write the table with the drift columns "
                                       "(default: rewrite RESULTS atomically)."),
    alpha: float = typer.Option(0.01, "--alpha", help="Probability that a drift-free axis is ever flagged "
                                "over the history (0 < alpha < 0.5)."),
    min_periods: int = typer.Option(5, "--min-periods", help="Periods with a fit before the first test."),
    schedule: Optional[list[str]] = typer.Option(None, "--schedule", help="Scheduling column to regress out "
                                                 "(repeatable; default: every one in the table)."),
    json_out: Optional[str] = typer.Option(None, "--json", help="Write a JSON summary (- for stdout)."),
) -> None:
    """Per-axis trends of the friction parameters; flag drift beyond the intervals (temperature regressed out)."""
    import pandas as pd

    from ..errors import DataError
    from ..fleet import drift_summary, monitor_drift
    from ..fleet.identify import write_table

    alpha = chk.positive(alpha, "--alpha")
    if not alpha < 0.5:
        raise DataError(f"--alpha {alpha!r}: must be < 0.5")
    min_periods = chk.integer(min_periods, "--min-periods", lo=3)
    if not results.is_file():
        raise DataError(f"'{results}': results file not found")
    target = out or results
    if out is not None:
        chk.outputs([results], files={"--out": out}, make_parents=True)
    _json_option(json_out, [results], out)
    try:
        df = pd.read_parquet(results)
    except Exception as exc:  # pyarrow raises several unrelated types
        raise DataError(f"'{results}': cannot be read as Parquet ({str(exc).splitlines()[0]})") from None
    df = monitor_drift(df, alpha=alpha, min_periods=min_periods, schedule=schedule or None)
    target.parent.mkdir(parents=True, exist_ok=True)
    write_table(df, target)
    axes = drift_summary(df)
    flagged = axes.loc[axes["drift_flag"], ["axis", "drift_alarm_period", "drift_detail"]]
    doc = {"out": str(target), "rows": int(len(df)), "axes": int(len(axes)), "alpha": alpha,
           "flagged_axes": flagged["axis"].tolist(),
           "alarms": {r["axis"]: {"period": r["drift_alarm_period"], "detail": r["drift_detail"]}
                      for _, r in flagged.iterrows()}}
    lines = [f"{len(axes)} axes, {len(flagged)} flagged (false-alarm probability per drift-free axis {alpha:g})"]
    lines += [f"  {r['axis']}: {r['drift_detail']}" for _, r in flagged.iterrows()]
    lines.append(f"wrote {target}")
    _summary(doc, json_out, "\n".join(lines))


@fleet_app.command("report", epilog="\b\nExample:\n  frictionkit fleet report results.parquet --out fleet.html")
def report_cmd(
    results: Path = typer.Argument(..., help="Results Parquet file of 'fleet identify'."),
    out: Path = typer.Option(..., "--out", help="HTML file to write (self-contained, plots embedded)."),
    max_axes: int = typer.Option(20, "--max-axes", help="Flagged axes drawn over time (all are listed)."),
    json_out: Optional[str] = typer.Option(None, "--json", help="Write a JSON summary (- for stdout)."),
) -> None:
    """The fleet page: parameter distributions, flagged axes and their history, failed files."""
    import pandas as pd

    from ..errors import DataError
    from ..fleet import fleet_report

    max_axes = chk.integer(max_axes, "--max-axes", lo=0, hi=10_000)
    if not results.is_file():
        raise DataError(f"'{results}': results file not found")
    chk.outputs([results], files={"--out": out}, make_parents=True)
    if out.suffix.lower() not in (".html", ".htm"):
        raise DataError(f"--out '{out}': the report is HTML; use a .html file name")
    _json_option(json_out, [results], out)
    try:
        df = pd.read_parquet(results)
    except Exception as exc:  # pyarrow raises several unrelated types
        raise DataError(f"'{results}': cannot be read as Parquet ({str(exc).splitlines()[0]})") from None
    for col in ("axis", "period", "ok"):
        if col not in df:
            raise DataError(f"'{results}': not a fleet results table (no column '{col}')")
    out.parent.mkdir(parents=True, exist_ok=True)
    doc = fleet_report(df, out, max_axes=max_axes)
    text = (f"{doc['axes']} axes, {doc['rows']} axis-periods ({doc['errors']} failed), "
            f"{len(doc['flagged'])} flagged; wrote {out}")
    _summary(doc, json_out, text)


@app.command("study", epilog="\b\nExample:\n  frictionkit study study.toml --out study.parquet --workers 2 --json summary.json\n"
             "  (the TOML format is in the docstring of frictionkit.study)")
def study_cmd(
    spec: Path = typer.Argument(..., help="Study TOML: [machine], [reference], [spread], [study]."),
    out: Path = typer.Option(..., "--out", help="Results Parquet file, one row per run (parts in OUT.parts/)."),
    workers: Optional[int] = typer.Option(None, "--workers", help="Worker processes of the local Dask cluster "
                                          "(default: the cores); 0 runs in this process without Dask."),
    scheduler: Optional[str] = typer.Option(None, "--scheduler", help="Address of a running Dask scheduler, "
                                            "or 'none'."),
    progress: bool = typer.Option(True, "--progress/--no-progress", help="Progress bar on stderr."),
    json_out: Optional[str] = typer.Option(None, "--json", help="Write a JSON summary (- for stdout)."),
) -> None:
    """Monte-Carlo robustness study: friction spreads x compensators x noise seeds, on Dask.

    Exit 1 when every run failed (one line: how many and the first error; the table is still
    written); a warning on stderr counts the failed runs otherwise."""
    from ..errors import ParameterError, SimulationError
    from ..study import load_study, run_study

    workers = dask_options(workers, scheduler)
    st = load_study(spec)
    chk.outputs([spec], files={"--out": out}, make_parents=True)
    if out.suffix.lower() not in (".parquet", ".pq"):
        raise ParameterError(f"--out '{out}': the results are Parquet; use a .parquet file name")
    _json_option(json_out, [spec], out)
    res = run_study(st, out=out, scheduler=scheduler, workers=workers, progress=progress)
    doc = res.to_dict()
    lines = [f"{res.runs} run(s): {res.computed} simulated, {res.skipped} done before (skipped); compensators best "
             "first by the median max tracking error"]
    for comp, s in doc["compensators"].items():
        med = s["max_error_median_m"]
        p95 = s["max_error_p95_m"]
        lines.append(f"  {comp:8s} max tracking error: median {1e6 * med:.2f} µm, 95th percentile {1e6 * p95:.2f} µm"
                     f" ({s['runs']} runs, {s['failed']} failed)" if med is not None else
                     f"  {comp:8s} every run failed")
    lines.append(f"wrote {out}")
    bad = res.table.loc[~res.table["ok"].astype(bool)] if len(res.table) else res.table
    if len(bad) and len(bad) == len(res.table):
        if json_out not in (None, "-"):
            chk.save_json(doc, Path(json_out))
        raise SimulationError(f"all {len(bad)} run(s) failed (their rows, with the errors, are in {out}); "
                              f"first: {bad['run'].iloc[0]}: {bad['error'].iloc[0]}")
    if len(bad):
        typer.echo(f"warning: {len(bad)} of {len(res.table)} run(s) failed; their rows carry the error "
                   "(column 'error')", err=True)
    _summary(doc, json_out, "\n".join(lines))
