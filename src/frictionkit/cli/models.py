"""``frictionkit models``: the friction laws and machine presets frictionkit knows, with their sources.

A thin wrapper over :func:`frictionkit.catalog.catalog`.
"""

from __future__ import annotations

from typing import Optional

import typer

from . import _common as chk
from . import app


@app.command("models", epilog="\b\nExamples:\n  frictionkit models\n  frictionkit models --json -\n"
                              "  frictionkit models --json models.json")
def models(
    json_out: Optional[str] = typer.Option(None, "--json", help="Write the list as JSON to a file (- for stdout, "
                                           "instead of the text)."),
) -> None:
    """List the friction laws (registry) and machine presets, with their fields, units and sources."""
    chk.check_json_target(json_out, [])
    from ..catalog import catalog

    cat = catalog()
    chk.emit(cat.to_dict(), json_out, cat.summary())
    for name, err in cat.errors.items():
        typer.echo(f"warning: preset {name} could not be imported: {err}", err=True)
