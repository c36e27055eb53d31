"""GMS kernels: force-driven mass (adaptive ROS2 with located switches) and motion-driven (exact).

State: position ``x``, velocity ``v``, element forces ``F_i`` and stick flags.

* sticking element: ``F_i' = k_i v``
* slipping element: ``F_i' = sgn(v) C (xi_i - F_i / s(v)) = C (xi_i sgn(v) - F_i / g)``
  with ``g = |s(v)|``
* a sticking element breaks away when ``sgn(v) F_i >= xi_i g``; every slipping
  element sticks when ``v`` changes sign.

Force-driven scheme
-------------------
Between switches the sticking elements are springs: ``F_i = F_i0 + k_i (x - x0)``
exactly, so the stiff part of the problem is a linear mass–spring–damper
(``K = sum of sticking k_i``, damping ``sigma2``) that ``kernels._oscillator``
solves exactly for an affine load — stiffness 1e8 N/m costs nothing and rings
with the right frequency and amplitude. Only the slipping elements (rate
``C/|s|``, slow) are approximated: their total force enters as an affine-in-time
load, predicted from their rates and corrected twice with the secant of their
exact exponential update at the mean velocity; the change between passes is the
error estimate that sizes the adaptive sub-step. In pure pre-sliding the step is
exact and one sub-step covers a sample interval.

Switches are located inside the sample interval instead of on the step grid:
when a trial sub-step crosses a breakaway or velocity-reversal surface, the event
function is interpolated linearly, the sub-step is shortened to land just past
the crossing (within ``1e-6 dt``) and retried; the switch is applied on the
accepted state.

Motion-driven scheme
--------------------
Piecewise-linear position: ``v`` is constant on each interval, so a sticking
element is linear in time, its breakaway instant is found in closed form, and a
slipping element relaxes exactly as ``xi s + (F - xi s) exp(-C t / g)``.

Status codes: 0 ok, 1 non-finite state, 2 sub-step budget exhausted.
"""

from __future__ import annotations

import math

import numpy as np

from .._jit import njit, prange
from ._oscillator import coefficients
from ._stribeck import g_only

OK, NONFINITE, BUDGET = 0, 1, 2
EVENT_TOL = 1e-6  # fraction of dt within which a switch is located


@njit(inline="always")
def _sgn(v):
    return 1.0 if v > 0.0 else (-1.0 if v < 0.0 else 0.0)


@njit(inline="always")
def _rates(v, F, stick, k, xi, C, static, row, g, out):
    """Fill ``out`` with ``F_i'`` and return ``sum F_i``."""
    sv = _sgn(v)
    tot = 0.0
    ig = 1.0 / g
    for i in range(F.size):
        tot += F[i]
        if stick[i]:
            out[i] = k[row, i] * v
        else:
            out[i] = C[row] * (xi[row, i] * sv - F[i] * ig)
    return tot


@njit(inline="always")
def _is_directional(static, k, xi, C):
    if C[0] != C[1]:
        return True
    for j in range(static.shape[1]):
        if static[0, j] != static[1, j]:
            return True
    for i in range(k.shape[1]):
        if k[0, i] != k[1, i] or xi[0, i] != xi[1, i]:
            return True
    return False


