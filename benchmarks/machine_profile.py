"""Where the machine kernel's time goes, per sample (issue 8): section timers and work counts.

Run:  .venv/bin/python benchmarks/machine_profile.py [--workloads sliding,flank,hertz,gms4,two] [--repeat 30]

An instrumented copy of ``kernels/machine.py`` is written to a temporary directory: the time-stamp
counter (LLVM ``readcyclecounter``, ~20-40 cycles a read) is read at the section boundaries of
``run``'s sample loop, and the site solves, law evaluations, Gauss-Seidel sweeps, attempts and
steps are counted. The kernel's arguments are captured from the benchmark's own workloads
(``benchmarks/machines.py``: the ball-screw stage with the paper's controller and sensors, 5 s;
the two-shaft drive, 2.5 s) and the copy is run ``--repeat`` times on them. A section's time is
its least total over the repeats (a preemption lands in one section of one run; with a few per
run, a section's minimum over ~30 runs is clean), so the sections' sum is below the run's time.
Ticks are converted to ns with the counter's rate measured against ``time.perf_counter``.

The copy differs from the kernel only by the counters: it follows the same path (the counts are
the kernel's). The anchors are source lines of ``run``; when ``run`` changes, an anchor that no
longer matches stops the script with its text (update the ``_SECTIONS`` table). Nothing is
asserted; the numbers go to the issue notes.

Measured 2026-11-24 (load 7-11, ~0.41 ns a tick; ``--repeat 30``): the Dahl sliding stage spends
~0.9-1 us per 0.5 ms sample in the kernel: record 6 %, controller 17-22 %, the coarse step ~55 %
(its state map ``Xf = Phi X + G w`` 10-13 %, the two site solves 28 % before run took the first
step of a LuGre/Dahl solve inline, 10 % after; the end check 6 %), the 3 % of samples in 10
sub-steps 18-20 %; ~2 law evaluations per sample. The flank and Hertz stages spend ~75 % in the
sub-steps' solves (60-85 site solves, 18-19 sweeps and 80-115 law evaluations per sample).

Measured 2026-11-24 (mspeed; load 1-2): the GMS-4 stage ~2.25 us per sample, 47 % of it in the
sub-steps of the 12 % of samples whose coarse step failed (the ~50 ms after each reversal: a held
GMS force fails the bound while the motion accelerates or sticks), coarse solves 19 %; the
two-shaft drive 5.3 us per sample (its user run; the hunting check reruns it at 4x the sub-steps),
coarse solves 51 % (12.7 law evaluations, 9 site solves, 2.7 sweeps per sample over its 4 GMS-3
sites), the 7 % sub-stepped samples (start, table reversals) 36 %. With the GMS coarse-step
profile (kernels/machine.py run, "Coarse steps") 97 % / 99 % of the samples are one step; the
two-shaft drive's coarse solves are then ~90 % of its kernel (13.7 law evaluations, 9.7 solves,
2.9 sweeps per sample; its ball pair and guide sit on the same coordinate, so the Gauss-Seidel
between them is the likely next target: not measured).

Measured 2026-11-24 (mcore; load 2-12, same-run kernel CPU against f22475c in a worktree,
/tmp scripts): the two-shaft drive's sweeps started from the last step's held forces, so the first
sweep's inputs were off by a sample's change of every force and a third sweep followed. The
sweeps now start from predicted forces (``run``: the recorded force plus half the profile's
change, else a linear extrapolation): 2.94 -> 2.03 coarse sweeps, 9.7 -> 7.1 site solves, 13.7
-> 10.9 law evaluations a sample; kernel 27.4 -> 26.1 ms (-5 %), the Dahl sliding stage 7.7 ->
7.0 ms, GMS-4 13.3 -> 13.1, flank / Hertz unchanged (89 % / 95 % of their samples sub-stepped).
Tried and not kept: a joint scalar solve of the sites on one coordinate (the ball pair and the
guide; the flank stage's nut and two flank sites) — solves 9.7 -> 6.3 a sample but law
evaluations only 13.7 -> 12.3; the two-shaft kernel +23 % (+8 % with the group calling its laws
directly, +0.2 % on top of the prediction), the flank stage +1 %, Hertz +13 %: the Gauss-Seidel
between sites on one coordinate was not where the evaluations go.

Measured 2026-11-24 (mtol; load 2-6, same-run kernel CPU against 98dccba in a worktree, least of
3 x 5 runs each, /tmp scripts): the site solves stopped at a residual of 1e-18 m, 1e6x below the
coarse steps' bound. At ``kernels.machine.SITE_XTOL`` = 1e-15 (1e-3 of the bound, scaled with
the sub-steps as the bound is) the two-shaft drive's coarse law evaluations 10.9 -> 4.3, site
solves 7.1 -> 4.1, sweeps 2.03 -> 1.05 a sample; flank / Hertz sub-step law evaluations 73.9 ->
56.1 / 107.4 -> 77.2 a sample. Kernel CPU (the two-shaft drive with its loop check's rerun):
two-shaft 51.6 -> 33.8 ms, Dahl sliding 7.2 -> 6.4, GMS-4 12.8 -> 11.9, flank 78.5 -> 66.9,
Hertz 110.6 -> 89.1; the errors against 640 sub-steps move by <= 5e-15 m (the constant's
comment has the sweep over 1e-16 ... 1e-12). 1e-14 would take flank and Hertz to -38 % (37.5 /
51.8 sub-step law evaluations a sample), but flips a quantised zhang2023 sub-step check verdict.

Measured 2026-11-24 (flk; a copy of ``run`` trying a coarse step at every sample and recording
which test rejects it, /tmp scripts): the flank stage's rejections (67 % of the samples tried)
were the flank sites' START deviation (median 1.14 of the bound, end 0.07): the profile took a
flank force as following its load at once (``dF = F_k dl / lam``) while a Dahl force lags a
rising load (``kernels.machine._lugre_mean``), so the profile's start missed by ``Fc dl q``. With
the law's own end-minus-start (``_predict_profile``) 82 % pass (Hertz 73 %); what is left are
symmetric end deviations (start and end each ~1.1 of the bound among the rejected, the load
prediction's term ~0.005): the Dahl lag's curvature, which a held-compliance bound prices at
its full size although a zero-mean quadratic force error moves a mass-dominated site's end
position by ~0 (not done: a bound through the chain's response to that shape); Hertz adds
its contact site turning inside the sample (8 % of the samples). The rejections come single or
in short runs (1-4 samples), so the back-off from the first rejection kept 53 / 38 % of the
samples (flank / Hertz) where retrying at once keeps 74 / 65 % (``COARSE_RETRIES``). Counts per
sample now (paper sensors, 5 s): flank 0.87 coarse tries, 0.74 kept, 0.26 sub-stepped samples,
18 sub-step law evaluations (56 before); Hertz 0.85, 0.65, 0.35, 31 (77 before).
"""

