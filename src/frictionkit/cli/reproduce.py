"""``frictionkit reproduce ...``: run a paper's virtual experiments, write JSON and a plot.

Options and output paths are checked before the (long) run; the files are written
atomically (:mod:`frictionkit._io`), so a failed write keeps the previous result.

The figure, one convention for every reproduction (as for ``simulate``, ``identify`` and
``compensate``, ``--plot`` takes a file): ``--plot FILE`` writes it there (format from the
extension); without it a PNG goes beside ``--json`` (``OUT.png``); ``--no-plot`` writes none.
The JSON's ``"plot"`` names the figure relative to the JSON's folder. ``--plot`` without a
file was the flag of ``zhu-fujimoto`` and ``zhang2023`` (``--plot/--no-plot``): it still means
the default, with a deprecation warning.
"""

from __future__ import annotations

import os
from contextlib import contextmanager
from pathlib import Path
from typing import Annotated, Any, Optional

import typer
from typer.core import TyperCommand

from ..errors import ParameterError
from . import _common as chk
from . import app

#: Key in the click context's ``meta``: the invocation gave ``--plot`` without a file (the old flag).
_BARE_PLOT_KEY = "frictionkit.reproduce.bare_plot"


class _ReproduceCommand(TyperCommand):
    """A reproduction verb: takes the old bare ``--plot`` flag out before click reads ``--plot FILE``.

    ``--plot`` followed by nothing or by another option (a word starting with ``-``, except ``-``
    itself) is the old flag; a file whose name starts with ``-`` is given as ``--plot=-name.png``.
    """

    def parse_args(self, ctx: Any, args: list[str]) -> list[str]:
        end = args.index("--") if "--" in args else len(args)
        bare = [i for i in range(end) if args[i] == "--plot"
                and (i + 1 >= end or (args[i + 1].startswith("-") and args[i + 1] != "-"))]
        if bare:
            ctx.meta[_BARE_PLOT_KEY] = True
            args = [a for i, a in enumerate(args) if i not in bare]
        return super().parse_args(ctx, args)


PlotFile = Annotated[Optional[Path], typer.Option(
    "--plot", help="Write the figure here (format from the extension: PNG, PDF, SVG ...); default: a PNG beside "
                   "--json.")]
NoPlot = Annotated[bool, typer.Option("--no-plot", help="Write no figure.")]


def _plot_path(plot: Path | None, no_plot: bool, json_out: Path, *, robustness: bool = False) -> Path | None:
    """Where a reproduction's figure goes (None: no figure); warns about the old bare ``--plot``."""
    from ._errors import _click_module

    ctx = _click_module("globals").get_current_context(silent=True)
    if ctx is not None and ctx.meta.get(_BARE_PLOT_KEY):
        typer.echo(f"warning: --plot without a file is deprecated (it will be refused in a later release): the "
                   f"figure goes beside --json by default ({json_out.with_suffix('.png')}); --plot FILE puts it "
                   "elsewhere, --no-plot writes none", err=True)
    if plot is not None and no_plot:
        raise ParameterError(f"--plot '{plot}' and --no-plot: give one (--no-plot writes no figure)")
    if robustness:
        if plot is not None:
            raise ParameterError(f"--plot '{plot}' goes with a single run; --robustness writes no figure")
        return None
    return None if no_plot else (plot if plot is not None else json_out.with_suffix(".png"))


def _plot_option(plot: Path | None) -> str:
    """The option an error about the figure's path names."""
    return "--plot" if plot is not None else "the figure beside --json (--no-plot for none)"


def _save_figure(fig: Any, path: Path, summary: dict, json_out: Path, *, dpi: int) -> None:
    """Write a reproduction's figure atomically, close it, and name it in the summary (relative to the JSON)."""
    import matplotlib.pyplot as plt

    try:
        path.parent.mkdir(parents=True, exist_ok=True)  # checked up front (make_parents), made like --json's
        chk.save_figure(fig, path, dpi=dpi)
    finally:
        plt.close(fig)
    summary["plot"] = os.path.relpath(path, json_out.parent)


