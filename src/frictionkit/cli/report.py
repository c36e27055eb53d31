"""``frictionkit report RESULT... -o DIR``: one self-contained HTML page from saved results.

Thin: the page is :class:`frictionkit.report.Report`, each file is read by its adapter in
:mod:`frictionkit.report.adapters` (dispatch on the file's own format / fields).
"""

from __future__ import annotations

import os
from pathlib import Path
from typing import Optional

import typer

from . import _common as chk
from . import app

_EPILOG = """\b
Examples:
  frictionkit report fit.json lugre.json compensate.json -o report/
  frictionkit report study.parquet fleet.parquet zf.json -o out/ --title "Axis 3, week 47" --json -
\b
Reads:
  identify ... --json, IdentificationResult.save_json   data, parameters with intervals and flags, fit plot
  fk.save_model (model files, bare law JSON)             parameters with units, provenance, steady state
  reproduce zhu-fujimoto | sdss | zhang2023 --json       findings beside the paper: holds / does not hold
  reproduce zhang2023 --robustness --json                fraction of variants where each finding holds
  compensate ... --json                                  tracking-error table [µm] (arcsec on a rotary axis)
  study --out S.parquet (or study --json)                per-compensator error statistics, box plot
  fleet identify --out R.parquet                         fleet numbers, distributions, flagged axes
  simulate --out traces.csv|.parquet                     time histories, hysteresis loop F(x)
Writes DIR/report.html (figures embedded, no external files), never over an input."""


@app.command("report", epilog=_EPILOG)
def report(
    results: list[Path] = typer.Argument(..., help="Result files (JSON, Parquet, trace CSV), in page order."),
    out: str = typer.Option(..., "-o", "--out", help="Folder for report.html (created if missing)."),
    title: str = typer.Option("frictionkit report", "--title", help="Title of the page."),
    json_out: Optional[str] = typer.Option(None, "--json", help="Write a JSON summary to a file (- for stdout, "
                                           "instead of the text)."),
) -> None:
    """Build one self-contained HTML report from saved results."""
    from .._io import check_not_input, check_output_dir
    from ..errors import DataError, ParameterError
    from ..report import Report

    if not out.strip():  # typer would turn '' into '.', the working folder
        raise ParameterError("-o/--out '': give a folder for report.html")
    out = Path(out)
    if not title.strip() or "\n" in title:
        raise ParameterError(f"--title {title!r}: must be a non-empty one-line text")
    seen: list[Path] = []
    for r in results:
        if not r.exists():
            raise DataError(f"result file '{r}': no such file")
        for q in seen:  # `report FIT FIT` built two identical sections (issue 13 round 8 leftover)
            if os.path.samefile(q, r):
                same = f"'{q}'" if str(q) == str(r) else f"'{q}' (the same file as '{r}')"
                raise DataError(f"result file {same} is given twice; each file makes one section of the page: "
                                "give it once")
        seen.append(r)
    check_output_dir(out, option="--out", inputs=results)
    page = out / "report.html"
    check_not_input(page, results, option="--out")
    chk.check_json_target(json_out, [*results, page])

    from rich.console import Console

    rep = Report(title)
    with Console(stderr=True).status("report: starting") as status:
        for i, r in enumerate(results, 1):
            status.update(f"report: reading {r} ({i}/{len(results)})")
            rep.add_file(r)
        status.update("report: writing the page")
        path = rep.write(out, inputs=results, footer=f"Built by 'frictionkit report' from {len(results)} file(s).")
    doc = {**rep.to_dict(), "report": str(path), "bytes": path.stat().st_size}
    text = "\n".join([rep.summary(), f"wrote {path}"])
    chk.emit(doc, json_out, text)