from __future__ import annotations

import argparse
import copy
import importlib
import math
import os
import sys
import tempfile
import time

import numpy as np

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, HERE)

_HEADER = '''
from numba.extending import intrinsic as _intrinsic
from numba import types as _types
from llvmlite import ir as _ir
from numba.core import cgutils as _cgutils


@_intrinsic
def rdtsc(typingctx):
    def codegen(context, builder, signature, args):
        fnty = _ir.FunctionType(_ir.IntType(64), [])
        fn = _cgutils.get_or_insert_function(builder.module, fnty, "llvm.readcyclecounter")
        return builder.call(fn, [])
    return _types.int64(), codegen


@njit
def ticks():
    return rdtsc()


@njit(error_model="numpy")
def _sm(cnt, co, kind, par, o, st, stw, so, s0, ds, h, lam, v0, dl):
    cnt[co] += 1
    return _site_mean(kind, par, o, st, stw, so, s0, ds, h, lam, v0, dl)
'''

#: (label index, label, anchor line in run, where the timer goes: "before"/"after")
_T = "tB = rdtsc(); tm[{i}] += tB - tA; tA = tB"
_SECTIONS = [
    ("        kn = k + 1 if k + 1 < N else k\n", "tA = rdtsc()", "before"),
    ("        # ---- inputs and sensors\n", _T.format(i=0), "before"),
    ("        if k == N - 1:\n            break\n", _T.format(i=1), "before"),
    ("        attempt = 0 if try_c else 1\n", _T.format(i=2), "before"),
    ("                if coarse_now and n_prof:\n", "tB = rdtsc(); tm[3 if coarse_now else 13] += tB - tA; tA = tB", "before"),
    ("                    # Gauss-Seidel over the sites, lazily", "tB = rdtsc(); tm[4 if coarse_now else 14] += tB - tA; tA = tB", "before"),
    ("                    if coarse_now:  # the held mean against", "tB = rdtsc(); tm[5 if coarse_now else 15] += tB - tA; tA = tB", "before"),
    ("                for r in range(n2):\n                    X[r] = Xf[r]\n", "tB = rdtsc(); tm[6 if coarse_now else 16] += tB - tA; tA = tB", "before"),
    ("                if coarse_now:  # ... and at its end", "tB = rdtsc(); tm[7 if coarse_now else 17] += tB - tA; tA = tB", "before"),
    ("                    if not ok:\n                        break\n", _T.format(i=8), "before"),
    ("            if coarse_now:\n                for j in range(ns):\n                    dlam[j] = 0.0\n",
     "tB = rdtsc(); tm[9 if coarse_now else 19] += tB - tA; tA = tB", "before"),
    ("                return STATUS_NONFINITE, k + 1, n_bad, n_one, n_sw\n    return STATUS_OK, N, n_bad, n_one, n_sw", None, None),
]
LABELS = {0: "record", 1: "controller", 2: "save start", 3: "coarse: Xf = Phi X + G w", 4: "coarse: site inputs",
          5: "coarse: solves (sweeps)", 6: "coarse: deviation + commit", 7: "coarse: X update", 8: "coarse: end check",
          9: "coarse: tail", 10: "sample tail", 13: "sub: Xf (+ loads)", 14: "sub: site inputs",
          15: "sub: solves (sweeps)", 16: "sub: commit", 17: "sub: X update", 19: "sub: tail"}