def _out():
    """The console of the text results: a line is not wrapped at 80 columns when the output is no terminal (a log
    file had "... before zero speed: / 55.0 ms" split over two lines; a terminal wraps it by itself)."""
    from rich.console import Console

    return Console(soft_wrap=True)


def _agg() -> None:
    import matplotlib

    matplotlib.use("Agg")

# Options of the two reproductions that have a --robustness sweep (zhu-fujimoto, zhang2023), declared once.
SweepSeed = Annotated[Optional[int], typer.Option(
    "--seed", help="Measurement-noise seed (0 to 2**32 - 1; default 0). Not with --robustness, which runs its own "
                   "seeds.")]
SweepWorkers = Annotated[Optional[int], typer.Option(
    "--workers", help="With --robustness: worker processes of the local Dask cluster (default: the cores); 0 runs "
                      "in this process without Dask.")]
SweepScheduler = Annotated[Optional[str], typer.Option(
    "--scheduler", help="With --robustness: address of a running Dask scheduler (e.g. tcp://10.0.0.5:8786), or "
                        "'none'.")]
SweepOut = Annotated[Optional[str], typer.Option(
    "--out", help="With --robustness: folder for the Parquet results (one row per variant); a rerun computes only "
                  "the missing variants.")]

reproduce_app = typer.Typer(help="Reproduce the source papers' findings in simulation.", no_args_is_help=True,
                            rich_markup_mode=None)
app.add_typer(reproduce_app, name="reproduce")


@contextmanager
def _stages(console, name: str, total: int):
    """A stage progress bar on stderr for a reproduction; yields ``(bar, task, step)``,
    where ``step(label)`` closes the running stage and names the next one."""
    from rich.progress import BarColumn, Progress, TextColumn, TimeElapsedColumn

    with Progress(TextColumn("{task.description}"), BarColumn(), TimeElapsedColumn(), console=console) as bar:
        task = bar.add_task(name, total=total)
        started = [False]

        def step(label: str) -> None:
            if started[0]:
                bar.advance(task)
            started[0] = True
            bar.update(task, description=label)

        yield bar, task, step
        # the bar's last frame stays on the screen: it read "plot" (or the last stage) after the run had ended
        bar.update(task, description=f"{name}: done")


_EX_ZHU_FUJIMOTO = """\b
Examples:
  frictionkit reproduce zhu-fujimoto --stage fig2 --quick --json fig2.json
  frictionkit reproduce zhu-fujimoto --quick --json zf.json --plot table3.pdf
  frictionkit reproduce zhu-fujimoto --robustness --quick --workers 2 --json robust.json
"""


