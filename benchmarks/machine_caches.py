"""Python-side cost of machine runs (issue 8): the core's caches on vs off, interleaved in one
process on the same compiled kernels.

Run:  .venv/bin/python benchmarks/machine_caches.py [--repeat 7]

"on" is the package as shipped. "off" restores the behaviour before the caches of 2026-11-23
(evening): the machine's JSON fingerprint computed on every ``simulate_machine`` call, and
``simulate_stage`` rebuilding the ball-screw machine (``ballscrew_machine`` + Rayleigh beta)
and the PTC feed-forward on every call. The pack cache (``machines.simulate._packed``) is on in
both. Each workload runs both ways alternately, best (least) of the repeats; CPU = the calling
thread's CPU time (the steadier number on a shared machine), "kernel" = CPU inside the compiled
loop (``kernels.machine.run`` / ``kernels.machine_axis.run_axis``), the rest is Python. Nothing
is asserted; the results are the same arrays either way (tests/unit/test_machine_cache.py).
"""

from __future__ import annotations

import argparse
import math
import os
import sys
import time

import numpy as np

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))

import frictionkit as fk  # noqa: E402
import machines as B  # noqa: E402  (installs the kernel clocks, builds the benchmark machines)
from frictionkit.control.trajectories import cosine_reference  # noqa: E402
from frictionkit.machines import simulate as sim  # noqa: E402
from frictionkit.presets import ballscrew as bsp  # noqa: E402
from frictionkit.reproduce.zhu_fujimoto import (  # noqa: E402
    _classify, paper_compensator, paper_controller, paper_plant, paper_sensors)

ON = (bsp._stage_machine, bsp._feedforward, sim._fingerprint)
OFF = (lambda p, c, s, n, g, f: (bsp.ballscrew_machine(p, c, s, nut_law=n, guide_law=g, flank_law=f),
                                 bsp.rayleigh_beta(p) if isinstance(p, bsp.ElasticBallScrew) else 0.0),
       lambda ptc, a, b: ptc.feedforward(a, b),
       lambda m: sim._CALL_FP.get(id(m)) or sim._json_form(m))


def _mode(fns) -> None:
    bsp._stage_machine, bsp._feedforward, sim._fingerprint = fns


def workloads(duration: float) -> dict:
    ctrl, sens = paper_controller(), paper_sensors()
    ref = cosine_reference(duration=duration)
    plant = paper_plant("sliding")
    u_f = paper_compensator().signal(ref, "sinc", _classify(ref, plant))
    nut, guide = B.gms4(plant.nut_friction), B.gms4(plant.guide_friction)
    ts, tin = B.two_shaft_machine(), B.two_shaft_reference(duration / 2, 250e-6)
    from frictionkit.presets.emps import PUBLISHED, emps_machine

    qg = np.loadtxt(B.EMPS_CSV, delimiter=",", skiprows=1, usecols=2)
    em = emps_machine(M=PUBLISHED["M"], friction=fk.CoulombViscous(Fc=PUBLISHED["Fc"], sigma2=PUBLISHED["Fv"]),
                      offset=PUBLISHED["offset"])
    return {
        f"ballscrew sliding ({duration:g} s)": (duration, 1, lambda: bsp.simulate_stage(
            plant, ctrl, ref, compensation=u_f, sensors=sens)),
        f"ballscrew GMS-4 ({duration:g} s)": (duration, 1, lambda: bsp.simulate_stage(
            plant, ctrl, ref, compensation=u_f, sensors=sens, nut_law=nut, guide_law=guide)),
        f"two-shaft ({duration / 2:g} s)": (duration / 2, 1, lambda: sim.simulate_machine(
            ts, dt=250e-6, inputs=tin, substeps=10)),
        "EMPS fast path (24.8 s)": ((qg.size - 1) * 1e-3, 8, lambda: sim.simulate_machine(
            em, dt=1e-3, inputs={"qg": qg}, substeps=40)),
    }


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--repeat", type=int, default=7)
    ap.add_argument("--duration", type=float, default=5.0)
    args = ap.parse_args()
    print(f"load average {os.getloadavg()[0]:.1f}; best of {args.repeat} (EMPS x8), caches off/on interleaved")
    print(f"{'workload':26s} {'rt CPU off':>10s} {'rt CPU on':>10s} {'rt wall on':>10s} {'kernel ms':>10s} "
          f"{'Python ms off':>13s} {'Python ms on':>12s}")
    for name, (T, mult, f) in workloads(args.duration).items():
        best = {k: [math.inf] * 3 for k in ("off", "on")}
        for k in ("off", "on"):  # warm-up: compile, caches
            _mode(OFF if k == "off" else ON)
            f()
        for _ in range(args.repeat * mult):
            for k in ("off", "on"):
                _mode(OFF if k == "off" else ON)
                B.KERNEL_CLOCK.cpu = B.AXIS_CLOCK.cpu = 0.0
                c0, t0 = time.thread_time(), time.perf_counter()
                f()
                b = best[k]
                b[0] = min(b[0], time.perf_counter() - t0)
                b[1] = min(b[1], time.thread_time() - c0)
                b[2] = min(b[2], B.KERNEL_CLOCK.cpu + B.AXIS_CLOCK.cpu)
        off, on = best["off"], best["on"]
        kern = min(off[2], on[2])
        print(f"{name:26s} {T / off[1]:9.0f}x {T / on[1]:9.0f}x {T / on[0]:9.0f}x {kern * 1e3:10.2f} "
              f"{(off[1] - off[2]) * 1e3:13.2f} {(on[1] - on[2]) * 1e3:12.2f}", flush=True)
    _mode(ON)


if __name__ == "__main__":
    main()
