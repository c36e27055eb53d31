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
from ._oscillator import coefficients
from .gms import _sgn
from ._stribeck import R_DELTA, R_DF, R_FS, R_IVS, R_S2, R_SHAPE, R_VCUT, g_row
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


# =========================================================================== force drive
@njit(inline="always")
def _g_and_slope(p, av):
    """``(g, dg/d|v|)`` at speed ``av`` from a row tuple."""
    g = g_row(p, av)
    if av > p[R_VCUT]:
        return g, 0.0
    r = av * p[R_IVS]
    if r == 0.0:
        return g, 0.0
    if p[R_SHAPE] == 0.0:
        d = p[R_DELTA]
        rd = r * r if d == 2.0 else (r if d == 1.0 else r**d)
        return g, -p[R_DF] * math.exp(-rd) * d * rd / r * p[R_IVS]
    q = 1.0 / (1.0 + r * r)
    return g, -p[R_DF] * 2.0 * r * q * q * p[R_IVS]


@njit(inline="always")
def _herm(x0, v0, a0, x1, v1, a1, dt, tau):
    """Position, velocity and acceleration at ``tau`` (fraction of the interval) of the cubic Hermite
    interpolants of the interval's end values (``x`` from ``x, v``; ``v`` from ``v, a``)."""
    t2 = tau * tau
    t3 = t2 * tau
    h00 = 2.0 * t3 - 3.0 * t2 + 1.0
    h10 = t3 - 2.0 * t2 + tau
    h01 = -2.0 * t3 + 3.0 * t2
    h11 = t3 - t2
    X = h00 * x0 + h10 * dt * v0 + h01 * x1 + h11 * dt * v1
    V = h00 * v0 + h10 * dt * a0 + h01 * v1 + h11 * dt * a1
    d00 = (6.0 * t2 - 6.0 * tau) / dt
    d10 = 3.0 * t2 - 4.0 * tau + 1.0
    d01 = (-6.0 * t2 + 6.0 * tau) / dt
    d11 = 3.0 * t2 - 2.0 * tau
    A = d00 * v0 + d10 * dt * a0 + d01 * v1 + d11 * dt * a1
    return X, V, A


@njit(inline="always")
def _dg_into(dgv, dst, row, pr, av):
    phi, dphi_vs, dphi_de = _phi_parts(pr, av)
    for j in range(dgv.size):
        dgv[j] = (dst[j, row, 0] * (1.0 - phi) + dst[j, row, 1] * phi
                  + pr[R_DF] * (dphi_vs * dst[j, row, 2] + dphi_de * dst[j, row, 3]))


@njit
def _sens_step(h, m, k, xi, C, row, pr, st_, XA, VA, AA, XB, VB, AB, FA_, FB_, sdef,
               dk, dxi, dC, dst, dm, doff, Sx, Sv, SF, SFs, dgv, Sx1, Sv1, cc):
    """One sub-step of length ``h`` of the sensitivities (see :func:`gms_force_sens`); ``cc`` caches
    the oscillator coefficients on ``(K, c, h)``."""
    M = k.shape[1]
    P = dk.shape[0]
    c = pr[R_S2]
    K = 0.0
    for i in range(M):
        if st_[i]:
            K += k[row, i]
    if K != cc[0] or c != cc[1] or h != cc[2]:
        _, cc[3], _, cc[4], cc[5], cc[6], cc[7], cc[8] = coefficients(K, c, m, h)
        cc[0] = K
        cc[1] = c
        cc[2] = h
    E12 = cc[3]
    E22 = cc[4]
    q1 = cc[5]
    r1 = cc[6]
    q2 = cc[7]
    r2 = cc[8]
    Cr = C[row]
    gA, gpA = _g_and_slope(pr, abs(VA))
    gB, gpB = _g_and_slope(pr, abs(VB))
    lam = Cr / (0.5 * (gA + gB))
    dec = math.exp(-lam * h)
    _dg_into(dgv, dst, row, pr, abs(0.5 * (VA + VB)))
    # the slip direction of the whole sub-step (its ends may sit on a reversal, just past zero)
    svA = 1.0 if row == 0 else -1.0
    svB = svA
    for i in range(M):
        if not st_[i]:
            for j in range(P):
                SFs[i, j] = SF[i, j]
    for j in range(P):
        Sv1[j] = Sv[j]
    for ps in range(2):
        for i in range(M):
            if st_[i]:
                continue
            xr = xi[row, i]
            for j in range(P):
                bA = (dC[j, row] * (xr * svA - FA_[i] / gA) + Cr * dxi[j, row, i] * svA
                      + Cr * FA_[i] * (gpA * svA * Sv[j] + dgv[j]) / (gA * gA))
                bB = (dC[j, row] * (xr * svB - FB_[i] / gB) + Cr * dxi[j, row, i] * svB
                      + Cr * FB_[i] * (gpB * svB * Sv1[j] + dgv[j]) / (gB * gB))
                SF[i, j] = dec * SFs[i, j] + (1.0 - dec) / lam * 0.5 * (bA + bB)
        for j in range(P):
            dK = 0.0
            stA = 0.0
            slipA = 0.0
            slipB = 0.0
            for i in range(M):
                if st_[i]:
                    dK += dk[j, row, i]
                    stA += SF[i, j]
                else:
                    slipA += SFs[i, j]
                    slipB += SF[i, j]
            f0 = -(doff[j] + stA + slipA + dst[j, row, 4] * VA + dm[j] * AA)
            fB = -(doff[j] + stA + dK * (XB - XA) + slipB + dst[j, row, 4] * VB + dm[j] * AB)
            f1 = (fB - f0) / h
            Sx1[j] = Sx[j] + E12 * Sv[j] + (q1 * f0 + q2 * f1) / m
            Sv1[j] = E22 * Sv[j] + (r1 * f0 + r2 * f1) / m
    for j in range(P):
        for i in range(M):
            if st_[i]:
                SF[i, j] += k[row, i] * (Sx1[j] - Sx[j]) + dk[j, row, i] * (XB - XA)
        Sx[j] = Sx1[j]
        Sv[j] = Sv1[j]


