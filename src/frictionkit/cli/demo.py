"""``frictionkit demo``: the main job of ``make demo``."""

from __future__ import annotations

from pathlib import Path

import typer

from . import _common as chk
from . import app


_EPILOG = """\b
Examples:
  frictionkit demo                        # writes out/demo/report.html
  frictionkit demo --out /tmp/demo
"""


@app.command("demo", epilog=_EPILOG)
def demo(out: str = typer.Option("out/demo", "--out", help="Folder for the report, plots and summary.")) -> None:
    """Simulate every friction law, identify on the shared real data, reproduce, and write a report."""
    from rich.progress import Progress, SpinnerColumn, TextColumn, TimeElapsedColumn

    from .._io import check_output_dir
    from ..report.demo import run_demo

    out = chk.folder(out, "--out")
    check_output_dir(out, option="--out")
    with Progress(SpinnerColumn(), TextColumn("{task.description}"), TimeElapsedColumn()) as bar:
        task = bar.add_task("demo", total=None)
        result = run_demo(out, progress=lambda label: bar.update(task, description=label))
    for note in result.get("skipped", []):
        typer.echo(f"warning: {note}", err=True)
    typer.echo(f"wrote {result['report']} ({len(result['files'])} figures) and {out / 'summary.txt'}")
