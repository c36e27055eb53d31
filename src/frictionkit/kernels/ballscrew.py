"""Numba kernel: ball-screw plant (any linear mechanical chain + Dahl friction sites) in a
closed loop with PID, disturbance observer, feed-forward and quantised sensors.

Flat arrays and floats in, arrays and a status code out; no validation here (the public
wrapper in :mod:`frictionkit.control.loop` validates).

Integration scheme
------------------
Over one sub-step ``h`` the linear part ``dX/dt = A X + B w`` is advanced *exactly* with
the zero-order-hold pair ``Phi = exp(A h)``, ``Gam = int_0^h exp(A s) ds B``, so stiff
springs cost nothing in stability. The kernel receives these in lifted form (see
:meth:`frictionkit.plants.ballscrew.LinearChain.lifted`) so one control period costs one
pass over the state instead of ``n_sub``. The friction forces ``w[1:]`` are held over the
sub-step; each Dahl state is advanced by its exact solution for the sub-step's velocity,
``F+ = s Fc + (F - s Fc) exp(-sigma0 |v| h / Fc)`` (``s = sgn v``), which keeps
``|F| <= Fc`` for any ``h``.

Flank sites (``fl_sign[j] = +1/-1``, nut model ``"flank"`` of
:class:`frictionkit.plants.ballscrew.ElasticBallScrew`): the Coulomb level follows the ball
load of one groove flank, ``Fc_j = fl_mu[j] N_j`` with
``N_j = max(P + s F_bn / 2, s F_bn, 0)`` (``P = fl_P[j]``, ``s = fl_sign[j]``) and ``F_bn``
the drive force through the nut at the start of the sub-step (row ``nf`` of the lifted
velocity rows). When ``N_j`` falls, the state is scaled by ``N_new / N_old`` (the shrinking
contacts lose their tangential traction); when it rises the state is kept (new contact area
carries no traction yet). The Dahl update then uses the fixed rate ``fl_lam[j] = ln 20 / x_s``
(``sigma0 / Fc`` does not depend on the level).

Hertzian contact (``hz = [site, c, d0, k]`` with ``site >= 0``, nut model ``"hertz"``): the
chain holds the contact's linear part ``k d``; site ``site`` (velocity row = the contact row,
so its force acts along the contact) carries the correction
``G(d) = c (d0 + d)_+^1.5 - c (d0 - d)_+^1.5 - k d``, held over each sub-step at the
predicted mid-sub-step deflection ``d + h d' / 2`` (``d`` from the last lifted row, ``d'`` from
the site's velocity row, both at the start of the sub-step). The flank sites then take their
ball loads from the Hertz law, ``N_j = c (d0 + s d)_+^1.5`` at the start of the sub-step,
instead of the linearised split. The drive-force output adds ``G(d)`` to the linear row.

Status codes: 0 ok, 1 non-finite state (run stopped at ``k_end``).
"""

from __future__ import annotations

import math

import numpy as np

from .._jit import njit

STATUS_OK = 0
STATUS_NONFINITE = 1

# Layout of the ``ctrl`` parameter vector.
C_KP, C_KI, C_KD, C_TAUD, C_T, C_DOB, C_AQ, C_KTAU, C_JN, C_BN, C_IMAX, C_FBMODE, C_R, C_QENC, C_QSCALE = range(15)
N_CTRL = 15


@njit
def _quantise(x, q):
    if q > 0.0:
        return math.floor(x / q) * q
    return x


@njit
def _hertz(d, c, d0):
    """Net Hertz force of two preloaded sets at deflection ``d``: ``c (d0+d)_+^1.5 - c (d0-d)_+^1.5``."""
    a = d0 + d
    b = d0 - d
    fa = c * a * math.sqrt(a) if a > 0.0 else 0.0
    fb = c * b * math.sqrt(b) if b > 0.0 else 0.0
    return fa - fb


