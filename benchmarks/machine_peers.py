"""Peers of the machine benchmark (issue 8, "Speed"): the same closed-loop machines written the
way a capable engineer would without frictionkit — the controller in numba at the sample rate,
the plant integrated sample by sample by ``numbalsoda`` LSODA on a compiled (``numba.cfunc``)
right-hand side, the whole loop in one ``@njit`` function. Imported by ``benchmarks/machines.py``
(its ``peer_ratio`` entries); run alone for the peers only:

    .venv/bin/python benchmarks/machine_peers.py [--quick] [--repeat N]

Needs numbalsoda (the ``bench`` extra); without it :func:`available` is False and the
benchmark prints one line saying the peers were skipped.

Peers
-----
* ``emps``: ``presets/emps.py``'s loop (rigid axis ``M q'' = gtau nu_{k-1} - offset -
  Fc sgn(q') - Fv q'``; FIR position filter, backward-difference velocity, P-P cascade, ±10 V,
  one-sample delay; memories start at zero) on the recorded EMPS reference. Coulomb is written
  switched with stop detection (the engineer's exact choice for a force that is constant
  within a sample): LSODA on the sliding right-hand side of the current direction; a velocity
  sign change at the sample end is located by LSODA calls over a grid of ``LOC_GRID`` points
  narrowed to ``EVENT_TOL dt``; at the stop the axis sticks while ``|drive force| <= Fc``
  (Karnopp), else slides the other way. (A smooth ``Fc tanh(v / eps)`` would add a model
  error — creep through every stop at ``eps atanh(F / Fc)`` m/s — that no solver tolerance
  removes, and a small ``eps`` is stiff; not measured.)
* ``ballscrew_dahl``: the seed 001 elastic stage with Dahl sites (sliding nut), the paper
  controller (PTC feed-forward + dual PID + DOB), sinc compensation and sensors (encoder
  2^20 counts, 100 nm scale, their noise drawn as ``simulate_machine`` draws it: one
  ``default_rng(seed)``, encoder first). Six DOFs (``theta_m, theta_s, x_l, x_m, x_r,
  x_t``), ``M``/``K``/``D`` written out here from the plant's parameters (Rayleigh ``D =
  diag(B) + beta K``; checked against ``ElasticBallScrew.linear_chain``), two Dahl states
  ``dF/dt = sigma0 v (1 - F sgn(v) / Fc)``; 14 states. The PTC feed-forward and the
  compensation are precomputed arrays for both (as for the core).
* ``ballscrew_gms4``: the same stage with ``machines.gms4`` at the nut and the guide (GMS-4
  over an exponential Stribeck curve; 20 states), event-stepped like the GMS peer of
  ``benchmarks/peers.py`` (whose switch tests ``_gms_switch`` / ``_gms_grazing`` it imports):
  LSODA per sample on the smooth right-hand side of the current stick/slip flags; a breakaway,
  a reversal of a site with slipping elements, or a reversal of an all-sticking site with an
  element within reach of its breakaway (grazing) at the sample's end is located by LSODA
  calls over grids of ``LOC_GRID`` points to ``EVENT_TOL dt``, applied, and the sample
  finished from there.

Accuracy: errors are max |dq| of the position (EMPS: the axis; ball screw: the table ``x_t``)
and the change of the RMS tracking error (``qg - q`` / ``r - x_t``) against a reference: the
peer at ``REF_RTOL`` = 1e-11, cross-checked against frictionkit at 640 sub-steps (the brief's
reference). Decision (measured 2026-11-23): for EMPS the general loop at 640 sub-steps is
5.8e-10 m from both the one-DOF fast path (the run timed) and the peer at 1e-11, which agree
to 1.5e-12 m with each other — two independent exact-to-round-off solutions beat a converging
one; for the ball screw frictionkit at 640 sub-steps and the peer at 1e-11 agree to 7e-13 m.
The peer runs at the loosest ``rtol`` (``atol = rtol * ATOL_SCALE``) of ``TOLS`` (half decades)
whose two errors are both at or below ``max(frictionkit's, FLOOR_M)`` ("matching accuracy").
The ball screw's tolerance is matched with ideal sensors: with the paper's quantised, noisy
sensors a one-count flip of the 100 nm scale or the encoder moves a run by a few 1e-8 m at any
tolerance (2 s run: the peer at rtol 1e-3 ... 1e-11 is 3.3e-8 ... 5.2e-8 m from frictionkit at
640 sub-steps, not falling with the tolerance), so accuracy cannot be compared there; the run
with the paper sensors (the benchmark's workload) is then timed at that
tolerance (``ratio``), the ideal-sensor run too (``acc_ratio``). Ratio = peer time /
frictionkit time, measured interleaved in the same run, min of ``--repeat`` (wall time;
the calling thread's CPU time ratio beside it is the steadier number on a loaded machine).

Not done: a peer for the two-shaft drive (GMS-3 over Stribeck curves with delta 1.5: the
switch tests of benchmarks/peers.py assume delta 2).
"""