@njit
def gms_force_sens(u, dt, m, static, k, xi, C, x, v, Fel, stick, dk, dxi, dC, dst, dm, doff, nsub,
                   Sx_out, Sv_out):
    """Sensitivities of a recorded force-driven GMS run (``x``, ``v``, ``Fel``, ``stick`` from
    :func:`frictionkit.simulate`, from rest) with respect to every parameter (see
    :func:`frictionkit.identify._jacobian.gms_force_driven`): ``Sx_out``, ``Sv_out`` (N, p).

    ``u`` is the applied force minus the offset. Per sample interval, ``nsub`` sub-steps: the mass on
    the springs of the sticking elements is solved exactly (``_oscillator.coefficients``) under the
    sensitivity load (the sticking springs' parameter terms ``dk (x(t) - x_s)``, the slipping
    elements, ``dsigma2 v``, ``dm a``, ``doff``; affine per sub-step, the trajectory inside the
    interval the cubic Hermite of its end values); the slipping elements' sensitivities relax
    exactly at their rate ``C / g`` under their load (trapezoid); two passes couple them with
    ``S_v``. A switch the record shows in the interval (an element sticking at its start and
    slipping at its end, or slipping -> sticking across a reversal) is located on the interpolated
    trajectory (bisection), the sub-step split there, and the saltation of its surface applied
    (breakaway: ``sgn(v) F_i = xi_i g(|v|)``, ``F_i'`` jumping from ``k_i v`` to its slip rate;
    reversal: ``v = 0``, the slip rate dropping to 0). Returns 0.
    """
    N = u.size
    M = k.shape[1]
    P = dk.shape[0]
    p0 = static_row(static, 0)
    p1 = static_row(static, 1)
    Sx = np.zeros(P)
    Sv = np.zeros(P)
    SF = np.zeros((M, P))
    SFs = np.zeros((M, P))
    dgv = np.zeros(P)
    Sx1 = np.zeros(P)
    Sv1 = np.zeros(P)
    st_ = np.zeros(M, dtype=np.bool_)
    brk = np.zeros(M, dtype=np.bool_)
    stk = np.zeros(M, dtype=np.bool_)
    FA_ = np.zeros(M)
    FB_ = np.zeros(M)
    Fev = np.zeros(M)  # an element's force where its slip began in this interval (at fraction tev)
    tev = np.zeros(M)
    cc = np.full(9, -1.0)  # oscillator coefficients cached on (K, c, h)
    Fend = np.zeros(M)  # ... and where it ended (at fraction tend: 1, or the reversal that re-sticks it)
    tend = np.zeros(M)
    for j in range(P):
        Sx_out[0, j] = 0.0
        Sv_out[0, j] = 0.0
    hs = 1.0 / nsub
    for kk in range(N - 1):
        x0 = x[kk]
        v0 = v[kk]
        x1 = x[kk + 1]
        v1 = v[kk + 1]
        ra = 0 if (v0 if v0 != 0.0 else v1) >= 0.0 else 1
        r1_ = 0 if v1 >= 0.0 else 1
        Ft0 = 0.0
        Ft1 = 0.0
        for i in range(M):
            Ft0 += Fel[kk, i]
            Ft1 += Fel[kk + 1, i]
        a0 = (u[kk] - Ft0 - (p0 if ra == 0 else p1)[R_S2] * v0) / m
        a1 = (u[kk + 1] - Ft1 - (p0 if r1_ == 0 else p1)[R_S2] * v1) / m
        sdef = 1.0 if (v0 if v0 != 0.0 else v1) > 0.0 else -1.0
        nbrk = 0
        nstk = 0
        for i in range(M):
            st_[i] = stick[kk, i]
            Fev[i] = Fel[kk, i]
            tev[i] = 0.0
            Fend[i] = Fel[kk + 1, i]
            tend[i] = 1.0
            brk[i] = stick[kk, i] and not stick[kk + 1, i]
            stk[i] = (not stick[kk, i]) and stick[kk + 1, i]
            nbrk += brk[i]
            nstk += stk[i]
        if nstk > 0 and v0 * v1 < 0.0:
            # the reversal on the interpolated trajectory: a re-sticking element's slip ended there, at
            # its recorded end force less the spring travel after it
            lo = 0.0
            hi = 1.0
            for _ in range(50):
                mid = 0.5 * (lo + hi)
                _, Vm, _ = _herm(x0, v0, a0, x1, v1, a1, dt, mid)
                if Vm * v0 > 0.0:
                    lo = mid
                else:
                    hi = mid
            Xr, _, _ = _herm(x0, v0, a0, x1, v1, a1, dt, hi)
            for i in range(M):
                if stk[i]:
                    Fend[i] = Fel[kk + 1, i] - k[r1_, i] * (x1 - Xr)
                    tend[i] = hi
        t = 0.0
        while t < 1.0 - 1e-12:
            tn = min(t + hs, 1.0)
            XA, VA, AA = _herm(x0, v0, a0, x1, v1, a1, dt, t)
            XB, VB, AB = _herm(x0, v0, a0, x1, v1, a1, dt, tn)
            # direction at the sub-step's start (the step is split at a reversal, so it holds)
            vd = VA if VA != 0.0 else 0.5 * (VA + VB)
            row = ra if vd == 0.0 else (0 if vd > 0.0 else 1)
            pr = p0 if row == 0 else p1
            # the earliest switch of the record inside [t, tn]
            te = tn
            kind = 0
            ie = -1
            if nstk > 0 and VA * VB < 0.0:
                lo = t
                hi = tn
                for _ in range(40):
                    mid = 0.5 * (lo + hi)
                    _, Vm, _ = _herm(x0, v0, a0, x1, v1, a1, dt, mid)
                    if Vm * VA > 0.0:
                        lo = mid
                    else:
                        hi = mid
                te = hi
                kind = 2
            if nbrk > 0:
                for i in range(M):
                    if not (brk[i] and st_[i]):
                        continue
                    xr = xi[row, i]
                    sB = 1.0 if VB > 0.0 else -1.0
                    FiB = Fel[kk, i] + k[row, i] * (XB - x0)
                    if sB * FiB - xr * g_row(pr, abs(VB)) >= 0.0:
                        lo = t
                        hi = tn
                        for _ in range(40):
                            mid = 0.5 * (lo + hi)
                            Xm, Vm, _ = _herm(x0, v0, a0, x1, v1, a1, dt, mid)
                            sm = 1.0 if Vm > 0.0 else -1.0
                            if sm * (Fel[kk, i] + k[row, i] * (Xm - x0)) - xr * g_row(pr, abs(Vm)) >= 0.0:
                                hi = mid
                            else:
                                lo = mid
                        if hi < te or (kind == 0 and hi <= te):
                            te = hi
                            kind = 1
                            ie = i
            # accelerations from the equation of motion (the interpolant's derivative is a poorer
            # load at resonance, and has a kink at a switch that its cubic cannot follow)
            AA = _accel(t, XA, VA, kk, row, pr, u, m, k, Fel, stick, st_, x0, x1, Fev, tev, Fend, tend)
            if te > t:
                XB, VB, AB = _herm(x0, v0, a0, x1, v1, a1, dt, te)
                AB = _accel(te, XB, VB, kk, row, pr, u, m, k, Fel, stick, st_, x0, x1, Fev, tev, Fend, tend)
                for i in range(M):  # slipping forces: linear from where the slip began in the interval
                    w = 1.0 / (tend[i] - tev[i]) if tend[i] > tev[i] else 0.0
                    FA_[i] = Fev[i] + (t - tev[i]) * w * (Fend[i] - Fev[i])
                    FB_[i] = Fev[i] + (min(te, tend[i]) - tev[i]) * w * (Fend[i] - Fev[i])
                _sens_step((te - t) * dt, m, k, xi, C, row, pr, st_, XA, VA, AA, XB, VB, AB, FA_, FB_, sdef,
                           dk, dxi, dC, dst, dm, doff, Sx, Sv, SF, SFs, dgv, Sx1, Sv1, cc)
            t = te
            if kind == 1:
                Fe = Fel[kk, ie] + k[row, ie] * (XB - x0)
                _breakaway(ie, row, pr, k, xi, C, Fe, VB, AB, dst, dxi, Sv, SF, dgv)
                st_[ie] = False
                Fev[ie] = Fe
                tev[ie] = te
                nbrk -= 1
            elif kind == 2:
                _restick(stk, st_, ra, p0 if ra == 0 else p1, xi, C, FB_, sdef, AB, Sv, SF)
                for i in range(M):
                    if stk[i]:
                        st_[i] = True
                nstk = 0
        # switches the interpolated trajectory did not show inside the interval: at its end
        if nbrk > 0:
            pq = p0 if r1_ == 0 else p1
            for i in range(M):
                if brk[i] and st_[i]:
                    _breakaway(i, r1_, pq, k, xi, C, Fel[kk + 1, i], v1, a1, dst, dxi, Sv, SF, dgv)
                    st_[i] = False
        if nstk > 0 and v0 * v1 < 0.0:
            for i in range(M):
                FB_[i] = Fel[kk + 1, i]
            _restick(stk, st_, ra, p0 if ra == 0 else p1, xi, C, FB_, sdef, a1, Sv, SF)
        for j in range(P):
            Sx_out[kk + 1, j] = Sx[j]
            Sv_out[kk + 1, j] = Sv[j]
    return OK


