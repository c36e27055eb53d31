"""Validation of command-line values at the boundary, and the CLI's file helpers.

Every check raises :class:`~frictionkit.ParameterError` or :class:`~frictionkit.DataError`
naming the option, the value and the rule, so the one error path of
:mod:`frictionkit.cli._errors` prints a one-line message that names the cause.
"""

from __future__ import annotations

import json
import math
from collections.abc import Iterable, Mapping
from pathlib import Path
from typing import Any

from .._io import atomic_open, atomic_write_text, check_output_file, missing_reason
from .._validate import HUGE
from ..errors import DataError, ParameterError
from ._errors import typed_value

#: Bounds of ``--*-scale`` factors (|scale|). Unit conversions in practice span
#: nm -> m (1e-9) to V -> N gains of a few hundred; outside 1e-12 ... 1e12 the scaled data
#: overflow or vanish in the fits.
SCALE_MIN, SCALE_MAX = 1e-12, 1e12

#: Largest ``--elements`` of ``identify presliding``: one branch rarely resolves more than a dozen
#: breakpoints. The breakpoint search takes (round 10, CPU on 2 busy cores) 0.3 s at 8, 3 s at 16, 5 s
#: at 32 on a 501-sample branch and 14 s at 32 on a 2,001-sample one (whole command 23 s); it took
#: 9 min at 32 before the candidates of a breakpoint were scored in one projection.
MAX_PRESLIDING_ELEMENTS = 32

#: Largest ``--starts`` of ``identify output-error``. The screening simulates every start
#: over the whole record: about 1-2 ms per start on 8,000 samples (4,000 starts: 8 s), so
#: 10,000 starts take tens of seconds and a million would run for hours.
MAX_OUTPUT_ERROR_STARTS = 10_000


# --------------------------------------------------------------------------- numbers
def _finite(value: Any, option: str) -> float:
    try:
        out = float(value)
    except (TypeError, ValueError, OverflowError):
        raise ParameterError(f"{option} {value!r}: must be a number") from None
    if not math.isfinite(out):
        raise ParameterError(f"{option} {value!r}: must be finite (not nan or inf)")
    return out


def scale(value: Any, option: str) -> float:
    """A unit factor: finite, non-zero, ``SCALE_MIN <= |value| <= SCALE_MAX`` (negative flips the sign)."""
    out = _finite(value, option)
    if not SCALE_MIN <= abs(out) <= SCALE_MAX:
        raise ParameterError(f"{option} {value!r}: a unit factor must satisfy {SCALE_MIN:g} <= |factor| <= "
                             f"{SCALE_MAX:g} (e.g. 1e-3 for mm -> m)")
    return out


def positive(value: Any, option: str, *, sized: bool = False) -> float:
    """A finite number > 0 (with ``sized``, also of a physical size: :func:`magnitude`)."""
    out = (magnitude if sized else _finite)(value, option)
    if out <= 0:
        raise ParameterError(f"{option} {value!r}: must be > 0")
    return out


def nonnegative(value: Any, option: str, *, sized: bool = False) -> float:
    """A finite number >= 0 (with ``sized``, also of a physical size: :func:`magnitude`)."""
    out = (magnitude if sized else _finite)(value, option)
    if out < 0:
        raise ParameterError(f"{option} {value!r}: must be >= 0")
    return out


def magnitude(value: Any, option: str) -> float:
    """A finite physical value whose square and (if not 0) reciprocal are finite: ``|value|`` in
    ``[1/HUGE, HUGE]`` or 0. Was (round 10): ``--Fs 1e308`` failed as "GMS.C = inf", ``--mass 1e308``
    as an "unexpected ZeroDivisionError", ``--mass 1e-320`` ran 83 s into a non-finite state, and
    ``--input u=1e200`` ran although the same sample in an input file is refused."""
    out = _finite(value, option)
    if abs(out) > HUGE:
        raise ParameterError(f"{option} {value!r}: beyond {HUGE:.0e}, a unit slip (its square overflows)")
    if 0 < abs(out) < 1.0 / HUGE:
        raise ParameterError(f"{option} {value!r}: below {1.0 / HUGE:.0e}, a unit slip (its reciprocal overflows)")
    return out