COUNTS = ["law evaluations (coarse)", "law evaluations (sub)", "site solves (coarse)", "site solves (sub)",
          "sweeps (coarse)", "sweeps (sub)", "coarse attempts", "sub-stepped samples", "steps (coarse)",
          "sub-steps", "coarse steps kept"]


def _indent(line: str) -> str:
    return line[:len(line) - len(line.lstrip())]


def instrumented_source(src: str) -> str:
    """``kernels/machine.py`` with the section timers and counters (see the module docstring)."""
    def rep(old, new):
        if src.count(old) != 1:
            raise SystemExit(f"machine_profile: anchor not found once in kernels/machine.py:\n{old}")
        return src.replace(old, new)

    src = rep("from .._jit import njit\n", "from frictionkit._jit import njit\n")
    src = src.replace("# --------------------------------------------------------------------------- main loop",
                      _HEADER + "\n\n# --------------------------------------------------------------------------- main loop", 1)
    a = src.index("def _solve_site(")
    b = src.index("def _loads(")
    body = src[a:b].replace("_site_mean(kind, par, o, st, stw, so, s0,", "_sm(cnt, co, kind, par, o, st, stw, so, s0,")
    body = body.replace("):", ", cnt, co):", 1)  # the def line's end
    src = src[:a] + body + src[b:]
    src = rep("q_out, v_out, F_out, sig_out, u_out, coarse=True,\n):",
              "q_out, v_out, F_out, sig_out, u_out, coarse=True, tm=None, cnt=None,\n):")
    for anchor, code, _ in _SECTIONS[:-1]:
        first = anchor.splitlines(keepends=True)[0]
        src = rep(anchor, _indent(first) + code + "\n" + anchor)
    last = _SECTIONS[-1][0]
    src = rep(last, last.replace("    return STATUS_OK", "        tB = rdtsc(); tm[10] += tB - tA; tA = tB\n    return STATUS_OK"))
    # the site solve in run: counters into its call (the law evaluations) and after it (the solves)
    a = src.index("= _solve_site(site_kind[j]")
    b = src.index(")\n", a)
    src = src[:b] + ", cnt, 0 if coarse_now else 1" + src[b:]
    src = rep("                            kt[j] = ktj\n",
              "                            cnt[2 if coarse_now else 3] += 1\n                            kt[j] = ktj\n")
    for first in ("F0, z0e = _lugre_mean(", "F0 = _gms_mean("):  # run's inline first step of a LuGre/Dahl, GMS solve
        if first in src[a - 2500:a]:
            i = src.index(first, a - 2500)
            i = src.rindex("\n", 0, i) + 1
            src = src[:i] + _indent(src[i:i + 80]) + "cnt[0 if coarse_now else 1] += 1\n" + src[i:]
            a = src.index("= _solve_site(site_kind[j]")
    src = rep("                    for sweep in range(60):\n",
              "                    for sweep in range(60):\n                        cnt[4 if coarse_now else 5] += 1\n")
    src = rep("            for sub in range(nsa):\n",
              "            cnt[6 if coarse_now else 7] += 1\n            for sub in range(nsa):\n"
              "                cnt[8 if coarse_now else 9] += 1\n")
    src = rep("                if ok:\n                    gap = 1\n", "                if ok:\n                    cnt[10] += 1\n                    gap = 1\n")
    return src


