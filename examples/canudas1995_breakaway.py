"""Break-away force rising with the rate of the applied force.

The varying break-away force experiment of Canudas de Wit, Olsson, Åström and Lischinsky
(IEEE TAC 1995), paper parameters (sigma0 = 1e5 N/m, sigma1 = sqrt(1e5) N·s/m,
sigma2 = 0.4 N·s/m, Fc = 1 N, Fs = 1.5 N, vs = 1e-3 m/s, m = 1 kg). A force ramp
``u = rate t`` pushes the mass from rest; the faster the ramp, the larger the applied force by
the time the mass breaks away.

Break-away is taken here as the applied force when the mass has slid ``X_BREAK = 0.3 mm``,
twenty times the bristle range ``Fs / sigma0 = 15 um``: clearly gross sliding, whatever the
pre-sliding creep. At slow rates it is ``Fs`` (within 0.3 % up to 1 N/s: the quasi-static
limit); from about 1 N/s on it rises with the rate. The peak friction force before
break-away is reported too.

    python examples/canudas1995_breakaway.py --json OUT [--rates 0.1 1 3 10 30 100]

writes ``{"rate": [...], "breakaway": [...], "peak_friction": [...]}`` ([N/s], [N], [N]).
"""

from __future__ import annotations

import argparse
import json
import math

import numpy as np

import frictionkit as fk

LAW = fk.LuGre(fk.Stribeck(Fc=1.0, Fs=1.5, vs=1e-3, sigma2=0.4), sigma0=1e5, sigma1=math.sqrt(1e5))
RATES = [0.1, 1.0, 3.0, 10.0, 30.0, 100.0]  # N/s
X_BREAK = 0.3e-3  # m


def machine() -> fk.Machine:
    m = fk.Machine("Canudas et al. 1995: break-away")
    x = m.dof("x", inertia=1.0)
    m.friction("friction", x, law=LAW)
    m.actuator("u", x)  # applied force [N], an input array
    return m


def breakaway(rate: float, samples: int = 8000) -> tuple[float, float]:
    """(break-away force, peak friction before it) [N] for a ramp of ``rate`` [N/s] up to 4 Fs."""
    T = 4.0 * LAW.static.Fs / rate
    dt = T / samples
    t = np.arange(samples + 1) * dt
    res = fk.simulate_machine(machine(), dt=dt, inputs={"u": rate * t}, raise_on_failure=True)
    slid = np.flatnonzero(res.position("x") > X_BREAK)
    if slid.size == 0:
        raise RuntimeError(f"rate {rate} N/s: no break-away within the ramp")
    k = int(slid[0])
    return float(rate * t[k]), float(res.force("friction")[: k + 1].max())


def main(argv=None) -> dict:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--json", metavar="OUT", help="write {rate, breakaway, peak_friction} to this file")
    ap.add_argument("--rates", type=float, nargs="+", default=RATES, help="force rates [N/s]")
    args = ap.parse_args(argv)
    pairs = [breakaway(r) for r in args.rates]
    out = {"rate": list(args.rates), "breakaway": [a for a, _ in pairs], "peak_friction": [b for _, b in pairs]}
    if args.json:
        with open(args.json, "w") as f:
            json.dump(out, f)
    for r, (fb, fp) in zip(args.rates, pairs):
        print(f"rate {r:8.3f} N/s: break-away at {fb:.4f} N (peak friction before it {fp:.4f} N)")
    return out


if __name__ == "__main__":
    main()
