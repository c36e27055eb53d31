"""Frictional lag: friction against velocity under velocity oscillations of several frequencies.

The hysteresis experiment of Canudas de Wit, Olsson, Åström and Lischinsky (IEEE TAC 1995),
paper parameters (sigma0 = 1e5 N/m, sigma1 = sqrt(1e5) N·s/m, sigma2 = 0.4 N·s/m, Fc = 1 N,
Fs = 1.5 N, vs = 1e-3 m/s, m = 1 kg). The contact slides at ``v(t) = 1e-3 (1 + 0.9 sin(w t))``
m/s, always forward and through the Stribeck region, for ``w = 1, 10, 25`` rad/s. The friction
lags the velocity: it is larger while the velocity rises than while it falls, and the loop
widens with the frequency.

The machine API prescribes positions, and a friction site must move with a degree of freedom,
so the 1 kg slider is dragged along the prescribed position through a very stiff, critically
damped coupling (1e9 N/m: 5 kHz, its lag is 60 us); the loop is friction against the slider's
own velocity.

    python examples/canudas1995_lag.py --json OUT [--omega 1 10 25]

writes ``{"omega": [...], "v": [[...], ...], "friction": [[...], ...], "area": [...], "width": [...]}``:
for each frequency the last full period of velocity [m/s] and friction [N], the loop area
``|closed integral of F dv|`` [N·m/s] and its widest gap between the rising and falling branches [N].
"""

from __future__ import annotations

import argparse
import json
import math

import numpy as np

import frictionkit as fk

LAW = fk.LuGre(fk.Stribeck(Fc=1.0, Fs=1.5, vs=1e-3, sigma2=0.4), sigma0=1e5, sigma1=math.sqrt(1e5))
K_DRIVE = 1e9  # N/m
V_MEAN, V_AMP = 1e-3, 0.9e-3  # m/s


def machine() -> fk.Machine:
    m = fk.Machine("Canudas et al. 1995: frictional lag")
    x = m.dof("x", inertia=1.0)
    drive = m.motion("drive")  # prescribed position [m], an input array
    m.spring(x, drive, k=K_DRIVE, c=2.0 * math.sqrt(K_DRIVE * 1.0))  # critically damped
    m.friction("friction", x, law=LAW)
    return m


def position(t: np.ndarray, omega: float) -> np.ndarray:
    """Integral of ``V_MEAN + V_AMP sin(omega t)`` from 0."""
    return V_MEAN * t + V_AMP * (1.0 - np.cos(omega * t)) / omega


def loop(omega: float, periods: float = 3.0, samples_per_period: int = 2000) -> dict:
    """Velocity and friction over the last full period at ``omega`` [rad/s]."""
    T = 2.0 * math.pi / omega
    dt = T / samples_per_period
    n = int(round(periods * samples_per_period))
    t = np.arange(n + 1) * dt
    res = fk.simulate_machine(machine(), dt=dt, inputs={"drive": position(t, omega)}, raise_on_failure=True)
    last = slice(n - samples_per_period, n + 1)
    v, F = res.velocity("x")[last], res.force("friction")[last]
    area = abs(float(np.sum(0.5 * (F[1:] + F[:-1]) * np.diff(v))))  # closed integral of F dv
    return {"v": v, "friction": F, "area": area, "width": width(v, F)}


def width(v: np.ndarray, F: np.ndarray, n: int = 200) -> float:
    """Largest gap [N] between the rising-velocity and falling-velocity branches of a loop."""
    i_lo, i_hi = int(np.argmin(v)), int(np.argmax(v))
    a, b = sorted((i_lo, i_hi))
    one = (v[a:b + 1], F[a:b + 1])
    other = (np.concatenate([v[b:], v[1:a + 1]]), np.concatenate([F[b:], F[1:a + 1]]))
    grid = np.linspace(v[i_lo], v[i_hi], n + 2)[1:-1]
    gaps = []
    for vv, FF in (one, other):
        order = np.argsort(vv)
        gaps.append(np.interp(grid, vv[order], FF[order]))
    return float(np.max(np.abs(gaps[0] - gaps[1])))


def main(argv=None) -> dict:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--json", metavar="OUT", help="write {omega, v, friction, area, width} to this file")
    ap.add_argument("--omega", type=float, nargs="+", default=[1.0, 10.0, 25.0],
                    help="velocity oscillation frequencies [rad/s] (default 1 10 25)")
    args = ap.parse_args(argv)
    loops = [loop(w) for w in args.omega]
    out = {"omega": list(args.omega), "v": [lp["v"].tolist() for lp in loops],
           "friction": [lp["friction"].tolist() for lp in loops], "area": [lp["area"] for lp in loops],
           "width": [lp["width"] for lp in loops]}
    if args.json:
        with open(args.json, "w") as f:
            json.dump(out, f)
    for w, lp in zip(args.omega, loops):
        print(f"omega = {w:6.2f} rad/s: loop area {lp['area']:.3e} N·m/s, widest gap {lp['width']:.4f} N, "
              f"F {lp['friction'].min():.4f}..{lp['friction'].max():.4f} N")
    return out


if __name__ == "__main__":
    main()