@njit(inline="always")
def _accel(tau, X, V, kk, row, pr, u, m, k, Fel, stick, st_, x0, x1, Fev, tev, Fend, tend):
    """The acceleration at ``tau`` from the equation of motion: sticking elements on their springs
    (from the interval's start, or back from its end after a re-stick), slipping ones interpolated."""
    tot = 0.0
    for i in range(st_.size):
        if st_[i]:
            if stick[kk, i]:
                tot += Fel[kk, i] + k[row, i] * (X - x0)
            else:
                tot += Fel[kk + 1, i] - k[row, i] * (x1 - X)
        else:
            w = 1.0 / (tend[i] - tev[i]) if tend[i] > tev[i] else 0.0
            tot += Fev[i] + (min(tau, tend[i]) - tev[i]) * w * (Fend[i] - Fev[i])
    return ((1.0 - tau) * u[kk] + tau * u[kk + 1] - tot - pr[R_S2] * V) / m


@njit
def _breakaway(i, row, pr, k, xi, C, Fi, V, A, dst, dxi, Sv, SF, dgv):
    """Saltation of element ``i``'s breakaway (surface ``sgn(v) F_i - xi_i g(|v|) = 0``)."""
    s1 = 1.0 if V > 0.0 else -1.0
    g1, gp1 = _g_and_slope(pr, abs(V))
    _dg_into(dgv, dst, row, pr, abs(V))
    xr = xi[row, i]
    D = k[row, i] * abs(V) - xr * gp1 * s1 * A
    if D == 0.0:
        return
    jump = k[row, i] * V - C[row] * (xr * s1 - Fi / g1)
    for j in range(dgv.size):
        Nj = s1 * SF[i, j] - xr * gp1 * s1 * Sv[j] - dxi[j, row, i] * g1 - xr * dgv[j]
        SF[i, j] += jump * (-Nj / D)


@njit
def _restick(stk, st_, row, pr, xi, C, F, sv, A, Sv, SF):
    """Saltation of the reversal ``v = 0`` for the slipping elements that stick there."""
    if A == 0.0:
        return
    g0 = pr[R_FS]
    for i in range(stk.size):
        if stk[i] and not st_[i]:
            fm = C[row] * (xi[row, i] * sv - F[i] / g0)
            for j in range(Sv.size):
                SF[i, j] += fm * (-Sv[j] / A)
