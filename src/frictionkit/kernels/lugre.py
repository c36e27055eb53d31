"""LuGre kernels: force-driven mass (adaptive ROS2 sub-steps) and motion-driven (exact).

Force-driven scheme
-------------------
State ``(x, v, z)`` plus the input ``w = u(t)``, linear inside each sample
interval (``w' = du/dt``). Each interval ``[t_k, t_k + dt]`` is covered by
sub-steps of the two-stage, L-stable Rosenbrock method ROS2 (Verwer, Spee, Blom
& Hundsdorfer 1999, ``gamma = 1 + 1/sqrt 2``)::

    (I - gamma h J) k1 = f(y)
    (I - gamma h J) k2 = f(y + h k1) - 2 k1
    y+ = y + 3/2 h k1 + 1/2 h k2,      error estimate  h/2 (k1 + k2)

ROS2 is second order for any matrix ``J`` (a W-method), so the kink of ``|v|``
at ``v = 0`` does not need an exact Jacobian. L-stability makes the bristle
relaxation (rate ``sigma0 |v| / |s(v)|``, up to 1e7 /s when sliding) and a
pre-sliding spring of 1e8 N/m harmless; the error estimate shrinks the
sub-step around breakaway and sticking and lets it grow to a whole sample
interval while sliding or resting. The 4x4 linear systems are solved in
closed form (rows for ``x`` and ``w`` are trivial).

Motion-driven scheme
--------------------
Position samples are interpolated linearly, so ``v`` is constant on each
interval and ``dz/dt = v - a z`` with constant ``a = sigma0 |v| / |s(v)|`` has
the exact solution ``z(h) = z_ss + (z0 - z_ss) exp(-a h)``; no error at all
beyond round-off.

Status codes: 0 ok, 1 non-finite state, 2 sub-step budget exhausted,
3 error control failed (the sub-step fell to ``H_MIN * dt`` and still did not
meet the tolerance: step-size underflow). A step is never accepted with its
error estimate above the tolerance.
"""

from __future__ import annotations

import math

import numpy as np

from .._jit import njit, prange
from ._stribeck import R_S2, g_row, ig_row, ig_slope_row
from ._stribeck import row as static_row

GAMMA = 1.0 + 1.0 / math.sqrt(2.0)

OK, NONFINITE, BUDGET, TOLERANCE = 0, 1, 2, 3

#: Smallest sub-step as a fraction of ``dt``; below it the error control gives up.
H_MIN = 1e-7

#: ``0.9 / sqrt(e) >= 5`` for ``e <= (0.9 / 5)^2``.
E_GROW = (0.9 / 5.0) ** 2


@njit(inline="always")
def _side(v, p0, p1, d0, d1):
    """Stribeck row tuple and ``(sigma0, sigma1)`` for the direction of ``v`` (row 0: ``v >= 0``)."""
    if v >= 0.0:
        return p0, d0
    return p1, d1


@njit(inline="always")
def _force(v, z, p0, p1, d0, d1):
    """Return ``(dz/dt, F)`` for the parameter row selected by the sign of ``v``.

    ``p0, p1`` are the Stribeck row tuples (``_stribeck.row``) and ``d0, d1`` the
    ``(sigma0, sigma1)`` pairs for ``v >= 0`` and ``v < 0``.
    """
    p, d = _side(v, p0, p1, d0, d1)
    av = abs(v)
    zd = v - d[0] * av * z * ig_row(p, av)
    return zd, d[0] * z + d[1] * zd + p[R_S2] * v


@njit(inline="always")
def _point(v, z, p0, p1, d0, d1):
    """Everything the step needs at one state: ``(zd, F, dzd/dv, dzd/dz, dF/dv, dF/dz)``."""
    p, d = _side(v, p0, p1, d0, d1)
    s0 = d[0]
    s1 = d[1]
    av = abs(v)
    ig, gr = ig_slope_row(p, av)
    a = s0 * av * ig
    zd = v - a * z
    sg = 1.0 if v > 0.0 else (-1.0 if v < 0.0 else 0.0)
    dzd_dv = 1.0 - s0 * z * sg * ig * (1.0 - av * gr * ig)
    return (
        zd,
        s0 * z + s1 * zd + p[R_S2] * v,
        dzd_dv,
        -a,
        s1 * dzd_dv + p[R_S2],
        s0 - s1 * a,
    )