@njit
def closed_loop(PhiN, GN, CvP, CvG, h, Fc, sig0, fl_sign, fl_mu, fl_P, fl_lam, hz, F, X,
                c_mot, c_tab, c_frc,
                theta_d, u_ff, u_f, noise_enc, noise_scale, ctrl,
                out_xt, out_thm, out_xt_meas, out_thm_meas, out_i, out_fbn, out_fric):
    """Run ``theta_d.size`` control periods. ``X`` and ``F`` are updated in place.

    Returns ``(status, k_end)``; samples ``k >= k_end`` of the outputs are left untouched.
    """
    n2 = X.size
    nf = Fc.size
    N = theta_d.size
    kp = ctrl[C_KP]
    ki = ctrl[C_KI]
    kd = ctrl[C_KD]
    taud = ctrl[C_TAUD]
    T = ctrl[C_T]
    dob_on = ctrl[C_DOB] > 0.5
    aq = ctrl[C_AQ]
    ktau = ctrl[C_KTAU]
    Jn = ctrl[C_JN]
    Bn = ctrl[C_BN]
    imax = ctrl[C_IMAX]
    fb_mode = int(ctrl[C_FBMODE] + 0.5)
    R = ctrl[C_R]
    qenc = ctrl[C_QENC]
    qscale = ctrl[C_QSCALE]

    n_sub = GN.shape[0]
    nw = 1 + nf
    W = np.zeros((n_sub, nw))
    Xn = np.empty(n2)
    has_flank = False
    lev_prev = np.zeros(nf)
    for j in range(nf):
        if fl_sign[j] != 0.0:
            has_flank = True
            lev_prev[j] = fl_mu[j] * fl_P[j]
    hz_j = int(hz[0]) if hz[0] >= 0.0 else -1
    hz_c = hz[1]
    hz_d0 = hz[2]
    hz_k = hz[3]
    rd = nf + 1  # lifted row of the contact deflection

    integ = 0.0
    dterm = 0.0
    e_prev = 0.0
    thm_prev = 0.0
    om_prev = 0.0
    dhat = 0.0
    i_dob_prev = 0.0  # current applied last period, excluding the friction compensation

    for k in range(N):
        # ---- sensors
        thm = 0.0
        xt = 0.0
        fbn = 0.0
        for a in range(n2):
            thm += c_mot[a] * X[a]
            xt += c_tab[a] * X[a]
            fbn += c_frc[a] * X[a]
        thm_m = _quantise(thm + noise_enc[k], qenc)
        xt_m = _quantise(xt + noise_scale[k], qscale)
        if hz_j >= 0:
            d = 0.0
            for a in range(n2):
                d += CvP[0, rd, a] * X[a]
            fbn += _hertz(d, hz_c, hz_d0) - hz_k * d
        out_xt[k] = xt
        out_thm[k] = thm
        out_xt_meas[k] = xt_m
        out_thm_meas[k] = thm_m
        out_fbn[k] = fbn
        for j in range(nf):
            out_fric[j, k] = F[j]

        # ---- PID (backward Euler, filtered derivative, conditional integration)
        # feedback mode: 0 motor encoder, 1 linear scale, 2 dual (P, I on the scale,
        # D on the motor encoder: collocated damping of the elastic chain)
        y = xt_m / R if fb_mode >= 1 else thm_m
        e = theta_d[k] - y
        ed = theta_d[k] - thm_m if fb_mode == 2 else e
        if k == 0:
            e_prev = ed
            thm_prev = thm_m
        dterm = (taud * dterm + kd * (ed - e_prev)) / (taud + T)
        u_c = kp * e + integ + dterm

        # ---- disturbance observer on motor velocity (inverse nominal model + 1st-order LPF)
        om = (thm_m - thm_prev) / T
        if dob_on and k > 0:
            raw = ktau * i_dob_prev - Bn * om - Jn * (om - om_prev) / T
            dhat = aq * dhat + (1.0 - aq) * raw
        i_dob = u_ff[k] + u_c + dhat / ktau
        i_cmd = i_dob + u_f[k]
        sat = False
        if i_cmd > imax:
            i_cmd = imax
            sat = True
        elif i_cmd < -imax:
            i_cmd = -imax
            sat = True
        if not sat:
            integ += ki * T * e
        i_dob_prev = i_cmd - u_f[k]
        e_prev = ed
        thm_prev = thm_m
        om_prev = om
        out_i[k] = i_cmd

        # ---- plant: n_sub exact linear sub-steps, Dahl sites advanced exactly.
        # Lifted form: site velocities at sub-step s come from X(0) and the inputs already
        # held, v(s) = CvP[s] X(0) + sum_{r<s} CvG[s, r] w(r); then
        # X(n_sub) = PhiN X(0) + sum_s GN[s] w(s) — the same numbers as stepping
        # X <- Phi X + Gam w n_sub times, at a fraction of the cost.
        for s in range(n_sub):
            W[s, 0] = i_cmd
            fb = 0.0
            dc = 0.0
            if hz_j >= 0:  # contact deflection and its rate at the start of the sub-step
                dv = 0.0
                for a in range(n2):
                    dc += CvP[s, rd, a] * X[a]
                    dv += CvP[s, hz_j, a] * X[a]
                for r in range(s):
                    for b in range(nw):
                        dc += CvG[s, r, rd, b] * W[r, b]
                        dv += CvG[s, r, hz_j, b] * W[r, b]
                dm = dc + 0.5 * h * dv
                F[hz_j] = _hertz(dm, hz_c, hz_d0) - hz_k * dm
            elif has_flank:  # drive force through the nut at the start of the sub-step
                for a in range(n2):
                    fb += CvP[s, nf, a] * X[a]
                for r in range(s):
                    for b in range(nw):
                        fb += CvG[s, r, nf, b] * W[r, b]
            for j in range(nf):
                if fl_sign[j] != 0.0:
                    if hz_j >= 0:  # Hertz ball load of this flank set
                        a1 = hz_d0 + fl_sign[j] * dc
                        load = hz_c * a1 * math.sqrt(a1) if a1 > 0.0 else 0.0
                    else:  # linearised equal-stiffness split of F_bn
                        sf = fl_sign[j] * fb
                        load = fl_P[j] + 0.5 * sf
                        if sf > load:
                            load = sf
                        if load < 0.0:
                            load = 0.0
                    lev = fl_mu[j] * load
                    if lev < lev_prev[j]:
                        F[j] = F[j] * (lev / lev_prev[j]) if lev_prev[j] > 0.0 else 0.0
                    lev_prev[j] = lev
                    v = 0.0
                    for a in range(n2):
                        v += CvP[s, j, a] * X[a]
                    for r in range(s):
                        for b in range(nw):
                            v += CvG[s, r, j, b] * W[r, b]
                    if lev > 0.0:
                        if v > 0.0:
                            F[j] = lev + (F[j] - lev) * math.exp(-fl_lam[j] * v * h)
                        elif v < 0.0:
                            F[j] = -lev + (F[j] + lev) * math.exp(fl_lam[j] * v * h)
                    else:
                        F[j] = 0.0
                elif Fc[j] > 0.0:
                    v = 0.0
                    for a in range(n2):
                        v += CvP[s, j, a] * X[a]
                    for r in range(s):
                        for b in range(nw):
                            v += CvG[s, r, j, b] * W[r, b]
                    if v > 0.0:
                        F[j] = Fc[j] + (F[j] - Fc[j]) * math.exp(-sig0[j] * v * h / Fc[j])
                    elif v < 0.0:
                        F[j] = -Fc[j] + (F[j] + Fc[j]) * math.exp(sig0[j] * v * h / Fc[j])
                W[s, 1 + j] = F[j]
        for a in range(n2):
            acc = 0.0
            for b in range(n2):
                acc += PhiN[a, b] * X[b]
            for s in range(n_sub):
                for b in range(nw):
                    acc += GN[s, a, b] * W[s, b]
            Xn[a] = acc
        for a in range(n2):
            X[a] = Xn[a]
        # non-finite states end the run (checked once per control period)
        for a in range(n2):
            if not math.isfinite(X[a]):
                return STATUS_NONFINITE, k + 1
    return STATUS_OK, N
