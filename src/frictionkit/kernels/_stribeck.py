"""Stribeck magnitude ``g(v) = |s(v)|`` and its slope, for the kernels.

``P`` is the packed static array ``(2, 6)``, rows ``[Fc, Fs, vs, delta, sigma2,
shape]`` (see ``frictionkit.models.pack``), ``i`` the row. Indexing the 2-D array
directly (no row views) keeps numba from reference-counting a view per call.
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


@njit(inline="always")
def g_and_slope(P, i, av):
    """Return ``(g, dg/d|v|)`` at speed ``av = |v| >= 0`` for row ``i``."""
    Fc = P[i, 0]
    dF = P[i, 1] - Fc
    vs = P[i, 2]
    r = av / vs
    if r == 0.0:
        return P[i, 1], 0.0
    if P[i, 5] == 0.0:
        d = P[i, 3]
        rd = _rpow(r, d)
        if rd > UNDERFLOW:
            return Fc, 0.0
        phi = math.exp(-rd)
        return Fc + dF * phi, -dF * d * (rd / r) * phi / vs
    q = 1.0 / (1.0 + r * r)
    return Fc + dF * q, -dF * 2.0 * r * q * q / vs


@njit(inline="always")
def g_only(P, i, av):
    """``g = |s(v)|`` at speed ``av >= 0`` for row ``i``."""
    r = av / P[i, 2]
    if P[i, 5] == 0.0:
        if r == 0.0:
            return P[i, 1]
        rd = _rpow(r, P[i, 3])
        if rd > UNDERFLOW:
            return P[i, 0]
        return P[i, 0] + (P[i, 1] - P[i, 0]) * math.exp(-rd)
    return P[i, 0] + (P[i, 1] - P[i, 0]) / (1.0 + r * r)
