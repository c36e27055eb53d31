"""Strong compiled peers for the single-axis kernels (issue 15), measured in one run.

Run:  .venv/bin/python benchmarks/peers.py [--quick] [--only gms4,gms16]
Needs the ``bench`` extra (``pip install -e .[bench]``: numbalsoda, which builds LSODA from
Fortran source and needs Debian's ``gfortran``).

Workload: the stick–slip run of ``benchmarks/simulate.py`` (1 kg, ``u = 2 sin(pi t)`` N,
sampled at 4 kHz, 10 s; ``--quick``: 2 s) for LuGre (``example_lugre``), Dahl
(Fc 1 N, sigma0 1e5 N/m, sigma2 0.4 N s/m) and GMS-4 / GMS-16 (``example_gms``).

Peers, written the way a performance-minded engineer would:

* **numbalsoda LSODA** (compiled LSODA called from numba) with the model as a
  ``numba.cfunc`` right-hand side; the force is read from the sample array and
  interpolated linearly inside the right-hand side (as the kernels do). One call over all
  samples (LSODA's own dense output at the samples). Batch: the same call per parameter
  set in a ``prange`` loop.
* **GMS, event-stepped numbalsoda**: GMS is hybrid (stick/slip flags), so LSODA runs
  between switches on the smooth right-hand side of the current flags; switches
  (breakaway, velocity reversal while an element slips) are detected at the samples of
  each call, located to ``1e-6 dt`` from the last good sample (each locating call
  integrates over a grid of ``LOC_GRID`` = 16 points and keeps the first sub-interval with
  the switch: 5 cold LSODA starts where bisection took 20), applied, and the integration
  restarts there. Calls cover ``CHUNK`` = 256 samples; after a switch the next call covers
  ``CHUNK_AFTER`` = 8 samples, doubling back to 256 (switches come in bursts -- GMS-16
  breaks 15 elements away within 9 ms, and a sticking contact rings through grazing
  reversals -- and a switch discards the rest of its call: with 256-sample calls GMS-16 cost
  7.7 million right-hand-side calls, with this 0.5 million). All in one njit function.
  A reversal while every element sticks is located too when a sticking element is within
  reach of its breakaway (``_gms_grazing``): a breakaway just before the reversal is undone
  by the sample after it. Without that check (before 2026-11-23, gms) the peer missed the
  breakaway of element 13 0.09 ms before the reversal at t = 2.19712 s of the 10 s GMS-16 run
  and its max|dF| stalled at 9.2e-3 N for every rtol.

Accuracy: max |dx| and max |dF| against the ``solve_ivp`` LSODA twin at rtol 1e-11
(GMS with located events; ``reference_force_driven``). A peer is run at the loosest
rtol (1e-4 … 1e-11, atol = rtol * 1e-3 on the scaled states) whose errors are both at or
below the kernel's ("matching accuracy"); the ratio printed is peer time / kernel time
(> 1: frictionkit faster). Best of ``--repeat``. Nothing is asserted.
"""

from __future__ import annotations

import argparse
import math
import os
import time

import numpy as np

import frictionkit as fk
from frictionkit.simulation.inputs import example_gms, example_lugre, stick_slip_force
from frictionkit.simulation.reference import reference_force_driven

try:
    import numba as nb
    from numbalsoda import lsoda, lsoda_sig
except ImportError as e:  # pragma: no cover - optional extra
    raise SystemExit(f"benchmarks/peers.py needs the bench extra (pip install -e .[bench]): {e}")

DT = 2.5e-4
CHUNK = 256
CHUNK_AFTER = 8  # samples in the first LSODA call after a switch (doubling back to CHUNK)
EVENT_TOL = 1e-6
LOC_GRID = 16  # points per LSODA call when locating a GMS switch
TOLS = (1e-4, 1e-5, 1e-6, 1e-7, 1e-8, 1e-9, 1e-10, 1e-11)
#: LuGre / Dahl / batch peers: half decades (issue 15, fairness): with whole decades the peer ran at
#: up to 10x tighter rtol than the kernel's accuracy needs (the issue's table: rtol 3.2e-8 matched
#: where the decade grid picks 1e-8).
TOLS_HALF = tuple(t * f for t in TOLS[:-1] for f in (1.0, 10 ** -0.5)) + TOLS[-1:]


