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
State ``y = (v, z)`` (and ``x``), ``v' = (u(t) - F - offset) / m``, ``z' = v - a z``, the input
linear between samples. The sensitivities ``S = dy/dtheta`` obey ``S' = J(y(t)) S + f_theta(y(t))``.
The state is integrated with the very steps of :func:`.lugre.lugre_force`: both call the one
spanning step :func:`.lugre._span` and, in the ROS2 intervals at reversals, the one sub-step
:func:`.lugre._ros2_sub` (with its invariant bounds of ``z``), at the same tolerances, so the
trajectory is that of :func:`frictionkit.simulate` (tests/kernels/test_sensitivity.py compares the
two; issue 11: this kernel held a copy of the step). The sensitivities ride on every accepted step:

* spanning step (linearisation ``B = J(y_k)`` on one side of ``|v|``): the only nonlinearity
  is ``dz/dt``, so along the step ``J(y(t)) = B + w c(t)^T`` exactly, with ``w = (-sigma1/m, 1)``
  and ``c = grad dz/dt (y(t)) - grad dz/dt (y_k)``. ``S' = B S + q(t)``, ``q = f_theta + w (c . S)``,
  is solved sample by sample with the step's own ``phi`` functions for ``q`` linear between
  samples (the exponential trapezoidal rule, ``S+ = E S + dt (phi1 - phi2) q + dt phi2 q+``,
  second order, exact for the linearised model), implicit in the scalar ``c+ . S+`` per
  column (closed form). ``f_theta`` is evaluated at the corrected samples; the ``phi``
  functions and ``E`` are the state step's, so a sample costs one ``exp`` and a few dozen
  flops per parameter;
* ROS2 interval: the W-method on the augmented system, ``W = I - gamma h J(y_n)`` for the
  state and every sensitivity column (a W-method is second order for any ``W``)::

    W k1s = J(y) s + f_theta(y),   W k2s = J(y2) (s + h k1s) + f_theta(y2) - 2 k1s,
    s+ = s + h (3 k1s + k2s) / 2

Assumption (named): the step size is controlled on the state only (as the plain kernel does);
the sensitivities ride on the same steps — the usual "staggered" choice. Measured on
``benchmarks/identify.py``'s record at the fitter's tolerances (rtol 1e-5): every column within
8e-4 (norm) of central differences of simulations at rtol 1e-8, and one augmented run with six
parameters costs 2.6 plain simulations (3.46 vs 1.35 ms CPU); the ROS2-W kernel it replaces,
with its own steps (23k sub-steps against 7k), cost 5.3.

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
from ._stribeck import row as static_row
from .lugre import BUDGET, E_GROW, H_MIN, NONFINITE, OK, TOLERANCE
from .lugre import _atol_run, _flat, _point, _ring_tight, _ros2_sub, _span_call, _z_bounds

#: Index of each packed quantity in ``coef[j, row, :]``.
C_S0, C_S1, C_FC, C_FS, C_VS, C_DELTA, C_S2 = 0, 1, 2, 3, 4, 5, 6
N_COEF = 7
#: ``(|v| / vs)^delta`` beyond which the Stribeck term ``exp(-.)`` (< 1e-30) is taken as 0. Its
#: products with the sensitivities otherwise run through subnormal numbers (~100x slower
#: arithmetic) on every fast-sliding sample; the level changes by < 1e-30 of ``Fs - Fc``.
PHI_CUT = 69.0