@njit(inline="always")
def _atol_run(atol_v, v_floor, rtol, vpk):
    """Absolute velocity tolerance that follows the run's range.

    ``min(atol_v, rtol * vpk)`` with ``vpk`` the largest ``|v|`` so far, but at least
    ``v_floor * atol_v``. ``atol_v`` is an a-priori scale (``F / sqrt(K m)``, the
    ringing speed if the whole friction level were released at once); a run that
    never moves that fast -- pre-sliding under a slow input, a heavy mass -- would
    otherwise be integrated with an absolute error comparable to its whole velocity
    range, and an undamped pre-sliding ringing (Dahl, GMS without sigma2) drifts in
    phase by a fraction of a period: measured 2.6 % of the position range on a Dahl
    run against the solve_ivp twin at the default rtol (issue 15).
    """
    return max(v_floor * atol_v, min(atol_v, rtol * vpk))


@njit(inline="always")
def _interval(x, v, z, h_try, u0, u1, dt, m, p0, p1, d0, d1, rtol, atol_v, atol_z, max_sub, vpk, v_floor):
    """Advance the force-driven state over one sample interval.

    Returns ``(x, v, z, F, h_try, n_substeps, status, vpk)`` with ``F`` the friction
    force at the end of the interval and ``vpk`` the largest ``|v|`` of the run so far
    (see :func:`_atol_run`). Scalars and tuples only (no arrays): see the note on
    reference counting in :mod:`._stribeck`.
    """
    im = 1.0 / m
    du = (u1 - u0) / dt
    t = 0.0
    w = u0
    n = 0
    zd, F, dzv, dzz, dFv, dFz = _point(v, z, p0, p1, d0, d1)
    tol_v = _atol_run(atol_v, v_floor, rtol, vpk)
    while t < dt:
        h = h_try
        rem = dt - t
        if h >= rem or rem - h < 1e-9 * dt:
            h = rem
        gh = GAMMA * h
        # I - gamma h J on (v, z); rows of x and w are trivial
        a11 = 1.0 + gh * dFv * im
        a12 = gh * dFz * im
        a21 = -gh * dzv
        a22 = 1.0 - gh * dzz
        idet = 1.0 / (a11 * a22 - a12 * a21)
        # stage 1
        b1 = (w - F + gh * du) * im
        k1v = (b1 * a22 - a12 * zd) * idet
        k1z = (a11 * zd - a21 * b1) * idet
        k1x = v + gh * k1v
        # stage 2 at y + h k1 (w advances by h du)
        v2 = v + h * k1v
        z2 = z + h * k1z
        zd2, F2 = _force(v2, z2, p0, p1, d0, d1)
        r_z = zd2 - 2.0 * k1z
        b1 = (w + h * du - F2 - gh * du) * im - 2.0 * k1v
        k2v = (b1 * a22 - a12 * r_z) * idet
        k2z = (a11 * r_z - a21 * b1) * idet
        k2x = v2 - 2.0 * k1x + gh * k2v
        xn = x + h * (1.5 * k1x + 0.5 * k2x)
        vn = v + h * (1.5 * k1v + 0.5 * k2v)
        zn = z + h * (1.5 * k1z + 0.5 * k2z)
        n += 1
        if not math.isfinite(xn + vn + zn):  # inf or NaN in any of them (inf - inf is NaN)
            if h > H_MIN * dt:
                h_try = 0.1 * h
                continue
            return x, v, z, F, h_try, n, NONFINITE, vpk
        # Error estimate of the embedded first-order solution, filtered through
        # (I - gamma h J)^-1 so that stiff, quickly damped components (the bristle
        # state while sliding) do not force needlessly small steps (Shampine).
        e1 = 0.5 * h * (k1v + k2v)
        e2 = 0.5 * h * (k1z + k2z)
        ev = (e1 * a22 - a12 * e2) * idet
        ez = (a11 * e2 - a21 * e1) * idet
        e = abs(ev) / (tol_v + rtol * abs(vn))
        q = abs(ez) / (atol_z + rtol * abs(zn))
        if q > e:
            e = q
        if e > 1.0 and h <= H_MIN * dt:
            # step-size underflow: the tolerance cannot be met (e.g. a mass so small that
            # the velocity follows the force faster than 1e-7 dt); stop, do not accept
            return x, v, z, F, h_try, n, TOLERANCE, vpk
        if e <= 1.0:
            x = xn
            v = vn
            z = zn
            t += h
            w = u0 + du * t
            if abs(v) > vpk:
                vpk = abs(v)
                tol_v = _atol_run(atol_v, v_floor, rtol, vpk)
            zd, F, dzv, dzz, dFv, dFz = _point(v, z, p0, p1, d0, d1)
        # growth factor 0.9 / sqrt(e) clipped to [0.2, 5]; below E_GROW it is 5 anyway,
        # which spares the sqrt and division on most sliding sub-steps
        fac = 0.9 / math.sqrt(e) if e > E_GROW else 5.0
        h_try = h * min(5.0, max(0.2, fac))
        if n >= max_sub:
            return x, v, z, F, h_try, n, BUDGET, vpk
    return x, v, z, F, h_try, n, OK, vpk


