"""Pre-sliding displacement: a unit mass under a slow force ramp that stays below break-away.

The pre-sliding experiment of Canudas de Wit, Olsson, Åström and Lischinsky (IEEE TAC 1995),
paper parameters (sigma0 = 1e5 N/m, sigma1 = sqrt(1e5) N·s/m, sigma2 = 0.4 N·s/m, Fc = 1 N,
Fs = 1.5 N, vs = 1e-3 m/s, m = 1 kg). The applied force rises at 0.1 N/s to 90 % of Fs, falls
to -90 % and rises again: the mass moves by micrometres like a (hysteretic) spring and never
slides. On the first rise, quasi-statically, ``sigma0 z = u`` and ``dz/dx = 1 - sigma0 z / Fs``
give the closed form ``x = -(Fs / sigma0) ln(1 - u / Fs)`` (the LuGre pre-sliding creep).

    python examples/canudas1995_presliding.py --json OUT

writes ``{"t", "u", "x", "friction", "x_closed_form"}`` (the closed form on the first rise, null after).
"""

from __future__ import annotations

import argparse
import json
import math

import numpy as np

import frictionkit as fk

LAW = fk.LuGre(fk.Stribeck(Fc=1.0, Fs=1.5, vs=1e-3, sigma2=0.4), sigma0=1e5, sigma1=math.sqrt(1e5))
RATE = 0.1  # N/s
PEAK = 0.9 * 1.5  # N


def machine() -> fk.Machine:
    m = fk.Machine("Canudas et al. 1995: pre-sliding")
    x = m.dof("x", inertia=1.0)
    m.friction("friction", x, law=LAW)
    m.actuator("u", x)  # applied force [N], an input array
    return m


def force(dt: float = 1e-3, rate: float = RATE, peak: float = PEAK) -> np.ndarray:
    """0 -> +peak -> -peak -> +peak at ``rate`` [N/s], sampled at ``dt``."""
    T = peak / rate
    t = np.arange(int(round(5.0 * T / dt)) + 1) * dt
    return np.interp(t, [0.0, T, 3.0 * T, 5.0 * T], [0.0, peak, -peak, peak])


def closed_form(u: np.ndarray, law=LAW) -> np.ndarray:
    """Quasi-static LuGre pre-sliding displacement under a rising force ``u < Fs`` from rest."""
    Fs = law.static.Fs
    return -(Fs / law.sigma0) * np.log1p(-np.asarray(u) / Fs)


def run(dt: float = 1e-3) -> dict:
    u = force(dt)
    res = fk.simulate_machine(machine(), dt=dt, inputs={"u": u}, raise_on_failure=True)
    rise = int(np.argmax(u))  # end of the first rise
    xc = [float(v) for v in closed_form(u[: rise + 1])] + [None] * (u.size - rise - 1)
    return {"t": res.t.tolist(), "u": u.tolist(), "x": res.position("x").tolist(),
            "friction": res.force("friction").tolist(), "x_closed_form": xc}


def main(argv=None) -> dict:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--json", metavar="OUT", help="write {t, u, x, friction, x_closed_form} to this file")
    ap.add_argument("--dt", type=float, default=1e-3, help="sample period [s] (default 1e-3)")
    args = ap.parse_args(argv)
    out = run(args.dt)
    if args.json:
        with open(args.json, "w") as f:
            json.dump(out, f)
    x = np.array(out["x"])
    rise = int(np.argmax(out["u"]))
    print(f"pre-sliding: x = {x[rise] * 1e6:.3f} um at u = {out['u'][rise]:.3f} N "
          f"(closed form {out['x_closed_form'][rise] * 1e6:.3f} um); stroke {np.ptp(x) * 1e6:.3f} um, "
          f"max |v| {np.abs(np.gradient(x, args.dt)).max() * 1e6:.2f} um/s")
    return out


if __name__ == "__main__":
    main()