def capture(workloads):
    """The kernel's arguments of each workload's first kernel call (deep copies)."""
    from frictionkit.kernels import machine as km

    import machines as B  # benchmarks/machines.py (installs its kernel clock on km.run)
    from frictionkit.control.trajectories import cosine_reference
    from frictionkit.machines import simulate_machine
    from frictionkit.presets.ballscrew import simulate_stage
    from frictionkit.reproduce.zhu_fujimoto import (_classify, paper_compensator, paper_controller, paper_plant,
                                                    paper_sensors)

    got = {}
    inner = km.run.inner if hasattr(km.run, "inner") else km.run

    def grab(*a, **k):
        if "x" not in got:
            got["x"] = (copy.deepcopy(a), dict(k))
        return inner(*a, **k)

    old = km.run
    km.run = grab
    out = {}
    try:
        ctrl, sens = paper_controller(), paper_sensors()
        ref = cosine_reference(duration=5.0)
        for w in workloads:
            got.clear()
            if w == "two":
                dt = 250e-6
                simulate_machine(B.two_shaft_machine(dt), dt=dt, inputs=B.two_shaft_reference(2.5, dt), substeps=10)
            else:
                plant = paper_plant("sliding" if w == "gms4" else w)
                u_f = paper_compensator().signal(ref, "sinc", _classify(ref, plant))
                kw = dict(nut_law=B.gms4(plant.nut_friction), guide_law=B.gms4(plant.guide_friction)) if w == "gms4" else {}
                simulate_stage(plant, ctrl, ref, compensation=u_f, sensors=sens, **kw)
            out[w] = got["x"]
    finally:
        km.run = old
    return out


def main() -> None:
    ap = argparse.ArgumentParser()
    ap.add_argument("--workloads", default="sliding,gms4,flank,hertz,two")
    ap.add_argument("--repeat", type=int, default=30)
    args = ap.parse_args()
    import frictionkit.kernels.machine as km

    d = tempfile.mkdtemp(prefix="fk_machine_profile_")
    with open(km.__file__) as fh:
        src = instrumented_source(fh.read())
    with open(os.path.join(d, "_fk_machine_profiled.py"), "w") as fh:
        fh.write(src)
    sys.path.insert(0, d)
    kp = importlib.import_module("_fk_machine_profiled")
    kp.ticks()
    t0, c0 = time.perf_counter(), kp.ticks()
    while time.perf_counter() - t0 < 0.2:
        pass
    ns_per_tick = (time.perf_counter() - t0) * 1e9 / (kp.ticks() - c0)
    caps = capture(args.workloads.split(","))
    print(f"load average {os.getloadavg()[0]:.2f}; counter {1.0 / ns_per_tick:.2f} ticks/ns; per-section least total "
          f"over {args.repeat} runs, per sample")
    for w, (a, k) in caps.items():
        best, cnt, cpu = None, None, math.inf
        for r in range(args.repeat + 1):
            tm = np.zeros(24, dtype=np.int64)
            cn = np.zeros(16)
            aa = copy.deepcopy(a)
            c = time.thread_time()
            out = kp.run(*aa, **k, tm=tm, cnt=cn)
            c = time.thread_time() - c
            if r == 0:
                continue  # compile / warm-up
            cpu = min(cpu, c)
            best = tm if best is None else np.minimum(best, tm)
            cnt = cn
        N = int(out[1])
        tot = best.sum()
        print(f"\n{w}: {N} samples, instrumented kernel {cpu * 1e3:.2f} ms CPU; sections sum "
              f"{tot * ns_per_tick / 1e6:.2f} ms = {tot * ns_per_tick / N:.0f} ns/sample")
        for i, lab in LABELS.items():
            if best[i]:
                print(f"  {lab:30s} {best[i] * ns_per_tick / N:8.1f} ns/sample  {100.0 * best[i] / tot:5.1f} %")
        print("  per sample: " + ", ".join(f"{nm} {cnt[i] / N:.3f}" for i, nm in enumerate(COUNTS)))


if __name__ == "__main__":
    main()