def best_of(fn, repeat):
    fn()
    best, out = math.inf, None
    for _ in range(repeat):
        t0 = time.perf_counter()
        out = fn()
        best = min(best, time.perf_counter() - t0)
    return best, out


def interleaved(fa, fb, repeat, clock=time.perf_counter):
    """Min times of ``fa`` and ``fb`` run alternately ``repeat`` times (a shared machine's load hits
    both alike; timing one after the other gave peer/kernel ratios 3.7x and 9.7x in two runs).
    ``clock``: ``time.process_time`` for single-threaded runs (CPU time: a preempted run does not
    count its wait; system time -- page faults -- still counts)."""
    fa()
    fb()
    ta = tb = math.inf
    for _ in range(repeat):
        t0 = clock()
        fa()
        t1 = clock()
        fb()
        t2 = clock()
        ta, tb = min(ta, t1 - t0), min(tb, t2 - t1)
    return ta, tb


def errors(x, F, ref):
    return float(np.abs(x - ref["x"]).max()), float(np.abs(F - ref["friction"]).max())


# --------------------------------------------------------------------------- LuGre / Dahl
# data layout: [Fc, Fs, vs, sigma0, sigma1, sigma2, m, dt, zscale, u_0, ..., u_{N-1}]
# state (x, v, zs) with zs = sigma0 z [N] so that one atol fits all three states' scales
LG_NP = 9


@nb.cfunc(lsoda_sig)
def _lugre_rhs(t, y, dy, p):
    Fc, Fs, vs, s0, s1, s2, m, dt = p[0], p[1], p[2], p[3], p[4], p[5], p[6], p[7]
    k = int(t / dt)
    # the input array has N = its length - LG_NP samples; clamp at the last interval
    n = int(p[8])
    if k > n - 2:
        k = n - 2
    if k < 0:
        k = 0
    th = t / dt - k
    u = p[LG_NP + k] * (1.0 - th) + p[LG_NP + k + 1] * th
    v = y[1]
    zsig = y[2]
    r = v / vs
    g = Fc + (Fs - Fc) * math.exp(-r * r)
    zd = v - abs(v) * zsig / g  # dz/dt with z = zsig / sigma0
    F = zsig + s1 * zd + s2 * v
    dy[0] = v
    dy[1] = (u - F) / m
    dy[2] = s0 * zd


LUGRE_PTR = _lugre_rhs.address


def lugre_data(Fc, Fs, vs, s0, s1, s2, m, u):
    return np.concatenate([[Fc, Fs, vs, s0, s1, s2, m, DT, u.size], u])


@nb.njit
def _lugre_forces(usol, data):
    """Friction force at the samples from the LSODA states."""
    Fc, Fs, vs, s1, s2 = data[0], data[1], data[2], data[4], data[5]
    N = usol.shape[0]
    F = np.empty(N)
    for i in range(N):
        v = usol[i, 1]
        r = v / vs
        g = Fc + (Fs - Fc) * math.exp(-r * r)
        zd = v - abs(v) * usol[i, 2] / g
        F[i] = usol[i, 2] + s1 * zd + s2 * v
    return F


@nb.njit
def lugre_single(data, t_eval, rtol, atol):
    usol, ok = lsoda(LUGRE_PTR, np.zeros(3), t_eval, data=data, rtol=rtol, atol=atol, mxstep=10**7)
    return usol[:, 0].copy(), _lugre_forces(usol, data), ok


@nb.njit(parallel=True)
def lugre_batch_sse(datas, t_eval, rtol, atol, target, out):
    """Per parameter set (row of ``datas``): sum of squared velocity errors against ``target``."""
    for j in nb.prange(datas.shape[0]):
        usol, ok = lsoda(LUGRE_PTR, np.zeros(3), t_eval, data=datas[j], rtol=rtol, atol=atol, mxstep=10**7)
        acc = 0.0
        for i in range(1, t_eval.size):
            d = usol[i, 1] - target[i]
            acc += d * d
        out[j] = acc if ok else np.inf