from __future__ import annotations

import argparse
import functools
import math
import os
import time

import numpy as np

try:
    import numba as nb
    from numbalsoda import lsoda, lsoda_sig
    MISSING = None
except ImportError as e:  # pragma: no cover - optional extra
    MISSING = f"numbalsoda missing ({e}); pip install -e .[bench]"

TOLS = tuple(float(f"{10 ** (-k / 2):.0e}") for k in range(6, 21))  # 1e-3, 3e-4, ... 1e-10
ATOL_SCALE = 1e-3   # atol = rtol * ATOL_SCALE (positions ~0.1 m / rad, velocities ~0.1 m/s)
LOC_GRID = 16       # points per LSODA call when locating a stop (EMPS) or a GMS switch
EVENT_TOL = 1e-9    # a stop / switch is located to EVENT_TOL * dt
REF_RTOL = 1e-11    # the reference: the peer at rtol 1e-11, atol 1e-14 (stops located to EVENT_TOL dt)
REF_SUBSTEPS = 640  # its cross-check: frictionkit at 640 sub-steps (EMPS: on the general loop)
#: Accuracy floor [m]: a peer matches when its errors are <= max(frictionkit's, FLOOR_M). Named
#: assumption: frictionkit's EMPS run is exact to round-off (piecewise-constant force on a
#: linear axis with located stops: 1.5e-12 m from the reference), which no affordable tolerance
#: of an ODE solver reaches; 0.1 nm is 1/1000 of the stage's 100 nm scale count and 1/500 of EMPS's
#: 50 nm encoder count.
FLOOR_M = 1e-10


def available() -> bool:
    return MISSING is None


def interleaved(fa, fb, repeat):
    """``(wall_a, wall_b, cpu_a, cpu_b)``: min wall times and min CPU times of the calling thread
    of ``fa`` and ``fb`` run alternately ``repeat`` times, after one warm-up each."""
    fa()
    fb()
    ta = tb = ca = cb = math.inf
    for _ in range(repeat):
        c0, t0 = time.thread_time(), time.perf_counter()
        fa()
        c1, t1 = time.thread_time(), time.perf_counter()
        fb()
        c2, t2 = time.thread_time(), time.perf_counter()
        ta, tb, ca, cb = min(ta, t1 - t0), min(tb, t2 - t1), min(ca, c1 - c0), min(cb, c2 - c1)
    return ta, tb, ca, cb


def _rms(x):
    return float(np.sqrt(np.mean(np.square(x))))


