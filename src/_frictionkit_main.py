"""Console-script entry point of ``frictionkit``: Ctrl-C while the package imports is one line too.

Importing :mod:`frictionkit` (numpy, scipy, numba) takes one to a few seconds, and the
console script would otherwise import it before any error handling exists: an interrupt
in that window ended in a Python traceback. This module imports nothing heavy itself;
everything after the import goes through :mod:`frictionkit.cli._errors`.
"""

from __future__ import annotations

import sys


def _interrupted() -> None:
    sys.stderr.write("error: interrupted\n")
    sys.exit(130)


def _fast_version() -> bool:
    """``frictionkit --version`` alone: answered from the installed metadata, without importing frictionkit."""
    if sys.argv[1:] != ["--version"]:
        return False
    from importlib.metadata import PackageNotFoundError, version

    try:
        sys.stdout.write(f"frictionkit {version('frictionkit')}\n")
    except PackageNotFoundError:  # running from a source tree that is not installed: ask the package
        return False
    return True


def main() -> None:
    if _fast_version():
        return
    try:
        from frictionkit.cli import main as cli_main
    except KeyboardInterrupt:
        _interrupted()
    try:
        cli_main()
    except KeyboardInterrupt:  # outside a verb, e.g. while the options are parsed
        _interrupted()


if __name__ == "__main__":
    main()
