"""One-DOF fast path of the machine core: a rigid axis with one static friction site.

The machine (checked by the wrapper ``machines.simulate._axis_plan``): one degree of freedom
of inertia ``M`` (no springs, no prescribed motions), one friction site on it holding a
static law with constant positive levels (``CoulombViscous``, ``Stribeck``, ``Directional``
of those; each direction its own levels and viscous coefficient; no schedule, normal load or
``eps``), actuators that follow controller signals (held over the sample) or input arrays
(linear over the sample, clipped at their limits; flat levels only), any sensors and
controller blocks.

Plant step, flat levels (``Fs = Fc``: Coulomb-viscous), exact. Over a sample the actuator
force ``U`` is constant, so between velocity zero crossings ``M v' = U - L_d - V_d v``
(direction ``d``: level ``L_d`` signed, viscous ``V_d``) has the closed form
``v = v_inf + (v0 - v_inf) e^(-beta t)``; a stop inside the sample is located exactly
(``t_s = ln((v0 - v_inf) / -v_inf) / beta``), then the axis sticks while ``-L_- <= U <= L_+``
(Karnopp, as the general kernel's static sites) or breaks away in the other direction. This
is the limit the general kernel converges to as its sub-steps grow; its sample-spanning step
is the same solution for samples that keep sliding. An input-array actuator makes ``U``
linear in time over the sample (in pieces between its limit crossings): the closed form
gains a ramp term, a stop is located by bisection to round-off and a stuck axis breaks away
where ``U`` leaves the band.

Plant step, Stribeck levels (``Fs != Fc``): no closed form; a slide takes classical RK4 steps
(the wrapper picks 20 per shortest time scale, ``M vs / |Fs - Fc|`` or ``M / sigma2``), a stop
inside a step is located on the step's cubic Hermite interpolant and the axis then sticks
while ``-Fs- <= U <= Fs+``. Converged, not exact: the tests compare it with the general loop
at 320/640 sub-steps (and 2560 where the general loop converges slowly).

Controller: the general kernel's controller section (``kernels.machine.run``: inputs, sensors,
blocks, actuators, PID integrators), statement for statement for one DOF without motions, so
the signals are the same numbers bit for bit on the same plant states
(``tests/kernels/test_machine_axis.py`` checks every block kind, sensor and actuator option
against ``run``). A COPY, deliberately: numba's ``inline="always"`` functions shared by both
loops were measured 2x slower here (199 vs 98 ns per EMPS sample, bit-identical results: the
inlined calls carry ~30 array arguments each), and last session's attempts to call them from
``run`` slowed the general kernel 33-55 %. A block kind added to ``run`` must be added here
and to the parity test; until then the wrapper (``machines.simulate._axis_plan``) sends
machines with it to the general loop. Two changes that keep the numbers: the delay lines
advance a slot counter instead of ``k % d``, and the one-DOF sensor rows are read directly.

Recorded site force: the force at the end of the previous sample (sliding: level plus
viscous; stuck: the holding force) in the site's units; 0 at ``k = 0`` when at rest.

Status codes as :mod:`frictionkit.kernels.machine`: 0 ok, 1 non-finite state.
"""

from __future__ import annotations

import math

import numpy as np

from .._jit import njit
from .machine import B_FFF, B_LINEAR, B_PID, B_SAT, B_SS, _quantise, _set_levels, _static_force

STATUS_OK = 0
STATUS_NONFINITE = 1


@njit(inline="always", error_model="numpy")
def _segment(v, U, L, V, Minv, T, emT):
    """``(dx, v_end, t_stop)`` of a slide with velocity sign fixed (level ``L`` signed, viscous
    ``V >= 0``) under force ``U`` for at most ``T``; ``t_stop < T`` when the velocity reaches 0
    first (then ``v_end = 0``), else ``t_stop = T``. ``emT``: ``expm1(-V Minv T)`` if known
    (a whole sample), else NaN."""
    if V > 0.0:
        beta = V * Minv
        vinf = (U - L) / V
        if vinf * v < 0.0:  # decelerating towards rest
            ts = math.log((v - vinf) / -vinf) / beta
            if ts < T:
                return vinf * ts - (v - vinf) * math.expm1(-beta * ts) / beta, 0.0, ts
        em = emT if emT == emT else math.expm1(-beta * T)
        return vinf * T - (v - vinf) * em / beta, v + (v - vinf) * em, T
    a = (U - L) * Minv
    if a * v < 0.0:
        ts = -v / a
        if ts < T:
            return 0.5 * v * ts, 0.0, ts
    return v * T + 0.5 * a * T * T, v + a * T, T


