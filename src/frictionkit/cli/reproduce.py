"""``frictionkit reproduce ...``: run a paper's virtual experiments, write JSON and a plot.

Options and output paths are checked before the (long) run; the files are written
atomically (:mod:`frictionkit._io`), so a failed write keeps the previous result.
"""

from __future__ import annotations

from pathlib import Path

import typer

from . import _common as chk
from . import app

reproduce_app = typer.Typer(help="Reproduce the source papers' findings in simulation.", no_args_is_help=True,
                            rich_markup_mode=None)
app.add_typer(reproduce_app, name="reproduce")


@reproduce_app.command("zhu-fujimoto")
def zhu_fujimoto(
    json_out: Path = typer.Option(..., "--json", help="Where to write the JSON summary (PNG goes beside it)."),
    quick: bool = typer.Option(False, "--quick", help="Shorter runs (one reversal per case)."),
    seed: int = typer.Option(0, "--seed", help="Measurement-noise seed (0 to 2**32 - 1)."),
    plot: bool = typer.Option(True, "--plot/--no-plot", help="Write the Fig. 10/15-like PNG beside the JSON."),
    nut_model: str = typer.Option("sliding", "--nut-model",
                                  help="Nut model: 'sliding' (Dahl on screw rotation), 'flank' "
                                       "(load transfer between groove flanks, tied to F_bn) or 'hertz' "
                                       "(flank friction on a preloaded Hertzian ball contact)."),
    stage: str = typer.Option("fig2", "--stage",
                              help="Stage: 'fig2' (default; inertia calibrated to the measured response, eq. 1 / "
                                   "Fig. 2: J = 0.01 kg m^2) or 'table1' (Table 1 inertias as printed, 4.3e-3 kg m^2)."),
) -> None:
    """Seed 001: Table 3 (sinc/Coulomb/sigmoid, post-only sigmoid), Fig. 5, Fig. 10 (l_d), the
    Table 2 selector and redesigned fast non-reverse stop, the Fig. 2 check."""
    from rich.console import Console
    from rich.progress import BarColumn, Progress, TextColumn, TimeElapsedColumn
    from rich.table import Table

    from ..presets import zhu_fujimoto as zf_preset
    from ..reproduce import zhu_fujimoto as zf_rep

    chk.choice(nut_model, "--nut-model", zf_preset.NUT_MODELS)
    chk.choice(stage, "--stage", zf_preset.STAGES)
    seed = chk.integer(seed, "--seed", lo=0, hi=2**32 - 1)
    png = json_out.with_suffix(".png")
    chk.outputs([], files={"--json": json_out}, plots={"the plot beside --json": png} if plot else {},
                make_parents=True)

    console = Console(stderr=True)
    with Progress(TextColumn("{task.description}"), BarColumn(), TimeElapsedColumn(), console=console) as bar:
        task = bar.add_task("zhu-fujimoto", total=3 + int(plot))
        started = [False]

        def step(label: str) -> None:
            if started[0]:
                bar.advance(task)
            started[0] = True
            bar.update(task, description=label)

        result = zf_rep.run(quick=quick, seed=seed, nut_model=nut_model, stage=stage, progress=step)
        bar.advance(task)
        summary = result.summary()
        json_out.parent.mkdir(parents=True, exist_ok=True)
        if plot:
            bar.update(task, description="plot")
            import matplotlib

            matplotlib.use("Agg")
            import matplotlib.pyplot as plt

            from ..plotting.ballscrew import reproduction_figure

            fig, _ = reproduction_figure(result)
            try:
                chk.save_figure(fig, png, dpi=110)
            finally:
                plt.close(fig)
            summary["plot"] = png.name
            bar.advance(task)
    chk.save_json(summary, json_out)

    tab = Table(title=f"Table 3: max tracking error during the reverse motion [µm] (stage: {stage}, "
                      f"nut model: {nut_model})")
    tab.add_column("law")
    tab.add_column("simulated", justify="right")
    tab.add_column("paper", justify="right")
    for law, v in summary["table3"].items():
        tab.add_row(law, f"{v['max_error_um']:.2f}", "-" if v["paper_um"] is None else f"{v['paper_um']:.2f}")
    out = Console()
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
    out.print(f"wrote {json_out}")
