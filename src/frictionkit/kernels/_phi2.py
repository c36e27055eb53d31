"""``phi`` functions of a real 2x2 matrix, for the exponential sub-sample propagators.

``phi_0(M) = exp(M)``, ``phi_k(M) = sum_j M^j / (j + k)!`` (so ``phi_k(M) = M phi_{k+1}(M)
+ I / k!``). With them the affine ODE ``y' = B y + c0 + c1 s + ...`` has its exact solution
over a step ``h`` (``M = h B``): ``y(h) = phi_0 y(0) + h phi_1 c0 + h^2 phi_2 c1 + ...``.

Method: scaling and squaring (Skaflestad & Wright 2009, "The scaling and modified squaring
method for matrix functions related to the exponential", Appl. Numer. Math. 59):
``M / 2^s`` with norm <= 1/2, a degree-9 Taylor polynomial of ``phi_4`` (truncation
< 1e-13 relative), the lower ``phi_k`` by the recurrence above, then ``s`` doublings
``phi_k(2M) = 2^-k [phi_0(M) phi_k(M) + sum_{j=1..k} phi_j(M) / (k - j)!]``.

The norm that picks ``s`` is that of the diagonally balanced matrix,
``max(|m11|, |m22|) + sqrt(|m12 m21|)`` (``phi_k(D^-1 M D) = D^-1 phi_k(M) D``): the LuGre
Jacobian couples a velocity and a bristle deflection of very different scales, so the
plain norm would overestimate a pre-sliding oscillation of ``omega dt = 0.08`` as ~25 and
square needlessly. Matrices are 4-tuples ``(m11, m12, m21, m22)`` (values, not arrays:
see the note on reference counting in :mod:`._stribeck`). Checked against
``scipy.linalg.expm`` of the block-companion matrix in tests/kernels/test_lugre_expo.py.
"""

from __future__ import annotations

import math

from .._jit import njit

#: ``1 / (j + 4)!`` for ``j = 0..9``: Taylor coefficients of ``phi_4``.
_C4 = tuple(1.0 / math.factorial(j + 4) for j in range(10))


@njit(inline="always")
def _mm(a, b):
    return (a[0] * b[0] + a[1] * b[2], a[0] * b[1] + a[1] * b[3],
            a[2] * b[0] + a[3] * b[2], a[2] * b[1] + a[3] * b[3])


@njit(inline="always")
def _plus_diag(a, c):
    return (a[0] + c, a[1], a[2], a[3] + c)


@njit(inline="always")
def phis(m):
    """``(phi_0, phi_1, phi_2, phi_3, phi_4)`` of the 2x2 matrix ``m`` (4-tuples, row-major)."""
    nrm = max(abs(m[0]), abs(m[3])) + math.sqrt(abs(m[1] * m[2]))
    s = 0
    if nrm > 0.5:
        s = int(math.ceil(math.log2(nrm / 0.5)))
        sc = math.ldexp(1.0, -s)
        m = (m[0] * sc, m[1] * sc, m[2] * sc, m[3] * sc)
    c = _C4[9]
    p = (c, 0.0, 0.0, c)
    for j in range(8, -1, -1):
        p = _plus_diag(_mm(m, p), _C4[j])
    p4 = p
    p3 = _plus_diag(_mm(m, p4), 1.0 / 6.0)
    p2 = _plus_diag(_mm(m, p3), 0.5)
    p1 = _plus_diag(_mm(m, p2), 1.0)
    p0 = _plus_diag(_mm(m, p1), 1.0)
    for _ in range(s):
        a0 = _mm(p0, p0)
        a1 = _mm(p0, p1)
        a2 = _mm(p0, p2)
        a3 = _mm(p0, p3)
        a4 = _mm(p0, p4)
        n1 = (0.5 * (a1[0] + p1[0]), 0.5 * (a1[1] + p1[1]), 0.5 * (a1[2] + p1[2]), 0.5 * (a1[3] + p1[3]))
        n2 = (0.25 * (a2[0] + p1[0] + p2[0]), 0.25 * (a2[1] + p1[1] + p2[1]),
              0.25 * (a2[2] + p1[2] + p2[2]), 0.25 * (a2[3] + p1[3] + p2[3]))
        n3 = (0.125 * (a3[0] + 0.5 * p1[0] + p2[0] + p3[0]), 0.125 * (a3[1] + 0.5 * p1[1] + p2[1] + p3[1]),
              0.125 * (a3[2] + 0.5 * p1[2] + p2[2] + p3[2]), 0.125 * (a3[3] + 0.5 * p1[3] + p2[3] + p3[3]))
        n4 = (0.0625 * (a4[0] + p1[0] / 6.0 + 0.5 * p2[0] + p3[0] + p4[0]),
              0.0625 * (a4[1] + p1[1] / 6.0 + 0.5 * p2[1] + p3[1] + p4[1]),
              0.0625 * (a4[2] + p1[2] / 6.0 + 0.5 * p2[2] + p3[2] + p4[2]),
              0.0625 * (a4[3] + p1[3] / 6.0 + 0.5 * p2[3] + p3[3] + p4[3]))
        p0, p1, p2, p3, p4 = a0, n1, n2, n3, n4
    return p0, p1, p2, p3, p4


@njit
def phis_array(m11, m12, m21, m22):
    """:func:`phis` callable from Python (tests): five 4-tuples."""
    return phis((m11, m12, m21, m22))