@njit(inline="always")
def _g_parts(Fc, Fs, vs, delta, shape, av, want_delta=True):
    """``(g, dg/d|v|, phi, dphi/dvs, dphi/ddelta)`` with ``g = Fc + (Fs - Fc) phi(|v| / vs)``
    (``dphi/ddelta`` is 0 unless ``want_delta``: it costs a logarithm)."""
    r = av / vs
    if r == 0.0:
        return Fs, 0.0, 1.0, 0.0, 0.0
    if shape == 0.0:
        rd = r * r if delta == 2.0 else (r if delta == 1.0 else r**delta)
        if rd > PHI_CUT:  # phi < 1e-30: g = Fc, flat (further terms would be subnormal: slow)
            return Fc, 0.0, 0.0, 0.0, 0.0
        phi = math.exp(-rd)
        dphi_dr = -phi * delta * rd / r
        return (Fc + (Fs - Fc) * phi, (Fs - Fc) * dphi_dr / vs, phi, -dphi_dr * r / vs,
                -phi * rd * math.log(r) if want_delta else 0.0)
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
            # 1 - E from expm1: zss + (z - zss) E cancels when a dt < ~1e-16 (kernels.lugre.lugre_motion);
            # E from it too, as lugre_motion does (one transcendental call per sample, not two)
            e1 = -math.expm1(-a * dt)
            E = 1.0 - e1
            sg = 1.0 if vk > 0.0 else -1.0
            zss = sg * g / s0
            zo = z
            z = zo * E + zss * e1
            for j in range(p):
                dgj = _dg(coef, j, row, Fc, Fs, phi, dphi_vs, dphi_de)
                da = av * (coef[j, row, C_S0] / g - s0 * dgj / (g * g))
                dzss = sg * (dgj / s0 - g * coef[j, row, C_S0] / (s0 * s0))
                dz[j] = dzss * e1 + dz[j] * E - (zo - zss) * dt * E * da
        else:  # a = 0 (v = 0, or s0 |v| / g below the smallest double): dz/dt = v, as lugre_motion
            z = z + vk * dt
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
def _pt(v, z, uu, im, Fc, Fs, vs, delta, shape, s0, s1, s2, want_delta):
    """Rates and their derivatives at one state, parameters of one row:
    ``(fv, zd, dzd/dv, dzd/dz, dF/dv, dF/dz, |v|, 1/g, phi, dphi/dvs, dphi/ddelta)``."""
    av = abs(v)
    g, gr, phi, dpv, dpd = _g_parts(Fc, Fs, vs, delta, shape, av, want_delta)
    ig = 1.0 / g
    a = s0 * av * ig
    zd = v - a * z
    sg = 1.0 if v > 0.0 else (-1.0 if v < 0.0 else 0.0)
    zdv = 1.0 - s0 * z * sg * ig * (1.0 - av * gr * ig)
    F = s0 * z + s1 * zd + s2 * v
    return (uu - F) * im, zd, zdv, -a, s1 * zdv + s2, s0 - s1 * a, av, ig, phi, dpv, dpd


@njit(inline="always")
def _ftheta(coef, j, row, dmj, doffj, v, z, av, im, fv, zd, ig, Fc, Fs, s0, s1, phi, dphi_vs, dphi_de):
    """``(d v' / d theta_j, d z' / d theta_j)`` at fixed state, parameter rows of ``row``
    (``im = 1/m``, ``ig = 1/g``: no division in the per-parameter loop)."""
    dgj = _dg(coef, j, row, Fc, Fs, phi, dphi_vs, dphi_de)
    ds0 = coef[j, row, C_S0]
    dzd = -av * (ds0 - s0 * dgj * ig) * ig * z
    dF = ds0 * z + coef[j, row, C_S1] * zd + s1 * dzd + coef[j, row, C_S2] * v
    return -(dF + doffj + fv * dmj) * im, dzd