# --------------------------------------------------------------------------- GMS, event-stepped
# data layout: [Fc, Fs, vs, sigma2, C, m, dt, N, M, k_0..k_{M-1}, xi_0..xi_{M-1},
#               stick_0..stick_{M-1} (1.0/0.0), u_0 .. u_{N-1}]
# state (x, v, F_0, ..., F_{M-1}). Measured and not kept (gms, 2026-11-23): the slipping
# elements' direction frozen per mode instead of sgn(v) in the right-hand side (smooth between
# switches, ~35 % fewer calls) -- LSODA then missed its accuracy by 1e3-1e5 x rtol near the
# reversals at rtol 1e-7 / 1e-8 (GMS-4 max|dF| 5e-3 N, GMS-16 1.4e-2 N).
GMS_NP = 9


@nb.cfunc(lsoda_sig)
def _gms_rhs(t, y, dy, p):
    Fc, Fs, vs, s2, C, m, dt = p[0], p[1], p[2], p[3], p[4], p[5], p[6]
    n = int(p[7])
    M = int(p[8])
    off_u = GMS_NP + 3 * M
    k = int(t / dt)
    if k > n - 2:
        k = n - 2
    if k < 0:
        k = 0
    th = t / dt - k
    u = p[off_u + k] * (1.0 - th) + p[off_u + k + 1] * th
    v = y[1]
    r = v / vs
    g = Fc + (Fs - Fc) * math.exp(-r * r)
    sg = 1.0 if v > 0.0 else (-1.0 if v < 0.0 else 0.0)
    Ft = s2 * v
    for i in range(M):
        Fi = y[2 + i]
        Ft += Fi
        if p[GMS_NP + 2 * M + i] != 0.0:
            dy[2 + i] = p[GMS_NP + i] * v
        else:
            dy[2 + i] = C * (p[GMS_NP + M + i] * sg - Fi / g)
    dy[0] = v
    dy[1] = (u - Ft) / m


GMS_PTR = _gms_rhs.address


@nb.njit
def _gms_switch(y, data, M):
    """Index of the first switch condition met at state ``y`` (or -1): breakaway of element i
    (``sgn(v) F_i >= xi_i g``) returns i; a velocity reversal with slipping elements returns M."""
    Fc, Fs, vs = data[0], data[1], data[2]
    v = y[1]
    r = v / vs
    g = Fc + (Fs - Fc) * math.exp(-r * r)
    sg = 1.0 if v > 0.0 else (-1.0 if v < 0.0 else 0.0)
    for i in range(M):
        if data[GMS_NP + 2 * M + i] != 0.0 and sg * y[2 + i] >= data[GMS_NP + M + i] * g and sg != 0.0:
            return i
    return -1


@nb.njit
def _gms_grazing(y, data, M, reach):
    """Whether a sticking element could break away within a displacement ``reach`` of ``y``
    (its force ``F_i + k_i reach`` against ``xi_i min(Fc, Fs)``)."""
    glo = min(data[0], data[1])
    for i in range(M):
        if data[GMS_NP + 2 * M + i] != 0.0 and abs(y[2 + i]) + data[GMS_NP + i] * reach >= data[GMS_NP + M + i] * glo:
            return True
    return False


