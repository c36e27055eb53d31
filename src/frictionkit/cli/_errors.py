"""The one error-handling path of the ``frictionkit`` command line.

Every verb runs inside :class:`FrictionKitGroup`, the click group of the top-level
app, so every error ends the same way:

* frictionkit's own errors (:class:`~frictionkit.FrictionKitError`), a ``ValueError``
  or an ``OSError`` print ONE line ``error: <message>`` on stderr;
* a usage error (unknown option, ``--seed abc``) prints one line too, with the
  ``--help`` to look at;
* Ctrl-C prints ``error: interrupted`` and exits with 130 (``error: interrupted: <what is left>`` where
  a verb can say what it leaves behind and how to go on: ``fleet simulate`` resumes);
* anything else is a bug: one line naming the exception type and asking for a rerun
  with ``--debug``.

Python warnings print as one ``warning: ...`` line each; numpy's floating-point
warnings ("overflow encountered in ...") are dropped — the result or the error says
what went wrong (``--debug`` shows them).

``frictionkit --debug ...`` (``--debug`` may also come after the verb) or
``FRICTIONKIT_DEBUG=1`` prints the traceback before that line.

Exit status: 0 success; 1 a computation could not be carried out
(:class:`~frictionkit.SimulationError`, :class:`~frictionkit.IdentificationError`,
a full disk, an unexpected error); 2 bad input (options, files, parameters, data);
130 interrupted.
"""

from __future__ import annotations

import contextlib
import os
import sys
import traceback
import warnings
from typing import Any

import typer
from typer.core import TyperGroup

#: Exit status for bad input (options, files, parameters, data), as for usage errors.
EXIT_BAD_INPUT = 2
#: Exit status when a computation or a write could not be carried out, or on a bug.
EXIT_FAILED = 1
#: Exit status after Ctrl-C (128 + SIGINT).
EXIT_INTERRUPTED = 130

_BAD_INPUT_OS = (FileNotFoundError, IsADirectoryError, NotADirectoryError, PermissionError, FileExistsError)
_DEBUG_FLAG = "--debug"


#: Key of the command line's words as typed in the click context's ``meta`` (shared by the whole context
#: tree of one invocation), for checks that the parsed values hide: a Path option drops a trailing '/'
#: (`--json DIR/sub/` arrived as 'DIR/sub' and became a file named 'sub', issue 13 round 10). Kept on the
#: context, not in a module global: a global outlived its invocation (a second `app` call in one process, as
#: the tests and the campaign make, or a library caller of a verb's function, read the previous words).
TYPED_ARGS_KEY = "frictionkit.typed_args"


def _typed_args() -> tuple[str, ...]:
    """The words of the invocation running now (empty outside one)."""
    cx = _click_module("globals")
    ctx = cx.get_current_context(silent=True)
    return ctx.meta.get(TYPED_ARGS_KEY, ()) if ctx is not None else ()


def typed_value(option: str, value: Any) -> str:
    """The text typed for ``option`` whose parsed value is ``value`` (``str(value)`` when not found)."""
    typed = _typed_args()
    for i, word in enumerate(typed):
        if word.startswith(option + "="):
            text = word[len(option) + 1:]
        elif word == option and i + 1 < len(typed):
            text = typed[i + 1]
        else:
            continue
        if text.rstrip("/") == str(value).rstrip("/") or os.path.normpath(text) == os.path.normpath(str(value)):
            return text
    return str(value)


def debug_requested(ctx: Any = None) -> bool:
    """``--debug`` given (on the command line or as ``FRICTIONKIT_DEBUG=1``)."""
    if os.environ.get("FRICTIONKIT_DEBUG", "").strip().lower() in ("1", "true", "yes", "on"):
        return True
    while ctx is not None:
        if ctx.params.get("debug"):
            return True
        ctx = ctx.parent
    return False


def _one_line(text: str) -> str:
    return " ".join(str(text).split())


def describe(exc: BaseException) -> tuple[int, str]:
    """Exit status and the one-line message (without ``error: ``) for ``exc``."""
    from ..errors import DataError, FrictionKitError, ParameterError

    if isinstance(exc, KeyboardInterrupt):  # a long verb may say what it leaves behind (fleet simulate)
        return EXIT_INTERRUPTED, "interrupted" + (f": {_one_line(exc)}" if str(exc) else "")
    if isinstance(exc, OSError):
        if exc.strerror and exc.filename:
            msg = f"'{exc.filename}': {exc.strerror}"
        else:
            msg = exc.strerror or str(exc) or type(exc).__name__
        code = EXIT_BAD_INPUT if isinstance(exc, _BAD_INPUT_OS) else EXIT_FAILED
        return code, _one_line(msg)
    if isinstance(exc, (ParameterError, DataError)):
        return EXIT_BAD_INPUT, _one_line(exc)
    if isinstance(exc, FrictionKitError):
        return EXIT_FAILED, _one_line(exc)
    if isinstance(exc, (UnicodeError, ValueError)) and str(exc):
        return EXIT_BAD_INPUT, _one_line(exc)
    detail = _one_line(exc)
    return EXIT_FAILED, (f"unexpected {type(exc).__name__}" + (f": {detail}" if detail else "")
                         + " — this is a bug in frictionkit; rerun with --debug for the traceback and report it")


