"""Issue 13 ("0 silent wrong answers"): random LuGre/Dahl runs, batches and machines against their twins.

Run:  .venv/bin/python benchmarks/robustness_lugre.py --part a|b|c|d --seeds FIRST STOP --out cases.jsonl
      .venv/bin/python benchmarks/robustness_lugre.py --summary cases.jsonl [more.jsonl ...]

Every case is classified against its twin and written as one JSON line (appended, so runs can be split
and resumed): ``passed-right`` / ``passed-WRONG`` (status 0 but outside the error bound) /
``flagged-right`` / ``flagged-wrong`` (status != 0 although the unchecked run was within the bound: a
false alarm) / ``error`` (an exception: a bug too, with its traceback) / ``twin-timeout``.

* ``a`` -- ``fk.simulate`` of one LuGre (70 %) or Dahl set on a mass: m 1e-3-1e2 kg, sigma0 1e3-1e8 N/m,
  omega dt = sqrt(sigma0/m) dt 0.1-100, sigma1 0 (10 %) or 0-2x critical, Fs/Fc 1-2, vs 1e-5-1e-2 m/s,
  sigma2 0 (15 %) or 1e-2-10; inputs by seed: sine, step, ramp above breakaway and down to stick,
  staircase, random-phase multisine, a force ramped to exactly Fs and held; 40 % of the runs at a random
  rtol 1e-8-1e-4 (atol_F left at its default). Twin: ``reference_force_driven`` (LSODA, rtol 1e-12, atol
  1e-16, steps <= dt/4 and <= 1/16 of the pre-sliding period). Bound: the README's error contract, 10 rtol
  of the twin's range of x and of the friction. A flagged run is judged by its unchecked run.
* ``b`` -- ``fk.simulate_batch`` (adaptive; every third batch ``method="fixed"``) of 3-5 sets sharing dt
  and the input, half "risky" (omega dt 0.2-20, damping ratio 1e-3-2), half easy. Each set's RMS error
  is the batch's own sse with the set's twin trace as the target (compare x, then F). Bound: adaptive
  10 rtol of the range (x and F); fixed: 0.25 % of the position range (the fixed method's measured
  accuracy within ``FIXED_RING_LIMITS_BELOW`` / ``_ABOVE``; the friction is reported, not judged).
* ``c`` -- ``fk.simulate_machine``: seeds 0, 1 mod 4 random open-loop 1-3 DOF chains (springs 1e4-1e7 N/m,
  LuGre/Dahl/GMS/Stribeck sites on a DOF or between two) against ``reference_machine`` (rtol 1e-10); 2 mod
  4 the same with a PID on the first DOF's position against the general loop at 160 sub-steps; 3 mod 4
  the EMPS preset (mass x0.1-3, friction levels x0.5-2, five law families; against 640 sub-steps) and the
  open-loop elastic ball screw (masses, stiffnesses and friction levels x0.3-3; Dahl/LuGre/GMS nut;
  against ``reference_machine``). Bound: the sub-step check's (``machines/simulate.py``), 1 % of each
  position's range and 10 % of each velocity's and site force's.
* ``d`` -- zhang2023's two-shaft drive with perturbed assumptions (:func:`case_d`), bound as ``c``.

First campaign (helper lugw2, 2026-11-24; a 0-190, b 0-32, c 0-100, d 0-24): a: 187 runs, 4 passed-WRONG
-- seed 40 (a single-sample step across a velocity peak, 16 rtol of the friction range at every rtol) and
seeds 49, 71 (overdamped LuGre, friction 10-15 rtol) fixed in ``kernels/lugre.py`` (reproducers in
``tests/robustness/test_passed_wrong.py``); seed 163 (LuGre, omega dt 0.30, damping ratio 0.31, rtol 9.6e-7
with the default atol_F: x 10.2 rtol of its range; 1.1 rtol at rtol 1e-5, 5.9 with atol_F = rtol) and
seeds 49/71 at their tight rtol are the atol_F-does-not-follow-rtol pattern (strict xfail there); 22
flagged-wrong (the accuracy check's false alarms: unchecked run within 10 rtol). 90 of them (seeds
100-190) ran on the fixed kernel: 1 passed-WRONG (163). b: 120 sets in 32 batches (seeds 23-32 on the fixed
kernel), adaptive all right; fixed method: one set over the 0.25 % -- seed 26 set 2, an undamped Dahl
(sigma0 1e8 N/m, 13.8 kg, omega h = 0.20 at 2 sub-steps, below FIXED_STEP_LIMIT = 0.5): RMS 0.34 % of its
position and 4.3 % of its friction range at status 0 (that limit's 0.25 % was measured on damped LuGre
sets); seeds 11 and 20: 0.05 % and 0.19 % of the position range, friction 0.47 % and 0.33 %. c: 102
machines (7 ball-screw cases rerun after a script error), none passed-WRONG. d: 24 two-shaft drives, 1
passed-WRONG -- seed 15, a hunting limit cycle whose support and ball-load frictions stay 13-20 % of their
range apart at every sub-step count while the loop check said "the run converges" (it compared positions,
velocities and commands only): now status 2 (``machines/stability.py``,
``tests/robustness/test_passed_wrong_machines.py``); 433 cases in all.

Round 11 (helper lug13, 2026-11-24; new seeds a 400-559, b 40-69): a: 160 runs, 1 passed-WRONG -- seed 519,
an overdamped LuGre (damping ratio 1.35, m/c 0.17 ms) at dt 36 ms under a staircase whose first level is on
at t = 0: x 3e-5 of its range off (2,360 rtol) at every rtol 1e-5 ... 1.3e-8; the spanning step from rest
saw no slip and its error estimate's nodes all fell after the transient. Fixed in ``kernels/lugre.py``
(an unbalanced force at exact rest takes an ROS2 interval; ``tests/robustness/test_passed_wrong_round11.py``);
now flagged (step-size underflow from rest at the default velocity tolerance). On the final code: 117
passed-right, 37 flagged-right, 6 flagged-wrong, 0 passed-WRONG. b: 123 sets in 30 batches: 103
passed-right, 7 flagged-right, 0 flagged-wrong, 0 passed-WRONG; 13 of the 41 fixed-method sets carry
status 4 under the new limits by damping ratio (``FIXED_RING_LIMITS_BELOW`` / ``_ABOVE``,
``benchmarks/fixed_step_limits.py``), the 28 others are within 0.048 % of their stroke (RMS). The
accuracy check's false alarms: a third run at rtol/100 near the bound (``CHECK_NEAR``): part a seeds
0-189 + 400-559 flagged-wrong 30 -> 16 with flagged-right 63 -> 63 (none beyond the contract passes);
b seeds 40-69 flagged-wrong 3 -> 0 (``tests/robustness/test_check_near_bound.py``). c, d: not rerun.
"""
from __future__ import annotations

