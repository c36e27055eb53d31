"""Forward sensitivities of the single-axis LuGre family (LuGre, Dahl): state and ``d state / d theta``.

Private kernels behind the exact Jacobians of the output-error fits
(:mod:`frictionkit.identify.output_error`, :mod:`frictionkit.identify.motion_error`):
one augmented run gives the simulated signal *and* its derivatives with respect to
every fitted parameter, instead of one extra simulation per parameter.

Parameters enter through the packed rows the other kernels read (``static`` ``(2, 6)``
``[Fc, Fs, vs, delta, sigma2, shape]``, ``dyn`` ``(2, 2)`` ``[sigma0, sigma1]``, row 0 for
``v >= 0``). A fitted parameter ``theta_j`` is described by its derivative of those rows,
``coef[j, row, :] = d[sigma0, sigma1, Fc, Fs, vs, delta, sigma2]_row / d theta_j``, and for the
force-driven mass also ``dm[j]``, ``doff[j]`` (``m a = u - F - offset``). So a tied parameter
(both rows), a per-direction one (one row), Dahl's ``Fc`` (``Fc`` and ``Fs`` of both rows)
or the mass are all the same code path.

Motion-driven (``lugre_motion_sens``)
-------------------------------------
The position is interpolated linearly, so ``v`` is constant on each interval and
``z`` has the exact exponential update ``z+ = z_ss + (z - z_ss) exp(-a dt)`` with
``a = sigma0 |v| / g(|v|)``, ``z_ss = sgn(v) g / sigma0``. The sensitivities are the exact
derivatives of that update (and of ``F = sigma0 z + sigma1 (v - a z) + sigma2 v``), i.e. of
the very map :func:`frictionkit.simulate` evaluates with ``position=`` — not of an
approximation of it.

Force-driven (``lugre_force_sens``)
-----------------------------------
State ``y = (x, v, z)``, ``v' = (u(t) - F - offset) / m``, ``z' = v - a z`` with the input
``u(t)`` linear between samples and evaluated exactly at the stage times. The augmented system
``y' = f(y)``, ``S' = J(y) S + f_theta(y)`` (``S = dy/dtheta``, ``J = df/dy``; the right-hand
side is continuous — ``|v|`` has a kink, not a jump — so ``S`` is continuous across
``v = 0``) is integrated by the two-stage L-stable Rosenbrock–W method ROS2 (Verwer, Spee,
Blom & Hundsdorfer 1999, ``gamma = 1 + 1/sqrt 2``), with the stage matrix
``W = I - gamma h J(y_n)`` block-diagonal over the state and every sensitivity column::

    W k1 = f(y),                    W k1s = J(y) s + f_theta(y)
    W k2 = f(y + h k1) - 2 k1,      W k2s = J(y2) (s + h k1s) + f_theta(y2) - 2 k1s
    y+ = y + h (3 k1 + k2) / 2,     s+ = s + h (3 k1s + k2s) / 2

A W-method is second order for any ``W``, so dropping the off-diagonal blocks
``d(J S)/dy`` of the augmented Jacobian, and the time column ``du/dt / m``, costs no order.
Steps are not tied to the samples (at most ``H_SPAN`` sample periods); the samples inside a
step are read off the cubic Hermite interpolant of the step (values and slopes at both ends;
the end slope is the next step's first stage). Measured on ``benchmarks/identify.py``'s
record at the fitter's tolerances: 23k sub-steps for 25k samples (38.7k when every sample
ended a sub-step), max |dv| 4e-6 m/s against LSODA at rtol 1e-10 (peak 0.39 m/s).
Assumption (named): the step size is
controlled on the state only (``v``, ``z``; as the plain kernel does), the sensitivities ride
on the same steps — the usual "staggered" choice; the test checks them against central
differences of tight simulations. This is a self-contained integrator: it does not share
step logic with :mod:`.lugre`, so its trajectory agrees with :func:`frictionkit.simulate`
to the integration tolerance, not bit for bit.

The levels ``Fc``, ``Fs`` are used as given (the plain kernels floor them at ``1e-9`` of the
largest level, which only matters for laws whose levels vanish; such fits are not
differentiable there anyway).

Status codes as :mod:`.lugre`: 0 ok, 1 non-finite state, 2 sub-step budget exhausted,
3 step-size underflow.
"""