def report(exc: BaseException, *, debug: bool) -> int:
    """Print ``exc`` (traceback first with ``debug``) and return the exit status."""
    code, msg = describe(exc)
    if debug:
        traceback.print_exception(exc, file=sys.stderr)
    typer.echo(f"error: {msg}", err=True)
    return code


def _show_warning(message, category, filename, lineno, file=None, line=None) -> None:
    typer.echo(f"warning: {_one_line(message)}", err=True)


@contextlib.contextmanager
def _one_line_warnings(debug: bool):
    with warnings.catch_warnings():
        if not debug:
            warnings.showwarning = _show_warning
            warnings.filterwarnings("ignore", message=r".*encountered in", category=RuntimeWarning)
        yield


def _usage_line(exc: Any) -> str:
    msg = _one_line(exc.format_message())
    ctx = getattr(exc, "ctx", None)
    if ctx is not None:
        msg += f" (see '{ctx.command_path} --help')"
    return msg


def jit_disabled_note() -> str | None:
    """One line when ``NUMBA_DISABLE_JIT`` is set: the kernels then run as plain Python.

    Round 6 of issue 13 ran the README examples so: every result equal to the compiled run
    (bit for bit on LuGre, Dahl, GMS, the batch and a machine), but the README's first
    example (1,000 batch sets of 40,001 samples) took 429 s instead of seconds without a word.
    """
    value = os.environ.get("NUMBA_DISABLE_JIT", "").strip()
    if value in ("", "0"):
        return None
    return (f"NUMBA_DISABLE_JIT={value}: the simulation kernels run as plain Python, the same results "
            "much slower (unset it for compiled speed)")


def _click_module(name: str) -> Any:
    """``click.<name>`` (``exceptions``, ``globals``) of the click typer runs on."""
    import importlib

    try:  # typer >= 0.20 vendors click
        return importlib.import_module(f"typer._click.{name}")
    except ImportError:  # pragma: no cover - older typer on click
        return importlib.import_module(f"click.{name}")


def _click_exceptions() -> Any:
    return _click_module("exceptions")


class FrictionKitGroup(TyperGroup):
    """The top-level click group: runs every verb inside the one error-handling path."""

    def parse_args(self, ctx: Any, args: list[str]) -> list[str]:
        ctx.meta[TYPED_ARGS_KEY] = tuple(args)
        # accept --debug anywhere before "--" (users append it when asked to rerun)
        if _DEBUG_FLAG in args:
            end = args.index("--") if "--" in args else len(args)
            if _DEBUG_FLAG in args[:end]:
                args = [_DEBUG_FLAG] + [a for a in args[:end] if a != _DEBUG_FLAG] + args[end:]
        cx = _click_exceptions()
        try:
            return super().parse_args(ctx, args)
        except cx.NoArgsIsHelpError:
            raise
        except cx.UsageError as exc:  # `frictionkit --bogus` printed click's three-line usage block (round 10)
            typer.echo(f"error: {_usage_line(exc)}", err=True)
            raise typer.Exit(code=exc.exit_code) from None
        except KeyboardInterrupt as exc:  # typer turned it into a silent exit 130 (Ctrl-C while parsing, round 10)
            raise typer.Exit(code=report(exc, debug=debug_requested(ctx))) from None

    def invoke(self, ctx: Any) -> Any:
        cx = _click_exceptions()
        try:
            with _one_line_warnings(debug_requested(ctx)):
                note = jit_disabled_note()
                if note:
                    typer.echo(f"warning: {note}", err=True)
                return super().invoke(ctx)
        except (typer.Exit, typer.Abort, cx.NoArgsIsHelpError):
            raise
        except cx.UsageError as exc:
            if debug_requested(ctx):
                traceback.print_exception(exc, file=sys.stderr)
            typer.echo(f"error: {_usage_line(exc)}", err=True)
            raise typer.Exit(code=exc.exit_code) from None
        except cx.ClickException:
            raise
        except (Exception, KeyboardInterrupt) as exc:
            raise typer.Exit(code=report(exc, debug=debug_requested(ctx))) from None
