"""Export a friction law for a drive or a PLC: lookup table (CSV), C header, IEC 61131-3 ST.

What is exported, by kernel family (:func:`frictionkit.models.kernel_family`):

* every law: its **steady-state map** ``Fss(v) = s(v) + sigma2 v`` — the static
  feed-forward a drive adds to its current command. For GMS that is
  ``(sum xi) s(v) + sigma2 v`` (the Maxwell-slip elements themselves are not exported).
* ``"lugre"`` (LuGre, Dahl): also a **discrete-time update with state** — one call per
  control sample with the velocity of the interval that just ended (position difference
  over ``dt``); the bristle deflection ``z`` advances by the exact exponential solution
  for constant velocity, ``z <- zss + (z - zss) exp(-a dt)`` with ``a = sigma0 |v| / |s(v)|``
  and ``zss = v / a``, and the force ``sigma0 z + sigma1 (v - a z) + sigma2 v`` is
  returned. This is the update of frictionkit's motion-driven simulation
  (``fk.simulate(model, position=..., dt=...)``, ``kernels/lugre.py``), so the exported
  code and the library agree to rounding; it is unconditionally stable for any ``dt``.

Formats (:data:`FORMATS`):

``"csv"``
    ``v [unit], friction [unit]`` on an odd, uniform grid over ``[-v_max, v_max]`` (0 included;
    interpolating linearly across 0 smooths the sign step over one grid interval).
``"json"``
    A model file (``frictionkit.model/1``, :mod:`frictionkit.models.files`): the law, its
    units and the provenance given — e.g. an identification result reduced to its model.
``"c"``
    A self-contained C99 header (``static inline`` functions, ``<math.h>``):
    ``<name>_steady(v)`` and, for the LuGre family, ``<name>_state``,
    ``<name>_reset(&s)`` and ``<name>_update(&s, v, dt)``.
``"st"``
    An IEC 61131-3 ``FUNCTION_BLOCK``: the steady-state map (input ``v``) or, for the
    LuGre family, the update with state (inputs ``v``, ``dt``, ``reset``); output ``F``; one statement per line; ``EXP``, ``EXPT`` and ``ABS``
    from the standard library.

Parameters are written per direction (row 0 for ``v >= 0``, row 1 for ``v < 0``, as the
kernels read them) in SI, as the shortest decimals that read back to the same doubles;
the C and ST files start with a comment naming the law, the units and the provenance
(method, date, data SHA-256) of the model they came from.

Where a level is zero, the LuGre update divides by ``|s(v)| = 0``; like the kernels
(``kernels/_stribeck.row``) it uses ``Fc`` and ``Fs`` floored at ``G_FLOOR = 1e-9`` times
the largest level (the C header keeps the unfloored levels for the steady-state map).
"""

from __future__ import annotations

import dataclasses
from collections.abc import Mapping
from dataclasses import dataclass
from datetime import datetime, timezone
from typing import Any

import numpy as np

from .errors import ParameterError
from .models.base import kernel_family, law_entry

__all__ = ["FORMATS", "export_model", "lookup_table"]

#: Export formats: lookup table, C header, IEC 61131-3 structured text.
FORMATS = ("csv", "json", "c", "st")

#: Floor of ``|s(v)|`` in the LuGre update, as a fraction of the largest level (the kernels' G_FLOOR).
G_FLOOR = 1e-9

_SHAPES = {0.0: "exponential", 1.0: "lorentzian"}