@reproduce_app.command("zhu-fujimoto", epilog=_EX_ZHU_FUJIMOTO, cls=_ReproduceCommand)
def zhu_fujimoto(
    json_out: Path = typer.Option(..., "--json", help="Where to write the JSON summary (the figure goes beside it)."),
    quick: bool = typer.Option(False, "--quick", help="Shorter runs (one reversal per case)."),
    seed: SweepSeed = None,
    plot: PlotFile = None,
    no_plot: NoPlot = False,
    nut_model: str = typer.Option("sliding", "--nut-model",
                                  help="Nut model: 'sliding' (Dahl on screw rotation), 'flank' "
                                       "(load transfer between groove flanks, tied to F_bn) or 'hertz' "
                                       "(flank friction on a preloaded Hertzian ball contact)."),
    stage: str = typer.Option("fig2", "--stage",
                              help="Stage: 'fig2' (default; inertia calibrated to the measured response, eq. 1 / "
                                   "Fig. 2: J = 0.01 kg m^2) or 'table1' (Table 1 inertias as printed, 4.3e-3 kg m^2)."),
    robustness: bool = typer.Option(False, "--robustness",
                                    help="Instead: the robustness sweep (noise seeds 0-2, each assumed stiffness "
                                         "x0.7 and x1.3: 13 variants; --quick runs per variant)."),
    workers: SweepWorkers = None,
    scheduler: SweepScheduler = None,
    out_dir: SweepOut = None,
) -> None:
    """Seed 001: Table 3 (sinc/Coulomb/sigmoid, post-only sigmoid), Fig. 5, Fig. 10 (l_d), the
    Table 2 selector and redesigned fast non-reverse stop, the Fig. 2 check."""
    from rich.console import Console
    from rich.table import Table

    from ..presets import zhu_fujimoto as zf_preset
    from ..reproduce import zhu_fujimoto as zf_rep

    chk.choice(nut_model, "--nut-model", zf_preset.NUT_MODELS)
    chk.choice(stage, "--stage", zf_preset.STAGES)
    if robustness and seed is not None:
        raise ParameterError("--seed goes with a single run; --robustness runs its own noise seeds (0, 1, 2)")
    seed = chk.integer(0 if seed is None else seed, "--seed", lo=0, hi=2**32 - 1)
    png = _plot_path(plot, no_plot, json_out, robustness=robustness)
    chk.outputs([], files={"--json": json_out}, plots={_plot_option(plot): png}, make_parents=True)
    workers, out_dir = _robustness_options(robustness, workers, scheduler, out_dir, json_out)
    if robustness:
        variants = zf_rep.robustness(quick=quick, nut_model=nut_model, stage=stage, progress=True, workers=workers,
                                     scheduler=scheduler, out=out_dir)
        laws = ("coulomb", "sinc", "sigmoid")
        t3 = {k: {law: v["table3"][law]["max_error_um"] for law in laws} for k, v in variants.items()}
        order = [k for k, v in t3.items() if v["sigmoid"] < v["sinc"] < v["coulomb"]]
        out_file = None if out_dir is None else out_dir / "zhu_fujimoto_robustness.parquet"
        chk.save_json({"quick": quick, "stage": stage, "nut_model": nut_model, "table3_max_error_um": t3,
                       "table3_order_holds": order, "variants": variants,
                       "out": None if out_file is None else str(out_file)}, json_out)
        tab = Table(title=f"robustness (stage {stage}, nut model {nut_model}): Table 3 max error [µm]")
        for c in ("variant", *laws):
            tab.add_column(c, justify="right")
        for k, v in t3.items():
            tab.add_row(k, *(f"{v[law]:.2f}" for law in laws))
        _out().print(tab)
        _out().print(f"Table 3 order sigmoid < sinc < Coulomb holds in {len(order)} of {len(t3)} variants")
        _out().print(f"wrote {json_out}" + (f" and {out_file}" if out_file else ""))
        return

    console = Console(stderr=True)
    with _stages(console, "zhu-fujimoto", total=3 + int(png is not None)) as (bar, task, step):

        result = zf_rep.run(quick=quick, seed=seed, nut_model=nut_model, stage=stage, progress=step)
        bar.advance(task)
        summary = result.to_dict()
        json_out.parent.mkdir(parents=True, exist_ok=True)
        if png is not None:
            bar.update(task, description="plot")
            _agg()
            from ..plotting.ballscrew import reproduction_figure

            fig, _ = reproduction_figure(result)
            _save_figure(fig, png, summary, json_out, dpi=110)
            bar.advance(task)
    chk.save_json(summary, json_out)

    tab = Table(title=f"Table 3: max tracking error during the reverse motion [µm] (stage: {stage}, "
                      f"nut model: {nut_model})")
    tab.add_column("law")
    tab.add_column("simulated", justify="right")
    tab.add_column("paper", justify="right")
    for law, v in summary["table3"].items():
        tab.add_row(law, f"{v['max_error_um']:.2f}", "-" if v["paper_um"] is None else f"{v['paper_um']:.2f}")
    out = _out()
    out.print(tab)
    ld = Table(title="Fig. 10: l_d / R over the deceleration")
    ld.add_column("case")
    ld.add_column("min", justify="right")
    ld.add_column("max", justify="right")
    for case, v in summary["ld"].items():
        ld.add_row(case, f"{v['min_ratio_before_zero']:.4f}", f"{v['max_ratio_before_zero']:.4f}")
    out.print(ld)
    def _ms(x):
        return "never" if x is None else f"{x:.1f} ms"

    f5b = summary["fig5b"]
    out.print(f"Fig. 5(b) (§5 reversal, sinc): motor input turns to braking before zero speed: "
              f"{_ms(f5b['motor_input_reverses_before_zero_ms'])}; drive force F_bn: "
              f"{_ms(f5b['drive_force_reverses_before_zero_ms'])}")
    for case, v in summary["fig5"].items():
        out.print(f"Fig. 5 {case.replace('_', ' ')} (sinc): max error {v['max_error_um']:.2f} µm; motor input "
                  f"turns {_ms(v['motor_input_reverses_before_zero_ms'])} before zero speed")
    s = summary["selector"]
    out.print(f"selector: {s['laws']} -> max {s['mixed_max_error_um']:.2f} µm; "
              f"best fixed {s['best_fixed_max_error_um']:.2f} µm")
    r2 = summary["table2_fast_non_reverse"]
    out.print(f"Table 2 fast non-reverse: original stop ({r2['original']['stop_ms']:.0f} ms, "
              f"{r2['original']['kind']}) max error {r2['original']['max_error_um']:.2f} µm; redesigned stop "
              f"({r2['redesigned']['stop_ms']:.0f} ms, {r2['redesigned']['kind']}) "
              f"{r2['redesigned']['max_error_um']:.2f} µm")
    if "fig2" in summary:
        g = summary["fig2"]
        out.print(f"Fig. 2 check (current -> theta_m): first anti-resonance {g['first_antiresonance_hz']:.1f} Hz, "
                  f"resonance {g['first_resonance_hz']:.1f} Hz; level vs eq. 1 fit in "
                  f"{g['band_hz'][0]:g}-{g['band_hz'][1]:g} Hz: {g['gain_offset_vs_eq1_db'][0]:+.1f} to "
                  f"{g['gain_offset_vs_eq1_db'][1]:+.1f} dB")
    out.print(f"wrote {json_out}" + (f" and {png}" if png is not None else ""))