# --------------------------------------------------------------------------- compiled pieces
@functools.lru_cache(maxsize=None)
def _compiled():
    """Compile the right-hand sides and the loops once (numbalsoda needed)."""
    if MISSING:
        raise ImportError(MISSING)

    # ---- EMPS: data = [M, Fv, Fc, F_drive, s]; y = [q, v]; sliding in direction s
    @nb.cfunc(lsoda_sig)
    def emps_rhs(t, y, dy, p):
        dy[0] = y[1]
        dy[1] = (p[3] - p[2] * p[4] - p[1] * y[1]) / p[0]

    emps_ptr = emps_rhs.address

    @nb.njit
    def emps_advance(y, data, h, rtol, atol):
        """Advance the axis over one sample of length ``h`` with the drive force data[3]."""
        Fc = data[2]
        t = 0.0
        te = np.empty(2)
        grid = np.empty(LOC_GRID + 1)
        while t < h:
            if data[4] == 0.0:  # at rest: sticks while the drive force is within Fc
                F = data[3]
                if abs(F) <= Fc:
                    return True
                data[4] = 1.0 if F > 0.0 else -1.0
            s = data[4]
            te[0] = t
            te[1] = h
            us, ok = lsoda(emps_ptr, y, te, data=data, rtol=rtol, atol=atol, mxstep=100000)
            if not ok:
                return False
            if us[1, 1] * s > 0.0:
                y[0] = us[1, 0]
                y[1] = us[1, 1]
                return True
            # the velocity reached zero inside [t, h]: locate the stop
            ta, tb = t, h
            ya = y.copy()
            while tb - ta > EVENT_TOL * h:
                for i in range(LOC_GRID + 1):
                    grid[i] = ta + (tb - ta) * i / LOC_GRID
                us, ok = lsoda(emps_ptr, ya, grid, data=data, rtol=rtol, atol=atol, mxstep=100000)
                if not ok:
                    return False
                for i in range(1, LOC_GRID + 1):
                    if us[i, 1] * s <= 0.0:
                        ta, tb = grid[i - 1], grid[i]
                        ya[0] = us[i - 1, 0]
                        ya[1] = us[i - 1, 1]
                        break
            y[0] = ya[0]
            y[1] = 0.0
            data[4] = 0.0
            t = tb
        return True

    @nb.njit
    def emps_loop(qg, par, rtol, atol, q_out):
        """par = [M, Fv, Fc, offset, gtau, kp, kv, vmax, dt]. Returns True on success."""
        M, Fv, Fc, off, gtau, kp, kv, vmax, dt = par[0], par[1], par[2], par[3], par[4], par[5], par[6], par[7], par[8]
        data = np.array([M, Fv, Fc, 0.0, 0.0])
        y = np.zeros(2)
        qm_prev = 0.0
        qf_prev = 0.0
        nu_prev = 0.0  # the one-sample delay
        N = qg.size
        for k in range(N):
            q_out[k] = y[0]
            qm = y[0]
            qf = 0.5 * (qm + qm_prev)
            vf = (qf - qf_prev) / dt
            nu = kv * (kp * (qg[k] - qm) - vf)
            nu = min(max(nu, -vmax), vmax)
            u = nu_prev
            nu_prev = nu
            qm_prev = qm
            qf_prev = qf
            if k == N - 1:
                break
            data[3] = gtau * u - off
            if not emps_advance(y, data, dt, rtol, atol):
                return False
        return True

    # ---- ball screw: data = [tau_m, Fc_g, s0_g, Fc_n, s0_n, R, 1/m (6), K (36), D (36)]
    # y = [q (6), v (6), F_guide, F_nut]
    OM, OK_, OD = 6, 12, 48

    @nb.cfunc(lsoda_sig)
    def bs_rhs(t, y, dy, p):
        R = p[5]
        vg = y[11]
        vn = R * y[7]
        Fg = y[12]
        Fn = y[13]
        sg = 1.0 if vg > 0.0 else (-1.0 if vg < 0.0 else 0.0)
        sn = 1.0 if vn > 0.0 else (-1.0 if vn < 0.0 else 0.0)
        dy[12] = p[2] * vg * (1.0 - Fg * sg / p[1])
        dy[13] = p[4] * vn * (1.0 - Fn * sn / p[3])
        for i in range(6):
            f = 0.0
            for j in range(6):
                f -= p[OK_ + 6 * i + j] * y[j] + p[OD + 6 * i + j] * y[6 + j]
            if i == 0:
                f += p[0]
            elif i == 1:
                f -= R * Fn
            elif i == 5:
                f -= Fg
            dy[i] = y[6 + i]
            dy[6 + i] = f * p[OM + i]

    bs_ptr = bs_rhs.address

    @nb.njit
    def bs_control(k, th_m, x_t, ctl, cs, theta_d, u_ff, u_f, n_enc, n_scale):
        """The stage's controller at sample k (sensors, dual PID with conditional integration,
        DOB, PTC feed-forward, compensation, current limit); returns the applied current.
        ctl = [T, R, q_enc, q_scale, Kp, Ki, Kd, tau_d, K_dob, J_dob, B_dob, a_dob, i_max, K_tau];
        cs = [I, D, ed_{k-1}, DOB x0..x3 (enc_{k-1}, omega_{k-1}, d_{k-1}, u_f,{k-1}), i_{k-1}]."""
        T, R, qe, qs = ctl[0], ctl[1], ctl[2], ctl[3]
        Kp, Ki, Kd, taud = ctl[4], ctl[5], ctl[6], ctl[7]
        Kn, Jn, Bn, a, imax = ctl[8], ctl[9], ctl[10], ctl[11], ctl[12]
        enc = th_m + n_enc[k]
        if qe > 0.0:
            enc = math.floor(enc / qe) * qe
        sc = x_t + n_scale[k]
        if qs > 0.0:
            sc = math.floor(sc / qs) * qs
        e = theta_d[k] - sc / R
        ed = theta_d[k] - enc
        if k == 0:
            cs[2] = ed
        cs[1] = (taud * cs[1] + Kd * (ed - cs[2])) / (taud + T)
        cs[2] = ed
        u_pid = Kp * e + cs[0] + cs[1]
        d = a * cs[5] + (1.0 - a) * (Kn * (cs[7] - cs[6]) - (Bn + Jn / T) * (enc - cs[3]) / T + (Jn / T) * cs[4])
        cs[4] = (enc - cs[3]) / T
        cs[3] = enc
        cs[5] = d
        cs[6] = u_f[k]
        i = u_ff[k] + u_pid + d / Kn + u_f[k]
        sat = False
        if i > imax:
            i = imax
            sat = True
        elif i < -imax:
            i = -imax
            sat = True
        cs[7] = i
        if not sat:
            cs[0] += Ki * T * e
        return i

    @nb.njit
    def bs_loop(data, ctl, theta_d, u_ff, u_f, n_enc, n_scale, rtol, atol, xt_out, i_out):
        """The Dahl stage, one LSODA call per sample. Returns True on success."""
        T, Ktau = ctl[0], ctl[13]
        y = np.zeros(14)
        te = np.array([0.0, T])
        cs = np.zeros(8)
        N = theta_d.size
        for k in range(N):
            xt_out[k] = y[5]
            i = bs_control(k, y[0], y[5], ctl, cs, theta_d, u_ff, u_f, n_enc, n_scale)
            i_out[k] = i
            if k == N - 1:
                break
            data[0] = Ktau * i
            us, ok = lsoda(bs_ptr, y, te, data=data, rtol=rtol, atol=atol, mxstep=100000)
            if not ok:
                return False
            for r in range(14):
                y[r] = us[1, r]
        return True

    return emps_loop, bs_loop, bs_control