@njit(inline="always", error_model="numpy")
def _piece(x, v, U, T, dt, Lp, Ln, Vp, Vn, Minv, emp, emn):
    """``(x, v, F_end)`` after ``T`` under the constant force ``U``: exact slide / stop / stick
    (at most: slide, stop, slide back). ``emp``, ``emn``: ``expm1(-V Minv dt)`` per direction,
    used when ``T`` is the whole sample ``dt``."""
    t = 0.0
    F = 0.0
    for seg in range(4):
        if v == 0.0:
            if U > Lp:
                d = 1.0
            elif U < -Ln:
                d = -1.0
            else:  # sticks for the rest of the piece
                return x, 0.0, U
        else:
            d = 1.0 if v > 0.0 else -1.0
        if d > 0.0:
            L, V, em = Lp, Vp, emp
        else:
            L, V, em = -Ln, Vn, emn
        rem = T - t
        dx, vn, ts = _segment(v, U, L, V, Minv, rem, em if (t == 0.0 and T == dt) else math.nan)
        x += dx
        v = vn
        F = L + V * v
        if ts >= rem:  # slid to the piece's end
            return x, v, F
        t += ts  # stopped inside: sticks or breaks away from rest
    return x, v, F


@njit(inline="always", error_model="numpy")
def _level(av, L, S, vs, delta, shape):
    """Stribeck level ``g(|v|)`` (``kernels.machine._g``'s formula, DOF units)."""
    if S == L:
        return L
    r = av / vs
    if r == 0.0:
        return S
    if shape == 0.0:
        if delta == 2.0:
            e = r * r
        elif delta == 1.0:
            e = r
        else:
            e = r**delta
        if e > 700.0:
            return L
        return L + (S - L) * math.exp(-e)
    return L + (S - L) / (1.0 + r * r)


@njit(inline="always", error_model="numpy")
def _acc(v, d, U, L, S, vs, delta, shape, V, Minv):
    """``v'`` while sliding in direction ``d``: ``(U - d g(|v|) - V v) / M``."""
    return (U - d * _level(abs(v), L, S, vs, delta, shape) - V * v) * Minv


@njit(error_model="numpy")
def _piece_str(x, v, U, T, Lp, Sp, vsp, dlp, shp, Vp, Ln, Sn, vsn, dln, shn, Vn, Minv, nrk):
    """``(x, v, F_end)`` after ``T`` under the constant force ``U`` with Stribeck levels (``S``
    at rest, ``L`` sliding, per direction): sticks while ``-Sn <= U <= Sp``, else slides with
    ``nrk`` classical Runge-Kutta steps over ``T`` (the level is not linear in ``v``: no closed
    form); a stop inside a step is located on the step's cubic Hermite interpolant of ``v``
    (bisection) and ``x`` there is its integral."""
    t = 0.0
    F = 0.0
    h0 = T / nrk
    for seg in range(4):
        if v == 0.0:
            if U > Sp:
                d = 1.0
            elif U < -Sn:
                d = -1.0
            else:
                return x, 0.0, U
        else:
            d = 1.0 if v > 0.0 else -1.0
        if d > 0.0:
            L, S, vs, dl, sh, V = Lp, Sp, vsp, dlp, shp, Vp
        else:
            L, S, vs, dl, sh, V = Ln, Sn, vsn, dln, shn, Vn
        stopped = False
        while t < T:
            h = min(h0, T - t)
            if T - t - h < 1e-9 * h0:
                h = T - t
            k1 = _acc(v, d, U, L, S, vs, dl, sh, V, Minv)
            k2 = _acc(v + 0.5 * h * k1, d, U, L, S, vs, dl, sh, V, Minv)
            k3 = _acc(v + 0.5 * h * k2, d, U, L, S, vs, dl, sh, V, Minv)
            k4 = _acc(v + h * k3, d, U, L, S, vs, dl, sh, V, Minv)
            vn = v + h * (k1 + 2.0 * k2 + 2.0 * k3 + k4) / 6.0
            if d * vn > 0.0:
                x += h * (v + h * (k1 + k2 + k3) / 6.0)
                v = vn
                t += h
                continue
            # stop inside the step: v(s) on [0, h] as the cubic Hermite of (v, k1) and (vn, f(vn))
            f1 = _acc(vn, d, U, L, S, vs, dl, sh, V, Minv)
            lo, hi = 0.0, 1.0
            for it in range(60):
                mid = 0.5 * (lo + hi)
                w = mid
                vm = ((2 * w**3 - 3 * w**2 + 1) * v + (w**3 - 2 * w**2 + w) * h * k1
                      + (-2 * w**3 + 3 * w**2) * vn + (w**3 - w**2) * h * f1)
                if d * vm > 0.0:
                    lo = mid
                else:
                    hi = mid
            w = hi
            # integral of the Hermite cubic from 0 to w (times h)
            x += h * ((w**4 / 2 - w**3 + w) * v + (w**4 / 4 - 2 * w**3 / 3 + w**2 / 2) * h * k1
                      + (-w**4 / 2 + w**3) * vn + (w**4 / 4 - w**3 / 3) * h * f1)
            v = 0.0
            t += w * h
            stopped = True
            break
        F = d * _level(abs(v), L, S, vs, dl, sh) + V * v
        if not stopped:
            return x, v, F
    return x, v, F


