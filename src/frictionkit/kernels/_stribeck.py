"""Stribeck magnitude ``g(v) = |s(v)|`` and its slope, for the kernels.

``P`` is the packed static array ``(2, 6)``, rows ``[Fc, Fs, vs, delta, sigma2,
shape]`` (see ``frictionkit.models.pack``). Kernels unpack a row once per run into
a tuple (:func:`row`) and evaluate ``g`` from it (see the note below on why).
``delta`` of 1 and 2 avoid ``pow``, which costs ~25 ns here.
"""

from __future__ import annotations

import math

from .._jit import njit


#: ``exp(-x)`` is below 1e-304 past this; glibc's underflow path is ~10x slower.
UNDERFLOW = 700.0


@njit(inline="always")
def _rpow(r, d):
    if d == 2.0:
        return r * r
    if d == 1.0:
        return r
    return r**d


# ---------------------------------------------------------------------------
# Row tuples for hot loops.
#
# Passing an array into a numba function -- even one inlined with
# ``inline="always"`` -- costs an ``NRT_incref``/``NRT_decref`` call pair per call
# site and per execution, and every call spills the floating-point registers: in
# the LuGre sub-step that was most of its ~170 cycles. Kernels therefore unpack a
# parameter row once per run into a tuple of floats (:func:`row`) and evaluate
# ``g`` from it (:func:`g_row`, :func:`g_slope_row`); tuples are values, not
# reference-counted objects.
#
# Layout (indices below): Fc, Fs - Fc, 1/vs, delta, sigma2, shape, v_cut, Fs, 1/Fc.
# ``v_cut`` is the speed above which the exponential term has underflowed
# (``(|v|/vs)^delta > UNDERFLOW``) so ``g = Fc`` exactly; ``inf`` for the Lorentzian
# shape, whose term never underflows.
#
# Levels of zero. ``Fc = 0`` (friction fading to nothing at speed) and ``Fs = 0`` (no
# breakaway level) are valid laws, but the kernels divide by ``g``: the relaxation
# rates ``sigma0 |v| / g`` (LuGre) and ``C / g`` (GMS). In the limit ``g -> 0`` the
# state settles on its target instantly -- LuGre ``z -> sgn(v) g / sigma0 -> 0``, so
# ``F -> sigma2 v``; a slipping GMS element ``F_i -> xi_i s(v) -> 0``. :func:`row`
# floors both levels at ``G_FLOOR`` times the largest level of the packed array, so
# ``g >= G_FLOOR max(Fc, Fs) > 0`` everywhere: the rates stay finite (~1e13 /s), the
# L-stable ROS2 step and the exact exponential slip updates reach the target within
# one sub-step, and the force differs from the limit by at most ``G_FLOOR max(Fc, Fs)``.
# Laws whose levels are both well above that floor are untouched, and the hot
# loops carry no extra test (the floor is applied once per run, here).
# ---------------------------------------------------------------------------

R_FC, R_DF, R_IVS, R_DELTA, R_S2, R_SHAPE, R_VCUT, R_FS, R_IFC = 0, 1, 2, 3, 4, 5, 6, 7, 8

#: Floor of the levels ``Fc``, ``Fs`` as a fraction of the largest level of the packed
#: array (the ``solve_ivp`` twin floors ``|s(v)|`` at the same value).
G_FLOOR = 1e-9


@njit(inline="always")
def row(P, i):
    """Row ``i`` of the packed static array as a tuple (see the layout above).

    Both levels are floored at ``G_FLOOR`` times the largest level in ``P``.
    """
    lo = G_FLOOR * max(max(P[0, 0], P[0, 1]), max(P[1, 0], P[1, 1]))
    Fc = max(P[i, 0], lo)
    Fs = max(P[i, 1], lo)
    if P[i, 5] == 0.0:
        vcut = P[i, 2] * UNDERFLOW ** (1.0 / P[i, 3])
    else:
        vcut = math.inf
    return (Fc, Fs - Fc, 1.0 / P[i, 2], P[i, 3], P[i, 4], P[i, 5], vcut, Fs, 1.0 / Fc)


@njit(inline="always")
def g_row(p, av):
    """``g = |s(v)|`` at speed ``av >= 0`` from a row tuple."""
    if av > p[R_VCUT]:
        return p[R_FC]
    r = av * p[R_IVS]
    if p[R_SHAPE] == 0.0:
        if r == 0.0:
            return p[R_FS]
        return p[R_FC] + p[R_DF] * math.exp(-_rpow(r, p[R_DELTA]))
    return p[R_FC] + p[R_DF] / (1.0 + r * r)


@njit(inline="always")
def g_slope_row(p, av):
    """``(g, dg/d|v|)`` at speed ``av >= 0`` from a row tuple."""
    if av > p[R_VCUT]:
        return p[R_FC], 0.0
    r = av * p[R_IVS]
    if r == 0.0:
        return p[R_FS], 0.0
    if p[R_SHAPE] == 0.0:
        d = p[R_DELTA]
        rd = _rpow(r, d)
        phi = math.exp(-rd)
        return p[R_FC] + p[R_DF] * phi, -p[R_DF] * d * (rd / r) * phi * p[R_IVS]
    q = 1.0 / (1.0 + r * r)
    return p[R_FC] + p[R_DF] * q, -p[R_DF] * 2.0 * r * q * q * p[R_IVS]


@njit(inline="always")
def ig_row(p, av):
    """``1/g`` at speed ``av >= 0``; no division in the fast-sliding range."""
    if av > p[R_VCUT]:
        return p[R_IFC]
    return 1.0 / g_row(p, av)


@njit(inline="always")
def ig_slope_row(p, av):
    """``(1/g, dg/d|v|)`` at speed ``av >= 0``; no division in the fast-sliding range."""
    if av > p[R_VCUT]:
        return p[R_IFC], 0.0
    g, gr = g_slope_row(p, av)
    return 1.0 / g, gr