@njit(error_model="numpy")  # a call, not inlined: reached only at reversals and where a step cannot start
def _ros2_sens(x, v, z, h_try, u0, u1, dt, m, p0, p1, d0, d1, rtol, atol_v, atol_z, max_sub, vpk, v_floor, zlo, zhi,
               static, dyn, coef, dm, doff, want_delta, want_x, sx, sv, sz):
    """One sample interval by adaptive ROS2 sub-steps (the scheme of ``lugre._interval``), the
    sensitivities ``sx, sv, sz`` (updated in place) riding on every accepted sub-step as a
    W-method on the augmented system (module docstring). Returns ``(x, v, z, h_try, n, status, vpk)``."""
    im = 1.0 / m
    du = (u1 - u0) / dt
    t = 0.0
    w = u0
    n = 0
    P = coef.shape[0]
    zd, F, dzv, dzz, dFv, dFz = _point(v, z, p0, p1, d0, d1)
    tol_v = _atol_run(atol_v, v_floor, rtol, vpk)
    tight = _ring_tight(dFv, dFz, dzv, dzz, im, dt)
    while t < dt:
        h = h_try
        rem = dt - t
        if h >= rem or rem - h < 1e-9 * dt:
            h = rem
        fin, xn, vn, zn, e, v2, z2, gh, a11, a12, a21, a22, idet = _ros2_sub(
            x, v, z, h, w, du, im, zd, F, dzv, dzz, dFv, dFz, p0, p1, d0, d1, tol_v, rtol, atol_z, zlo, zhi)
        n += 1
        e *= tight  # as lugre._interval (lugre.RING_FAST)
        if not fin:
            if h > H_MIN * dt:
                h_try = 0.1 * h
                continue
            return x, v, z, h_try, n, NONFINITE, vpk
        if e > 1.0 and h <= H_MIN * dt:
            return x, v, z, h_try, n, TOLERANCE, vpk
        if e <= 1.0:
            # sensitivities on the same sub-step: stage 1 at (v, z), stage 2 at (v2, z2)
            r = 0 if v >= 0.0 else 1
            Fc, Fs, s0, s1 = static[r, 0], static[r, 1], dyn[r, 0], dyn[r, 1]
            fa, zda, zva, zza, Fva, Fza, ava, iga, pha, dva, dda = _pt(
                v, z, w, im, Fc, Fs, static[r, 2], static[r, 3], static[r, 5], s0, s1, static[r, 4], want_delta)
            r2 = 0 if v2 >= 0.0 else 1
            Fc2, Fs2, s02, s12 = static[r2, 0], static[r2, 1], dyn[r2, 0], dyn[r2, 1]
            fb, zdb, zvb, zzb, Fvb, Fzb, avb, igb, phb, dvb, ddb = _pt(
                v2, z2, w + h * du, im, Fc2, Fs2, static[r2, 2], static[r2, 3], static[r2, 5], s02, s12,
                static[r2, 4], want_delta)
            for j in range(P):
                ftv, ftz = _ftheta(coef, j, r, dm[j], doff[j], v, z, ava, im, fa, zda, iga, Fc, Fs, s0, s1,
                                   pha, dva, dda)
                rv = -(Fva * sv[j] + Fza * sz[j]) * im + ftv
                rz = zva * sv[j] + zza * sz[j] + ftz
                q1v = (a22 * rv - a12 * rz) * idet
                q1z = (a11 * rz - a21 * rv) * idet
                q1x = sv[j] + gh * q1v
                sv2 = sv[j] + h * q1v
                sz2 = sz[j] + h * q1z
                ftv, ftz = _ftheta(coef, j, r2, dm[j], doff[j], v2, z2, avb, im, fb, zdb, igb, Fc2, Fs2, s02, s12,
                                   phb, dvb, ddb)
                rv = -(Fvb * sv2 + Fzb * sz2) * im + ftv - 2.0 * q1v
                rz = zvb * sv2 + zzb * sz2 + ftz - 2.0 * q1z
                q2v = (a22 * rv - a12 * rz) * idet
                q2z = (a11 * rz - a21 * rv) * idet
                if want_x:
                    sx[j] += h * (1.5 * q1x + 0.5 * ((sv2 - 2.0 * q1x) + gh * q2v))
                sv[j] += h * (1.5 * q1v + 0.5 * q2v)
                sz[j] += h * (1.5 * q1z + 0.5 * q2z)
            x = xn
            v = vn
            z = min(max(zn, zlo), zhi)  # projected onto the invariant bounds (lugre._z_bounds)
            t += h
            w = u0 + du * t
            if abs(v) > vpk:
                vpk = abs(v)
                tol_v = _atol_run(atol_v, v_floor, rtol, vpk)
            zd, F, dzv, dzz, dFv, dFz = _point(v, z, p0, p1, d0, d1)
        fac = 0.9 / math.sqrt(e) if e > E_GROW else 5.0
        h_try = h * min(5.0, max(0.2, fac))
        if n >= max_sub:
            return x, v, z, h_try, n, BUDGET, vpk
    return x, v, z, h_try, n, OK, vpk