@dataclass(frozen=True)
class _Rows:
    """Per-direction parameters of the exported formulas (index 0: ``v >= 0``, 1: ``v < 0``)."""

    Fc: tuple[float, float]
    Fs: tuple[float, float]
    vs: tuple[float, float]
    delta: tuple[float, float]
    sigma2: tuple[float, float]
    shape: tuple[float, float]
    sigma0: tuple[float, float] | None = None  # LuGre family only
    sigma1: tuple[float, float] | None = None

    def floored(self) -> _Rows:
        """The levels as the kernels use them in the LuGre update: ``Fc``, ``Fs`` each floored at
        ``G_FLOOR`` times the largest level (``kernels/_stribeck.row``)."""
        lo = G_FLOOR * max(max(self.Fc), max(self.Fs))
        return dataclasses.replace(self, Fc=(max(self.Fc[0], lo), max(self.Fc[1], lo)),
                                   Fs=(max(self.Fs[0], lo), max(self.Fs[1], lo)))


def _rows(model: Any) -> _Rows:
    from .models.pack import pack_gms, pack_lugre

    family = kernel_family(model)
    dyn = None
    if family == "static":
        if not callable(getattr(model, "static_rows", None)):  # e.g. a TDMSSC: its levels follow a schedule input
            raise ParameterError(f"export: {law_entry(model).name} has no fixed static map (its levels depend on "
                                 "a scheduling input); export a law with fixed levels, e.g. the Stribeck curve at "
                                 "one operating point")
        st = np.asarray(model.static_rows(), dtype=float)
    elif family == "lugre":
        pk = pack_lugre(model)
        st, dyn = np.array(pk.static, dtype=float), pk.dyn
    else:  # GMS: the steady state is (sum xi) s(v) + sigma2 v
        pk = pack_gms(model)
        st = np.array(pk.static, dtype=float)
        scale = pk.xi.sum(axis=1)
        st[:, 0] *= scale
        st[:, 1] *= scale

    def pair(a: np.ndarray) -> tuple[float, float]:
        return (float(a[0]), float(a[1]))

    return _Rows(Fc=pair(st[:, 0]), Fs=pair(st[:, 1]), vs=pair(st[:, 2]), delta=pair(st[:, 3]),
                 sigma2=pair(st[:, 4]), shape=pair(st[:, 5]),
                 sigma0=None if dyn is None else pair(dyn[:, 0]), sigma1=None if dyn is None else pair(dyn[:, 1]))


#: Allowed grid half-width of the lookup table [m/s or rad/s]. Assumption (no source): far beyond
#: any motion axis on both sides; below 1e-12 the grid steps of a large table come near the
#: subnormal range (at v_max = 1e-320 the written grid was not uniform), above 1e12 a viscous
#: term overflows (v_max = 1e308 wrote a table of nan and inf with exit status 0).
V_MAX_RANGE = (1e-12, 1e12)


def _v_max(model: Any, v_max: float | None) -> float:
    from .models.files import _speed_scale

    if v_max is None:
        return _speed_scale(model)
    try:
        out = float(v_max)
    except (TypeError, ValueError):
        raise ParameterError(f"export: v_max = {v_max!r}: must be a number") from None
    if not np.isfinite(out) or out <= 0:
        raise ParameterError(f"export: v_max = {v_max!r}: must be finite and > 0 [m/s or rad/s]")
    lo, hi = V_MAX_RANGE
    if not lo <= out <= hi:
        raise ParameterError(f"export: v_max = {v_max!r}: must be in {lo:g} ... {hi:g} [m/s or rad/s] "
                             "(outside it the grid's steps lose precision or the map overflows)")
    return out


