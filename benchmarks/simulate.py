"""Simulation benchmark: frictionkit kernels against scipy solve_ivp, measured in one run.

Run:  .venv/bin/python benchmarks/simulate.py [--quick]

Workload: the 10 s stick–slip run (1 kg, 2 N at 0.5 Hz against Fs = 1.5 N) sampled
at 4 kHz (dt = 250 µs), for LuGre, GMS-4 and GMS-16 (``frictionkit.simulation.inputs``).

For each model it prints
* the kernel's ns per sample step, real-time factor and its errors (max |Δx|,
  max |ΔF|) against a tight LSODA reference (rtol 1e-11, GMS with located events);
* solve_ivp RK45 and LSODA at their default tolerances (time, errors);
* solve_ivp at *matching accuracy*: the loosest rtol in 1e-3 … 1e-10 whose errors are
  both <= the kernel's, its time and the speed ratio (kernel faster by ×N);
* batch throughput: 1,000 parameter sets (10 s each) through ``simulate_batch``, adaptive
  and fixed (n_sub 1, 2, 4), and the fixed method's accuracy against the adaptive one.

Nothing here is asserted: the numbers go to the README and the issue notes.
"""

from __future__ import annotations

import argparse
import os
import time

import numpy as np

import frictionkit as fk
from frictionkit.simulation.inputs import example_gms, example_lugre, stick_slip_force
from frictionkit.simulation.reference import reference_force_driven

DT = 2.5e-4


def best_of(fn, repeat=5):
    best = np.inf
    out = None
    for _ in range(repeat):
        t0 = time.perf_counter()
        out = fn()
        best = min(best, time.perf_counter() - t0)
    return best, out


def errors(a, ref):
    return float(np.abs(a["x"] - ref["x"]).max()), float(np.abs(a["F"] - ref["F"]).max())