from __future__ import annotations

import math

import numpy as np

from .._jit import njit

GAMMA = 1.0 + 1.0 / math.sqrt(2.0)
OK, NONFINITE, BUDGET, TOLERANCE = 0, 1, 2, 3
#: Smallest sub-step as a fraction of ``dt``.
H_MIN = 1e-9
#: Index of each packed quantity in ``coef[j, row, :]``.
C_S0, C_S1, C_FC, C_FS, C_VS, C_DELTA, C_S2 = 0, 1, 2, 3, 4, 5, 6
N_COEF = 7


@njit(inline="always")
def _g_parts(Fc, Fs, vs, delta, shape, av):
    """``(g, dg/d|v|, phi, dphi/dvs, dphi/ddelta)`` with ``g = Fc + (Fs - Fc) phi(|v| / vs)``."""
    r = av / vs
    if r == 0.0:
        return Fs, 0.0, 1.0, 0.0, 0.0
    if shape == 0.0:
        rd = r * r if delta == 2.0 else (r if delta == 1.0 else r**delta)
        if rd > 700.0:  # phi has underflowed: g = Fc, flat
            return Fc, 0.0, 0.0, 0.0, 0.0
        phi = math.exp(-rd)
        dphi_dr = -phi * delta * rd / r
        return (Fc + (Fs - Fc) * phi, (Fs - Fc) * dphi_dr / vs, phi, -dphi_dr * r / vs,
                -phi * rd * math.log(r))
    q = 1.0 / (1.0 + r * r)
    dphi_dr = -2.0 * r * q * q
    return Fc + (Fs - Fc) * q, (Fs - Fc) * dphi_dr / vs, q, -dphi_dr * r / vs, 0.0


@njit(inline="always")
def _dg(coef, j, row, Fc, Fs, phi, dphi_vs, dphi_de):
    """``dg/dtheta_j`` from the coefficients of row ``row`` (indexed in place: a slice would
    cost a reference-counted view per call)."""
    return (coef[j, row, C_FC] * (1.0 - phi) + coef[j, row, C_FS] * phi
            + (Fs - Fc) * (dphi_vs * coef[j, row, C_VS] + dphi_de * coef[j, row, C_DELTA]))


@njit
def lugre_motion_sens(xpos, dt, static, dyn, coef, F_out, S_out):
    """Motion-driven LuGre from ``z = 0``: force ``F_out[N]`` and ``S_out[N, p] = dF/dtheta``.

    Returns the status (1 if a state turned non-finite).
    """
    N = xpos.size
    p = coef.shape[0]
    z = 0.0
    dz = np.zeros(p)
    if N == 0:
        return OK
    for k in range(max(N - 1, 1)):
        vk = (xpos[k + 1] - xpos[k]) / dt if N > 1 else 0.0
        row = 0 if vk >= 0.0 else 1
        Fc = static[row, 0]
        Fs = static[row, 1]
        s0 = dyn[row, 0]
        s1 = dyn[row, 1]
        s2 = static[row, 4]
        av = abs(vk)
        g, _, phi, dphi_vs, dphi_de = _g_parts(Fc, Fs, static[row, 2], static[row, 3], static[row, 5], av)
        a = s0 * av / g
        if k == 0:  # sample 0: z = 0, dz = 0, zd = v
            F_out[0] = s1 * vk + s2 * vk
            for j in range(p):
                S_out[0, j] = (coef[j, row, C_S1] + coef[j, row, C_S2]) * vk
            if N == 1:
                return OK
        if a > 0.0:
            E = math.exp(-a * dt)
            sg = 1.0 if vk > 0.0 else -1.0
            zss = sg * g / s0
            zo = z
            z = zss + (zo - zss) * E
            for j in range(p):
                dgj = _dg(coef, j, row, Fc, Fs, phi, dphi_vs, dphi_de)
                da = av * (coef[j, row, C_S0] / g - s0 * dgj / (g * g))
                dzss = sg * (dgj / s0 - g * coef[j, row, C_S0] / (s0 * s0))
                dz[j] = dzss * (1.0 - E) + dz[j] * E - (zo - zss) * dt * E * da
        zd = vk - a * z
        F = s0 * z + s1 * zd + s2 * vk
        F_out[k + 1] = F
        for j in range(p):
            if a > 0.0:
                dgj = _dg(coef, j, row, Fc, Fs, phi, dphi_vs, dphi_de)
                da = av * (coef[j, row, C_S0] / g - s0 * dgj / (g * g))
            else:
                da = 0.0
            dzd = -da * z - a * dz[j]
            S_out[k + 1, j] = (coef[j, row, C_S0] * z + s0 * dz[j] + coef[j, row, C_S1] * zd + s1 * dzd
                               + coef[j, row, C_S2] * vk)
        if not math.isfinite(F):
            return NONFINITE
    return OK