@njit(error_model="numpy")  # IEEE division: non-finite states are caught by the step logic
def lugre_force_sens(u, dt, m, static, dyn, coef, dm, doff, rtol, atol_v, atol_z, max_sub, v_floor, want_x,
                     x, v, z, Sx, Sv):
    """Force-driven LuGre on a mass from rest, with forward sensitivities (module docstring).

    ``u`` is the force on the mass less the constant ``offset`` (as :func:`frictionkit.simulate`
    is given it); ``dm``, ``doff`` the derivatives of the mass and the offset. Fills ``x, v, z``
    (``N``) and ``Sv`` (``N, p``: ``dv/dtheta``), and ``Sx`` (``dx/dtheta``) when ``want_x``.
    The state steps are those of :func:`.lugre.lugre_force` (tolerances and ``v_floor`` as it
    takes them). Returns ``(status, k, substeps)`` as it does.
    """
    p0 = _flat(static_row(static, 0))
    p1 = _flat(static_row(static, 1))
    d0 = (dyn[0, 0], dyn[0, 1])
    d1 = (dyn[1, 0], dyn[1, 1])
    im = 1.0 / m
    dt2 = dt * dt
    N = u.size
    P = coef.shape[0]
    want_delta = P < 0  # False as an expression: a literal False types the callees twice (Literal[bool], bool)
    for j in range(P):
        if coef[j, 0, C_DELTA] != 0.0 or coef[j, 1, C_DELTA] != 0.0:
            want_delta = True
    K, Ki, Kv = _k_table(coef, dm, doff)
    AB = np.zeros((2, 9))
    sx = np.zeros(P)
    sv = np.zeros(P)
    sz = np.zeros(P)
    qv = np.zeros(P)  # forcing d f / d theta + w c.S of the sensitivity equation at the current sample
    qz = np.zeros(P)
    xs, vs_, zs = 0.0, 0.0, 0.0
    x[0] = xs
    v[0] = vs_
    z[0] = zs
    for j in range(P):
        Sv[0, j] = 0.0
        if want_x:
            Sx[0, j] = 0.0
    total = 0
    vpk = 0.0
    zlo, zhi = _z_bounds(p0, p1, d0, d1, 0.0)
    # k, n_try, have start as expressions, not literals: numba would type the first call of
    # _span_call with literal argument types and compile it twice
    k = N - N
    n_try = k + 1
    have = k < 0
    pt = (0.0, 0.0, 0.0, 0.0, 0.0, 0.0)
    F = np.empty(N)  # the friction force of the shared step (the fits take theirs from simulate)
    h_ros = dt
    while k < N - 1:
        j, n_try, vpk, tries, pt, lin = _span_call(u, k, n_try, xs, vs_, zs, have, pt, vpk, dt, m, p0, p1, d0, d1,
                                                   rtol, atol_v, atol_z, v_floor, zlo, zhi, x, v, F, z)
        total += tries
        have = j > 0
        if j > 0:
            sd, E, P1, P2, P3, b21, b22, wv = lin
            _span_sens(k, j, sd, vs_, zs, u, dt, dt2, im, static, dyn, K, Ki, Kv, AB, want_delta, want_x,
                       E, P1, P2, P3, b21, b22, wv, v, z, sx, sv, sz, qv, qz, Sx, Sv)
            k += j
            xs = x[k]
            vs_ = v[k]
            zs = z[k]
            h_ros = dt
            continue
        xs, vs_, zs, h_ros, nn, st, vpk = _ros2_sens(
            xs, vs_, zs, min(h_ros, dt), u[k], u[k + 1], dt, m, p0, p1, d0, d1, rtol, atol_v, atol_z, max_sub,
            vpk, v_floor, zlo, zhi, static, dyn, coef, dm, doff, want_delta, want_x, sx, sv, sz)
        have = False
        total += nn
        k += 1
        x[k] = xs
        v[k] = vs_
        z[k] = zs
        for jj in range(P):
            Sv[k, jj] = sv[jj]
            if want_x:
                Sx[k, jj] = sx[jj]
        n_try = 1
        if st != OK:
            return st, k, total
    return OK, N - 1, total