@njit(inline="always", error_model="numpy")
def _lin_state(t, v0, a, b, beta, V, Minv, A, s):
    """``(dx, v)`` at ``t`` of a slide under a force linear in time (see :func:`_slide_lin`)."""
    if V > 0.0:
        em = math.expm1(-beta * t)
        return a * t + 0.5 * b * t * t - (v0 - a) * em / beta, a + b * t + (v0 - a) * (1.0 + em)
    return v0 * t + 0.5 * A * t * t + s * Minv * t * t * t / 6.0, v0 + A * t + 0.5 * s * Minv * t * t


@njit(error_model="numpy")
def _slide_lin(v0, d, U0, s, L, V, Minv, T):
    """``(dx, v_end, t_stop)`` of a slide in direction ``d`` (``v0`` of sign ``d``, or 0 with
    ``d (U0 - L) > 0``) under the force ``U0 + s t`` for at most ``T``: ``M v' = U0 + s t - L - V v``,
    ``v = a + b t + (v0 - a) e^(-beta t)`` (``V > 0``) or a cubic in ``t`` (``V = 0``). ``v`` is
    convex or concave, so it has at most one zero besides ``t = 0``; a stop is bracketed between a
    point of sign ``d`` (the start, or the extremum) and one of sign ``-d`` (the end or the
    extremum) and located by bisection to round-off."""
    beta = V * Minv
    A = (U0 - L) * Minv
    if V > 0.0:
        b = s / V
        a = (U0 - L) / V - b / beta
        # extremum: v' = b - beta (v0 - a) e^(-beta t) = 0
        q = beta * (v0 - a) / b if b != 0.0 else -1.0
        tx = math.log(q) / beta if q > 0.0 else -1.0
    else:
        b = 0.0
        a = 0.0
        tx = -A / (s * Minv) if s != 0.0 else -1.0
    _, vT = _lin_state(T, v0, a, b, beta, V, Minv, A, s)
    lo, hi = -1.0, -1.0
    if d * vT < 0.0:
        hi = T
        lo = 0.0 if v0 != 0.0 else (tx if 0.0 < tx < T else 0.0)
    elif v0 != 0.0 and 0.0 < tx < T:
        _, vx = _lin_state(tx, v0, a, b, beta, V, Minv, A, s)
        if d * vx < 0.0:
            lo, hi = 0.0, tx
    if hi < 0.0:
        dx, vT = _lin_state(T, v0, a, b, beta, V, Minv, A, s)
        return dx, vT, T
    for it in range(200):  # bisection to adjacent floats: d v(lo) >= 0 > d v(hi)
        mid = 0.5 * (lo + hi)
        if mid <= lo or mid >= hi:
            break
        _, vm = _lin_state(mid, v0, a, b, beta, V, Minv, A, s)
        if d * vm < 0.0:
            hi = mid
        else:
            lo = mid
    dx, _ = _lin_state(hi, v0, a, b, beta, V, Minv, A, s)
    return dx, 0.0, hi