def main() -> None:
    ap = argparse.ArgumentParser()
    ap.add_argument("--quick", action="store_true", help="2 s instead of 10 s, fewer tolerance steps")
    args = ap.parse_args()
    duration = 2.0 if args.quick else 10.0
    u = stick_slip_force(duration=duration, dt=DT)
    N = u.size
    print(f"stick-slip run: {duration:g} s at 4 kHz ({N} samples), cores: {os.cpu_count()}")
    rows = []
    for name, model in (("LuGre", example_lugre()), ("GMS-4", example_gms(4)), ("GMS-16", example_gms(16))):
        fk.simulate(model, plant=fk.Mass(1.0), force=u, dt=DT)  # compile
        t_k, res = best_of(lambda: fk.simulate(model, plant=fk.Mass(1.0), force=u, dt=DT), repeat=25)
        ref = reference_force_driven(model, 1.0, u, DT, method="LSODA", rtol=1e-11, atol=1e-13)
        ex, eF = errors({"x": res.x, "F": res.friction}, ref)
        print(f"\n== {name}")
        print(
            f"kernel: {t_k * 1e3:8.2f} ms  {t_k / (N - 1) * 1e9:7.1f} ns/step  "
            f"real-time x{duration / t_k:,.0f}  substeps/step {res.substeps / (N - 1):.2f}  "
            f"max|dx| {ex * 1e6:.3f} um  max|dF| {eF:.2e} N"
        )
        row = {"model": name, "kernel_s": t_k, "ns_per_step": t_k / (N - 1) * 1e9, "rt": duration / t_k}
        for method in ("RK45", "LSODA"):
            r = reference_force_driven(model, 1.0, u, DT, method=method, rtol=1e-3, atol=1e-6)
            dx, dF = errors(r, ref)
            print(f"{method:6s} default tol: {r['wall_s']:8.3f} s  max|dx| {dx * 1e6:10.3f} um  max|dF| {dF:.2e} N  "
                  f"-> kernel x{r['wall_s'] / t_k:,.0f} faster (and {'more' if ex <= dx and eF <= dF else 'less'} accurate)")
            matched = None
            tols = [1e-4, 1e-6, 1e-8, 1e-10] if args.quick else [1e-3, 1e-4, 1e-5, 1e-6, 1e-7, 1e-8, 1e-9, 1e-10]
            for rtol in tols:
                r = reference_force_driven(model, 1.0, u, DT, method=method, rtol=rtol, atol=rtol * 1e-3)
                dx, dF = errors(r, ref)
                if dx <= ex and dF <= eF:
                    matched = (rtol, r["wall_s"], dx, dF)
                    break
                if r["wall_s"] > 120.0:
                    break
            if matched:
                rtol, wall, dx, dF = matched
                print(f"{method:6s} matching accuracy (rtol {rtol:g}): {wall:8.3f} s  max|dx| {dx * 1e6:.3f} um  "
                      f"max|dF| {dF:.2e} N  -> kernel x{wall / t_k:,.0f} faster")
                row[method] = wall / t_k
            else:
                print(f"{method:6s} did not reach the kernel's accuracy within the tolerance sweep")
                row[method] = None
        rows.append(row)

    print("\n== batch: 1,000 parameter sets, one input, error norm only")
    print("   (best of N; wall time on a possibly shared machine, and the CPU-time equivalent on")
    print("    2 dedicated cores = 2 x runs / CPU seconds of the process)")
    rng = np.random.default_rng(0)
    base = example_lugre()
    target = fk.simulate(base, plant=fk.Mass(1.0), force=u, dt=DT).v
    lugre_sets = [fk.LuGre(base.static, sigma0=s0, sigma1=s1) for s0, s1 in zip(
        rng.uniform(5e4, 2e5, 1000), rng.uniform(20.0, 100.0, 1000))]
    gms_sets = [fk.GMS(example_gms(4).static, k=example_gms(4).k * f, xi=example_gms(4).xi, C=c) for f, c in zip(
        rng.uniform(0.5, 2.0, 1000), rng.uniform(10.0, 40.0, 1000))]

    def batch_rate(models, repeat, **kw):
        fk.simulate_batch(models[:4], masses=1.0, force=u, dt=DT, target=target, compare="v", **kw)  # compile
        best, best_cpu, out = np.inf, np.inf, None
        for _ in range(repeat):
            t0, c0 = time.perf_counter(), time.process_time()
            out = fk.simulate_batch(models, masses=1.0, force=u, dt=DT, target=target, compare="v", **kw)
            best = min(best, time.perf_counter() - t0)
            best_cpu = min(best_cpu, time.process_time() - c0)
        n = len(models)
        return n / best, 2 * n / best_cpu, int((out.status != 0).sum())

    cases = [("LuGre adaptive", lugre_sets, 2, {})]
    cases += [(f"LuGre fixed n_sub={n}", lugre_sets, 5, {"method": "fixed", "options": fk.SimOptions(batch_substeps=n)})
              for n in (1, 2, 4)]
    cases += [("GMS-4 adaptive", gms_sets, 2, {})]
    for name, models, repeat, kw in cases:
        rate, rate_cpu, fails = batch_rate(models, repeat, **kw)
        print(f"{name:22s} {rate:8,.0f} simulations/s wall  ({rate * duration:,.0f}x real time in aggregate)  "
              f"{rate_cpu:8,.0f} /s CPU-time equivalent  failures: {fails}")

    print("\nfixed method vs adaptive (LuGre example, 1 kg, this run): max errors over the trace")
    from frictionkit.kernels.lugre import lugre_force_ros2
    from frictionkit.models.pack import pack_lugre

    pk = pack_lugre(base)
    tight = fk.simulate(base, plant=fk.Mass(1.0), force=u, dt=DT, options=fk.SimOptions(rtol=1e-9, atol_v=1e-12, atol_F=1e-10))
    adapt = fk.simulate(base, plant=fk.Mass(1.0), force=u, dt=DT)

    def fixed_trace(n):
        # the batch kernel keeps no traces; the scalar ROS2 kernel with loose tolerances takes exactly
        # one ROS2 step per (resampled) interval: the same scheme (tests/kernels/test_batch.py)
        nf = (N - 1) * n + 1
        uf = np.interp(np.arange(nf) / n, np.arange(N), u)
        x, v, F, z = (np.empty(nf) for _ in range(4))
        lugre_force_ros2(uf, DT / n, 1.0, pk.static, pk.dyn, 0.0, 0.0, 0.0, 1e300, 1e300, 1e300, 10, x, v, F, z)
        return x[::n], v[::n], F[::n]

    def maxerr(a, b):
        return tuple(float(np.abs(p - q).max()) for p, q in zip(a, (b.x, b.v, b.friction)))

    ex, ev, eF = maxerr((adapt.x, adapt.v, adapt.friction), tight)
    print(f"  adaptive (default tol) vs tight adaptive: |dx| {ex * 1e6:6.2f} um  |dv| {ev:.2e} m/s  |dF| {eF:.2e} N")
    for n in (1, 2, 4):
        tr = fixed_trace(n)
        ex, ev, eF = maxerr(tr, adapt)
        tx, tv, tF = maxerr(tr, tight)
        print(f"  fixed n_sub={n}: vs adaptive |dx| {ex * 1e6:6.2f} um  |dv| {ev:.2e} m/s  |dF| {eF:.2e} N;"
              f"  vs tight |dx| {tx * 1e6:6.2f} um  |dF| {tF:.2e} N")

    print("\nsummary (kernel ns/step, real-time factor, speed-up at matching accuracy vs RK45 / LSODA):")
    for r in rows:
        f = lambda v: "n/a" if v is None else f"x{v:,.0f}"
        print(f"  {r['model']:7s} {r['ns_per_step']:7.1f} ns/step  real-time x{r['rt']:,.0f}  RK45 {f(r.get('RK45'))}  LSODA {f(r.get('LSODA'))}")


if __name__ == "__main__":
    main()