def between(value: Any, option: str, lo: float, hi: float, why: str) -> float:
    """A finite number in ``[lo, hi]``, checked here so the error names the option (the library's bound
    named its own parameter: ``--v-max 1e308`` was "export: v_max = 1e+308", round 10)."""
    out = _finite(value, option)
    if not lo <= out <= hi:
        raise ParameterError(f"{option} {value!r}: must be in {lo:g} ... {hi:g} ({why})")
    return out


def optional(check, value: Any, option: str, **how: Any) -> Any:
    """``check(value, option, **how)`` unless ``value`` is None."""
    return None if value is None else check(value, option, **how)


def integer(value: int, option: str, *, lo: int, hi: int | None = None, why: str = "") -> int:
    """An integer in ``[lo, hi]``."""
    if value < lo or (hi is not None and value > hi):
        rng = f"between {lo} and {hi}" if hi is not None else f">= {lo}"
        raise ParameterError(f"{option} {value}: must be {rng}" + (f" ({why})" if why else ""))
    return int(value)


def fraction(value: Any, option: str, *, below: float = 0.5) -> float:
    """A number in ``[0, below)``."""
    out = _finite(value, option)
    if not 0.0 <= out < below:
        raise ParameterError(f"{option} {value!r}: must be >= 0 and < {below:g}")
    return out


def choice(value: str, option: str, allowed: Iterable[str]) -> str:
    allowed = tuple(allowed)
    if value not in allowed:
        raise ParameterError(f"{option} {value!r}: must be one of {', '.join(allowed)}")
    return value


# --------------------------------------------------------------------------- units
def units(rotary: bool, force_unit: str | None, velocity_unit: str | None) -> dict[str, str]:
    """Unit labels of the signals after scaling: ``{"F", "v", "x"}``.

    ``--rotary`` gives N·m, rad/s and rad; ``--force-unit`` / ``--velocity-unit`` override
    either (the position unit is the velocity unit without ``/s``). They label the JSON,
    the tables and the plots; the numbers are converted by the ``--*-scale`` factors.
    """
    F = force_unit if force_unit is not None else ("N·m" if rotary else "N")
    v = velocity_unit if velocity_unit is not None else ("rad/s" if rotary else "m/s")
    for option, label in (("--force-unit", F), ("--velocity-unit", v)):
        if not label.strip() or any(c in label for c in "\n\r"):
            raise ParameterError(f"{option} {label!r}: must be a non-empty one-line unit label (e.g. N·m, rad/s)")
    x = v[:-2] if v.endswith("/s") else ("rad" if rotary else "m")
    return {"F": F, "v": v, "x": x}


def where_items(items: Iterable[str] | None) -> dict[str, str]:
    """``--where COLUMN=VALUE`` options as a mapping."""
    out = {}
    for it in items or []:
        if "=" not in it or not it.split("=", 1)[0].strip():
            raise DataError(f"--where {it!r}: expected COLUMN=VALUE")
        k, v = it.split("=", 1)
        k, v = k.strip(), v.strip()
        if k in out and out[k] != v:
            # was: the last value silently replaced the first (--where drive_id=1 --where drive_id=2 fitted drive 2)
            raise DataError(f"--where {k}={out[k]} and --where {k}={v}: one value per column (the rows must match "
                            "every --where); run once per value")
        out[k] = v
    return out


# --------------------------------------------------------------------------- output files
def folder(value: str | None, option: str) -> Path | None:
    """A folder option given as text: ``""`` (an unset shell variable, ``--out "$DIR"``) is refused.

    Was (issue 13 round 9): typer turns ``""`` into ``Path(".")``, so ``fleet simulate --out ""`` wrote
    the fleet into the working folder and ``demo --out ""`` its report, without a word.
    """
    if value is None:
        return None
    if not value.strip():
        raise ParameterError(f"{option} {value!r}: give a folder (an empty value would mean the working folder; "
                             "write '.' for that)")
    return Path(value)