# ---- ball screw with a GMS at the nut and at the guide, event-stepped (issue 8 brief, item 3)
# data = [tau_m, R, 1/m (6), K (36), D (36), guide block, nut block]; each block in the layout of
# benchmarks/peers.py's GMS peer ([Fc, Fs, vs, sigma2, C, m, dt, N, M, k.., xi.., stick..]; m, dt,
# N unused) so that its switch tests (_gms_switch, _gms_grazing) are reused by import.
# y = [q (6), v (6), guide element forces (M), nut element forces (M)]
GMS_M = 4


@functools.lru_cache(maxsize=None)
def _compiled_gms():
    if MISSING:
        raise ImportError(MISSING)
    from peers import GMS_NP, _gms_grazing, _gms_switch

    M = GMS_M
    OM, OK_, OD = 2, 8, 44
    OB = 80                       # the guide block; the nut block follows
    NB_ = GMS_NP + 3 * M          # block length
    NY = 12 + 2 * M

    @nb.cfunc(lsoda_sig)
    def rhs(t, y, dy, p):
        R = p[1]
        Fg = 0.0
        Fn = 0.0
        for j in range(2):
            o = OB + j * NB_
            v = y[11] if j == 0 else R * y[7]
            r = v / p[o + 2]
            g = p[o] + (p[o + 1] - p[o]) * math.exp(-r * r)
            sg = 1.0 if v > 0.0 else (-1.0 if v < 0.0 else 0.0)
            F = p[o + 3] * v
            for i in range(M):
                Fi = y[12 + j * M + i]
                F += Fi
                if p[o + GMS_NP + 2 * M + i] != 0.0:
                    dy[12 + j * M + i] = p[o + GMS_NP + i] * v
                else:
                    dy[12 + j * M + i] = p[o + 4] * (p[o + GMS_NP + M + i] * sg - Fi / g)
            if j == 0:
                Fg = F
            else:
                Fn = F
        for i in range(6):
            f = 0.0
            for j in range(6):
                f -= p[OK_ + 6 * i + j] * y[j] + p[OD + 6 * i + j] * y[6 + j]
            if i == 0:
                f += p[0]
            elif i == 1:
                f -= R * Fn
            elif i == 5:
                f -= Fg
            dy[i] = y[6 + i]
            dy[6 + i] = f * p[OM + i]

    ptr = rhs.address

    @nb.njit
    def site_y(y, j, R, ys):
        """Site j's state in the peers' single-mass layout [x, v, F_0..F_{M-1}] (x unused)."""
        ys[0] = 0.0
        ys[1] = y[11] if j == 0 else R * y[7]
        for i in range(M):
            ys[2 + i] = y[12 + j * M + i]

    @nb.njit
    def event(ya, yb, data, h, grazing_ok, ys):
        """Whether a switch happened between states ya and yb (h apart): a breakaway at yb, a
        reversal of a site with slipping elements, or (grazing_ok) a reversal of an all-sticking
        site with an element within reach of its breakaway. Returns 0 none, 1 switch, 2 grazing."""
        R = data[1]
        out = 0
        for j in range(2):
            blk = data[OB + j * NB_:OB + (j + 1) * NB_]
            site_y(yb, j, R, ys)
            if _gms_switch(ys, blk, M) >= 0:
                return 1
            vb = ys[1]
            site_y(ya, j, R, ys)
            va = ys[1]
            if va * vb < 0.0:
                anyslip = False
                for i in range(M):
                    if blk[GMS_NP + 2 * M + i] == 0.0:
                        anyslip = True
                if anyslip:
                    return 1
                if grazing_ok and _gms_grazing(ys, blk, M, 2.0 * abs(va) * h):
                    out = 2
        return out

    @nb.njit
    def apply_switches(y, va_sites, data, ys):
        """At a located switch: a site whose velocity reversed with slipping elements sticks
        all its elements, then every element at its breakaway slips."""
        R = data[1]
        for j in range(2):
            blk = data[OB + j * NB_:OB + (j + 1) * NB_]
            site_y(y, j, R, ys)
            anyslip = False
            for i in range(M):
                if blk[GMS_NP + 2 * M + i] == 0.0:
                    anyslip = True
            if anyslip and ys[1] * va_sites[j] < 0.0:
                for i in range(M):
                    blk[GMS_NP + 2 * M + i] = 1.0
            while True:
                i = _gms_switch(ys, blk, M)
                if i < 0:
                    break
                blk[GMS_NP + 2 * M + i] = 0.0

    @nb.njit
    def advance(y, data, T, rtol, atol, ys, counts):
        """One sample of length T with the motor torque data[0]; switches located to EVENT_TOL T."""
        t = 0.0
        te = np.empty(2)
        tg = np.empty(LOC_GRID + 1)
        va_s = np.empty(2)
        R = data[1]
        while t < T:
            te[0] = t
            te[1] = T
            us, ok = lsoda(ptr, y, te, data=data, rtol=rtol, atol=atol, mxstep=100000)
            if not ok:
                return False
            ev = event(y, us[1], data, T - t, True, ys)
            if ev == 0:
                for r in range(NY):
                    y[r] = us[1, r]
                return True
            counts[0] += 1
            ya = y.copy()
            yb = us[1].copy()
            ta, tb = t, T
            while tb - ta > EVENT_TOL * T:
                for i in range(LOC_GRID + 1):
                    tg[i] = ta + (tb - ta) * i / LOC_GRID
                us, ok = lsoda(ptr, ya, tg, data=data, rtol=rtol, atol=atol, mxstep=100000)
                if not ok:
                    return False
                jj = LOC_GRID  # the end state, from a path of its own, may disagree by round-off
                for i in range(1, LOC_GRID + 1):
                    if event(us[i - 1], us[i], data, tg[i] - tg[i - 1], ev == 2, ys) != 0:
                        jj = i
                        break
                ta, tb = tg[jj - 1], tg[jj]
                ya = us[jj - 1].copy()
                yb = us[jj].copy()
            for j in range(2):
                site_y(ya, j, R, ys)
                va_s[j] = ys[1]
            apply_switches(yb, va_s, data, ys)
            for r in range(NY):
                y[r] = yb[r]
            t = tb
        return True

    bs_control = _compiled()[2]

    @nb.njit
    def loop(data, ctl, theta_d, u_ff, u_f, n_enc, n_scale, rtol, atol, xt_out, i_out):
        """As the Dahl loop, event-stepped; returns the number of located switches (-1: LSODA failed)."""
        T, Ktau = ctl[0], ctl[13]
        for j in range(2):  # every element sticks at rest
            for i in range(M):
                data[OB + j * NB_ + GMS_NP + 2 * M + i] = 1.0
        y = np.zeros(NY)
        ys = np.zeros(2 + M)
        counts = np.zeros(1, dtype=np.int64)
        cs = np.zeros(8)
        N = theta_d.size
        for k in range(N):
            xt_out[k] = y[5]
            i = bs_control(k, y[0], y[5], ctl, cs, theta_d, u_ff, u_f, n_enc, n_scale)
            i_out[k] = i
            if k == N - 1:
                break
            data[0] = Ktau * i
            if not advance(y, data, T, rtol, atol, ys, counts):
                return -1
        return counts[0]

    return loop, GMS_NP


