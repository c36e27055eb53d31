"""``frictionkit export MODEL.json --format csv|c|st --out FILE``: a model for a drive or a PLC.

Thin: :meth:`frictionkit.models.files.ModelFile.load` reads the model,
:func:`frictionkit.export.export_model` writes the text (see its module docstring for
what each format holds), written atomically.
"""

from __future__ import annotations

from pathlib import Path
from typing import Optional

import typer

from . import _common as chk
from . import app

_EPILOG = """\b
Examples:
  frictionkit export fit.json --format csv --out friction_table.csv --v-max 0.05 --points 1001
  frictionkit export lugre.json --format c --out friction.h --name axis1_friction
  frictionkit export lugre.json --format st --out friction.st --json -
  frictionkit export fit.json --format json --out model.json
\b
csv: steady-state map F(v) on a uniform grid. json: a model file (frictionkit.model/1),
e.g. an identification result reduced to its model. c: C99 header, steady-state map and, for
LuGre/Dahl, a discrete-time update with state. st: IEC 61131-3 FUNCTION_BLOCK, same."""


@app.command("export", epilog=_EPILOG)
def export(
    model: Path = typer.Argument(..., help="Model file: 'frictionkit.model/1' JSON, an identification result or a "
                                 "law's JSON form."),
    fmt: str = typer.Option(..., "--format", help="csv (lookup table), json (model file), c (C header) or st (IEC 61131-3 structured "
                            "text)."),
    out: Path = typer.Option(..., "--out", help="File to write."),
    name: Optional[str] = typer.Option(None, "--name", help="C function prefix (default fk_friction) or function "
                                       "block name (default FK_Friction)."),
    v_max: Optional[float] = typer.Option(None, "--v-max", help="csv: grid half-width [m/s] (default 10 x the "
                                          "largest Stribeck velocity)."),
    points: Optional[int] = typer.Option(None, "--points", help="csv: grid points, odd (v = 0 is one of them; "
                                         "default 201)."),
    json_out: Optional[str] = typer.Option(None, "--json", help="Write a JSON summary to a file (- for stdout, "
                                           "instead of the text)."),
) -> None:
    """Export a friction model as a lookup table (CSV), a C header or IEC 61131-3 structured text."""
    from ..errors import ParameterError
    from ..export import FORMATS

    chk.choice(fmt, "--format", FORMATS)
    if fmt != "csv" and (v_max is not None or points is not None):  # were silently ignored
        given = " and ".join(k for k, x in (("--v-max", v_max), ("--points", points)) if x is not None)
        raise ParameterError(f"{given}: only --format csv has a grid; --format {fmt} does not use it "
                             "(leave it out)")
    if v_max is not None:
        from ..export import V_MAX_RANGE

        chk.between(chk.positive(v_max, "--v-max"), "--v-max", *V_MAX_RANGE, "[m/s or rad/s]; outside it the grid's steps lose precision "
                    "or the map overflows")
    if points is not None:
        chk.integer(points, "--points", lo=3, hi=1_000_001)
    if points is not None and points % 2 == 0:
        raise ParameterError(f"--points {points}: must be odd (so that v = 0 is a grid point)")
    chk.outputs([model], files={"--out": out, **({"--json": Path(json_out)} if json_out not in (None, "-") else {})})

    from .._io import atomic_write_text
    from ..export import export_model
    from ..models.base import kernel_family, law_entry
    from ..models.files import ModelFile

    mf = ModelFile.load(model)
    prov = dict(mf.provenance)
    if fmt == "json":  # the new file says where it came from and which frictionkit wrote it
        from datetime import datetime, timezone

        from .. import __version__

        prov["converted_from"] = {"file": str(model), "format": mf.format}
        prov["converted"] = datetime.now(timezone.utc).isoformat(timespec="seconds")
        prov.setdefault("frictionkit_version", __version__)
    text = export_model(mf.model, fmt, name=name, v_max=v_max, points=points, units=mf.units, provenance=prov)
    atomic_write_text(out, text)
    family = kernel_family(mf.model)
    what = {"csv": "steady-state map", "json": "model file", "c": "steady-state map" + (" and discrete-time update with state"
                                                                  if family == "lugre" else ""),
            "st": "discrete-time update with state" if family == "lugre" else "steady-state map"}[fmt]
    doc = {"model": str(model), "law": law_entry(mf.model).name, "family": family, "format": fmt, "out": str(out),
           "contents": what, "bytes": len(text.encode("utf-8")), "units": dict(mf.units)}
    if fmt == "csv":
        doc["rows"] = text.count("\n") - 1
    chk.emit(doc, json_out, f"wrote {out}: {doc['law']} {what} ({fmt}, {doc['bytes']} bytes)")