def input_files(inputs: Mapping[str, Path | None]) -> None:
    """Check every input file up front, named by its option: it exists, is a file and can be read.

    Was (issue 13 round 6): ``identify ... --validate 0.5`` fitted first and then failed on the
    missing validation record.
    """
    import os

    for option, path in inputs.items():
        if path is None:
            continue
        p = Path(path)
        if not p.exists():
            raise DataError(f"{option} '{p}': {missing_reason(p)}")
        if p.is_dir():
            raise DataError(f"{option} '{p}' is a folder; give a data file")
        if not os.access(p, os.R_OK):
            raise DataError(f"{option} '{p}': the file cannot be read (permission denied)")


def outputs(inputs: Iterable[Path | None] | Mapping[str, Path | None], *,
            plots: Mapping[str, Path | None] = {},  # noqa: B006 (read-only)
            files: Mapping[str, Path | None] = {}, make_parents: bool = False) -> None:  # noqa: B006
    """Check every output path up front: writable folder, not an input, plots in a known format, all distinct.

    ``inputs`` given as ``{option: path}`` are also checked as input files (:func:`input_files`).
    """
    if isinstance(inputs, Mapping):
        input_files(inputs)
        inputs = inputs.values()
    inputs = [p for p in inputs if p is not None]
    seen: dict[str, str] = {}
    for opts, is_plot in ((files, False), (plots, True)):
        for option, path in opts.items():
            if path is None:
                continue
            if str(path) == "-":  # was written as a file named '-' in the working folder (issue 13 round 4)
                raise DataError(f"{option} -: this verb writes {option} to a file, not to stdout; give a file name")
            out = check_output_file(typed_value(option, path), option=option, inputs=inputs, plot=is_plot,
                                    make_parents=make_parents)
            key = str(out.resolve())
            if key in seen:
                raise DataError(f"{option} '{path}' and {seen[key]} name the same file")
            seen[key] = f"{option} '{path}'"


def save_plot(result: Any, path: Path, *, dpi: int = 120) -> None:
    """``result.plot()`` written atomically to ``path`` (format from the extension)."""
    import matplotlib

    matplotlib.use("Agg", force=False)
    import matplotlib.pyplot as plt

    ax = result.plot()
    fig = ax.figure
    try:
        fig.tight_layout()
        save_figure(fig, path, dpi=dpi)
    finally:
        plt.close(fig)


def save_figure(fig: Any, path: Path, *, dpi: int = 120) -> None:
    """``fig.savefig`` through the atomic writer."""
    fmt = Path(path).suffix.lower().lstrip(".") or "png"
    with atomic_open(path, "wb") as f:
        fig.savefig(f, format=fmt, dpi=dpi)


def save_json(doc: Any, path: Path, *, indent: int = 2) -> None:
    """A JSON document written atomically."""
    atomic_write_text(path, json.dumps(doc, indent=indent, ensure_ascii=False) + "\n")


# --------------------------------------------------------------------------- static-map JSON
def load_static_json(path: Path, option: str = "--static-json") -> Any:
    """The static map in a JSON written by ``identify static --json`` (one ``DataError`` naming the option).

    The checks are the library's (:func:`frictionkit.identify.start_values.load_static_law`).
    """
    from ..identify.start_values import load_static_law

    return load_static_law(path, where=f"{option} '{path}'")


# --------------------------------------------------------------------------- --json PATH|-
def check_json_target(json_out: str | None, inputs: Iterable[Path | None]) -> None:
    """Check a ``--json PATH`` up front (``-`` means stdout and needs no check)."""
    if json_out is not None and json_out != "-":
        outputs(inputs, files={"--json": Path(json_out)})


def emit(doc: Any, json_out: str | None, text: str) -> None:
    """The verb's output: ``text`` on stdout, or with ``--json -`` the JSON ``doc`` instead;
    with ``--json PATH`` the text and the JSON written atomically to PATH."""
    import typer

    if json_out == "-":
        typer.echo(json.dumps(doc, indent=2, ensure_ascii=False, default=str))
        return
    if text:
        typer.echo(text)
    if json_out is not None:
        save_json(doc, Path(json_out))
        typer.echo(f"wrote {json_out}")
