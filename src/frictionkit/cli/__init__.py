"""The ``frictionkit`` command line: thin wrappers around the public API.

Each command group lives in its own module and is registered here. Every verb runs
inside the one error-handling path of :mod:`frictionkit.cli._errors` (one ``error:``
line on stderr, ``--debug`` for the traceback), and every result file is written by
:mod:`frictionkit._io` (atomically, never over an input).

Help texts are plain text (``rich_markup_mode=None``): units in square brackets,
``[s]`` or ``[N·s/m]``, are printed as written.
"""

from __future__ import annotations

import sys

import typer

from ._errors import FrictionKitGroup
from ._errors import report as _report_error  # 'report' is also the name of the report verb's module

app = typer.Typer(
    name="frictionkit",
    help="Model, identify, simulate and compensate friction in precision motion axes.",
    cls=FrictionKitGroup,
    no_args_is_help=True,
    # '-h' as well: 'frictionkit identify static -h' was "No such option: -h" (issue 13 round 11, family S);
    # click passes the names on to every verb's context
    context_settings={"help_option_names": ["-h", "--help"]},
    add_completion=False,
    pretty_exceptions_enable=False,
    rich_markup_mode=None,
)


def _print_version(value: bool) -> None:
    if value:
        from .. import __version__

        typer.echo(f"frictionkit {__version__}")
        raise typer.Exit()


@app.callback()
def _root(
    debug: bool = typer.Option(False, "--debug",
                               help="On an error, print the full traceback (also FRICTIONKIT_DEBUG=1)."),
    version: bool = typer.Option(False, "--version", callback=_print_version, is_eager=True,
                                 help="Print the frictionkit version and exit."),
) -> None:
    """Model, identify, simulate and compensate friction in precision motion axes."""


def _register() -> None:
    """Import the command modules; each adds its commands to ``app``."""
    for name in ("demo", "identify", "reproduce", "fleet", "models", "simulate", "export", "compensate", "report"):
        try:
            __import__(f"{__name__}.{name}")
        except ModuleNotFoundError as exc:  # command group not built yet
            if exc.name != f"{__name__}.{name}":
                raise


def main() -> None:
    try:
        _register()
    except KeyboardInterrupt as exc:  # Ctrl-C while the command modules import
        sys.exit(_report_error(exc, debug=False))
    app()