@njit(error_model="numpy")
def _piece_lin(x, v, U0, s, T, Lp, Ln, Vp, Vn, Minv):
    """``(x, v, F_end)`` after ``T`` under the force ``U0 + s t`` (``s != 0``): slides, stops,
    sticks while ``-Ln <= U <= Lp`` and breaks away where the force leaves that band."""
    t = 0.0
    F = 0.0
    for seg in range(8):
        rem = T - t
        if rem <= 0.0:
            break
        Ut = U0 + s * t
        if v == 0.0:
            if Ut > Lp or (Ut == Lp and s > 0.0):
                d = 1.0
            elif Ut < -Ln or (Ut == -Ln and s < 0.0):
                d = -1.0
            else:  # stuck until the force leaves the band
                tb = ((Lp if s > 0.0 else -Ln) - Ut) / s
                if tb >= rem:
                    return x, 0.0, U0 + s * T
                t += tb
                Ut = Lp if s > 0.0 else -Ln
                d = 1.0 if s > 0.0 else -1.0
                rem = T - t
        else:
            d = 1.0 if v > 0.0 else -1.0
        if d > 0.0:
            L, V = Lp, Vp
        else:
            L, V = -Ln, Vn
        dx, vn, ts = _slide_lin(v, d, Ut, s, L, V, Minv, rem)
        x += dx
        v = vn
        F = L + V * v
        if ts >= rem:
            return x, v, F
        t += ts
    return x, v, F


