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

with ``s = sgn(v) g(|v|)`` the static level. The static fields enter through ``g`` (``v`` is the
data's, so only the law moves it): ``T = xi_i s`` gives ``dT = s dxi_i + xi_i sgn(v) dg`` in the
breakaway and slipping updates, the decay ``e = exp(-C dt / g)`` gives
``de = -e dt (dC / g - C dg / g^2)``, and the output's viscous term ``sigma2 v`` gives ``v dsigma2``;
``dg = dFc (1 - phi) + dFs phi + (Fs - Fc)(dphi/dvs dvs + dphi/ddelta ddelta)`` with
``g = Fc + (Fs - Fc) phi(|v| / vs)`` (exponential ``phi = exp(-(|v|/vs)^delta)`` or Lorentzian
``1 / (1 + (|v|/vs)^2)``). The levels are used as packed (the kernels' floor at ``1e-9`` of the
largest level only matters for a law whose level vanishes, where the fit is not differentiable).
The parameters reach ``k``, ``xi``, ``C`` through coefficients ``dk[j] = d k / d theta_j``
(``2 x M`` per parameter, both rows), likewise ``dxi``, ``dC``, and the packed static rows through
``dst[j] = d [Fc, Fs, vs, delta, sigma2] / d theta_j`` (``2 x 5``).
"""

from __future__ import annotations

import math

import numpy as np

from .._jit import njit
from .gms import _sgn
from ._stribeck import R_DELTA, R_DF, R_IVS, R_S2, R_SHAPE, R_VCUT, g_row
from ._stribeck import row as static_row

OK = 0


@njit(inline="always")
def _phi_parts(p, av):
    """``(phi, dphi/dvs, dphi/ddelta)`` of ``g = Fc + (Fs - Fc) phi`` at speed ``av`` (row tuple ``p``)."""
    if av > p[R_VCUT]:
        return 0.0, 0.0, 0.0
    r = av * p[R_IVS]
    if r == 0.0:
        return 1.0, 0.0, 0.0
    if p[R_SHAPE] == 0.0:
        d = p[R_DELTA]
        rd = r * r if d == 2.0 else (r if d == 1.0 else r**d)
        phi = math.exp(-rd)
        return phi, phi * d * rd * p[R_IVS], -phi * rd * math.log(r)
    q = 1.0 / (1.0 + r * r)
    return q, 2.0 * r * r * q * q * p[R_IVS], 0.0


@njit
def gms_motion_sens(xpos, dt, static, k, xi, C, dk, dxi, dC, dst, F_out, S_out):
    """Force of the motion-driven GMS from the unloaded state and ``dF/d theta``.

    ``xpos`` (N,), ``k``/``xi`` (2, M), ``C`` (2,), ``dk``/``dxi`` (p, 2, M), ``dC`` (p, 2),
    ``dst`` (p, 2, 5) (static rows ``[Fc, Fs, vs, delta, sigma2]``); writes ``F_out`` (N,) and
    ``S_out`` (N, p). Returns 0.
    """
    N = xpos.size
    M = k.shape[1]
    P = dk.shape[0]
    Fi = np.zeros(M)
    dF = np.zeros((M, P))
    dg = np.zeros(P)  # d g / d theta_j at the interval's speed
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
                pr = p0 if row == 0 else p1
                g = g_row(pr, abs(vk))
                s = sv * g
                decay = math.exp(-C[row] * dt / g)
                phi, dphi_vs, dphi_de = _phi_parts(pr, abs(vk))
                for j in range(P):
                    dg[j] = (dst[j, row, 0] * (1.0 - phi) + dst[j, row, 1] * phi
                             + pr[R_DF] * (dphi_vs * dst[j, row, 2] + dphi_de * dst[j, row, 3]))
                for i in range(M):
                    target = xi[row, i] * s
                    if st_[i]:
                        Fe = Fi[i] + k[row, i] * vk * dt
                        if sv * Fe >= xi[row, i] * g:
                            if sv * Fi[i] >= xi[row, i] * g:
                                for j in range(P):
                                    dT = s * dxi[j, row, i] + xi[row, i] * sv * dg[j]
                                    dF[i, j] = ((1.0 - decay) * dT + decay * dF[i, j]
                                                - (Fi[i] - target) * decay * dt / g
                                                * (dC[j, row] - C[row] * dg[j] / g))
                                Fi[i] = target + (Fi[i] - target) * decay
                            else:
                                for j in range(P):
                                    dF[i, j] = s * dxi[j, row, i] + xi[row, i] * sv * dg[j]
                                Fi[i] = target
                            st_[i] = False
                        else:
                            for j in range(P):
                                dF[i, j] += vk * dt * dk[j, row, i]
                            Fi[i] = Fe
                    else:
                        for j in range(P):
                            dT = s * dxi[j, row, i] + xi[row, i] * sv * dg[j]
                            dF[i, j] = ((1.0 - decay) * dT + decay * dF[i, j]
                                        - (Fi[i] - target) * decay * dt / g * (dC[j, row] - C[row] * dg[j] / g))
                        Fi[i] = target + (Fi[i] - target) * decay
        row = 0 if vk >= 0.0 else 1
        tot = 0.0
        for i in range(M):
            tot += Fi[i]
        F_out[kk] = tot + (p0 if row == 0 else p1)[R_S2] * vk
        for j in range(P):
            acc = dst[j, row, 4] * vk  # the viscous term sigma2 v
            for i in range(M):
                acc += dF[i, j]
            S_out[kk, j] = acc
    return OK
