"""Matrix exponential of small dense matrices (the machine core's exact discretisation).

Padé approximant of degree 13 with scaling and squaring (Higham, "The scaling and squaring
method for the matrix exponential revisited", SIAM J. Matrix Anal. Appl. 26, 2005; the
algorithm of ``scipy.linalg.expm`` for large norms, used here at every norm). Products are
plain loops, so nothing here calls a multi-threaded BLAS: on a shared 2-core machine,
``scipy.linalg.expm`` of a 4x4 matrix was measured at 13 ms with OpenBLAS threads waiting on
each other (0.02 ms single-threaded), more than the whole compiled run of the EMPS axis.
"""

from __future__ import annotations

import math

import numpy as np

from .._jit import njit

# Padé-13 coefficients b_0..b_13 (Higham 2005, table 10.4)
_B = np.array([64764752532480000.0, 32382376266240000.0, 7771770303897600.0, 1187353796428800.0,
               129060195264000.0, 10559470521600.0, 670442572800.0, 33522128640.0, 1323241920.0,
               40840800.0, 960960.0, 16380.0, 182.0, 1.0])
_THETA13 = 5.371920351148152


@njit(error_model="numpy")
def _mm(A, B, out):
    n = A.shape[0]
    for i in range(n):
        for j in range(n):
            out[i, j] = 0.0
        for k in range(n):
            a = A[i, k]
            if a != 0.0:
                for j in range(n):
                    out[i, j] += a * B[k, j]


@njit(error_model="numpy")
def expm_small(A):
    """``exp(A)`` of a square float matrix (a new array)."""
    n = A.shape[0]
    norm = 0.0
    for j in range(n):
        c = 0.0
        for i in range(n):
            c += abs(A[i, j])
        if c > norm:
            norm = c
    s = 0
    if norm > _THETA13:
        s = int(math.ceil(math.log2(norm / _THETA13)))
    scale = 0.5**s
    As = A * scale
    A2 = np.empty((n, n))
    A4 = np.empty((n, n))
    A6 = np.empty((n, n))
    _mm(As, As, A2)
    _mm(A2, A2, A4)
    _mm(A4, A2, A6)
    b = _B
    W = b[13] * A6 + b[11] * A4 + b[9] * A2
    T = np.empty((n, n))
    _mm(A6, W, T)
    W1 = T + b[7] * A6 + b[5] * A4 + b[3] * A2
    for i in range(n):
        W1[i, i] += b[1]
    U = np.empty((n, n))
    _mm(As, W1, U)
    Z = b[12] * A6 + b[10] * A4 + b[8] * A2
    _mm(A6, Z, T)
    V = T + b[6] * A6 + b[4] * A4 + b[2] * A2
    for i in range(n):
        V[i, i] += b[0]
    R = np.linalg.solve(V - U, V + U)
    for _ in range(s):
        _mm(R, R, T)
        R, T = T, R
    return R