@njit(inline="always")
def _interval(
    x, v, F, stick, h_try, u0, u1, dt, m, static, k, xi, C, directional, rtol, atol_v, atol_F, max_sub, sc, cc
):
    """Advance one sample interval in place (``F``, ``stick``); returns ``(x, v, h_try, n, status)``.

    ``sc`` is scratch of shape ``(3, M)`` (rows: first and second slip pass); ``cc`` (9,) caches the oscillator
    coefficients ``[K, c, h, E12, E22, q1, r1, q2, r2]`` across calls. Each sub-step solves the mass on the
    springs of the sticking elements exactly (``kernels._oscillator``), with the
    slipping elements' total force as an affine-in-time load: predicted from
    their rates, then corrected with the secant of their exact exponential
    update at the mean velocity (twice). The difference between the passes is
    the error estimate.
    """
    M = F.size
    du = (u1 - u0) / dt
    t = 0.0
    n = 0
    h_ev = EVENT_TOL * dt
    while t < dt:
        h = h_try
        rem = dt - t
        if h >= rem or rem - h < 1e-9 * dt:
            h = rem
        w = u0 + du * t
        row = 0 if v >= 0.0 else 1
        c = static[row, 4]
        sv = _sgn(v)
        g0 = g_only(static, row, abs(v))
        K = 0.0
        S0 = 0.0
        P0 = 0.0
        R0 = 0.0
        any_slip = False
        for i in range(M):
            if stick[i]:
                K += k[row, i]
                S0 += F[i]
            else:
                any_slip = True
                P0 += F[i]
                R0 += C[row] * (xi[row, i] * sv - F[i] / g0)
        if K != cc[0] or c != cc[1] or h != cc[2]:
            _, E12, _, E22, q1, r1, q2, r2 = coefficients(K, c, m, h)
            cc[0] = K
            cc[1] = c
            cc[2] = h
            cc[3] = E12
            cc[4] = E22
            cc[5] = q1
            cc[6] = r1
            cc[7] = q2
            cc[8] = r2
        else:
            E12 = cc[3]
            E22 = cc[4]
            q1 = cc[5]
            r1 = cc[6]
            q2 = cc[7]
            r2 = cc[8]
        im = 1.0 / m
        f0 = (w - S0 - P0) * im
        # predictor: slip forces linear in time with their initial rates
        f1 = (du - R0) * im
        xi_n = E12 * v + q1 * f0 + q2 * f1
        vn = E22 * v + r1 * f0 + r2 * f1
        e = 0.0
        if any_slip:
            Pa = 0.0
            Pb = 0.0
            for sweep in range(2):
                vb = xi_n / h  # mean velocity over the sub-step (exact for the current pass)
                rb = 0 if vb >= 0.0 else 1
                gb = g_only(static, rb, abs(vb))
                sb = _sgn(vb) * gb
                decay = math.exp(-C[rb] * h / gb)
                P = 0.0
                for i in range(M):
                    if not stick[i]:
                        tgt = xi[rb, i] * sb
                        val = tgt + (F[i] - tgt) * decay
                        if sweep == 0:
                            sc[0, i] = val
                        else:
                            sc[1, i] = val
                        P += val
                f1 = (du - (P - P0) / h) * im
                v_prev = vn
                xi_n = E12 * v + q1 * f0 + q2 * f1
                vn = E22 * v + r1 * f0 + r2 * f1
                if sweep == 0:
                    Pa = P
                else:
                    Pb = P
            e = abs(vn - v_prev) / (atol_v + rtol * abs(vn))
            # truncation indicator: frozen s at the mean velocity (midpoint) against
            # the mean of the updates frozen at both ends (trapezoid); both second
            # order, their gap measures how much s(v) varies over the sub-step
            r_0 = 0 if v >= 0.0 else 1
            r_n = 0 if vn >= 0.0 else 1
            g_n = g_only(static, r_n, abs(vn))
            s_0 = sv * g0
            s_n = _sgn(vn) * g_n
            d_0 = math.exp(-C[r_0] * h / g0)
            d_n = math.exp(-C[r_n] * h / g_n)
            # the load was taken affine between P0 and P(h); a cubic Hermite with the
            # end rates differs from it by (h^2/12)(R0 - Rh) in impulse: its effect
            # on the velocity is the coupling error
            svn_ = _sgn(vn)
            Rh = 0.0
            for i in range(M):
                if not stick[i]:
                    Rh += C[r_n] * (xi[r_n, i] * svn_ - sc[1, i] / g_n)
            q = (h * h / 12.0) * abs(R0 - Rh) * im / (atol_v + rtol * abs(vn))
            if q > e:
                e = q
            for i in range(M):
                if not stick[i]:
                    t0_ = xi[r_0, i] * s_0
                    tn_ = xi[r_n, i] * s_n
                    trap = 0.5 * (t0_ + (F[i] - t0_) * d_0 + tn_ + (F[i] - tn_) * d_n)
                    q = max(abs(sc[1, i] - sc[0, i]), abs(sc[1, i] - trap)) / (atol_F + rtol * abs(sc[1, i]))
                    if q > e:
                        e = q
        n += 1
        if n >= max_sub:
            return x, v, h_try, n, BUDGET
        if not (math.isfinite(xi_n) and math.isfinite(vn)):
            if h > 1e-7 * dt:
                h_try = 0.1 * h
                continue
            return x, v, h_try, n, NONFINITE
        if e > 1.0 and h > 1e-7 * dt:
            h_try = h * max(0.2, 0.9 / math.sqrt(e))
            continue
        # --- switching surfaces crossed inside this trial step?
        theta = 2.0
        reversed_ = (v > 0.0 and vn <= 0.0) or (v < 0.0 and vn >= 0.0)
        if reversed_ and v != 0.0:
            th_r = v / (v - vn)
            if th_r * h > h_ev:
                # A sticking element's force peaks where v = 0 (the displacement
                # extremum), so a breakaway can fall between the step's ends and go
                # unseen (grazing). If one could be within reach, first land just
                # *before* the reversal, where the breakaway test below applies in the
                # old direction; the next sub-step then crosses v = 0.
                reach = abs(v) * h
                for i in range(M):
                    if stick[i] and xi[row, i] * g0 - sv * F[i] <= k[row, i] * reach:
                        theta = th_r - h_ev / h
                        break
            if theta > 1.0 and (any_slip or directional):
                theta = th_r
        rown = 0 if vn >= 0.0 else 1
        gn = g_only(static, rown, abs(vn))
        svn = _sgn(vn)
        if vn != 0.0 and not reversed_:
            for i in range(M):
                if stick[i]:
                    Fe = F[i] + k[row, i] * xi_n
                    e1 = xi[rown, i] * gn - svn * Fe
                    if e1 <= 0.0:
                        e0 = xi[row, i] * g0 - svn * F[i]
                        th = e0 / (e0 - e1) if e0 > 0.0 else 0.0
                        if th < theta:
                            theta = th
        if theta < 1.0 and (1.0 - theta) * h > h_ev:
            # land just past the first crossing (just before a reversal) and try again
            h_try = max(theta * h + 0.5 * h_ev, 0.5 * h_ev)
            continue
        # accept
        for i in range(M):
            if stick[i]:
                F[i] += k[row, i] * xi_n
            else:
                F[i] = sc[1, i]
        x += xi_n
        v = vn
        t += h
        if theta <= 1.0:
            if reversed_:
                for i in range(M):
                    stick[i] = True
            if vn != 0.0:
                for i in range(M):
                    if stick[i] and svn * F[i] >= xi[rown, i] * gn:
                        stick[i] = False
        fac = 0.9 / math.sqrt(e) if e > 0.0 else 5.0
        h_try = h * min(5.0, max(0.2, fac))
    return x, v, h_try, n, OK