@njit(error_model="numpy")
def run_axis(dt, X, Minv, Lp, Ln, Vp, Vn, c_site, act_gain, stribeck,
             inputs, in_sig, sen_row, sen_qty, sen_res, sen_delay, sen_sig, noise,
             blk_code, blk_iptr, blk_idx, blk_fptr, blk_par, blk_sptr, blk_st,
             act_sig, act_lim, act_delay, act_foh, act_applied_sig, act_col, sig,
             q_out, v_out, F_out, sig_out, u_out):
    """Run ``N = q_out.shape[0]`` samples; ``X = [q, q']`` (updated in place), ``blk_st``,
    ``blk_par``, ``sig`` and the controller arrays as in ``kernels.machine.run``. Friction in
    DOF units: ``Lp + Vp v`` for ``v > 0``, ``-Ln + Vn v`` for ``v < 0`` (``Lp, Ln > 0``); the
    site's coefficient ``c_site`` converts the recorded force to site units (``F_site = F_dof /
    c_site``). ``act_gain[i]``: actuator ``i``'s force on the DOF per unit command; an actuator
    with ``act_foh[i]`` follows input column ``act_col[i]`` linearly over the sample (delayed
    by ``act_delay[i]`` whole samples, clipped at ``act_lim[i]``), the others hold
    their controller signal. Returns ``(status, k_end, 0)``."""
    N = q_out.shape[0]
    nact = act_sig.size
    nsen = sen_sig.size
    nin = in_sig.size
    nb = blk_code.size
    maxd_a = 0
    for i in range(nact):
        if act_delay[i] > maxd_a:
            maxd_a = act_delay[i]
    abuf = np.zeros((nact, maxd_a + 1))
    aslot = np.zeros(nact, dtype=np.int64)
    maxd_s = 0
    for i in range(nsen):
        if sen_delay[i] > maxd_s:
            maxd_s = sen_delay[i]
    sbuf = np.zeros((nsen, maxd_s + 1))
    sslot = np.zeros(nsen, dtype=np.int64)
    sat = np.zeros(nact, dtype=np.bool_)
    u_now = np.zeros(nact)
    # Stribeck levels (stribeck: Sp, vsp, delta, shape, Sn, vsn, delta, shape, n_rk; empty: flat)
    n_rk = 0
    Sp = vsp = dlp = shp = Sn = vsn = dln = shn = 0.0
    if stribeck.size:
        Sp, vsp, dlp, shp = stribeck[0], stribeck[1], stribeck[2], stribeck[3]
        Sn, vsn, dln, shn = stribeck[4], stribeck[5], stribeck[6], stribeck[7]
        n_rk = int(stribeck[8])
    has_foh = False
    for i in range(nact):
        if act_foh[i]:
            has_foh = True
    bk = np.zeros(2 + 2 * nact)  # piece boundaries of a sample, and the FOH inputs at its ends
    fa = np.zeros(nact)
    fb = np.zeros(nact)
    emp = math.expm1(-Vp * Minv * dt)  # a whole sample's relaxation factor per direction
    emn = math.expm1(-Vn * Minv * dt)
    x = X[0]
    v = X[1]
    Fend = 0.0
    if v > 0.0:
        Fend = Lp + Vp * v
    elif v < 0.0:
        Fend = -Ln + Vn * v
    for k in range(N):
        q_out[k, 0] = x
        v_out[k, 0] = v
        F_out[k, 0] = Fend / c_site
        # ---- inputs and sensors (run's code for one DOF and no motions)
        for i in range(nin):
            sig[in_sig[i]] = inputs[k, i]
        for i in range(nsen):
            y = 0.0
            y += sen_row[i, 0] * (v if sen_qty[i] == 1 else x)
            y = _quantise(y + noise[k, i], sen_res[i])
            d = sen_delay[i]
            if d > 0:  # ring buffer (zeros until filled), as run's ``k % d`` slot
                slot = sslot[i]
                out = sbuf[i, slot]
                sbuf[i, slot] = y
                y = out
                sslot[i] = slot + 1 if slot + 1 < d else 0
            sig[sen_sig[i]] = y
        # ---- blocks
        for bi in range(nb):
            code = blk_code[bi]
            ip = blk_iptr[bi]
            fp = blk_fptr[bi]
            sp = blk_sptr[bi]
            if code == B_LINEAR:  # idx: out, nin, in...; par: bias, w...
                nin_b = blk_idx[ip + 1]
                y = blk_par[fp]
                for r in range(nin_b):
                    y += blk_par[fp + 1 + r] * sig[blk_idx[ip + 2 + r]]
                sig[blk_idx[ip]] = y
            elif code == B_PID:  # idx: out, e, ed, act; par: Kp Ki Kd tau_d T; st: integ, dterm, ed_prev, started
                e = sig[blk_idx[ip + 1]]
                ed = sig[blk_idx[ip + 2]]
                Kp = blk_par[fp]
                Kd = blk_par[fp + 2]
                taud = blk_par[fp + 3]
                T = blk_par[fp + 4]
                if blk_st[sp + 3] == 0.0:
                    blk_st[sp + 2] = ed
                    blk_st[sp + 3] = 1.0
                blk_st[sp + 1] = (taud * blk_st[sp + 1] + Kd * (ed - blk_st[sp + 2])) / (taud + T)
                blk_st[sp + 2] = ed
                sig[blk_idx[ip]] = Kp * e + blk_st[sp] + blk_st[sp + 1]
            elif code == B_SS:  # idx: nin, nout, in..., out...; par: nx, A, B, C, D
                nu = blk_idx[ip]
                ny = blk_idx[ip + 1]
                nx = int(blk_par[fp])
                pA = fp + 1
                pB = pA + nx * nx
                pC = pB + nx * nu
                pD = pC + ny * nx
                for r in range(ny):
                    y = 0.0
                    for c in range(nx):
                        y += blk_par[pC + r * nx + c] * blk_st[sp + c]
                    for c in range(nu):
                        y += blk_par[pD + r * nu + c] * sig[blk_idx[ip + 2 + c]]
                    sig[blk_idx[ip + 2 + nu + r]] = y
                # state update x+ = A x + B u (scratch after the states)
                for r in range(nx):
                    y = 0.0
                    for c in range(nx):
                        y += blk_par[pA + r * nx + c] * blk_st[sp + c]
                    for c in range(nu):
                        y += blk_par[pB + r * nu + c] * sig[blk_idx[ip + 2 + c]]
                    blk_st[sp + nx + r] = y
                for r in range(nx):
                    blk_st[sp + r] = blk_st[sp + nx + r]
            elif code == B_SAT:  # idx: out, in; par: lo, hi
                y = sig[blk_idx[ip + 1]]
                if y > blk_par[fp + 1]:
                    y = blk_par[fp + 1]
                elif y < blk_par[fp]:
                    y = blk_par[fp]
                sig[blk_idx[ip]] = y
            else:  # B_FFF: idx: out, in, schedule (-1: none); par: scale, static law (N_STATIC_SITE)
                if blk_idx[ip + 2] >= 0:
                    _set_levels(blk_par, fp + 1, sig[blk_idx[ip + 2]])
                sig[blk_idx[ip]] = blk_par[fp] * _static_force(blk_par, fp + 1, sig[blk_idx[ip + 1]], 1.0)
        # ---- actuators
        for i in range(nact):
            if act_foh[i]:
                u = inputs[k, act_col[i]]
            else:
                u = sig[act_sig[i]]
            sat[i] = False
            if u > act_lim[i]:
                u = act_lim[i]
                sat[i] = True
            elif u < -act_lim[i]:
                u = -act_lim[i]
                sat[i] = True
            d = act_delay[i]
            if d > 0:  # ring buffer (zeros until filled), as run's ``k % d`` slot
                slot = aslot[i]
                out = abuf[i, slot]
                abuf[i, slot] = u
                u = out
                aslot[i] = slot + 1 if slot + 1 < d else 0
            u_now[i] = u
            u_out[k, i] = u
            if act_applied_sig[i] >= 0:
                sig[act_applied_sig[i]] = u
        # ---- PID integrators (conditional integration)
        for bi in range(nb):
            if blk_code[bi] == B_PID:
                ip = blk_iptr[bi]
                ai = blk_idx[ip + 3]
                if ai < 0 or not sat[ai]:
                    blk_st[blk_sptr[bi]] += blk_par[blk_fptr[bi] + 1] * blk_par[blk_fptr[bi] + 4] * sig[blk_idx[ip + 1]]
        for r in range(sig.size):
            sig_out[k, r] = sig[r]
        if k == N - 1:
            break
        U = 0.0
        for i in range(nact):
            if not act_foh[i]:
                U += act_gain[i] * u_now[i]
        if has_foh:  # force linear over the sample (input arrays), in pieces between limit crossings
            nbk = 2
            bk[0] = 0.0
            bk[1] = dt
            for i in range(nact):
                if act_foh[i]:
                    dl = act_delay[i]
                    ua = inputs[k - dl, act_col[i]] if k >= dl else 0.0
                    ub = inputs[k + 1 - dl, act_col[i]] if k + 1 >= dl else 0.0
                    fa[i] = ua
                    fb[i] = ub
                    lim = act_lim[i]
                    for edge in (lim, -lim):
                        if (ua - edge) * (ub - edge) < 0.0:  # crosses the limit inside the sample
                            tc = dt * (edge - ua) / (ub - ua)
                            j = nbk
                            while j > 0 and bk[j - 1] > tc:  # insertion, sorted
                                bk[j] = bk[j - 1]
                                j -= 1
                            bk[j] = tc
                            nbk += 1
            Fend = 0.0
            for pc in range(nbk - 1):
                t0 = bk[pc]
                t1 = bk[pc + 1]
                if t1 <= t0:
                    continue
                Ua = U
                Ub = U
                for i in range(nact):
                    if act_foh[i]:
                        lim = act_lim[i]
                        r0 = fa[i] + (fb[i] - fa[i]) * (t0 / dt)
                        r1 = fa[i] + (fb[i] - fa[i]) * (t1 / dt)
                        Ua += act_gain[i] * min(max(r0, -lim), lim)
                        Ub += act_gain[i] * min(max(r1, -lim), lim)
                sl = (Ub - Ua) / (t1 - t0)
                if sl != 0.0:
                    x, v, Fend = _piece_lin(x, v, Ua, sl, t1 - t0, Lp, Ln, Vp, Vn, Minv)
                else:
                    x, v, Fend = _piece(x, v, Ua, t1 - t0, dt, Lp, Ln, Vp, Vn, Minv, emp, emn)
        elif n_rk > 0:  # Stribeck levels
            x, v, Fend = _piece_str(x, v, U, dt, Lp, Sp, vsp, dlp, shp, Vp, Ln, Sn, vsn, dln, shn, Vn, Minv, n_rk)
        else:
            x, v, Fend = _piece(x, v, U, dt, dt, Lp, Ln, Vp, Vn, Minv, emp, emn)
        if not (math.isfinite(x) and math.isfinite(v)):
            X[0] = x
            X[1] = v
            return STATUS_NONFINITE, k + 1, 0
    X[0] = x
    X[1] = v
    return STATUS_OK, N, 0