# --------------------------------------------------------------------------- EMPS
def emps_setup(qg):
    """frictionkit's EMPS run (published model) and the peer's runner on the same reference."""
    import frictionkit as fk
    from frictionkit.presets.emps import EMPS_CONSTANTS as C, PUBLISHED as P, emps_machine

    m = emps_machine(M=P["M"], friction=fk.CoulombViscous(Fc=P["Fc"], sigma2=P["Fv"]), offset=P["offset"])
    par = np.array([P["M"], P["Fv"], P["Fc"], P["offset"], C["gtau"], C["kp"], C["kv"], C["vmax"], C["dt"]])
    emps_loop = _compiled()[0]

    def core(substeps):
        # as a user runs the preset (the one-DOF fast path; benchmarks/machines.py's emps_realtime);
        # the reference (REF_SUBSTEPS) on the general loop, as machines.py's EMPS rows
        return lambda: fk.simulate_machine(m, dt=C["dt"], inputs={"qg": qg}, substeps=substeps,
                                           fast_path=substeps != REF_SUBSTEPS)

    def peer(rtol):
        q = np.empty(qg.size)

        def run():
            if not emps_loop(qg, par, rtol, rtol * ATOL_SCALE, q):
                raise RuntimeError(f"EMPS peer: LSODA failed at rtol {rtol:g}")
            return q
        return run

    return core, peer