@njit(error_model="numpy")
def _span_sens(k, n, sd, v0, z0, u, dt, dt2, im, static, dyn, K, Ki, Kv, AB, want_delta, want_x,
               E, P1, P2, P3, b21, b22, wv, v, z, sx, sv, sz, qv, qz, Sx, Sv):
    """Sensitivities over an accepted spanning step of ``n`` samples from sample ``k``.

    ``S' = B S + q(t)`` with ``B`` the step's linearisation and the forcing
    ``q = df/dtheta (y(t)) + w (c(t) . S)``, ``c = grad dz/dt (y(t)) - grad dz/dt (y_k)`` (the
    Jacobian along the path is ``B + w c^T`` exactly: the remainder is in ``dz/dt`` alone).
    Each sample interval is solved exactly for ``q`` linear between the samples (the
    exponential trapezoidal rule: ``S+ = E S + dt (phi1 - phi2) q + dt phi2 q+``), implicit in
    ``c+ . S+`` (a scalar per column, closed form). ``K, Ki, Kv``: the packed-row derivatives
    per column (:func:`_k_table`); ``AB`` ``(2, 9)`` scratch.
    """
    P = sv.size
    rs = 0 if sd > 0.0 else 1
    Fc = static[rs, 0]
    Fs = static[rs, 1]
    vsr = static[rs, 2]
    de = static[rs, 3]
    sh = static[rs, 5]
    s2 = static[rs, 4]
    s0 = dyn[rs, 0]
    s1 = dyn[rs, 1]
    Kr = K[rs]
    q10, q11, q12, q13 = dt * (P1[0] - P2[0]), dt * (P1[1] - P2[1]), dt * (P1[2] - P2[2]), dt * (P1[3] - P2[3])
    q20, q22 = dt * P2[0], dt * P2[2]
    omv = q20 * wv + dt * P2[1]  # dt phi2 w
    omz = q22 * wv + dt * P2[3]
    x0v, x0z = dt * P1[0], dt * P1[1]
    xav, xaz = dt2 * (P2[0] - P3[0]), dt2 * (P2[1] - P3[1])
    xbv, xbz = dt2 * P3[0], dt2 * P3[1]
    omx = xbv * wv + xbz
    dF = Fs - Fc
    for i in range(n + 1):
        b = k + i
        if i == 0:
            vb = v0 if v0 != 0.0 else sd  # the side the step is on (from rest: sd = +-1e-300)
            zb = z0
        else:
            vb = v[b]
            zb = z[b]
        av = abs(vb)
        g, gr, phi, dpv, dpd = _g_parts(Fc, Fs, vsr, de, sh, av, want_delta)
        ig = 1.0 / g
        a = s0 * av * ig
        zd = vb - a * zb
        sg = 1.0 if vb > 0.0 else -1.0
        zdv = 1.0 - s0 * zb * sg * ig * (1.0 - av * gr * ig)
        G = s0 * av * ig * ig * zb  # d(dz/dt)/dg
        # the forcing per unit change of each packed quantity: al along w, be along e_v
        # [sigma0, sigma1, Fc, Fs, vs, delta, sigma2, m, offset]
        AB[0, 0] = -av * ig * zb  # d(dz/dt)/dsigma0
        AB[0, 2] = G * (1.0 - phi)
        AB[0, 3] = G * phi
        AB[0, 4] = G * dF * dpv
        AB[0, 5] = G * dF * dpd
        AB[1, 0] = -zb * im
        AB[1, 1] = -zd * im
        AB[1, 6] = -vb * im
        AB[1, 7] = -(u[b] - (s0 * zb + s1 * zd + s2 * vb)) * im * im  # -v' / m
        AB[1, 8] = -im
        if i == 0:  # forcing at the step's first sample (c = 0 there by construction)
            for j in range(P):
                al, be = _forcing(Kr, Ki[rs, j], Kv[rs, j], j, AB)
                qv[j] = be + wv * al
                qz[j] = al
            continue
        cv = zdv - b21
        cz = -a - b22
        den = 1.0 / (1.0 - (cv * omv + cz * omz))
        for j in range(P):
            al, be = _forcing(Kr, Ki[rs, j], Kv[rs, j], j, AB)
            svo = sv[j]
            szo = sz[j]
            qvo = qv[j]
            qzo = qz[j]
            # dt phi2 ft+ with ft+ = be e_v + al w
            # (parenthesised: short dependency chains through the recurrence)
            av_ = ((E[0] * svo + E[1] * szo) + (q10 * qvo + q11 * qzo)) + (q20 * be + omv * al)
            az_ = ((E[2] * svo + E[3] * szo) + (q12 * qvo + q13 * qzo)) + (q22 * be + omz * al)
            kap = (cv * av_ + cz * az_) * den
            nsv = av_ + omv * kap
            nqv = be + wv * (al + kap)
            nqz = al + kap
            if want_x:
                sx[j] += x0v * svo + x0z * szo + xav * qvo + xaz * qzo + xbv * be + omx * (al + kap)
                Sx[b, j] = sx[j]
            sv[j] = nsv
            sz[j] = az_ + omz * kap
            qv[j] = nqv
            qz[j] = nqz
            Sv[b, j] = nsv