def lookup_table(model: Any, *, v_max: float | None = None, points: int = 201) -> tuple[np.ndarray, np.ndarray]:
    """The steady-state map on a uniform velocity grid: ``(v, F)``.

    Parameters
    ----------
    model : friction law
        Any registered law.
    v_max : float, optional
        Grid half-width [m/s or rad/s]; default 10 times the largest Stribeck velocity
        (1 for laws without one).
    points : int
        Grid points, odd (so that ``v = 0`` is one of them), 3 ... 1,000,001.

    Examples
    --------
    >>> import frictionkit as fk
    >>> from frictionkit.export import lookup_table
    >>> v, F = lookup_table(fk.CoulombViscous(Fc=2.0, sigma2=10.0), v_max=0.1, points=3)
    >>> v.tolist(), F.tolist()
    ([-0.1, 0.0, 0.1], [-3.0, 0.0, 3.0])
    """
    if isinstance(points, bool) or not isinstance(points, (int, np.integer)) or not 3 <= points <= 1_000_001 \
            or points % 2 == 0:
        raise ParameterError(f"export: points = {points!r}: must be an odd integer in 3 ... 1,000,001 "
                             "(odd, so that v = 0 is a grid point)")
    vm = _v_max(model, v_max)
    v = np.linspace(-vm, vm, int(points))
    v[int(points) // 2] = 0.0
    F = np.asarray(model.steady_state(v), dtype=float)
    if not np.all(np.isfinite(F)):
        bad = float(v[~np.isfinite(F)][0])
        raise ParameterError(f"export: v_max = {vm!r}: the steady-state map is not finite at v = {bad!r} "
                             "(the law's parameters overflow there); choose a smaller v_max")
    return v, F


# --------------------------------------------------------------------------- text helpers
def _num(x: float) -> str:
    """A literal both C and IEC 61131-3 read exactly (17 significant digits, a '.' in the mantissa)."""
    s = repr(float(x))
    if "inf" in s or "nan" in s:
        raise ParameterError(f"export: parameter value {x!r} is not finite")
    mant, _, exp = s.partition("e")
    if "." not in mant:
        mant += ".0"
    return mant + (f"E{exp}" if exp else "")


def _header_lines(model: Any, units: Mapping[str, str], provenance: Mapping[str, Any]) -> list[str]:
    from . import __version__
    from .models.base import law_to_dict

    lines = [f"frictionkit {__version__} export, {datetime.now(timezone.utc).isoformat(timespec='seconds')}",
             f"law: {law_entry(model).name} ({kernel_family(model)} family)",
             f"units: F [{units['F']}], v [{units['v']}], x [{units['x']}], dt [s]; parameters SI",
             f"model: {_compact(law_to_dict(model))}"]
    for key in ("method", "created", "frictionkit_version", "data_file", "file", "data_sha256", "source"):
        if key in provenance:
            lines.append(f"{key}: {provenance[key]}")
    return lines


def _compact(node: Any) -> str:
    import json

    return json.dumps(node, separators=(",", ":"), ensure_ascii=True)


def _phi_c(r: _Rows, name: str) -> str:
    one = {1.0: "1.0 / (1.0 + r * r)", 0.0: f"exp(-pow(r, {name}_delta[i]))"}
    if r.shape[0] == r.shape[1]:
        return one[r.shape[0]]
    return f"(i == 0) ? {one[r.shape[0]]} : {one[r.shape[1]]}"


def _ascii(text: str) -> str:
    """Comment text for C and ST compilers that read ASCII only."""
    text = text.replace("·", "*").replace("²", "^2").replace("µ", "u")
    return text.encode("ascii", "backslashreplace").decode("ascii")


# --------------------------------------------------------------------------- C
def _c_source(model: Any, name: str, units: Mapping[str, str], provenance: Mapping[str, Any]) -> str:
    r = _rows(model)
    lugre = r.sigma0 is not None
    guard = f"{name.upper()}_H"
    out = ["/*"] + [f" * {ln.replace('*/', '* /')}" for ln in _header_lines(model, units, provenance)]
    out += [" *",
            f" * {name}_steady(v): steady-state friction F = s(v) + sigma2 v [{units['F']}] at velocity v "
            f"[{units['v']}].",
            " * Parameter arrays: index 0 for v >= 0, index 1 for v < 0.",
            " * Shapes: " + ", ".join(f"[{i}] {_SHAPES[r.shape[i]]}" for i in (0, 1)) + ".", " */",
            f"#ifndef {guard}", f"#define {guard}", "", "#include <math.h>", ""]
    params = [("Fc", r.Fc, units["F"]), ("Fs", r.Fs, units["F"]), ("vs", r.vs, units["v"]), ("delta", r.delta, "-"),
              ("sigma2", r.sigma2, f"{units['F']}·s/{units['x']}")]
    if lugre:
        params += [("sigma0", r.sigma0, f"{units['F']}/{units['x']}"),
                   ("sigma1", r.sigma1, f"{units['F']}·s/{units['x']}")]
    for p, vals, unit in params:
        out.append(f"static const double {name}_{p}[2] = {{{_num(vals[0])}, {_num(vals[1])}}}; /* [{unit}] */")
    if lugre:
        fl = r.floored()
        out += [f"/* levels of the LuGre update, floored at {G_FLOOR:g} x the largest level (a zero level would "
                "divide by zero) */"]
        out += [f"static const double {name}_{p}_floor[2] = {{{_num(vals[0])}, {_num(vals[1])}}}; /* [{units['F']}] */"
                for p, vals in (("Fc", fl.Fc), ("Fs", fl.Fs))]
    out += ["", "/* |s(v)| at speed av >= 0 for direction i (0: v >= 0, 1: v < 0) with levels Fc, Fs */",
            f"static inline double {name}_g(int i, double av, const double *Fc, const double *Fs)", "{",
            f"    double r = av / {name}_vs[i];",
            f"    double phi = {_phi_c(r, name)};",
            "    return Fc[i] + (Fs[i] - Fc[i]) * phi;", "}", "",
            f"/* steady-state friction [{units['F']}] at velocity v [{units['v']}]; 0 at v = 0 */",
            f"static inline double {name}_steady(double v)", "{",
            "    if (v == 0.0) return 0.0;",
            "    int i = v < 0.0;",
            f"    double g = {name}_g(i, fabs(v), {name}_Fc, {name}_Fs);",
            f"    return (i ? -g : g) + {name}_sigma2[i] * v;", "}"]
    if lugre:
        out += ["", f"/* LuGre state: bristle deflection z [{units['x']}]; z = 0 is the unloaded state */",
                f"typedef struct {{ double z; }} {name}_state;", "",
                f"static inline void {name}_reset({name}_state *s) {{ s->z = 0.0; }}", "",
                f"/* One control sample. v [{units['v']}]: mean velocity over the interval that just ended",
                " * (position difference / dt); dt [s] > 0. Advances z exactly for constant v and returns",
                f" * the friction force [{units['F']}] at the end of the interval. */",
                f"static inline double {name}_update({name}_state *s, double v, double dt)", "{",
                "    int i = v < 0.0;",
                "    double av = fabs(v);",
                f"    double g = {name}_g(i, av, {name}_Fc_floor, {name}_Fs_floor);",
                f"    double a = {name}_sigma0[i] * av / g;",
                "    if (a > 0.0) {",
                "        double zss = v / a;",
                "        s->z = zss + (s->z - zss) * exp(-a * dt);",
                "    }",
                f"    return {name}_sigma0[i] * s->z + {name}_sigma1[i] * (v - a * s->z) + {name}_sigma2[i] * v;",
                "}"]
    out += ["", f"#endif /* {guard} */", ""]
    return "\n".join(out)


# --------------------------------------------------------------------------- IEC 61131-3 ST
def _st_source(model: Any, name: str, units: Mapping[str, str], provenance: Mapping[str, Any]) -> str:
    r = _rows(model)
    lugre = r.sigma0 is not None
    if lugre:  # the function block is the LuGre update: the kernels' floored levels
        r = r.floored()
    out = [f"(* {ln.replace('*)', '* )')} *)" for ln in _header_lines(model, units, provenance)]
    out += [f"FUNCTION_BLOCK {name}", "VAR_INPUT",
            f"    v : LREAL; (* velocity [{units['v']}]"
            + ("; mean over the sample interval that just ended *)" if lugre else " *)")]
    if lugre:
        out += ["    dt : LREAL; (* sample period [s] *)", "    reset : BOOL; (* TRUE: back to the unloaded state *)"]
    out += ["END_VAR", "VAR_OUTPUT", f"    F : LREAL; (* friction force [{units['F']}] *)", "END_VAR", "VAR"]
    if lugre:
        out.append(f"    z : LREAL := 0.0; (* bristle deflection [{units['x']}] *)")
    temps = ["Fc", "Fs", "vs", "delta", "sigma2", "av", "r", "phi", "g"] + (["sigma0", "sigma1", "a", "zss"] if lugre else [])
    out += [f"    {t} : LREAL;" for t in temps] + ["END_VAR", ""]
    if lugre:
        out += ["IF reset THEN", "    z := 0.0;", "END_IF;"]
    out += ["av := ABS(v);"]

    def branch(i: int) -> list[str]:
        lines = [f"    Fc := {_num(r.Fc[i])};", f"    Fs := {_num(r.Fs[i])};", f"    vs := {_num(r.vs[i])};",
                 f"    delta := {_num(r.delta[i])};", f"    sigma2 := {_num(r.sigma2[i])};"]
        if lugre:
            lines += [f"    sigma0 := {_num(r.sigma0[i])};", f"    sigma1 := {_num(r.sigma1[i])};"]
        lines.append("    r := av / vs;")
        lines.append("    phi := 1.0 / (1.0 + r * r);" if r.shape[i] == 1.0 else "    phi := EXP(-EXPT(r, delta));")
        return lines

    out += ["IF v < 0.0 THEN"] + branch(1) + ["ELSE"] + branch(0) + ["END_IF;", "g := Fc + (Fs - Fc) * phi;"]
    if lugre:
        out += ["a := sigma0 * av / g;", "IF a > 0.0 THEN", "    zss := v / a;",
                "    z := zss + (z - zss) * EXP(-a * dt);", "END_IF;",
                "F := sigma0 * z + sigma1 * (v - a * z) + sigma2 * v;"]
    else:
        out += ["IF v > 0.0 THEN", "    F := g + sigma2 * v;", "ELSIF v < 0.0 THEN", "    F := -g + sigma2 * v;",
                "ELSE", "    F := 0.0;", "END_IF;"]
    out += ["END_FUNCTION_BLOCK", ""]
    return "\n".join(out)


# --------------------------------------------------------------------------- entry point
def _check_name(name: str, fmt: str) -> str:
    import re

    if not isinstance(name, str) or not re.fullmatch(r"[A-Za-z_][A-Za-z0-9_]{0,62}", name):
        raise ParameterError(f"export: name = {name!r}: must be an identifier (letters, digits, '_', "
                             f"not starting with a digit, at most 63 characters) for the {fmt} code")
    if fmt == "structured-text" and (name.upper() in ST_KEYWORDS or "__" in name or name.endswith("_")):
        # `--name END_FUNCTION_BLOCK` wrote "FUNCTION_BLOCK END_FUNCTION_BLOCK" with exit 0 (campaign round 5)
        raise ParameterError(f"export: name = {name!r}: a reserved word of IEC 61131-3 or not a valid ST identifier "
                             "(no '__', no trailing '_'); choose another function block name")
    return name


#: IEC 61131-3 (3rd ed.) keywords and elementary type names: not usable as a function block
#: name (ST is case-insensitive). Assumption: the common set; vendors reserve more.
ST_KEYWORDS = frozenset("""
ABS ACOS ACTION AND ANY ARRAY ASIN AT ATAN BOOL BY BYTE CASE CLASS CONFIGURATION CONSTANT COS DATE DATE_AND_TIME DINT
DO DT DWORD ELSE ELSIF END_ACTION END_CASE END_CLASS END_CONFIGURATION END_FOR END_FUNCTION END_FUNCTION_BLOCK END_IF
END_INTERFACE END_METHOD END_PROGRAM END_REPEAT END_RESOURCE END_STEP END_STRUCT END_TRANSITION END_TYPE END_VAR
END_WHILE EXIT EXP EXTENDS FALSE FOR FROM FUNCTION FUNCTION_BLOCK IF IMPLEMENTS INITIAL_STEP INT INTERFACE LINT LN
LOG LREAL LWORD METHOD MOD NOT NULL OF ON OR OVERLAP PRIVATE PROGRAM PROTECTED PUBLIC READ_ONLY READ_WRITE REAL
REPEAT RESOURCE RETAIN RETURN SIN SINT SQRT STEP STRING STRUCT SUPER TAN TASK THEN THIS TIME TO TOD TRANSITION TRUE
TYPE UDINT UINT ULINT UNTIL USINT VAR VAR_ACCESS VAR_CONFIG VAR_EXTERNAL VAR_GLOBAL VAR_INPUT VAR_IN_OUT VAR_OUTPUT
VAR_TEMP WHILE WITH WORD WSTRING XOR""".split())


def export_model(model: Any, fmt: str, *, name: str | None = None, v_max: float | None = None,
                 points: int | None = None,
                 units: Mapping[str, str] | None = None, provenance: Mapping[str, Any] | None = None) -> str:
    """A friction law as the text of a lookup table, a C header or an IEC 61131-3 function block.

    Parameters
    ----------
    model : friction law
        Any registered law; see the module docstring for what each family exports.
    fmt : {"csv", "json", "c", "st"}
        Format.
    name : str, optional
        Identifier prefix of the C functions (default ``fk_friction``) or name of the
        function block (default ``FK_Friction``).
    v_max, points : float, int, optional
        Grid of the lookup table (see :func:`lookup_table`; default 201 points); CSV only —
        given with another format they are refused (they were silently ignored).
    units : mapping, optional
        Axis unit labels ``{"F", "v", "x"}`` for the comments and the CSV header
        (numbers are SI; default N, m/s, m).
    provenance : mapping, optional
        Written into the header comment (``method``, ``created``, ``data_sha256`` ...).

    Returns
    -------
    str

    Examples
    --------
    >>> import frictionkit as fk
    >>> from frictionkit.export import export_model
    >>> text = export_model(fk.LuGre(fk.Stribeck(Fc=1.0, Fs=1.5, vs=1e-3), sigma0=1e5), "c")
    >>> "fk_friction_update(fk_friction_state *s, double v, double dt)" in text
    True
    """
    from .models.files import _axis_units

    if fmt not in FORMATS:
        raise ParameterError(f"export: format {fmt!r}: must be one of {', '.join(FORMATS)}")
    if fmt != "csv" and (v_max is not None or points is not None):
        given = ", ".join(k for k, x in (("v_max", v_max), ("points", points)) if x is not None)
        raise ParameterError(f"export: {given} set the csv lookup table's grid; format {fmt!r} has no grid "
                             "(leave them out, or use format 'csv')")
    law_entry(model)
    ax = _axis_units(units)
    prov = dict(provenance or {})
    if fmt == "csv":
        v, F = lookup_table(model, v_max=v_max, points=201 if points is None else points)
        lines = [f"v [{ax['v']}],friction [{ax['F']}]"] + [f"{a!r},{b!r}" for a, b in zip(v.tolist(), F.tolist())]
        return "\n".join(lines) + "\n"
    if fmt == "json":
        import json

        from .models.files import ModelFile

        doc = ModelFile(model=model, units=ax, provenance=prov).to_dict()
        return json.dumps(doc, indent=2, ensure_ascii=False) + "\n"
    if fmt == "c":
        return _ascii(_c_source(model, _check_name("fk_friction" if name is None else name, "C"), ax, prov))
    return _ascii(_st_source(model, _check_name("FK_Friction" if name is None else name, "structured-text"), ax, prov))