@njit
def lugre_force(u, dt, m, static, dyn, x0, v0, z0, rtol, atol_v, atol_z, max_sub, x, v, F, z, v_floor=1.0):
    """Force-driven run over all samples; fills ``x, v, F, z``. Returns ``(status, k, substeps)``.

    ``v_floor`` (<= 1): the velocity tolerance follows the run's largest speed down to
    ``v_floor * atol_v`` (:func:`_atol_run`); 1 keeps ``atol_v`` fixed.
    """
    xs, vs_, zs = x0, v0, z0
    p0 = static_row(static, 0)
    p1 = static_row(static, 1)
    d0 = (dyn[0, 0], dyn[0, 1])
    d1 = (dyn[1, 0], dyn[1, 1])
    x[0] = xs
    v[0] = vs_
    z[0] = zs
    F[0] = _force(vs_, zs, p0, p1, d0, d1)[1]
    h_try = dt
    total = 0
    vpk = abs(v0)
    for k in range(u.size - 1):
        xs, vs_, zs, Fs_, h_try, n, st, vpk = _interval(
            xs, vs_, zs, h_try, u[k], u[k + 1], dt, m, p0, p1, d0, d1, rtol, atol_v, atol_z, max_sub,
            vpk, v_floor,
        )
        total += n
        x[k + 1] = xs
        v[k + 1] = vs_
        z[k + 1] = zs
        F[k + 1] = Fs_
        if st != OK:
            return st, k + 1, total
    return OK, u.size - 1, total


@njit(parallel=True)
def lugre_force_batch_sse(
    u, dt, m, static, dyn, rtol, atol_v, atol_z, max_sub, target, which, weight, out_sse, out_status, v_floor=1.0
):
    """Simulate P parameter sets on one input; return only the weighted squared error.

    ``static (P, 2, 6)``, ``dyn (P, 2, 2)``, ``m (P,)``. ``which`` selects the compared
    signal: 0 position, 1 velocity, 2 friction force. ``weight (N,)`` masks samples.
    """
    P = m.size
    for j in prange(P):
        xs = 0.0
        vs_ = 0.0
        zs = 0.0
        h_try = dt
        p0 = static_row(static[j], 0)
        p1 = static_row(static[j], 1)
        d0 = (dyn[j, 0, 0], dyn[j, 0, 1])
        d1 = (dyn[j, 1, 0], dyn[j, 1, 1])
        mj = m[j]
        acc = 0.0
        st = OK
        vpk = 0.0
        for k in range(u.size - 1):
            xs, vs_, zs, Fe, h_try, n, st, vpk = _interval(
                xs, vs_, zs, h_try, u[k], u[k + 1], dt, mj, p0, p1, d0, d1,
                rtol, atol_v, atol_z, max_sub, vpk, v_floor,
            )
            if st != OK:
                break
            if which == 0:
                y = xs
            elif which == 1:
                y = vs_
            else:
                y = Fe
            d = y - target[k + 1]
            acc += weight[k + 1] * d * d
        out_sse[j] = acc if st == OK else np.inf
        out_status[j] = st


@njit
def lugre_motion(xpos, dt, static, dyn, z0, v_out, F_out, z_out):
    """Motion-driven LuGre with piecewise-constant velocity: exact exponential update."""
    N = xpos.size
    z = z0
    p0 = static_row(static, 0)
    p1 = static_row(static, 1)
    d0 = (dyn[0, 0], dyn[0, 1])
    d1 = (dyn[1, 0], dyn[1, 1])
    for k in range(N - 1):
        vk = (xpos[k + 1] - xpos[k]) / dt
        p, (s0, s1) = _side(vk, p0, p1, d0, d1)
        av = abs(vk)
        a = s0 * av / g_row(p, av)
        if a > 0.0:
            zss = vk / a  # = sgn(v) g / sigma0
            z = zss + (z - zss) * math.exp(-a * dt)
        if k == 0:
            v_out[0] = vk
            zd0 = vk - a * z0
            F_out[0] = s0 * z0 + s1 * zd0 + p[R_S2] * vk
            z_out[0] = z0
        zd = vk - a * z
        v_out[k + 1] = vk
        z_out[k + 1] = z
        F_out[k + 1] = s0 * z + s1 * zd + p[R_S2] * vk
    return OK