@njit(inline="always")
def _forcing(Kr, c, kv, j, AB):
    """``(al, be)`` of column ``j``: its forcing ``be e_v + al w`` from the per-quantity basis ``AB``.
    A column that moves one packed quantity (``c >= 0``, factor ``kv``: every plain parameter)
    takes one product each; tied or mapped ones (Dahl's ``Fc``) the full sums."""
    if c >= 0:
        return kv * AB[0, c], kv * AB[1, c]
    al = 0.0
    be = 0.0
    for q in range(9):
        al += Kr[q, j] * AB[0, q]
        be += Kr[q, j] * AB[1, q]
    return al, be


@njit
def _k_table(coef, dm, doff):
    """``K[row, :, j]`` = the derivatives of ``[sigma0, sigma1, Fc, Fs, vs, delta, sigma2, m, offset]``
    (row ``row``) with respect to ``theta_j``, contiguous in ``j``; ``Ki[row, j]`` the one quantity
    column ``j`` moves in that row (-1: several or none) and ``Kv[row, j]`` its factor."""
    P = coef.shape[0]
    K = np.empty((2, 9, P))
    Ki = np.full((2, P), -1, dtype=np.int64)
    Kv = np.zeros((2, P))
    for r in range(2):
        for j in range(P):
            for c in range(N_COEF):
                K[r, c, j] = coef[j, r, c]
            K[r, 7, j] = dm[j]
            K[r, 8, j] = doff[j]
            nz = 0
            for c in range(9):
                if K[r, c, j] != 0.0:
                    nz += 1
                    Ki[r, j] = c
                    Kv[r, j] = K[r, c, j]
            if nz == 0:  # not in this row (a per-direction parameter): a zero factor
                Ki[r, j] = 0
            elif nz > 1:
                Ki[r, j] = -1
    return K, Ki, Kv
