"""Forward sensitivities of the motion-driven GMS update (issue 11 part 6, private kernel).

:func:`frictionkit.kernels.gms.gms_motion` maps a piecewise-linear position onto element
forces with explicit per-sample updates; :func:`gms_motion_sens` takes the same steps (same
branches, same arithmetic: the force equals ``gms_motion``'s to round-off, tested) and
differentiates each of them — the exact derivative of the discrete map wherever it is
differentiable (everywhere but on the stick/slip switching surfaces, a set of measure zero):

* sticking: ``F_i += k_i v dt``                         -> ``dF_i += v dt dk_i``
* breaking away inside the interval: ``F_i = xi_i s``   -> ``dF_i = s dxi_i``
* slipping: ``F_i = T + (F_i - T) e^(-C dt/g)``, ``T = xi_i s``
  -> ``dF_i = (1 - e) s dxi_i + e dF_i - (F_i - T) e dt/g dC``

with ``s = sgn(v) g(|v|)`` the static level (its fields are not differentiated: a fit that
frees them uses differences). The parameters reach ``k``, ``xi``, ``C`` through coefficients
``dk[j] = d k / d theta_j`` (``2 x M`` per parameter, both rows), likewise ``dxi``, ``dC``.
The viscous term ``sigma2 v`` of the output does not depend on them.
"""

from __future__ import annotations

import math

import numpy as np

from .._jit import njit
from .gms import _sgn
from ._stribeck import R_S2, g_row
from ._stribeck import row as static_row

OK = 0


@njit
def gms_motion_sens(xpos, dt, static, k, xi, C, dk, dxi, dC, F_out, S_out):
    """Force of the motion-driven GMS from the unloaded state and ``dF/d theta``.

    ``xpos`` (N,), ``k``/``xi`` (2, M), ``C`` (2,), ``dk``/``dxi`` (p, 2, M), ``dC`` (p, 2);
    writes ``F_out`` (N,) and ``S_out`` (N, p). Returns 0.
    """
    N = xpos.size
    M = k.shape[1]
    P = dk.shape[0]
    Fi = np.zeros(M)
    dF = np.zeros((M, P))
    st_ = np.ones(M, dtype=np.bool_)
    p0 = static_row(static, 0)
    p1 = static_row(static, 1)
    last_sign = 0.0
    vk = 0.0
    for kk in range(N):
        if kk == 0:
            vk = (xpos[1] - xpos[0]) / dt
        else:
            vk = (xpos[kk] - xpos[kk - 1]) / dt
            sv = _sgn(vk)
            if sv != last_sign:
                for i in range(M):
                    st_[i] = True
                last_sign = sv
            if sv != 0.0:
                row = 0 if vk >= 0.0 else 1
                g = g_row(p0 if row == 0 else p1, abs(vk))
                s = sv * g
                decay = math.exp(-C[row] * dt / g)
                for i in range(M):
                    target = xi[row, i] * s
                    if st_[i]:
                        Fe = Fi[i] + k[row, i] * vk * dt
                        if sv * Fe >= xi[row, i] * g:
                            if sv * Fi[i] >= xi[row, i] * g:
                                for j in range(P):
                                    dF[i, j] = ((1.0 - decay) * s * dxi[j, row, i] + decay * dF[i, j]
                                                - (Fi[i] - target) * decay * dt / g * dC[j, row])
                                Fi[i] = target + (Fi[i] - target) * decay
                            else:
                                for j in range(P):
                                    dF[i, j] = s * dxi[j, row, i]
                                Fi[i] = target
                            st_[i] = False
                        else:
                            for j in range(P):
                                dF[i, j] += vk * dt * dk[j, row, i]
                            Fi[i] = Fe
                    else:
                        for j in range(P):
                            dF[i, j] = ((1.0 - decay) * s * dxi[j, row, i] + decay * dF[i, j]
                                        - (Fi[i] - target) * decay * dt / g * dC[j, row])
                        Fi[i] = target + (Fi[i] - target) * decay
        row = 0 if vk >= 0.0 else 1
        tot = 0.0
        for i in range(M):
            tot += Fi[i]
        F_out[kk] = tot + (p0 if row == 0 else p1)[R_S2] * vk
        for j in range(P):
            acc = 0.0
            for i in range(M):
                acc += dF[i, j]
            S_out[kk, j] = acc
    return OK