@njit
def gms_force(
    u, dt, m, static, k, xi, C, x0, v0, F0, stick0, rtol, atol_v, atol_F, max_sub,
    x, v, F, Fel, stick_out,
):
    """Force-driven run; fills ``x, v, F`` (N,), ``Fel`` (N, M) and ``stick_out`` (N, M)."""
    M = F0.size
    Fi = F0.copy()
    st_ = stick0.copy()
    sc = np.empty((3, M))
    cc = np.full(9, -1.0)
    directional = _is_directional(static, k, xi, C)
    xs = x0
    vs_ = v0
    h_try = dt
    total = 0
    for kk in range(u.size):
        if kk > 0:
            xs, vs_, h_try, n, status = _interval(
                xs, vs_, Fi, st_, h_try, u[kk - 1], u[kk], dt, m, static, k, xi, C, directional,
                rtol, atol_v, atol_F, max_sub, sc, cc,
            )
            total += n
        else:
            status = OK
        x[kk] = xs
        v[kk] = vs_
        row = 0 if vs_ >= 0.0 else 1
        tot = 0.0
        for i in range(M):
            tot += Fi[i]
            Fel[kk, i] = Fi[i]
            stick_out[kk, i] = st_[i]
        F[kk] = tot + static[row, 4] * vs_
        if status != OK:
            return status, kk, total
    return OK, u.size - 1, total