@nb.njit
def gms_event_stepped(data, N, rtol, atol, x_out, F_out):
    """Event-stepped LSODA over the whole record; returns (ok, number of switches)."""
    M = int(data[8])
    dt = data[6]
    s2 = data[3]
    y = np.zeros(2 + M)
    for i in range(M):
        data[GMS_NP + 2 * M + i] = 1.0
    x_out[0] = 0.0
    F_out[0] = 0.0
    t0 = 0.0
    k0 = 0  # last sample written
    nsw = 0
    chunk = CHUNK
    while k0 < N - 1:
        k1 = min(k0 + chunk, N - 1)
        # t_eval: t0 then the samples k0+1 .. k1
        te = np.empty(k1 - k0 + 1)
        te[0] = t0
        for i in range(1, k1 - k0 + 1):
            te[i] = (k0 + i) * dt
        usol, ok = lsoda(GMS_PTR, y, te, data=data, rtol=rtol, atol=atol, mxstep=10**7)
        if not ok:
            return False, nsw
        # first sample with a switch condition or a sign change of v with slipping elements
        anyslip = False
        for i in range(M):
            if data[GMS_NP + 2 * M + i] == 0.0:
                anyslip = True
        hit = -1
        grazing = False
        v0 = y[1]
        for i in range(1, te.size):
            if _gms_switch(usol[i], data, M) >= 0:
                hit = i
                break
            vp = usol[i - 1, 1] if i > 1 else v0
            if usol[i, 1] * vp < 0.0:
                if anyslip:
                    hit = i
                    break
                # every element sticks: a sticking element's force peaks at the reversal, so
                # a breakaway just before it is undone by the sample after it (grazing). If one
                # is within reach (the displacement to the turn is at most |v| dt), locate it.
                if _gms_grazing(usol[i - 1] if i > 1 else y, data, M, 2.0 * abs(vp) * (te[i] - te[i - 1])):
                    hit = i
                    grazing = True
                    break
        last = te.size - 1 if hit < 0 else hit - 1
        for i in range(1, last + 1):
            x_out[k0 + i] = usol[i, 0]
            Ft = s2 * usol[i, 1]
            for e in range(M):
                Ft += usol[i, 2 + e]
            F_out[k0 + i] = Ft
        if hit < 0:
            y = usol[te.size - 1].copy()
            t0 = te[te.size - 1]
            k0 = k1
            chunk = min(2 * chunk, CHUNK)
            continue
        # locate the switch between te[hit-1] and te[hit] to EVENT_TOL * dt: each LSODA call
        # restarts cold, so every call integrates from the last good state over a grid of
        # LOC_GRID points and keeps the first sub-interval with the switch (5 calls for 1e-6 dt
        # where bisection took 20)
        ya = usol[hit - 1].copy()
        y = usol[hit].copy()
        ta = te[hit - 1]
        tb = te[hit]
        va = ya[1]
        tg = np.empty(LOC_GRID + 1)
        while tb - ta > EVENT_TOL * dt:
            for j in range(LOC_GRID + 1):
                tg[j] = ta + (tb - ta) * j / LOC_GRID
            us, ok = lsoda(GMS_PTR, ya, tg, data=data, rtol=rtol, atol=atol, mxstep=10**7)
            j = LOC_GRID  # the end state, from a path of its own, may disagree by round-off
            for jj in range(1, LOC_GRID + 1):
                ym = us[jj]
                if _gms_switch(ym, data, M) >= 0 or ((anyslip or grazing) and ym[1] * va < 0.0):
                    j = jj
                    break
            ta = tg[j - 1]
            tb = tg[j]
            ya = us[j - 1].copy()
            y = us[j].copy()
        if anyslip and y[1] * va < 0.0:
            for i in range(M):
                data[GMS_NP + 2 * M + i] = 1.0
        while True:
            i = _gms_switch(y, data, M)
            if i < 0:
                break
            data[GMS_NP + 2 * M + i] = 0.0
        nsw += 1
        chunk = CHUNK_AFTER  # switches come in bursts: short calls, doubling back to CHUNK
        t0 = tb
        k0 = k0 + hit - 1
        if tb >= (k0 + 1) * dt - 1e-12 * dt:
            # landed on the sample itself: record it and move on
            k0 += 1
            x_out[k0] = y[0]
            Ft = s2 * y[1]
            for e in range(M):
                Ft += y[2 + e]
            F_out[k0] = Ft
    return True, nsw


def gms_data(model, m, u):
    st = model.static
    return np.concatenate([[st.Fc, st.Fs, st.vs, st.sigma2, model.C, m, DT, u.size, len(model.k)],
                           np.asarray(model.k, float), np.asarray(model.xi, float), np.ones(len(model.k)), u])


# --------------------------------------------------------------------------- runs
def matched(run, ex, eF, ref, tols=TOLS):
    """Loosest rtol whose errors are both <= (ex, eF); returns (rtol, dx, dF) or None."""
    for rtol in tols:
        x, F, ok = run(rtol)
        if not ok:
            continue
        dx, dF = errors(x, F, ref)
        if dx <= ex and dF <= eF:
            return rtol, dx, dF
    return None