def _robustness_options(robustness, workers, scheduler, out_dir, json_out):
    """Check --workers/--scheduler/--out of a reproduction's --robustness; the worker count and the folder."""
    if not robustness:
        if workers is not None or scheduler is not None or out_dir is not None:
            raise ParameterError("--workers, --scheduler and --out go with --robustness")
        return workers, None
    from .fleet import dask_options

    workers = dask_options(workers, scheduler)
    out_dir = chk.folder(out_dir, "--out")
    if out_dir is not None and out_dir.resolve() == json_out.resolve():  # else the sweep ran, then --json failed
        raise ParameterError(f"--out '{out_dir}' and --json '{json_out}' name the same path; --out is a folder")
    if out_dir is not None:
        from .._io import check_output_dir

        check_output_dir(out_dir, option="--out")  # writable, not a file, before the sweep
    return workers, out_dir


_EX_SDSS = """\b
Examples:
  frictionkit reproduce sdss --quick --json sdss.json
  frictionkit reproduce sdss --quick --json sdss.json --plot figs.pdf
"""


@reproduce_app.command("sdss", epilog=_EX_SDSS, cls=_ReproduceCommand)
def sdss(
    json_out: Path = typer.Option(..., "--json", help="Where to write the JSON summary (the figure goes beside it)."),
    quick: bool = typer.Option(False, "--quick", help="Fewer speeds and shorter runs (under a minute)."),
    seed: int = typer.Option(0, "--seed", help="Measurement-noise seed (0 to 2**16 - 1)."),
    plot: PlotFile = None,
    no_plot: NoPlot = False,
) -> None:
    """Seed 002 (SDSS 2.5 m telescope): the two-step LuGre estimation on the three simulated axes,
    Figs. 3, 4a-c, 6a-b, 7, 8 and sidereal tracking with LuGre feed-forward (ours)."""
    from rich.console import Console
    from rich.table import Table

    from ..reproduce import sdss as sdss_rep

    seed = chk.integer(seed, "--seed", lo=0, hi=2**16 - 1)
    png = _plot_path(plot, no_plot, json_out)
    chk.outputs([], files={"--json": json_out}, plots={_plot_option(plot): png}, make_parents=True)
    console = Console(stderr=True)
    with _stages(console, "sdss", total=4 + int(png is not None)) as (bar, task, step):

        result = sdss_rep.run(quick=quick, seed=seed, progress=step)
        bar.advance(task)
        summary = result.to_dict()
        json_out.parent.mkdir(parents=True, exist_ok=True)
        if png is not None:
            bar.update(task, description="plot")
            _agg()
            fig, _ = result.plot()
            _save_figure(fig, png, summary, json_out, dpi=100)
            bar.advance(task)
    chk.save_json(summary, json_out)
    out = _out()
    for name, ax in summary["axes"].items():
        tab = Table(title=f"{name}: truth vs identified (95 % interval)")
        for c in ("parameter", "truth", "identified", "95 % interval", "error %"):
            tab.add_column(c, justify="right")
        for k, p in ax["identified"].items():
            tv = ax["truth"].get(k)
            err = "-" if not tv else f"{100 * (p['value'] / tv - 1):+.2f}"
            tab.add_row(k, f"{tv:.5g}" if tv is not None else "-", f"{p['value']:.5g}",
                        f"[{p['ci95'][0]:.5g}, {p['ci95'][1]:.5g}]", err)
        out.print(tab)
        if ax.get("status"):  # an axis whose fit warned or failed said so only in the JSON and the report
            from ..report.adapters import _clip

            out.print(f"{name}: status {ax['status']}: {_clip(ax.get('message') or '')}", markup=False)
        if ax.get("nrmse_by_figure_percent"):
            out.print("velocity NRMSE [%] (identified / true model on the same data): " + ", ".join(
                f"{k} {v:.2f} / {ax['nrmse_true_model_percent'].get(k, float('nan')):.2f}"
                for k, v in ax["nrmse_by_figure_percent"].items()))
        for key in ("constant_velocity_screen", "hd_bench_screen"):
            if key in ax:
                s = ax[key]
                out.print(f"{key.replace('_', ' ')} (ripple <= {s['max_ripple_percent']:g} %): kept {s['kept']} of "
                          f"{s['runs']} runs; rejected: " + (", ".join(
                              f"{r['speed_rad_s']:+.3e} rad/s ({r['ripple_percent']:.1f} %)" for r in s["rejected"])
                              or "none"))
    trk = summary["sidereal_tracking_rms_arcsec"]
    out.print(f"sidereal tracking RMS (ours): no compensation {trk['no_compensation']:.4f} arcsec, "
              f"LuGre feed-forward {trk['lugre_feedforward']:.4f} arcsec")
    if summary.get("status"):  # the whole run's (worst of its parts: the rotator's maps too), as zhang2023 prints it
        from ..report.adapters import _clip

        out.print(f"status {summary['status']}: {_clip(summary.get('message') or '')}", markup=False)
    out.print(f"wrote {json_out}" + (f" and {png}" if png is not None else ""))