# --------------------------------------------------------------------------- ball screw
def ballscrew_matrices(plant):
    """``(1/m, K, D)`` of the six-DOF chain written out from the plant's parameters."""
    R = plant.R
    m = np.array([plant.J_m, plant.J_b, plant.M_b / 3, plant.M_b / 3, plant.M_b / 3, plant.M_t])
    K = np.zeros((6, 6))

    def spring(c, k):
        c = np.asarray(c, float)
        K[:] += k * np.outer(c, c)

    spring([1, -1, 0, 0, 0, 0], plant.k_o)           # coupling + torsion in series
    spring([0, 0, 1, 0, 0, 0], plant.k_bearing)      # left bearing set
    spring([0, 0, 0, 0, 1, 0], plant.k_bearing)      # right bearing set
    spring([0, 0, 1, -1, 0, 0], plant.k_axial)       # screw left of the nut
    spring([0, 0, 0, 1, -1, 0], plant.k_axial_right)  # screw right of the nut
    spring([0, R, 0, 1, 0, -1], plant.k_nut)         # ball-nut contact R theta_s + x_m - x_t
    # Rayleigh damping of the first elastic mode: beta = 2 zeta / omega_1 (undamped modes of M, K)
    w2 = np.linalg.eigvalsh(K / np.sqrt(np.outer(m, m)))
    w1 = math.sqrt(min(w for w in w2 if w > 1e-6 * max(w2)))
    beta = 2.0 * plant.damping_ratio / w1
    D = np.diag([plant.B_m, plant.B_b, 0, 0, 0, plant.C_t]) + beta * K
    return 1.0 / m, K, D


def ballscrew_setup(duration, seed=0, sensors=True, gms=None):
    """frictionkit's stage run (sliding nut, sinc compensation; Dahl sites, or ``gms(level)`` —
    a GMS with ``GMS_M`` elements — at the nut and the guide) and the peer's runner."""
    from frictionkit.control.loop import Sensors
    from frictionkit.control.trajectories import cosine_reference
    from frictionkit.plants.ballscrew import DAHL_SPAN
    from frictionkit.presets.ballscrew import simulate_stage
    from frictionkit.reproduce.zhu_fujimoto import (_classify, paper_compensator, paper_controller, paper_plant,
                                                    paper_sensors)

    plant, ctrl = paper_plant("sliding"), paper_controller()
    sens = paper_sensors() if sensors else Sensors(encoder_counts=0, scale_resolution=0.0)
    ref = cosine_reference(duration=duration)
    u_f = paper_compensator().signal(ref, "sinc", _classify(ref, plant))
    minv, K, D = ballscrew_matrices(plant)
    lc = plant.linear_chain()  # the check only: the peer's matrices are the plant's
    assert np.allclose(K, lc.K, rtol=1e-12, atol=0) and np.allclose(D, lc.D, rtol=1e-9, atol=0)
    assert np.allclose(1.0 / minv, np.diag(lc.M), rtol=1e-12)
    L = plant.presliding_length
    data = np.concatenate([[0.0, plant.guide_friction, DAHL_SPAN * plant.guide_friction / L,
                            plant.nut_friction, DAHL_SPAN * plant.nut_friction / L, plant.R], minv,
                           K.ravel(), D.ravel()])
    R, p, d = ctrl.R, ctrl.pid, ctrl.dob
    q_enc = sens.encoder_step
    ctl = np.array([ctrl.T, R, q_enc, sens.scale_resolution, p.Kp, p.Ki, p.Kd, p.tau_d, d.K_tau, d.J, d.B, d.a,
                    ctrl.i_max, plant.K_tau])
    theta_d_u = ctrl.ptc.feedforward(ref.x / R, ref.v / R)
    u_ff, theta_d = (np.ascontiguousarray(a, dtype=float) for a in theta_d_u)
    uf_a = np.ascontiguousarray(u_f / ctrl.ptc.K_tau, dtype=float)
    N = len(ref)
    # the core's draws (machines/simulate.py): one default_rng(seed), sensors in order, noisy ones only
    rng = np.random.default_rng(seed)
    n_enc = rng.standard_normal(N) * sens.encoder_noise_counts * q_enc if sens.encoder_noise_counts > 0 else np.zeros(N)
    n_sc = rng.standard_normal(N) * sens.scale_noise if sens.scale_noise > 0 else np.zeros(N)
    laws = {}
    if gms is None:
        loop = _compiled()[1]
    else:
        loop, gms_np = _compiled_gms()
        blocks = []
        for level in (plant.guide_friction, plant.nut_friction):
            law = gms(level)
            st = law.static
            if len(law.k) != GMS_M or getattr(st, "delta", 2.0) != 2.0 or st.shape != "exponential":
                raise ValueError("the GMS peer is written for GMS-4 over an exponential Stribeck curve, delta 2")
            blocks.append(np.concatenate([[st.Fc, st.Fs, st.vs, st.sigma2, law.C, 0.0, 0.0, 0.0, GMS_M],
                                          np.zeros(gms_np - 9), law.k, law.xi, np.ones(GMS_M)]))
            laws["guide_law" if not laws else "nut_law"] = law
        data = np.concatenate([[0.0, plant.R], minv, K.ravel(), D.ravel(), *blocks])
    switches = []

    def core(substeps):
        return lambda: simulate_stage(plant, ctrl, ref, compensation=u_f, sensors=sens, seed=seed, substeps=substeps,
                                      **laws)

    def peer(rtol):
        xt = np.empty(N)
        i = np.empty(N)

        def run():
            n = loop(data.copy(), ctl, theta_d, u_ff, uf_a, n_enc, n_sc, rtol, rtol * ATOL_SCALE, xt, i)
            if n is False or n < 0:
                raise RuntimeError(f"ball-screw peer: LSODA failed at rtol {rtol:g}")
            switches.append(int(n))
            return xt
        return run

    peer.switches = switches  # GMS: located switches per run
    return core, peer, ref.x


