"""Response of the sticking springs' oscillator to the slipping elements' exponential load.

Between switches, with the Stribeck magnitude frozen at ``g0``, the slipping elements of a
GMS model relax with one rate ``lam = C / g0``, so their total force is
``P(s) = P_inf + (P0 - P_inf) exp(-lam s)``. It loads the linear mass–spring–damper of
the sticking elements (:mod:`._oscillator`). :func:`exp_load` gives the response over a
step ``h`` to a unit acceleration ``exp(-lam s)`` from rest:

``m xi'' + c xi' + K xi = m exp(-lam s)``, ``xi(0) = xi'(0) = 0``  ->  ``(xi(h), xi'(h))``.

With ``A = [[0, 1], [-K/m, -c/m]]`` this is ``G(A) (0, 1)`` for
``G(A) = int_0^h exp(A (h - s)) exp(-lam s) ds``, whose scalar function is the divided
difference ``G(l) = (exp(l h) - exp(-lam h)) / (l + lam)`` of the exponential at ``l h``
and ``-lam h``. As in :func:`._oscillator.coefficients`, ``G(A) = alpha I + beta (A - mu I)``
with ``alpha, beta`` the mean and divided difference of ``G`` at the eigenvalues
``mu +- d`` (``d`` floored at ``1e-5 / h`` when they coincide). ``G(l)`` is evaluated as
``h exp(a) phi1(b - a)`` with ``a`` the argument of larger real part (both real parts are
<= 0 here), so neither exponential overflows and a resonance ``l = -lam`` is regular.
Checked against ``scipy.linalg.expm`` of the 3x3 augmented matrix in
tests/kernels/test_gms_span.py.
"""

from __future__ import annotations

from .._jit import njit
from ._oscillator import _cexp, _phi12, _roots


@njit(inline="always")
def _dd_exp(a, b, h):
    """``h (exp(a) - exp(b)) / (a - b)`` for complex ``a`` and real ``b``."""
    z = a - b
    if abs(z) >= 0.5:
        # away from a = b the quotient directly: one complex and one real exp and one division
        # (the phi1 route below costs two complex exps and two divisions: exp_load ~420 -> ~250 ns);
        # both real parts are <= 0 here, so nothing overflows
        return h * (_cexp(a) - _cexp(complex(b, 0.0))) / z
    if a.real >= b:
        return h * _cexp(a) * _phi12(b - a)[0]
    return h * _cexp(complex(b, 0.0)) * _phi12(a - b)[0]


@njit
def exp_load(K, c, m, lam, h):
    """``(xi(h), v(h))`` of ``m xi'' + c xi' + K xi = m exp(-lam s)`` from rest (module docstring)."""
    mu, d = _roots(K, c, m, h)
    b = -lam * h
    G1 = _dd_exp((mu + d) * h, b, h)
    G2 = _dd_exp((mu - d) * h, b, h)
    alpha = (0.5 * (G1 + G2)).real
    beta = ((G1 - G2) / (2.0 * d)).real
    return beta, alpha + beta * mu