@njit(parallel=True)
def gms_force_batch_sse(
    u, dt, m, static, k, xi, C, rtol, atol_v, atol_F, max_sub, target, which, weight, out_sse, out_status
):
    """P parameter sets on one input; weighted squared error of position (0), velocity (1) or force (2)."""
    P = m.size
    M = k.shape[2]
    for j in prange(P):
        Fi = np.zeros(M)
        st_ = np.ones(M, dtype=np.bool_)
        sc = np.empty((3, M))
        cc = np.full(9, -1.0)
        directional = _is_directional(static[j], k[j], xi[j], C[j])
        xs = 0.0
        vs_ = 0.0
        h_try = dt
        acc = 0.0
        status = OK
        for kk in range(1, u.size):
            xs, vs_, h_try, n, status = _interval(
                xs, vs_, Fi, st_, h_try, u[kk - 1], u[kk], dt, m[j], static[j], k[j], xi[j], C[j], directional,
                rtol, atol_v, atol_F, max_sub, sc, cc,
            )
            if status != OK:
                break
            if which == 0:
                y = xs
            elif which == 1:
                y = vs_
            else:
                row = 0 if vs_ >= 0.0 else 1
                y = Fi.sum() + static[j][row, 4] * vs_
            dd = y - target[kk]
            acc += weight[kk] * dd * dd
        out_sse[j] = acc if status == OK else np.inf
        out_status[j] = status


@njit
def gms_motion(xpos, dt, static, k, xi, C, F0, stick0, v_out, F_out, Fel, stick_out):
    """Motion-driven GMS, exact for piecewise-linear position."""
    N = xpos.size
    M = F0.size
    Fi = F0.copy()
    st_ = stick0.copy()
    last_sign = 0.0
    for kk in range(N):
        if kk == 0:
            vk = (xpos[1] - xpos[0]) / dt
        else:
            vk = (xpos[kk] - xpos[kk - 1]) / dt
            sv = _sgn(vk)
            if sv != last_sign:
                # reversal or rest: every slipping element sticks again
                for i in range(M):
                    st_[i] = True
                last_sign = sv
            if sv != 0.0:
                row = 0 if vk >= 0.0 else 1
                g = g_only(static, row, abs(vk))
                s = sv * g
                decay = math.exp(-C[row] * dt / g)
                for i in range(M):
                    target = xi[row, i] * s
                    if st_[i]:
                        Fe = Fi[i] + k[row, i] * vk * dt
                        if sv * Fe >= xi[row, i] * g:
                            if sv * Fi[i] >= xi[row, i] * g:
                                # already past the (lowered) limit: slips the whole interval
                                Fi[i] = target + (Fi[i] - target) * decay
                            else:
                                # breaks away inside the interval at F = xi s, then stays there
                                Fi[i] = target
                            st_[i] = False
                        else:
                            Fi[i] = Fe
                    else:
                        Fi[i] = target + (Fi[i] - target) * decay
        row = 0 if vk >= 0.0 else 1
        tot = 0.0
        for i in range(M):
            tot += Fi[i]
            Fel[kk, i] = Fi[i]
            stick_out[kk, i] = st_[i]
        v_out[kk] = vk
        F_out[kk] = tot + static[row, 4] * vk
    return OK
