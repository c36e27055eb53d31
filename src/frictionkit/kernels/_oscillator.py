"""Exact sub-step of a linear mass–spring–damper under an affine force.

``m ξ'' + c ξ' + K ξ = f0 + f1 τ``,  ``ξ(0) = 0``, ``ξ'(0) = v0``.

The solution over a step ``h`` is ``y(h) = E y0 + Φ1 b0 + Φ2 b1`` with
``E = exp(A h)``, ``Φ1 = ∫ exp(A(h-s)) ds``, ``Φ2 = ∫ exp(A(h-s)) s ds`` and
``A = [[0, 1], [-K/m, -c/m]]``. For a 2×2 matrix any such function is
``f(A) = α I + β (A - μ I)`` with ``μ`` the mean of the eigenvalues ``μ ± d`` and
``α, β`` the mean and divided difference of ``f`` at them. The divided
differences are evaluated in complex arithmetic; ``φ`` functions use their Taylor
series near 0 and, when the eigenvalues (almost) coincide, ``d`` is floored at
``1e-5/h`` (relative error ~1e-10). Stiff springs (``K`` up to 1e9 N/m) and
strong damping are exact, not merely stable.
"""

from __future__ import annotations

import cmath
import math

from .._jit import njit


@njit(inline="always")
def _cexp(z):
    if z.real < -700.0:
        return 0j
    return cmath.exp(z)


#: ``1/(j+2)!`` for ``j = 0 .. 14``: the Taylor series of ``φ2`` to below 1e-16 of it for ``|z| < 0.5``.
_IFACT2 = tuple(1.0 / math.factorial(j + 2) for j in range(15))


@njit
def _phi12(z):
    """``(φ1(z), φ2(z))`` with ``φ1 = (e^z - 1)/z``, ``φ2 = (e^z - 1 - z)/z^2``."""
    if abs(z) < 0.5:
        # Taylor: φ2(z) = sum_j z^j / (j+2)! by Horner, φ1 = 1 + z φ2 (the loop of complex
        # divisions this replaces cost ~0.3 µs per call: most of a GMS sub-step, issue 15)
        p2 = complex(_IFACT2[14], 0.0)
        for j in range(13, -1, -1):
            p2 = p2 * z + _IFACT2[j]
        return 1.0 + z * p2, p2
    ez = _cexp(z)
    p1 = (ez - 1.0) / z
    return p1, (p1 - 1.0) / z


@njit(inline="always")
def _roots(K, c, m, h):
    """``(mu, d)``: the roots ``mu ± d`` of ``m s² + c s + K`` (``d`` complex), ``d`` kept off zero
    (``|d| h >= 1e-5``) so the critically damped case uses the same formulas."""
    mu = -0.5 * c / m
    disc = mu * mu - K / m
    if disc >= 0.0:
        d = complex(math.sqrt(disc), 0.0)
    else:
        d = complex(0.0, math.sqrt(-disc))
    if abs(d) * h < 1e-5:
        d = complex(1e-5 / h, 0.0)
    return mu, d


@njit
def coefficients(K, c, m, h):
    """Return ``(E11, E12, E21, E22, q1, r1, q2, r2)``.

    ``ξ(h) = E12 v0 + q1 f0/m + q2 f1/m`` and
    ``v(h) = E22 v0 + r1 f0/m + r2 f1/m`` (``E11, E21`` act on ``ξ0``, here 0 but
    returned for completeness).
    """
    mu, d = _roots(K, c, m, h)
    l1 = mu + d
    l2 = mu - d
    e1 = _cexp(l1 * h)
    e2 = _cexp(l2 * h)
    a0 = (0.5 * (e1 + e2)).real
    b0 = ((e1 - e2) / (2.0 * d)).real
    p11, p21 = _phi12(l1 * h)
    p12, p22 = _phi12(l2 * h)
    a1 = (0.5 * h * (p11 + p12)).real
    b1 = (h * (p11 - p12) / (2.0 * d)).real
    a2 = (0.5 * h * h * (p21 + p22)).real
    b2 = (h * h * (p21 - p22) / (2.0 * d)).real
    km = K / m
    return (a0 - b0 * mu, b0, -b0 * km, a0 + b0 * mu, b1, a1 + b1 * mu, b2, a2 + b2 * mu)