@njit(inline="always")
def _rates(v, z, w, m, off, Fc, Fs, vs, delta, shape, s0, s1, s2):
    """``(fv, zd, Fv, Fz, zdv, a, phi, dphi_vs, dphi_de, 1/g)`` at one state (``zd = dz/dt``)."""
    av = abs(v)
    g, gr, phi, dphi_vs, dphi_de = _g_parts(Fc, Fs, vs, delta, shape, av)
    ig = 1.0 / g
    a = s0 * av * ig
    zd = v - a * z
    sg = 1.0 if v > 0.0 else (-1.0 if v < 0.0 else 0.0)
    zdv = 1.0 - s0 * z * sg * ig * (1.0 - av * gr * ig)
    F = s0 * z + s1 * zd + s2 * v
    fv = (w - F - off) / m
    return fv, zd, s1 * zdv + s2, s0 - s1 * a, zdv, a, phi, dphi_vs, dphi_de, ig


@njit(inline="always")
def _ftheta(coef, j, row, dmj, doffj, v, z, im, fv, zd, ig, Fc, Fs, s0, s1, phi, dphi_vs, dphi_de):
    """``(d fv / d theta_j, d fz / d theta_j)`` at fixed state, parameter rows of ``row``
    (``im = 1/m``, ``ig = 1/g``: no division in the per-parameter loop)."""
    dgj = _dg(coef, j, row, Fc, Fs, phi, dphi_vs, dphi_de)
    ds0 = coef[j, row, C_S0]
    dzd = -abs(v) * (ds0 - s0 * dgj * ig) * ig * z
    dF = ds0 * z + coef[j, row, C_S1] * zd + s1 * dzd + coef[j, row, C_S2] * v
    return -(dF + doffj + fv * dmj) * im, dzd


@njit(inline="always")
def _u_at(u, dt, t):
    """The input force at time ``t``, linear between samples (clamped at the record's end)."""
    q = t / dt
    k = int(q)
    if k >= u.size - 1:
        return u[u.size - 1]
    return u[k] + (u[k + 1] - u[k]) * (q - k)


@njit(inline="always")
def _hermite(a0, d0, a1, d1, h, th):
    """Cubic Hermite interpolant at ``t_n + th h`` from values and slopes at both step ends."""
    th2 = th * th
    th3 = th2 * th
    return ((2.0 * th3 - 3.0 * th2 + 1.0) * a0 + (th3 - 2.0 * th2 + th) * h * d0
            + (3.0 * th2 - 2.0 * th3) * a1 + (th3 - th2) * h * d1)


#: Longest step, in sample periods. Steps may span samples (the input is evaluated exactly
#: at the stage times and the W-matrix leaves out the time column, which a W-method allows);
#: the samples inside a step are read off the cubic Hermite interpolant of the step.
H_SPAN = 50.0


