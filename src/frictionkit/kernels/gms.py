"""GMS kernels: force-driven mass (adaptive ROS2 with located switches) and motion-driven (exact).

State: position ``x``, velocity ``v``, element forces ``F_i`` and stick flags.

* sticking element: ``F_i' = k_i v``
* slipping element: ``F_i' = sgn(v) C (xi_i - F_i / s(v)) = C (xi_i sgn(v) - F_i / g)``
  with ``g = |s(v)|``
* a sticking element breaks away when ``sgn(v) F_i >= xi_i g``; every slipping
  element sticks when ``v`` changes sign.

Force-driven scheme
-------------------
The same ROS2 sub-steps as the LuGre kernel (see ``kernels/lugre.py``), on the
arrow-shaped system ``(x, v, F_1..F_M, w)``; the linear stage equations are
solved in O(M) through the Schur complement of the velocity row. Switches are
located inside the sample interval instead of on the step grid: when a trial
sub-step crosses a breakaway or velocity-reversal surface, the event function is
interpolated linearly, the sub-step is shortened to land just past the crossing
(within ``1e-6 dt``) and retried; the switch is applied on the accepted state.

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
from ._stribeck import g_and_slope, g_only

GAMMA = 1.0 + 1.0 / math.sqrt(2.0)
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


@njit
def _interval(
    x, v, F, stick, h_try, u0, u1, dt, m, static, k, xi, C, rtol, atol_v, atol_F, max_sub, sc
):
    """Advance one sample interval in place (``F``, ``stick``); returns ``(x, v, h_try, n, status)``.

    ``sc`` is scratch of shape ``(7, M)``.
    """
    M = F.size
    k1 = sc[0]
    k2 = sc[1]
    d = sc[2]
    Jiv = sc[3]
    Fn = sc[4]
    r = sc[5]
    F2 = sc[6]
    im = 1.0 / m
    du = (u1 - u0) / dt
    t = 0.0
    w = u0
    n = 0
    h_ev = EVENT_TOL * dt
    directional = _is_directional(static, k, xi, C)
    while t < dt:
        h = h_try
        rem = dt - t
        if h >= rem or rem - h < 1e-9 * dt:
            h = rem
        row = 0 if v >= 0.0 else 1
        sig2 = static[row, 4]
        av = abs(v)
        g, gr = g_and_slope(static, row, av)
        ig = 1.0 / g
        sv = _sgn(v)
        gh = GAMMA * h
        # Jacobian pieces: dF_i'/dv (Jiv) and 1/(1 - gh dF_i'/dF_i) (d)
        for i in range(M):
            if stick[i]:
                Jiv[i] = k[row, i]
                d[i] = 1.0
            else:
                Jiv[i] = C[row] * F[i] * sv * gr * ig * ig
                d[i] = 1.0 / (1.0 + gh * C[row] * ig)
        S = 0.0
        for i in range(M):
            S += d[i] * Jiv[i]
        piv = 1.0 / (1.0 + gh * sig2 * im + gh * gh * im * S)
        # stage 1
        tot = _rates(v, F, stick, k, xi, C, static, row, g, r)
        rv = (w - tot - sig2 * v + gh * du) * im
        acc = 0.0
        for i in range(M):
            acc += d[i] * r[i]
        k1v = (rv - gh * im * acc) * piv
        for i in range(M):
            k1[i] = (r[i] + gh * Jiv[i] * k1v) * d[i]
        k1x = v + gh * k1v
        # stage 2
        v2 = v + h * k1v
        for i in range(M):
            F2[i] = F[i] + h * k1[i]
        row2 = 0 if v2 >= 0.0 else 1
        g2 = g_only(static, row2, abs(v2))
        tot2 = _rates(v2, F2, stick, k, xi, C, static, row2, g2, r)
        for i in range(M):
            r[i] -= 2.0 * k1[i]
        rv = (w + h * du - tot2 - static[row2, 4] * v2 - gh * du) * im - 2.0 * k1v
        acc = 0.0
        for i in range(M):
            acc += d[i] * r[i]
        k2v = (rv - gh * im * acc) * piv
        for i in range(M):
            k2[i] = (r[i] + gh * Jiv[i] * k2v) * d[i]
        k2x = v2 - 2.0 * k1x + gh * k2v
        xn = x + h * (1.5 * k1x + 0.5 * k2x)
        vn = v + h * (1.5 * k1v + 0.5 * k2v)
        ok = math.isfinite(xn) and math.isfinite(vn)
        # error: velocity and element forces, filtered through (I - gh J)^-1
        ev_raw = 0.5 * h * (k1v + k2v)
        acc = 0.0
        for i in range(M):
            Fn[i] = F[i] + h * (1.5 * k1[i] + 0.5 * k2[i])
            ok = ok and math.isfinite(Fn[i])
            acc += d[i] * 0.5 * h * (k1[i] + k2[i])
        ev = (ev_raw - gh * im * acc) * piv
        e = abs(ev) / (atol_v + rtol * abs(vn))
        for i in range(M):
            ei = (0.5 * h * (k1[i] + k2[i]) + gh * Jiv[i] * ev) * d[i]
            q = abs(ei) / (atol_F + rtol * abs(Fn[i]))
            if q > e:
                e = q
        n += 1
        if n >= max_sub:
            return x, v, h_try, n, 2
        if not ok:
            if h > 1e-7 * dt:
                h_try = 0.1 * h
                continue
            return x, v, h_try, n, NONFINITE
        if e > 1.0 and h > 1e-7 * dt:
            h_try = h * max(0.2, 0.9 / math.sqrt(e))
            continue
        # --- switching surfaces crossed inside this trial step?
        theta = 2.0
        any_slip = False
        for i in range(M):
            if not stick[i]:
                any_slip = True
        reversed_ = (v > 0.0 and vn <= 0.0) or (v < 0.0 and vn >= 0.0)
        if reversed_ and (any_slip or directional) and v != 0.0:
            theta = v / (v - vn)
        rown = 0 if vn >= 0.0 else 1
        gn = g_only(static, rown, abs(vn))
        svn = _sgn(vn)
        if vn != 0.0:
            for i in range(M):
                if stick[i]:
                    e1 = xi[rown, i] * gn - svn * Fn[i]
                    if e1 <= 0.0:
                        e0 = xi[row, i] * g - svn * F[i]
                        th = e0 / (e0 - e1) if e0 > 0.0 else 0.0
                        if th < theta:
                            theta = th
        if theta < 1.0 and (1.0 - theta) * h > h_ev:
            # land just past the first crossing and try again
            h_try = theta * h + 0.5 * h_ev
            continue
        # accept
        x = xn
        v = vn
        for i in range(M):
            F[i] = Fn[i]
        t += h
        w = u0 + du * t
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
    sc = np.empty((7, M))
    xs = x0
    vs_ = v0
    h_try = dt
    total = 0
    for kk in range(u.size):
        if kk > 0:
            xs, vs_, h_try, n, status = _interval(
                xs, vs_, Fi, st_, h_try, u[kk - 1], u[kk], dt, m, static, k, xi, C,
                rtol, atol_v, atol_F, max_sub, sc,
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
        sc = np.empty((7, M))
        xs = 0.0
        vs_ = 0.0
        h_try = dt
        acc = 0.0
        status = OK
        for kk in range(1, u.size):
            xs, vs_, h_try, n, status = _interval(
                xs, vs_, Fi, st_, h_try, u[kk - 1], u[kk], dt, m[j], static[j], k[j], xi[j], C[j],
                rtol, atol_v, atol_F, max_sub, sc,
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
            if sv != 0.0:
                if last_sign != 0.0 and sv != last_sign:
                    for i in range(M):
                        st_[i] = True
                last_sign = sv
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
