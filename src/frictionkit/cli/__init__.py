"""The ``frictionkit`` command line: thin wrappers around the public API.

Each command group lives in its own module and is registered here.
"""

from __future__ import annotations

import typer

app = typer.Typer(
    name="frictionkit",
    help="Model, identify, simulate and compensate friction in precision motion axes.",
    no_args_is_help=True,
    add_completion=False,
    pretty_exceptions_enable=False,
)


def _register() -> None:
    """Import the command modules; each adds its commands to ``app``."""
    for name in ("demo", "identify", "reproduce"):
        try:
            __import__(f"{__name__}.{name}")
        except ModuleNotFoundError as exc:  # command group not built yet
            if exc.name != f"{__name__}.{name}":
                raise


def main() -> None:
    _register()
    app()