# --------------------------------------------------------------------------- matching and timing
def compare(name, acc, timed, target, core_pos, substeps, repeat, duration, fk_label=None):
    """Pick the peer's tolerance on the accuracy run ``acc`` and time the run ``timed``.

    ``acc`` / ``timed``: ``(core, peer)`` factories (``core(substeps)``, ``peer(rtol)`` -> a
    callable running the machine); ``core_pos(result)`` -> frictionkit's position array;
    ``target``: what the tracking error is taken to. Errors of frictionkit at ``substeps`` and
    of the peer per tolerance against frictionkit at REF_SUBSTEPS on ``acc``; the peer runs at
    the loosest tolerance whose max |dq| and |dRMS e| are both <= max(frictionkit's, FLOOR_M).
    ``timed`` (the benchmark's workload; may be ``acc``) is timed interleaved at that tolerance.
    """
    core, peer = acc
    ref = peer(REF_RTOL)()
    e_ref = _rms(target - ref)
    fk_pos = core_pos(core(substeps)())
    fk_dq = float(np.abs(fk_pos - ref).max())
    fk_drms = abs(_rms(target - fk_pos) - e_ref)
    rows = {}
    match = None
    for rtol in TOLS:
        try:
            q = peer(rtol)()
        except RuntimeError as e:
            rows[rtol] = {"failed": str(e)}
            continue
        dq = float(np.abs(q - ref).max())
        drms = abs(_rms(target - q) - e_ref)
        rows[rtol] = {"max_dq": dq, "d_rms": drms}
        if match is None and dq <= max(fk_dq, FLOOR_M) and drms <= max(fk_drms, FLOOR_M):
            match = rtol
    fk_ref = core_pos(core(REF_SUBSTEPS)())
    out = {"name": name, "substeps": substeps, "fk_label": fk_label or f"{substeps} sub", "duration_s": duration,
           "rms_tracking_error_ref": e_ref,
           "fk_max_dq": fk_dq, "fk_d_rms": fk_drms, "scan": {f"{k:.0e}": v for k, v in rows.items()},
           "fk_640_vs_ref_max_dq": float(np.abs(fk_ref - ref).max()), "peer_rtol": match}
    if match is None:
        return out
    out.update(peer_max_dq=rows[match]["max_dq"], peer_d_rms=rows[match]["d_rms"])
    runs = [("", acc)] if timed is acc else [("", timed), ("acc_", acc)]
    for pre, (core, peer) in runs:
        fk_run, peer_run = core(substeps), peer(match)
        t_fk, t_peer, c_fk, c_peer = interleaved(fk_run, peer_run, repeat)
        out.update({pre + "fk_s": t_fk, pre + "peer_s": t_peer, pre + "ratio": t_peer / t_fk,
                    pre + "ratio_cpu": c_peer / c_fk,
                    pre + "fk_rt": duration / t_fk, pre + "peer_rt": duration / t_peer,
                    pre + "peer_vs_fk_max_dq": float(np.abs(peer_run() - core_pos(fk_run())).max())})
    return out


def bench_emps(repeat, csv, substeps=40):
    qg = np.ascontiguousarray(np.loadtxt(csv, delimiter=",", skiprows=1, usecols=2))
    run = emps_setup(qg)
    return compare("EMPS, 1 ms", run, run, qg, lambda r: r.position("q"), substeps, repeat, (qg.size - 1) * 1e-3,
                   fk_label="(one-DOF fast path)")


