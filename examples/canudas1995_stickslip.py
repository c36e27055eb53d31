"""Stick-slip: a unit mass pulled through a 2 N/m spring whose free end moves at 0.1 m/s.

The stick-slip experiment of Canudas de Wit, Olsson, Åström and Lischinsky, "A new model for
control of systems with friction", IEEE TAC 40(3), 1995, with the paper's LuGre parameters:
sigma0 = 1e5 N/m, sigma1 = sqrt(1e5) N·s/m, sigma2 = 0.4 N·s/m, Fc = 1 N, Fs = 1.5 N,
vs = 1e-3 m/s, m = 1 kg, 20 s.

    python examples/canudas1995_stickslip.py --json OUT

writes ``{"t": [...], "x": [...], "friction": [...]}`` (time [s], mass position [m], friction force
[N] at the samples) and prints the stick phases it found.
"""

from __future__ import annotations

import argparse
import json
import math

import numpy as np

import frictionkit as fk

LAW = fk.LuGre(fk.Stribeck(Fc=1.0, Fs=1.5, vs=1e-3, sigma2=0.4), sigma0=1e5, sigma1=math.sqrt(1e5))
SPRING = 2.0  # N/m
PULL_SPEED = 0.1  # m/s


def machine() -> fk.Machine:
    m = fk.Machine("Canudas et al. 1995: stick-slip")
    x = m.dof("x", inertia=1.0)  # kg
    pull = m.motion("pull")  # the free end of the spring [m], an input array
    m.spring(x, pull, k=SPRING)
    m.friction("friction", x, law=LAW)
    return m


def inputs(duration: float = 20.0, dt: float = 1e-3) -> dict:
    t = np.arange(int(round(duration / dt)) + 1) * dt
    return {"pull": PULL_SPEED * t}


def run(duration: float = 20.0, dt: float = 1e-3) -> dict:
    res = fk.simulate_machine(machine(), dt=dt, inputs=inputs(duration, dt), raise_on_failure=True)
    return {"t": res.t.tolist(), "x": res.position("x").tolist(), "friction": res.force("friction").tolist()}


def stick_phases(t, x, dt: float, v_stick: float = 1e-3) -> list[tuple[float, float]]:
    """(start, end) [s] of the intervals where the mass moves slower than ``v_stick``."""
    v = np.gradient(np.asarray(x), dt)
    slow = np.abs(v) < v_stick
    edges = np.flatnonzero(np.diff(slow.astype(int)))
    bounds = np.concatenate(([0] if slow[0] else [], edges + 1, [slow.size] if slow[-1] else []))
    return [(float(t[a]), float(t[b - 1])) for a, b in zip(bounds[::2].astype(int), bounds[1::2].astype(int))]


def main(argv=None) -> dict:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--json", metavar="OUT", help="write {t, x, F} to this file")
    ap.add_argument("--duration", type=float, default=20.0, help="simulated time [s] (default 20)")
    ap.add_argument("--dt", type=float, default=1e-3, help="sample period [s] (default 1e-3)")
    args = ap.parse_args(argv)
    out = run(args.duration, args.dt)
    if args.json:
        with open(args.json, "w") as f:
            json.dump(out, f)
    phases = stick_phases(out["t"], out["x"], args.dt)
    print(f"stick phases (|v| < 1 mm/s): {', '.join(f'{a:.2f}-{b:.2f} s' for a, b in phases)}")
    print(f"peak friction {max(out['friction']):.3f} N (Fs = {LAW.static.Fs} N), final x = {out['x'][-1]:.4f} m")
    return out


if __name__ == "__main__":
    main()