def single(name, model, m, u, data, run_peer, repeat, tols=TOLS, clock=time.perf_counter):
    t_k, res = best_of(lambda: fk.simulate(model, plant=fk.Mass(m), force=u, dt=DT), repeat)
    ref = reference_force_driven(model, m, u, DT, method="LSODA", rtol=1e-11, atol=1e-13)
    ex, eF = errors(res.x, res.friction, ref)
    N = u.size
    print(f"\n== {name}: kernel {t_k * 1e3:7.2f} ms ({t_k / (N - 1) * 1e9:5.1f} ns/sample, "
          f"{res.substeps / (N - 1):.2f} sub-steps/sample)  max|dx| {ex * 1e6:.3f} um  max|dF| {eF:.2e} N")
    mt = matched(run_peer, ex, eF, ref, tols)
    if mt is None:
        print(f"   peer did not reach the kernel's accuracy at rtol >= {tols[-1]:g}")
        return {"model": name, "kernel_s": t_k, "ratio": None}
    rtol, dx, dF = mt
    t_k, t_p = interleaved(lambda: fk.simulate(model, plant=fk.Mass(m), force=u, dt=DT), lambda: run_peer(rtol), repeat,
                           clock)
    what = "CPU" if clock is time.process_time else "wall"
    print(f"   peer at rtol {rtol:.3g}: {t_p * 1e3:7.2f} ms  max|dx| {dx * 1e6:.3f} um  max|dF| {dF:.2e} N"
          f"  -> ratio peer/kernel {t_p / t_k:.2f} (min {what} of {repeat} interleaved pairs: kernel {t_k * 1e3:.2f} ms)")
    # and the peer at its loosest tolerance that is at least as accurate in x only
    return {"model": name, "kernel_s": t_k, "peer_s": t_p, "ratio": t_p / t_k, "kernel_err": (ex, eF),
            "peer_err": (dx, dF), "peer_rtol": rtol}