_EX_ZHANG2023 = """\b
Examples:
  frictionkit reproduce zhang2023 --quick --json zhang2023.json
  frictionkit reproduce zhang2023 --quick --json zhang2023.json --plot figs.svg
  frictionkit reproduce zhang2023 --robustness --workers 2 --out runs/ --json robust.json
"""


@reproduce_app.command("zhang2023", epilog=_EX_ZHANG2023, cls=_ReproduceCommand)
def zhang2023(
    json_out: Path = typer.Option(..., "--json", help="Where to write the JSON summary (the six-panel figure -- "
                                                       "Fig. 16, Tables 7-8, Figs. 17-20, crawling -- goes beside it)."),
    quick: bool = typer.Option(False, "--quick", help="Fewer plateaus and base speeds, shorter runs (< 60 s)."),
    seed: SweepSeed = None,
    plot: PlotFile = None,
    no_plot: NoPlot = False,
    robustness: bool = typer.Option(False, "--robustness",
                                    help="Instead: the robustness sweep (3 noise seeds, +-20 % on the preset's "
                                         "assumptions; --quick runs per variant); long."),
    workers: SweepWorkers = None,
    scheduler: SweepScheduler = None,
    out_dir: SweepOut = None,
) -> None:
    """Seed 000 (TDMS): WSIM vs ACIM (Table 7), LuGre vs GMS (Table 8), identified Tables 3-6,
    Fig. 16 hysteresis RMS, CDFS vs TDMS crawling (ours)."""
    from rich.console import Console
    from rich.table import Table

    from ..reproduce import zhang2023 as zr

    if robustness and seed is not None:
        raise ParameterError("--seed goes with a single run; --robustness runs its own noise seeds (0, 1, 2)")
    seed = chk.integer(0 if seed is None else seed, "--seed", lo=0, hi=2**32 - 1)
    png = _plot_path(plot, no_plot, json_out, robustness=robustness)
    chk.outputs([], files={"--json": json_out}, plots={_plot_option(plot): png}, make_parents=True)
    workers, out_dir = _robustness_options(robustness, workers, scheduler, out_dir, json_out)
    console = Console(stderr=True)
    if robustness:
        out = zr.robustness(quick=quick, progress=True, workers=workers, scheduler=scheduler, out=out_dir)
        chk.save_json(out, json_out)
        tab = Table(title=f"robustness: fraction of variants where each finding holds ({out['runtime_s']:.0f} s)")
        tab.add_column("finding")
        tab.add_column("holds", justify="right")
        for k, v in out["holds_fraction"].items():
            miss = out.get("not_evaluated", {}).get(k, {})   # e.g. a fit that failed in a variant
            tab.add_row(k, ("n/a" if v is None else f"{v:.2f}")
                        + (f" (not evaluated in {len(miss)}: {', '.join(miss)})" if miss else ""))
        _out().print(tab)
        _out().print("sensitivity ranking: " + ", ".join(out["ranking"]))
        _out().print(f"{out['computed']} variant(s) run, {out['skipped']} done before (skipped)"
                        + (f"; failed: {', '.join(out['failed'])}" if out["failed"] else ""))
        _out().print(f"wrote {json_out}" + (f" and {out['out']}" if out["out"] else ""))
        return
    with _stages(console, "zhang2023", total=10 + int(png is not None)) as (bar, task, step):

        result = zr.run(quick=quick, seed=seed, progress=step)
        bar.advance(task)
        summary = result.to_dict()
        summary["findings"] = zr.findings(summary)
        if png is not None:
            bar.update(task, description="plot")
            _agg()
            _save_figure(result.plot()[0].figure, png, summary, json_out, dpi=110)
            bar.advance(task)
    chk.save_json(summary, json_out)
    out = _out()
    for name, key in (("Table 7: ACIM vs WSIM", "method"), ("Table 8: LuGre vs GMS (WSIM)", "model")):
        tab = Table(title=f"{name}, worktable tracking error [µm] mean (std); paper beside")
        for c in ("speeds", "base mm/s", key, "simulated", "paper"):
            tab.add_column(c)
        for r in summary["table7" if key == "method" else "table8"]:
            if r["structure"] == "worktable":
                tab.add_row(r["speeds"], str(r["base_speed_mm_s"]), r[key],
                            f"{r['mean_um']:+.4f} ({r['std_um']:.4f})",
                            f"{r['paper_mean_um']:+.4g} ({r['paper_std_um']:.4g})")
        out.print(tab)
    h = summary["hysteresis_rms_force_N"]
    if h:
        out.print("Fig. 16 RMS force error [N]: reciprocating " + ", ".join(f"{k} {v:.2f}" for k, v in
                                                                            h["reciprocating"].items())
                  + "; unidirectional " + ", ".join(f"{k} {v:.2f}" for k, v in h["unidirectional"].items()))
    for r in summary["crawling"]:
        out.print(f"crawling {r['table_speed_um_s']:g} µm/s: CDFS ripple {r['cdfs_ripple_percent']:.1f} %, "
                  f"TDMS {r['tdms_ripple_percent']:.1f} %")
    # a finding a failed fit left unevaluated (holds None) printed as "no" (README walk, round walk3)
    verdict = {True: "yes", False: "no", None: "n/a (not evaluated)"}
    out.print("findings: " + ", ".join(f"{k}={verdict[v['holds']]}" for k, v in summary["findings"].items()))
    if summary.get("status"):  # was only in the JSON and the report: the text said nothing of WSIM's flags
        from ..report.adapters import _clip

        out.print(f"status {summary['status']}: {_clip(summary.get('message') or '')}", markup=False)
    out.print(f"wrote {json_out}" + (f" and {png}" if png is not None else ""))