@njit(error_model="numpy")  # IEEE division: no zero test per division; non-finite states are caught below
def lugre_force_sens(u, dt, m, off, static, dyn, coef, dm, doff, rtol, atol_v, atol_z, max_sub,
                     x_out, v_out, Sx_out, Sv_out):
    """Force-driven LuGre on a mass from rest, with forward sensitivities (ROS2-W, see above).

    Fills ``x_out``, ``v_out`` (``N``) and ``Sx_out``, ``Sv_out`` (``N, p``: ``dx/dtheta``,
    ``dv/dtheta``). Steps span samples where the error control allows (at most ``H_SPAN``
    sample periods); ``max_sub`` is the sub-step budget per sample interval on average.
    Returns ``(status, sub-steps)``.
    """
    N = u.size
    p = coef.shape[0]
    x_out[0] = 0.0
    v_out[0] = 0.0
    for j in range(p):
        Sx_out[0, j] = 0.0
        Sv_out[0, j] = 0.0
    if N < 2:
        return OK, 0
    T = (N - 1) * dt
    im = 1.0 / m
    x = 0.0
    v = 0.0
    z = 0.0
    t = 0.0
    sx = np.zeros(p)
    sv = np.zeros(p)
    sz = np.zeros(p)
    dsv = np.zeros(p)  # d(sv)/dt = (J S + f_theta)_v at the current point
    dsz = np.zeros(p)
    sx0 = np.zeros(p)
    sv0 = np.zeros(p)
    dsv0 = np.zeros(p)
    k1v = np.zeros(p)
    k1z = np.zeros(p)
    k1x = np.zeros(p)
    # rates and sensitivity slopes at the start
    row = 0
    Fc = static[row, 0]
    Fs = static[row, 1]
    s0 = dyn[row, 0]
    s1 = dyn[row, 1]
    fv, zd, Fv, Fz, zdv, a, phi, dpv, dpd, ig = _rates(v, z, u[0], m, off, Fc, Fs, static[row, 2],
                                                       static[row, 3], static[row, 5], s0, s1, static[row, 4])
    for j in range(p):
        ftv, ftz = _ftheta(coef, j, row, dm[j], doff[j], v, z, im, fv, zd, ig, Fc, Fs, s0, s1, phi, dpv, dpd)
        dsv[j] = ftv
        dsz[j] = ftz
    h = dt
    nsub = 0
    budget = max_sub * (N - 1)
    kout = 1
    while kout < N:
        if nsub >= budget:
            return BUDGET, nsub
        h = min(h, H_SPAN * dt)
        if t + h >= T - 1e-9 * dt:
            h = T - t
        gh = GAMMA * h
        A11 = 1.0 + gh * Fv * im
        A12 = gh * Fz * im
        A21 = -gh * zdv
        A22 = 1.0 + gh * a
        idet = 1.0 / (A11 * A22 - A12 * A21)
        k1v_ = (A22 * fv - A12 * zd) * idet
        k1z_ = (A11 * zd - A21 * fv) * idet
        k1x_ = v + gh * k1v_
        v2 = v + h * k1v_
        z2 = z + h * k1z_
        row2 = 0 if v2 >= 0.0 else 1
        Fc2 = static[row2, 0]
        Fs2 = static[row2, 1]
        s02 = dyn[row2, 0]
        s12 = dyn[row2, 1]
        fv2, zd2, Fv2, Fz2, zdv2, a2, phi2, dpv2, dpd2, ig2 = _rates(
            v2, z2, _u_at(u, dt, t + h), m, off, Fc2, Fs2, static[row2, 2], static[row2, 3], static[row2, 5],
            s02, s12, static[row2, 4])
        bv = fv2 - 2.0 * k1v_
        bz = zd2 - 2.0 * k1z_
        k2v_ = (A22 * bv - A12 * bz) * idet
        k2z_ = (A11 * bz - A21 * bv) * idet
        k2x_ = (v2 - 2.0 * k1x_) + gh * k2v_
        vn = v + 0.5 * h * (3.0 * k1v_ + k2v_)
        zn = z + 0.5 * h * (3.0 * k1z_ + k2z_)
        e1 = abs(0.5 * h * (k1v_ + k2v_)) / (atol_v + rtol * max(abs(v), abs(vn)))
        e2 = abs(0.5 * h * (k1z_ + k2z_)) / (atol_z + rtol * max(abs(z), abs(zn)))
        err = max(e1, e2)
        nsub += 1
        if not math.isfinite(err) or not math.isfinite(vn + zn):
            if h <= H_MIN * dt:
                return NONFINITE, nsub
            h *= 0.2
            continue
        if err > 1.0:
            if h <= H_MIN * dt:
                return TOLERANCE, nsub
            h *= max(0.2, 0.9 / math.sqrt(err))
            continue
        # accepted: the sensitivities on the same step (stage 1: their slope at the current point)
        for j in range(p):
            k1v[j] = (A22 * dsv[j] - A12 * dsz[j]) * idet
            k1z[j] = (A11 * dsz[j] - A21 * dsv[j]) * idet
            k1x[j] = sv[j] + gh * k1v[j]
        for j in range(p):
            ftv, ftz = _ftheta(coef, j, row2, dm[j], doff[j], v2, z2, im, fv2, zd2, ig2, Fc2, Fs2, s02, s12,
                               phi2, dpv2, dpd2)
            sv2 = sv[j] + h * k1v[j]
            sz2 = sz[j] + h * k1z[j]
            bv = (-Fv2 * sv2 - Fz2 * sz2) * im + ftv - 2.0 * k1v[j]
            bz = zdv2 * sv2 - a2 * sz2 + ftz - 2.0 * k1z[j]
            k2v = (A22 * bv - A12 * bz) * idet
            k2z = (A11 * bz - A21 * bv) * idet
            k2x = (sv2 - 2.0 * k1x[j]) + gh * k2v
            sx0[j] = sx[j]
            sv0[j] = sv[j]
            dsv0[j] = dsv[j]
            sx[j] += 0.5 * h * (3.0 * k1x[j] + k2x)
            sv[j] += 0.5 * h * (3.0 * k1v[j] + k2v)
            sz[j] += 0.5 * h * (3.0 * k1z[j] + k2z)
        x0 = x
        v0 = v
        fv0 = fv
        x += 0.5 * h * (3.0 * k1x_ + k2x_)
        v = vn
        z = zn
        t0 = t
        t = T if h == T - t0 else t0 + h
        # rates and sensitivity slopes at the new point (the next step's first stage)
        row = 0 if v >= 0.0 else 1
        Fc = static[row, 0]
        Fs = static[row, 1]
        s0 = dyn[row, 0]
        s1 = dyn[row, 1]
        fv, zd, Fv, Fz, zdv, a, phi, dpv, dpd, ig = _rates(v, z, _u_at(u, dt, t), m, off, Fc, Fs, static[row, 2],
                                                           static[row, 3], static[row, 5], s0, s1, static[row, 4])
        for j in range(p):
            ftv, ftz = _ftheta(coef, j, row, dm[j], doff[j], v, z, im, fv, zd, ig, Fc, Fs, s0, s1, phi, dpv, dpd)
            dsv[j] = (-Fv * sv[j] - Fz * sz[j]) * im + ftv
            dsz[j] = zdv * sv[j] - a * sz[j] + ftz
        # the samples inside (t0, t]
        while kout < N and kout * dt <= t + 1e-9 * dt:
            th = min(1.0, (kout * dt - t0) / h)
            x_out[kout] = _hermite(x0, v0, x, v, h, th)
            v_out[kout] = _hermite(v0, fv0, v, fv, h, th)
            for j in range(p):
                Sx_out[kout, j] = _hermite(sx0[j], sv0[j], sx[j], sv[j], h, th)
                Sv_out[kout, j] = _hermite(sv0[j], dsv0[j], sv[j], dsv[j], h, th)
            kout += 1
        fac = 5.0 if err < 0.0324 else 0.9 / math.sqrt(err)
        h = h * fac
    return OK, nsub