def main() -> None:
    ap = argparse.ArgumentParser()
    ap.add_argument("--quick", action="store_true", help="2 s instead of 10 s, 200 batch sets")
    ap.add_argument("--repeat", type=int, default=None)
    ap.add_argument("--only", default="lugre,dahl,gms4,gms16,batch",
                    help="comma-separated subset of lugre, dahl, gms4, gms16, batch (default: all)")
    args = ap.parse_args()
    only = {w.strip().lower() for w in args.only.split(",") if w.strip()}
    unknown = only - {"lugre", "dahl", "gms4", "gms16", "batch"}
    if unknown:
        ap.error(f"--only: unknown part(s) {sorted(unknown)}; choose from lugre, dahl, gms4, gms16, batch")
    repeat = args.repeat or (3 if args.quick else 10)
    duration = 2.0 if args.quick else 10.0
    u = stick_slip_force(duration=duration, dt=DT)
    N = u.size
    t_eval = np.arange(N) * DT
    print(f"stick-slip run {duration:g} s at 4 kHz ({N} samples), cores {os.cpu_count()}, "
          f"load average {os.getloadavg()[0]:.1f}")
    rows = []

    lg = example_lugre()
    st = lg.static
    d = lugre_data(st.Fc, st.Fs, st.vs, lg.sigma0, lg.sigma1, st.sigma2, 1.0, u)
    if "lugre" in only:
        # LuGre / Dahl (issue 15): CPU time, 3x the repeats (a ~1-2 ms run: min of 10 wall-clock pairs
        # spread ~15 % between quiet runs), half-decade peer tolerances
        rows.append(single("LuGre", lg, 1.0, u, d, lambda r: lugre_single(d, t_eval, r, r * 1e-3), 3 * repeat,
                           TOLS_HALF, time.process_time))

    if "dahl" in only:
        dahl = fk.Dahl(Fc=1.0, sigma0=1e5, sigma2=0.4)
        dd = lugre_data(1.0, 1.0, 1.0, dahl.sigma0, 0.0, dahl.sigma2, 1.0, u)  # g = Fc: Fs = Fc
        rows.append(single("Dahl", dahl, 1.0, u, dd, lambda r: lugre_single(dd, t_eval, r, r * 1e-3), 3 * repeat,
                           TOLS_HALF, time.process_time))

    for M in (4, 16):
        if f"gms{M}" not in only:
            continue
        gm = example_gms(M)
        gd = gms_data(gm, 1.0, u)

        def run_g(r, gd=gd):
            x, F = np.empty(N), np.empty(N)
            ok, _ = gms_event_stepped(gd.copy(), N, r, r * 1e-3, x, F)
            return x, F, ok

        # CPU time (issue 15, gms15): both sides run single-threaded, and under a shared machine's load
        # the wall-clock minimum of 3 pairs swung the GMS-4 ratio 2.3-5.4 between runs
        rows.append(single(f"GMS-{M}", gm, 1.0, u, gd, run_g, repeat, clock=time.process_time))

    # ------------------------------------------------------------------ batch
    if "batch" not in only:
        _summary(rows, None, None)
        return
    P = 200 if args.quick else 1000
    print(f"\n== batch: {P} LuGre parameter sets (the sets of benchmarks/simulate.py), 1 kg, error norm only")
    rng = np.random.default_rng(0)
    target = fk.simulate(lg, plant=fk.Mass(1.0), force=u, dt=DT).v
    s0s, s1s = rng.uniform(5e4, 2e5, P), rng.uniform(20.0, 100.0, P)
    sets = [fk.LuGre(st, sigma0=a, sigma1=b) for a, b in zip(s0s, s1s)]
    datas = np.stack([lugre_data(st.Fc, st.Fs, st.vs, a, b, st.sigma2, 1.0, u) for a, b in zip(s0s, s1s)])
    # worst-case position error over a sample of sets against their tight twins
    probe = list(range(0, P, P // 8))[:8]
    refs = [reference_force_driven(sets[j], 1.0, u, DT, method="LSODA", rtol=1e-11, atol=1e-13) for j in probe]

    def worst_kernel(**kw):
        w = 0.0
        for j, ref in zip(probe, refs):
            r = fk.simulate(sets[j], plant=fk.Mass(1.0), force=u, dt=DT, **kw)
            w = max(w, float(np.abs(r.x - ref["x"]).max()))
        return w

    def batch_time(fn):
        t, _ = best_of(fn, max(2, repeat // 3))
        return P / t

    wk = worst_kernel()
    rate_k = batch_time(lambda: fk.simulate_batch(sets, masses=1.0, force=u, dt=DT, target=target, compare="v"))
    print(f"   simulate_batch adaptive: {rate_k:8,.0f} sets/s   worst max|dx| over {len(probe)} probed sets "
          f"{wk * 1e6:.3f} um")
    rate_p, wp, rtol_p = None, None, None
    for rtol in TOLS_HALF:
        w = 0.0
        for j, ref in zip(probe, refs):
            x, F, ok = lugre_single(datas[j], t_eval, rtol, rtol * 1e-3)
            w = max(w, float(np.abs(x - ref["x"]).max()))
        if w <= wk:
            out = np.empty(P)
            t_k, t_p = interleaved(
                lambda: fk.simulate_batch(sets, masses=1.0, force=u, dt=DT, target=target, compare="v"),
                lambda: lugre_batch_sse(datas, t_eval, rtol, rtol * 1e-3, target, out), max(2, repeat // 3))
            rate_k, rate_p = P / t_k, P / t_p
            wp, rtol_p = w, rtol
            break
    if rate_p is None:
        print("   numbalsoda prange did not reach the kernel's worst-case accuracy")
    else:
        print(f"   numbalsoda prange rtol {rtol_p:.3g}: {rate_p:8,.0f} sets/s   worst max|dx| {wp * 1e6:.3f} um"
              f"   -> ratio kernel/peer {rate_k / rate_p:.2f} (interleaved: kernel {rate_k:,.0f} sets/s)")

    _summary(rows, rate_k, rate_p)


def _summary(rows, rate_k, rate_p):
    print("\nsummary (peer time / kernel time at matching accuracy; > 1: frictionkit faster)")
    for r in rows:
        print(f"  {r['model']:7s} " + ("n/a" if r["ratio"] is None else f"x{r['ratio']:.2f}"))
    if rate_p is not None:
        print(f"  batch   x{rate_k / rate_p:.2f}")


if __name__ == "__main__":
    main()