import argparse
import json
import math
import signal
import time
import traceback
import warnings

import numpy as np

import frictionkit as fk
from frictionkit.simulation import core
from frictionkit.simulation.reference import reference_force_driven

TWIN_S = 90  # seconds per twin (assumption: LSODA at rtol 1e-12 on <= 600 samples; slower ones are skipped)


class Timeout(Exception):
    pass


def _alarm(signum, frame):
    raise Timeout()


signal.signal(signal.SIGALRM, _alarm)


def bounded(fn, seconds=TWIN_S):
    signal.alarm(seconds)
    try:
        return fn()
    finally:
        signal.alarm(0)


def errs(x, v, F, tw):
    out = {}
    for name, a in (("x", x), ("v", v), ("friction", F)):
        b = tw[name]
        out[name] = float(np.max(np.abs(a - b)) / max(np.ptp(b), 1e-300))
    return out


# --------------------------------------------------------------------------- inputs
def make_input(rng, shape, n, Fs, Fc):
    k = np.arange(n)
    if shape == "sine":
        amp = Fs * 10 ** rng.uniform(np.log10(0.3), np.log10(3))
        return amp * np.sin(2 * np.pi * rng.uniform(1, 3) * k / n), dict(amp=amp)
    if shape == "step":
        lvl = Fs * 10 ** rng.uniform(np.log10(0.3), np.log10(3)) * rng.choice([-1, 1])
        at = int(rng.integers(1, n // 3))
        u = np.where(k >= at, lvl, 0.0)
        return u, dict(lvl=lvl, at=at)
    if shape == "ramp_stick":  # ramp above breakaway, then down below Fc -> sticks
        peak = Fs * rng.uniform(1.1, 3)
        low = Fc * rng.uniform(0.0, 0.8)
        a, b = n // 3, 2 * n // 3
        u = np.interp(k, [0, a, b, n - 1], [0, peak, low, low])
        return u, dict(peak=peak, low=low)
    if shape == "staircase":
        levels = Fs * rng.uniform(-2.0, 2.0, size=6)
        u = levels[np.minimum(k * 6 // n, 5)]
        return u, dict(levels=levels.tolist())
    if shape == "multisine":
        f = rng.uniform(0.5, 8, size=4)
        ph = rng.uniform(0, 2 * np.pi, size=4)
        u = sum(np.sin(2 * np.pi * fi * k / n + p) for fi, p in zip(f, ph))
        u = u / np.max(np.abs(u)) * Fs * rng.uniform(0.5, 2.5)
        return u, dict(f=f.tolist())
    if shape == "hold_Fs":  # ramp to exactly the breakaway level and hold it
        a = int(rng.integers(2, n // 3))
        u = np.minimum(k / a, 1.0) * Fs
        return u, dict(at=a)
    raise ValueError(shape)


SHAPES = ("sine", "step", "ramp_stick", "staircase", "multisine", "hold_Fs")


def rand_law(rng, m, kind=None, wdt_range=(-1, 2)):
    kind = kind or ("dahl" if rng.random() < 0.3 else "lugre")
    Fc = 10 ** rng.uniform(-1, 1)
    Fs = Fc * rng.uniform(1.0, 2.0)
    vs = 10 ** rng.uniform(-5, -2)
    sigma2 = 10 ** rng.uniform(-2, 1) if rng.random() < 0.85 else 0.0
    sigma0 = 10 ** rng.uniform(3, 8)
    wdt = 10 ** rng.uniform(*wdt_range)
    dt = wdt / math.sqrt(sigma0 / m)
    if kind == "dahl":
        law = fk.Dahl(Fc=Fc, sigma0=sigma0, sigma2=sigma2)
        Fs = Fc
        s1 = 0.0
    else:
        crit = 2 * math.sqrt(sigma0 * m)
        r = rng.random()
        s1 = 0.0 if r < 0.1 else crit * (rng.uniform(0, 2) if r < 0.5 else 10 ** rng.uniform(-3, np.log10(2)))
        law = fk.LuGre(fk.Stribeck(Fc=Fc, Fs=Fs, vs=vs, sigma2=sigma2), sigma0=sigma0, sigma1=s1)
    p = dict(kind=kind, Fc=Fc, Fs=Fs, vs=vs, sigma2=sigma2, sigma0=sigma0, sigma1=s1, m=m, dt=dt, wdt=wdt,
             zeta=(s1 + sigma2) / (2 * math.sqrt(sigma0 * m)))
    return law, p, Fs, Fc, dt


def twin_of(law, m, u, dt, p):
    period = 2 * np.pi / math.sqrt(p["sigma0"] / m)
    return bounded(lambda: reference_force_driven(law, m, u, dt, rtol=1e-12, atol=1e-16,
                                                  max_step=min(dt / 4, period / 16)))


def case_a(seed):
    rng = np.random.default_rng(10_000 + seed)
    m = 10 ** rng.uniform(-3, 2)
    law, p, Fs, Fc, dt = rand_law(rng, m)
    n = int(rng.integers(120, 260))
    shape = SHAPES[seed % len(SHAPES)]
    u, ip = make_input(rng, shape, n, Fs, Fc)
    if rng.random() < 0.4:
        opts = fk.SimOptions(rtol=10 ** rng.uniform(-8, -4))
    else:
        opts = fk.SimOptions()
    p.update(shape=shape, n=n, rtol=opts.rtol, input=ip)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", RuntimeWarning)
        t0 = time.process_time()
        res = fk.simulate(law, dt=dt, plant=fk.Mass(m), force=u, options=opts)
        cpu = time.process_time() - t0
        kind, pk = core._pack(law)
        raw = core._force_run(kind, pk, u, dt, m, 0.0, 0.0, None, opts, core._f_scale(pk.static), law, warn=False)
    tw = twin_of(law, m, u, dt, p)
    e_raw = errs(raw.x, raw.v, raw.friction, tw) if raw.status == 0 else None
    out = dict(part="a", seed=seed, params=p, status=res.status, msg=res.message[:160], cpu=cpu,
               per_sample=res.substeps / (n - 1), raw_status=raw.status, raw_err=e_raw)
    bound = 10 * opts.rtol
    if res.status == 0:
        e = errs(res.x, res.v, res.friction, tw)
        out["err"] = e
        out["class"] = "passed-right" if e["x"] <= bound and e["friction"] <= bound else "passed-WRONG"
    else:
        if e_raw is None:
            out["class"] = "flagged-right"  # the unchecked run failed itself
        else:
            out["class"] = "flagged-wrong" if e_raw["x"] <= bound and e_raw["friction"] <= bound else "flagged-right"
    return out


# --------------------------------------------------------------------------- batch
def case_b(seed):
    rng = np.random.default_rng(20_000 + seed)
    P = int(rng.integers(3, 6))
    # a shared dt; each set's sigma0 picked from its own omega dt
    dt = 10 ** rng.uniform(-5, -3)
    method = "fixed" if seed % 3 == 2 else "adaptive"
    kind = "dahl" if rng.random() < 0.3 else "lugre"
    laws, ms, ps = [], [], []
    for j in range(P):
        m = 10 ** rng.uniform(-3, 2)
        risky = rng.random() < 0.5
        wdt = 10 ** (rng.uniform(-0.7, 1.3) if risky else rng.uniform(-2, -0.8))
        sigma0 = (wdt / dt) ** 2 * m
        if not 1e3 <= sigma0 <= 1e8:
            sigma0 = float(np.clip(sigma0, 1e3, 1e8))
        Fc = 1.0 * 10 ** rng.uniform(-0.3, 0.3)
        Fs = Fc * rng.uniform(1, 1.8)
        crit = 2 * math.sqrt(sigma0 * m)
        zr = 10 ** rng.uniform(-3, 0.3) if risky else rng.uniform(0.3, 1.5)
        sigma2 = 10 ** rng.uniform(-2, 0.5)
        if kind == "dahl":
            law = fk.Dahl(Fc=Fc, sigma0=sigma0, sigma2=sigma2)
            s1 = 0.0
        else:
            s1 = zr * crit
            law = fk.LuGre(fk.Stribeck(Fc=Fc, Fs=Fs, vs=10 ** rng.uniform(-5, -2), sigma2=sigma2), sigma0=sigma0,
                           sigma1=s1)
        laws.append(law)
        ms.append(m)
        ps.append(dict(m=m, sigma0=sigma0, sigma1=s1, sigma2=sigma2, Fc=Fc, Fs=Fs, wdt=math.sqrt(sigma0 / m) * dt,
                       zeta=(s1 + sigma2) / crit, risky=risky))
    n = int(rng.integers(150, 260))
    shape = SHAPES[seed % len(SHAPES)]
    u, ip = make_input(rng, shape, n, 1.5, 1.0)
    opts = fk.SimOptions() if rng.random() < 0.7 else fk.SimOptions(rtol=10 ** rng.uniform(-7, -4))
    rows = []
    for j in range(P):
        p = dict(ps[j], kind=kind, dt=dt, n=n, shape=shape, method=method, rtol=opts.rtol)
        try:
            tw = twin_of(laws[j], ms[j], u, dt, dict(sigma0=ps[j]["sigma0"]))
        except Timeout:
            rows.append(dict(part="b", seed=seed, set=j, params=p, **{"class": "twin-timeout"}))
            continue
        rms = {}
        st = None
        with warnings.catch_warnings():
            warnings.simplefilter("ignore", RuntimeWarning)
            for name, cmp in (("x", "x"), ("friction", "F")):
                b = fk.simulate_batch(laws, masses=ms, force=u, dt=dt, target=tw[name], compare=cmp,
                                      options=opts, method=method)
                st = int(b.status[j])
                rms[name] = float(b.rms[j] / max(np.ptp(tw[name]), 1e-300))
        row = dict(part="b", seed=seed, set=j, params=p, status=st, err_rms=rms, msg=b.message[:160])
        if st == 0:
            if method == "adaptive":
                bound = 10 * opts.rtol
            else:
                bound = 2.5e-3  # FIXED_STEP_LIMIT's measured 0.25 % of the stroke (RMS) below 0.5
            row["bound"] = bound
            okF = rms["friction"] <= bound or method == "fixed"  # fixed: documented for x only
            row["class"] = "passed-right" if rms["x"] <= bound and okF else "passed-WRONG"
        else:
            # the set alone, unchecked
            kind_, pk = core._pack(laws[j])
            raw = core._force_run(kind_, pk, u, dt, ms[j], 0.0, 0.0, None, opts, core._f_scale(pk.static), laws[j],
                                  warn=False)
            if raw.status != 0 or method == "fixed":
                row["class"] = "flagged-right" if raw.status != 0 else "flagged(fixed)"
                if raw.status == 0:
                    e = errs(raw.x, raw.v, raw.friction, tw)
                    row["raw_err"] = e
            else:
                e = errs(raw.x, raw.v, raw.friction, tw)
                row["raw_err"] = e
                row["class"] = ("flagged-wrong" if e["x"] <= 10 * opts.rtol and e["friction"] <= 10 * opts.rtol
                                else "flagged-right")
        rows.append(row)
    return rows


# --------------------------------------------------------------------------- machines
def rand_site_law(rng, fam, K_hint):
    Fc = 10 ** rng.uniform(-0.5, 1)
    Fs = Fc * rng.uniform(1, 1.8)
    vs = 10 ** rng.uniform(-4, -2)
    s2 = 10 ** rng.uniform(-2, 1)
    st = fk.Stribeck(Fc=Fc, Fs=Fs, vs=vs, sigma2=s2)
    if fam == "lugre":
        s0 = 10 ** rng.uniform(4, 7)
        return fk.LuGre(st, sigma0=s0, sigma1=10 ** rng.uniform(-1, 0.3) * 2 * math.sqrt(s0 * K_hint)), s0
    if fam == "dahl":
        s0 = 10 ** rng.uniform(4, 7)
        return fk.Dahl(Fc=Fc, sigma0=s0, sigma2=s2), s0
    if fam == "gms":
        M = int(rng.integers(2, 5))
        k = 10 ** rng.uniform(4, 7, size=M)
        xi = rng.uniform(0.2, 1, size=M)
        xi /= xi.sum()
        return fk.GMS(st, k=k.tolist(), xi=xi.tolist(), C=10 ** rng.uniform(0, 2.5)), float(k.sum())
    return st, 0.0


def _chain(rng, name, relative):
    """1-3 DOF chain (masses 1e-2-10 kg, springs 1e4-1e7 N/m) with 1-ndof random friction sites (at most one
    static), on a DOF or, ``relative``, sometimes between two: ``(machine, dofs, masses, ndof, families)``."""
    ndof = int(rng.integers(1, 4))
    mach = fk.Machine(name)
    dofs = [mach.dof(f"d{i}", inertia=10 ** rng.uniform(-2, 1)) for i in range(ndof)]
    masses = [mach.dofs[i].inertia for i in range(ndof)]
    for i in range(ndof - 1):
        mach.spring(dofs[i], dofs[i + 1], k=10 ** rng.uniform(4, 7), c=10 ** rng.uniform(0, 2.5), name=f"s{i}")
    fams = []
    static_used = False
    for j in range(int(rng.integers(1, ndof + 1))):
        fam = str(rng.choice(["lugre", "dahl", "gms", "static"], p=[0.35, 0.25, 0.25, 0.15]))
        if fam == "static" and static_used:
            fam = "lugre"
        static_used |= fam == "static"
        i = int(rng.integers(0, ndof))
        at = dofs[i] - dofs[(i + 1) % ndof] if relative and ndof > 1 and rng.random() < 0.3 else dofs[i]
        law, _ = rand_site_law(rng, fam, masses[i])
        mach.friction(f"f{j}", at, law=law)
        fams.append(fam)
    return mach, dofs, masses, ndof, fams


def rand_machine(rng):
    """An open-loop chain (``_chain``), one force actuator on the first DOF."""
    mach, dofs, masses, ndof, fams = _chain(rng, "camp", True)
    mach.actuator("act", dofs[0], command="u")
    n = int(rng.integers(200, 500))
    dt = 10 ** rng.uniform(-4, -3)
    Fsum = 5.0
    shape = SHAPES[int(rng.integers(0, len(SHAPES)))]
    u, ip = make_input(rng, shape, n, Fsum * rng.uniform(1, 3), Fsum)
    return mach, {"u": u}, dt, dict(ndof=ndof, fams=fams, masses=masses, n=n, dt=dt, shape=shape)


def rand_closed(rng):
    """A chain (``_chain``) with a PID on the first DOF's position: twin = the general loop at 16x sub-steps."""
    from frictionkit.machines import PID, Sum

    mach, dofs, masses, ndof, fams = _chain(rng, "camp-cl", False)
    mach.actuator("act", dofs[0], command="i", limit=100.0)
    mach.sensor("enc", dofs[0])
    Mtot = sum(masses)
    wc = 2 * np.pi * 10 ** rng.uniform(0.5, 1.5)  # 3-100 Hz bandwidth
    dt = 10 ** rng.uniform(-4, -3)
    mach.add(Sum("e", {"r": 1.0, "enc": -1.0}),
             PID("i", "e", Kp=Mtot * wc ** 2, Ki=Mtot * wc ** 3 / 10, Kd=2 * Mtot * wc, tau_d=2 * dt))
    n = int(rng.integers(300, 600))
    k = np.arange(n)
    r = 1e-3 * 10 ** rng.uniform(-2, 0) * np.sin(2 * np.pi * rng.uniform(1, 3) * k / n)
    return mach, {"r": r}, dt, dict(ndof=ndof, fams=fams, masses=masses, n=n, dt=dt, wc=wc)


def mach_errs(res, ref, machine):
    """Largest |run - twin| of each trace kind over a range: positions and velocities over the largest range
    of their kind (a DOF held by a sticking static site barely moves: the default run's first-order creep of
    5e-10 m, falling 16x per 4x sub-steps, was 170x its own range but 2e-4 of the 2.5e-6 m the machine moves;
    kinds: translational and rotational apart); site forces over their own range, as the sub-step check judges them
    (a static site's force is a sub-step mean that check leaves out: skipped here too)."""
    from frictionkit.machines.simulate import law_family

    static = [s.role == "friction" and law_family(s.law) == "static" for s in machine.sites]
    kinds = np.array([d.kind for d in machine.dofs])
    e = {}
    for what, a, b in (("q", res.q, ref.q), ("v", res.v, ref.v), ("F", res.site_forces, ref.site_forces)):
        spans = np.ptp(b, axis=0) if b.size else np.zeros(0)
        worst = 0.0
        for i in range(a.shape[1]):
            if what == "F" and i < len(static) and static[i]:
                continue
            span = float(spans[i]) if what == "F" else float(spans[kinds == kinds[i]].max())
            floor = 1e-9 * float(np.max(np.abs(b[:, i]))) + 1e-15
            worst = max(worst, float(np.max(np.abs(a[:, i] - b[:, i]))) / (span + floor))
        e[what] = worst
    return e


def machine_class(res, e):
    # contract used: the sub-step check's bounds (1 % position range, 10 % velocity and site force)
    ok = e["q"] <= 0.01 and e["v"] <= 0.1 and e["F"] <= 0.1
    if res.status == 0:
        return "passed-right" if ok else "passed-WRONG"
    return "flagged-wrong" if ok else "flagged-right"


def _emps_case(rng):
    """The EMPS preset, mass x0.1-3, friction levels x0.5-2, one of five law families, a raised cosine."""
    from frictionkit.presets.emps import PUBLISHED, emps_machine

    fam = str(rng.choice(["cv", "lugre", "dahl", "gms", "stribeck"]))
    Fc = PUBLISHED["Fc"] * rng.uniform(0.5, 2)
    Fv = PUBLISHED["Fv"] * rng.uniform(0.5, 2)
    st = fk.Stribeck(Fc=Fc, Fs=Fc * 1.3, vs=1e-3, sigma2=Fv)
    if fam == "cv":
        law = fk.CoulombViscous(Fc=Fc, sigma2=Fv)
    elif fam == "stribeck":
        law = st
    elif fam == "lugre":
        law = fk.LuGre(st, sigma0=10 ** rng.uniform(5, 8), sigma1=10 ** rng.uniform(2, 4))
    elif fam == "dahl":
        law = fk.Dahl(Fc=Fc, sigma0=10 ** rng.uniform(5, 8), sigma2=Fv)
    else:
        law = fk.GMS(st, k=[1e6, 1e7], xi=[0.6, 0.4], C=30.0)
    M = PUBLISHED["M"] * 10 ** rng.uniform(-1, 0.5)
    mach = emps_machine(M=M, friction=law, offset=PUBLISHED["offset"])
    n = 2000
    qg = 0.1 * (1 - np.cos(2 * np.pi * np.arange(n) / n * rng.uniform(1, 3)))
    return mach, {"qg": qg}, 1e-3, dict(preset="emps", fam=fam, M=M, Fc=Fc, Fv=Fv)


def _ballscrew_case(rng):
    """The open-loop elastic ball screw (seed 001), masses, stiffnesses and friction levels x0.3-3."""
    import dataclasses as dc

    from frictionkit.plants.ballscrew import ElasticBallScrew
    from frictionkit.presets.ballscrew import ballscrew_machine
    from frictionkit.presets.zhu_fujimoto import plant_kwargs

    base = ElasticBallScrew(**plant_kwargs())
    scale = {f: getattr(base, f) * 10 ** rng.uniform(-0.5, 0.5)
             for f in ("J_m", "M_t", "k_coupling", "k_nut", "guide_friction", "nut_friction")}
    plant = dc.replace(base, **scale)
    nut = str(rng.choice(["dahl", "lugre", "gms"]))
    st = fk.Stribeck(Fc=plant.nut_friction, Fs=1.2 * plant.nut_friction, vs=1e-3)
    nut_law = None
    if nut == "lugre":
        nut_law = fk.LuGre(st, sigma0=10 ** rng.uniform(6, 8), sigma1=10 ** rng.uniform(1, 3))
    elif nut == "gms":
        nut_law = fk.GMS(st, k=[1e6, 1e7, 1e8], xi=[0.5, 0.3, 0.2], C=30.0)
    n = 800
    i_in = 10 ** rng.uniform(-1, 0.5) * np.sin(2 * np.pi * rng.uniform(1, 4) * np.arange(n) / n)
    return (ballscrew_machine(plant, nut_law=nut_law), {"i": i_in}, 5e-4,
            dict(preset="ballscrew-open", nut=nut, scale={k: float(v) for k, v in scale.items()}))


def case_c(seed):
    from frictionkit.machines.reference import reference_machine

    rng = np.random.default_rng(30_000 + seed)
    kindc = seed % 4  # 0,1: open loop random; 2: closed loop random; 3: presets
    if kindc in (0, 1):
        mach, inputs, dt, p = rand_machine(rng)
    elif kindc == 2:
        mach, inputs, dt, p = rand_closed(rng)
    elif (seed // 4) % 2 == 0:
        mach, inputs, dt, p = _emps_case(rng)
    else:
        mach, inputs, dt, p = _ballscrew_case(rng)
    if kindc == 2 or p.get("preset") == "emps":  # closed loops: no solve_ivp twin
        fine = 160 if kindc == 2 else 640
        twin = f"general loop, {fine} sub-steps"
        make_ref = lambda: fk.simulate_machine(mach, dt=dt, inputs=inputs, substeps=fine, fast_path=False)  # noqa: E731
    else:
        twin = "solve_ivp"
        rt = 1e-9 if "preset" in p else 1e-10
        make_ref = lambda: bounded(lambda: reference_machine(mach, dt=dt, inputs=inputs, rtol=rt), 150)  # noqa: E731
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", RuntimeWarning)
        t0 = time.process_time()
        res = fk.simulate_machine(mach, dt=dt, inputs=inputs)
        cpu = time.process_time() - t0
        ref = make_ref()
    e = mach_errs(res, ref, mach)
    p = json.loads(json.dumps(p, default=float))
    return dict(part="c", seed=seed, params=p, twin=twin, status=res.status, msg=res.message[:200], cpu=cpu,
                err=e, path=res.path[:80], substeps=res.substeps, **{"class": machine_class(res, e)})


def case_d(seed):
    """zhang2023's two-shaft drive (``tdms_machine``, closed loop at 250 us) with its named assumptions perturbed
    (table mass x0.3-3, axial stiffness x0.2-5 and damping x0.3-3, guide and ball-preload levels x0.5-2; noise
    off), the differential-mode reference of ``benchmarks/machines.py`` (nut at 4 mm/s, table 0.2-2 mm out and
    back in 0.6 s), against the general loop at 160 sub-steps."""
    import dataclasses as dc

    from frictionkit.presets.zhang2023.plant import tdms_machine
    from frictionkit.presets.zhang2023.truth import Assumptions

    rng = np.random.default_rng(40_000 + seed)
    base = Assumptions()
    kw = dict(table_mass=base.table_mass * 10 ** rng.uniform(-0.5, 0.5),
              k_axial=base.k_axial * 10 ** rng.uniform(-0.7, 0.7), c_axial=base.c_axial * 10 ** rng.uniform(-0.5, 0.5),
              guide_level=base.guide_level * 10 ** rng.uniform(-0.3, 0.3),
              ball_preload_level=base.ball_preload_level * 10 ** rng.uniform(-0.3, 0.3))
    mach = tdms_machine(dc.replace(base, torque_noise=0.0, scale_noise=0.0, **kw))
    dt, R0 = 250e-6, 5e-3 / (2 * np.pi)
    t = np.arange(int(0.6 / dt) + 1) * dt
    ramp = np.minimum(t / 0.2, 1.0)
    th_base = 4e-3 / R0 * np.cumsum(ramp * ramp * (3 - 2 * ramp)) * dt
    x_ref = 1e-3 * rng.uniform(0.2, 2) * (1 - np.cos(2 * np.pi * t / 0.6))
    z = np.zeros_like(t)
    inputs = {"th1_ref": th_base + x_ref / R0, "th2_ref": -th_base, "ff1": z, "ff2": z, "w1": z, "w2": z}
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", RuntimeWarning)
        t0 = time.process_time()
        res = fk.simulate_machine(mach, dt=dt, inputs=inputs)
        cpu = time.process_time() - t0
        ref = fk.simulate_machine(mach, dt=dt, inputs=inputs, substeps=160, fast_path=False)
    e = mach_errs(res, ref, mach)
    return dict(part="d", seed=seed, params={k: float(v) for k, v in kw.items()}, twin="general loop, 160 sub-steps",
                status=res.status, msg=res.message[:200], cpu=cpu, err=e, **{"class": machine_class(res, e)})


def summary(paths):
    import collections

    rows = [json.loads(line) for p in paths for line in open(p)]
    for part in sorted({r["part"] for r in rows}):
        mine = [r for r in rows if r["part"] == part]
        print(part, len(mine), dict(collections.Counter(r["class"] for r in mine)))
        for r in mine:
            if r["class"] in ("passed-WRONG", "error"):
                print("  ", r["class"], "seed", r["seed"], r.get("err") or r.get("err_rms") or r.get("exc"))


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--part", choices=("a", "b", "c", "d"))
    ap.add_argument("--seeds", nargs=2, type=int)
    ap.add_argument("--out")
    ap.add_argument("--summary", nargs="+", help="print the classes of these JSON-lines files and stop")
    a = ap.parse_args()
    if a.summary:
        return summary(a.summary)
    if not (a.part and a.seeds and a.out):
        ap.error("--part, --seeds and --out are required (or --summary FILES)")
    fn = {"a": case_a, "b": case_b, "c": case_c, "d": case_d}[a.part]
    with open(a.out, "a") as fh:
        for seed in range(*a.seeds):
            t0 = time.time()
            try:
                rows = fn(seed)
                rows = rows if isinstance(rows, list) else [rows]
            except Timeout:
                rows = [dict(part=a.part, seed=seed, **{"class": "twin-timeout"})]
            except Exception as exc:  # a traceback is a finding too
                rows = [dict(part=a.part, seed=seed, **{"class": "error"}, exc=repr(exc)[:300],
                             tb=traceback.format_exc()[-1500:])]
            for r in rows:
                r["wall"] = time.time() - t0
                fh.write(json.dumps(r, default=float) + "\n")
                fh.flush()
                print(a.part, seed, r.get("class"), r.get("status"), {k: f"{v:.2g}" for k, v in
                                                                         (r.get("err") or r.get("err_rms") or {}).items()},
                      f"{r['wall']:.1f}s", flush=True)


if __name__ == "__main__":
    main()
