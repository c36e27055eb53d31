"""The physics behind an identifiability verdict: time constants, units and the experiment to run.

:mod:`.identifiability` finds which parameters a record cannot pin; this module turns
each into numbers a test engineer can act on — the bristle (or element) time constant
against the sample period, the sampling rate that would resolve it, the pre-sliding
displacement a sub-breakaway test would have to resolve — and gives every parameter
of a motion-driven fit its unit.
"""

from __future__ import annotations

import math

import numpy as np

from ..models.gms import GMS
from ..models.lugre import Dahl, LuGre
from ..models.static import Directional
from ._law_params import base_name

__all__ = ["advisor", "level", "time_constants", "unit"]


def level(model, v: float) -> float:
    return float(np.mean(np.abs(model.steady_state(np.array([v, -v])))))


def time_constants(model, v_typ: float) -> dict:
    """Pre-sliding / slip time constants at the typical speed [s]."""
    out = {}
    laws = [model.positive, model.negative] if isinstance(model, Directional) else [model]
    for side, law in zip(("pos", "neg") if len(laws) == 2 else ("",), laws):
        sfx = f"_{side}" if side else ""
        s = level(law, v_typ)
        if isinstance(law, (LuGre, Dahl)):
            out[f"bristle{sfx}"] = s / (law.sigma0 * v_typ)
        elif isinstance(law, GMS):
            for i, (k, xi) in enumerate(zip(law.k, law.xi), start=1):
                out[f"element{i}_breakaway{sfx}"] = float(xi * s / (k * v_typ))
            out[f"slip{sfx}"] = s / law.C
    return out


def _fmt_time(tau: float) -> str:
    if not math.isfinite(tau):
        return "unbounded"
    for unit, f in (("s", 1.0), ("ms", 1e-3), ("µs", 1e-6), ("ns", 1e-9)):
        if tau >= f:
            return f"{tau / f:.3g} {unit}"
    return f"{tau:.3g} s"


def _fmt_rate(hz: float) -> str:
    if not math.isfinite(hz):
        return "a rate no record can reach"
    for unit, f in (("MHz", 1e6), ("kHz", 1e3), ("Hz", 1.0)):
        if hz >= f:
            return f"{hz / f:.3g} {unit}"
    return f"{hz:.3g} Hz"


def advisor(model, names, theta, v_typ: float, dt: float, units: dict):
    """``advice(name, info)``: the experiment that would pin the parameter, in numbers."""
    vals = dict(zip(names, theta))
    xu, vu, Fu = units["x"], units["v"], units["F"]

    def law_for(name):
        if isinstance(model, Directional):
            return model.negative if name.endswith("_neg") else model.positive
        return model

    def advice(name: str, info: dict) -> str | None:
        b = base_name(name)
        law = law_for(name)
        s = level(law, v_typ)
        lo = info["ci95"][0]
        if b in ("sigma0", "k"):
            stiff = vals[name]
            tau = s / (stiff * v_typ)
            tau_max = s / (lo * v_typ) if lo > 0 else math.inf
            bound = (f"; the data only bound it below {_fmt_time(tau_max)}" if math.isfinite(tau_max)
                     else "; the data allow any value")
            what = "bristle" if b == "sigma0" else "element breakaway"
            z = s / stiff
            return (f"sampling {_fmt_time(dt)} against a {what} time constant of ~{_fmt_time(tau)} "
                    f"(|s(v)|/({b}·|v|) at the typical speed {v_typ:.3g} {vu}{bound}): sample at ≥ "
                    f"{_fmt_rate(1.0 / tau)}, or record a pre-sliding test (force below breakaway) resolving "
                    f"displacements of ~{z:.2g} {xu}")
        if b == "sigma1":
            s0 = getattr(law, "sigma0", None)
            tau = s / (s0 * v_typ) if s0 else math.nan
            return (f"micro-damping acts only while the bristles deflect, ~{_fmt_time(tau)} after each start or "
                    f"reversal; with {_fmt_time(dt)} samples no sample sees it: sample at ≥ {_fmt_rate(1.0 / tau)} "
                    "around starts and reversals, or fix sigma1 (e.g. 0)")
        if b == "C":
            tau = s / vals[name]
            return (f"the slip attraction acts over |s|/C ~{_fmt_time(tau)} after each breakaway; "
                    f"sampling {_fmt_time(dt)}: sample at ≥ {_fmt_rate(1.0 / tau)}, or fix C")
        if b == "xi":
            return ("the element weights shape the pre-sliding hysteresis: record small back-and-forth "
                    "motions below breakaway, or keep the weights fixed")
        if b == "J":
            return (f"J·a needs accelerations the record resolves: here speed changes take about one "
                    f"{_fmt_time(dt)} sample; record faster sampling through starts and stops, or give J "
                    f"from the data sheet (fixed)")
        if b == "offset":
            partner = info.get("partner")
            return (f"an offset is confounded with direction-symmetric levels{f' ({partner})' if partner else ''}; "
                    f"fit the static map per direction and fix the offset at 0 [{Fu}]")
        if b in ("Fc", "Fs", "vs", "delta", "sigma2"):
            return ("fit the static map from constant-speed plateaus ('identify static', with plateaus near "
                    "the Stribeck velocity) and keep it fixed here")
        return None

    return advice


#: The unit printed for a dimensionless parameter (δ, ξ) everywhere: parameter tables, model files, the
#: ``models`` listing, exports. Was "1" in the static fits' tables and "-" elsewhere (the new-user walk).
DIMENSIONLESS = "-"


def unit(name: str, units: dict) -> str:
    """The unit of a law or fit parameter by its (base) name, for the axis units ``{"F", "x"[, "v"]}``;
    :data:`DIMENSIONLESS` for δ, ξ and names it does not know."""
    Fu, xu = units["F"], units["x"]
    vu = units.get("v", f"{xu}/s")
    b = base_name(name)
    if b in ("Fc0", "Fs0"):  # TDMSSC's levels at zero schedule
        return Fu
    if b in ("Fc1", "Fs1"):  # TDMSSC's level slopes per unit of the schedule (a speed)
        return f"{Fu}·s/{xu}"
    if b == "eps":  # TDMSSC's -eps·v·|v|
        return f"{Fu}·s²/{xu}²"
    if b in ("sigma0", "k"):
        return f"{Fu}/{xu}"
    if b in ("sigma1", "sigma2"):
        return f"{Fu}·s/{xu}"
    if b in ("Fc", "Fs", "offset"):
        return Fu
    if b == "vs":
        return vu
    if b == "C":
        return f"{Fu}/s"
    if b == "J":
        if xu == "m" and Fu == "N":
            return "kg"
        if xu == "rad" and Fu == "N·m":
            return "kg·m²"
        return f"{Fu}·s²/{xu}"
    return DIMENSIONLESS