def bench_ballscrew(duration, repeat, substeps=10, gms=None):
    ideal = ballscrew_setup(duration, sensors=False, gms=gms)
    paper = ballscrew_setup(duration, sensors=True, gms=gms)
    name = "ball screw, Dahl, sliding nut, 0.5 ms" if gms is None else "ball screw, GMS-4 at nut and guide, 0.5 ms"
    out = compare(name, ideal[:2], paper[:2], ideal[2], lambda res: res.x_t, substeps, repeat, duration)
    if gms is not None:  # located switches per peer run (last run of each: the timed tolerance)
        out["switches"] = {"ideal_sensors": ideal[1].switches[-1], "paper_sensors": paper[1].switches[-1]}
    return out


def run_all(duration, repeat, emps_csv, gms=None):
    """The peers' rows for ``benchmarks/machines.py``: ``{key: row}`` or ``{"skipped": why}``.
    ``gms(level)``: the GMS-4 of the ball-screw GMS workload (``machines.gms4``); None: not run."""
    if not available():
        return {"skipped": MISSING}
    out = {"emps_numbalsoda": bench_emps(repeat, emps_csv),
           "ballscrew_dahl_numbalsoda": bench_ballscrew(duration, repeat)}
    if gms is not None:
        out["ballscrew_gms4_numbalsoda"] = bench_ballscrew(duration, repeat, gms=gms)
    return out


def format_row(r) -> str:
    s = (f"  {r['name']}, {r['duration_s']:.1f} s: accuracy run: frictionkit {r['fk_label']} max|dq| "
         f"{r['fk_max_dq']:.2e} m, |dRMS e| {r['fk_d_rms']:.2e} m against the peer at rtol {REF_RTOL:.0e} "
         f"(frictionkit {REF_SUBSTEPS} sub is {r['fk_640_vs_ref_max_dq']:.1e} m from it)")
    if r["peer_rtol"] is None:
        return s + "\n    peer: no tolerance in " + ", ".join(f"{t:.0e}" for t in TOLS) + " matches"
    s += (f"\n    peer numbalsoda LSODA rtol {r['peer_rtol']:.0e} atol {r['peer_rtol'] * ATOL_SCALE:.0e}: max|dq| "
          f"{r['peer_max_dq']:.2e} m, |dRMS e| {r['peer_d_rms']:.2e} m (target <= max(frictionkit's, {FLOOR_M:.0e} m))")
    for pre, what in (("", "timed run" if "acc_ratio" not in r else "timed run (paper sensors)"),
                      ("acc_", "accuracy run (ideal sensors)")):
        if pre + "ratio" in r:
            s += (f"\n    {what}: peer {r[pre + 'peer_s']:.3f} s ({r[pre + 'peer_rt']:,.0f}x rt), frictionkit "
                  f"{r[pre + 'fk_s']:.3f} s ({r[pre + 'fk_rt']:,.0f}x rt) -> ratio {r[pre + 'ratio']:.2f} "
                  f"(CPU {r[pre + 'ratio_cpu']:.2f}); "
                  f"peer vs frictionkit max|dq| {r[pre + 'peer_vs_fk_max_dq']:.1e} m")
    return s


def main() -> None:
    from machines import EMPS_CSV, gms4

    ap = argparse.ArgumentParser()
    ap.add_argument("--quick", action="store_true")
    ap.add_argument("--repeat", type=int, default=3)
    ap.add_argument("--emps-csv", default=EMPS_CSV)
    ap.add_argument("--only", choices=("emps", "dahl", "gms4"), help="one peer only")
    args = ap.parse_args()
    if not available():
        print(f"machine peers: skipped ({MISSING})")
        return
    dur = 5.0 if args.quick else 20.0
    if args.only:
        out = {"emps": lambda: {"emps": bench_emps(args.repeat, args.emps_csv)},
               "dahl": lambda: {"dahl": bench_ballscrew(dur, args.repeat)},
               "gms4": lambda: {"gms4": bench_ballscrew(dur, args.repeat, gms=gms4)}}[args.only]()
    else:
        out = run_all(dur, args.repeat, args.emps_csv, gms=gms4)
    if "skipped" in out:
        print(f"machine peers: skipped ({out['skipped']})")
        return
    print(f"load average {os.getloadavg()[0]:.2f}")
    for r in out.values():
        print(format_row(r))
        if "switches" in r:
            print(f"    peer's located switches: {r['switches']}")
        for k, v in r["scan"].items():
            print(f"      rtol {k}: {v}")


if __name__ == "__main__":
    main()
