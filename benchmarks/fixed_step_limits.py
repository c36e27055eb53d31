"""How far ``simulate_batch(method="fixed")`` is off, by damping ratio and step (issue 13).

Run:  .venv/bin/python benchmarks/fixed_step_limits.py [--sets 20] [--out rows.jsonl]

The fixed method takes ``batch_substeps`` equal ROS2 sub-steps ``h = dt / batch_substeps`` per sample
without error control. Its limit (``FIXED_STEP_LIMIT``) was measured on damped LuGre sets only; an
undamped contact rings at ``omega = sqrt(sigma0 / m)``, and the L-stable ROS2 stage damps that ringing
numerically (and shifts its phase), so the error of an undamped set grows with ``omega h`` much sooner.

Grid: damping ratio ``zeta = (sigma1 + sigma2) / (2 sqrt(sigma0 m))`` x ``omega h``; at each point
``--sets`` random LuGre sets and as many Dahl sets (``zeta`` from ``sigma2`` alone), half driven by a
sine below breakaway (0.3-0.9 Fs: pre-sliding only), half above it (1.2-3 Fs: stick-slip); sigma0
1e4-1e8 N/m, dt 1e-4-1e-3 s, the mass from ``omega h``; 2 sub-steps per sample (the default); a 1 s run
of a 1-4 Hz sine. Errors against a tight adaptive run (``simulate``, rtol 1e-9, no accuracy check):
RMS of x as a share of the stroke (the reference's range of x) and of the friction as a share of its
range from the batch kernel itself (its sse with the reference trace as the target; called directly, as
``simulate_batch`` returns no number for a set beyond its limit), max from the fixed scheme's scalar
twin (the ROS2 kernel with loose tolerances takes exactly one step per sub-step,
``tests/kernels/test_batch.py``); the twin's RMS is kept too (``twin_rms_*``): it equals the batch's
except on chaotic stick-slip (lightly damped at large omega h), where rounding differences grow.

Prints, per model and zeta, the worst set's RMS x error (% of the stroke) at each omega h, then the
same for the friction and the median, and the largest omega h on the grid whose worst RMS x error
stays within ``BOUND`` (0.25 % of the stroke: the fixed method's documented accuracy), below and
above breakaway apart: ``FIXED_RING_LIMITS_BELOW`` / ``_ABOVE`` in ``simulation/core.py``.

Measured 2026-11-24 (seed 13, 20 sets, 2,239 sets with a reference; split over three processes with
``--zetas``, tables merged with ``--tables``): below breakaway zeta 0 / 0.01: 0.02, 0.05: 0.1, 0.1 and
up: 0.5; above: zeta 0: 0.05, 0.01: 0.2, 0.05: 0.3, 0.1: 0.1, 0.3: 0.3, 0.7 / 1: 0.2, 2: 0.5 (a row of
the tables covering several grid zetas takes the smallest of their limits: from 0.3 on, 0.2).
"""
from __future__ import annotations

import argparse
import json
import math
import time
import warnings

import numpy as np

import frictionkit as fk
from frictionkit.kernels import batch as _batch
from frictionkit.kernels.lugre import lugre_force_ros2
from frictionkit.models.pack import pack_lugre

ZETAS = (0.0, 0.01, 0.05, 0.1, 0.3, 0.7, 1.0, 2.0)
OMEGA_H = (0.01, 0.02, 0.05, 0.1, 0.2, 0.3, 0.5)
N_SUB = 2
DURATION = 1.0  # s
BOUND = 2.5e-3  # RMS x error, share of the stroke: what FIXED_STEP_LIMIT's docs promise
TIGHT_RTOL = 1e-9  # the reference run; atol_v fixed at TIGHT_RTOL x the pre-sliding velocity scale (from rest
# the default, which follows the speed so far, exhausts the sub-step budget on undamped contacts)


def random_set(rng, kind, zeta, wh, below):
    """One random set at damping ratio ``zeta`` and ``omega h = wh``: (law, m, dt, u)."""
    Fc = 10 ** rng.uniform(-1, 1)
    Fs = Fc * rng.uniform(1.0, 2.0)
    sigma0 = 10 ** rng.uniform(4, 8)
    dt = 10 ** rng.uniform(-4, -3)
    h = dt / N_SUB
    m = sigma0 * (h / wh) ** 2
    c = 2.0 * zeta * math.sqrt(sigma0 * m)
    if kind == "dahl":
        law = fk.Dahl(Fc=Fc, sigma0=sigma0, sigma2=c)
        Fs = Fc
    else:
        s2 = c * rng.uniform(0.0, 0.3)
        law = fk.LuGre(fk.Stribeck(Fc=Fc, Fs=Fs, vs=10 ** rng.uniform(-4, -2), sigma2=s2), sigma0=sigma0,
                       sigma1=c - s2)
    amp = Fs * (rng.uniform(0.3, 0.9) if below else rng.uniform(1.2, 3.0))
    n = int(round(DURATION / dt)) + 1
    u = amp * np.sin(2 * np.pi * rng.uniform(1.0, 4.0) * np.arange(n) * dt)
    return law, m, dt, u


def fixed_trace(law, m, dt, u):
    """The fixed method's trace (x, F) at every sample: the scalar twin of the batch kernel."""
    pk = pack_lugre(law)
    n = u.size
    nf = (n - 1) * N_SUB + 1
    uf = np.interp(np.arange(nf) / N_SUB, np.arange(n), u)
    x, v, F, z = (np.empty(nf) for _ in range(4))
    lugre_force_ros2(uf, dt / N_SUB, m, pk.static, pk.dyn, 0.0, 0.0, 0.0, 1e300, 1e300, 1e300, 10, x, v, F, z)
    return x[::N_SUB], F[::N_SUB]


def one(law, m, dt, u):
    pk = pack_lugre(law)
    vscale = float(pk.static[:, :2].max()) / math.sqrt(float(pk.dyn[:, 0].max()) * m)
    tight = fk.SimOptions(rtol=TIGHT_RTOL, atol_v=TIGHT_RTOL * vscale, max_substeps=100_000, check=False)
    ref = fk.simulate(law, plant=fk.Mass(m), force=u, dt=dt, options=tight)
    if ref.status != 0:
        return None
    out = {}
    x, F = fixed_trace(law, m, dt, u)
    static, dyn = pk.static[None], pk.dyn[None]
    w = np.ones(u.size)
    for name, a, b, which in (("x", x, ref.x, 0), ("F", F, ref.friction, 2)):
        span = max(float(np.ptp(b)), 1e-300)
        sse, st = np.empty(1), np.empty(1, dtype=np.int64)
        # the batch kernel itself (simulate_batch would return status 4 and no number beyond its limit)
        _batch.lugre_fixed_batch_sse(u, dt, np.array([m]), static, dyn, N_SUB, b, which, w,
                                     _batch.chunk_modes(static, dyn), sse, st)
        out[f"rms_{name}"] = math.sqrt(float(sse[0]) / (u.size - 1)) / span if st[0] == 0 else math.inf
        out[f"max_{name}"] = float(np.max(np.abs(a - b))) / span
        # the twin's RMS: equal to the batch's unless the run is chaotic (rounding differences grow)
        out[f"twin_rms_{name}"] = float(np.sqrt(np.mean((a[1:] - b[1:]) ** 2))) / span
    out["status"] = int(fk.simulate_batch([law], masses=m, force=u, dt=dt, target=ref.x, method="fixed",
                                          options=fk.SimOptions(batch_substeps=N_SUB)).status[0])
    return out


def table(rows, kind, key, stat):
    print(f"\n{kind}: {stat} {key} (% of the {'stroke' if key.endswith('x') else 'friction range'})")
    print("  zeta  " + "".join(f"{wh:>9g}" for wh in OMEGA_H))
    for z in ZETAS:
        cells = []
        for wh in OMEGA_H:
            vals = [r[key] for r in rows if r["kind"] == kind and r["zeta"] == z and r["wh"] == wh]
            if not vals:
                cells.append(f"{'-':>9}")
                continue
            v = max(vals) if stat == "worst" else float(np.median(vals))
            cells.append(f"{100 * v:9.3g}")
        print(f"  {z:<5g} " + "".join(cells))


def limits(rows):
    """The largest grid omega h per zeta within BOUND, below and above breakaway apart: the tables of
    simulation/core.py FIXED_RING_LIMITS_BELOW / _ABOVE."""
    for below in (True, False):
        print(f"\nlargest omega h on the grid whose worst RMS x error is <= {100 * BOUND:g} % of the stroke, "
              f"{'below' if below else 'above'} breakaway (LuGre and Dahl together; every smaller grid point too):")
        for z in ZETAS:
            best = None
            for wh in OMEGA_H:
                vals = [r["rms_x"] for r in rows if r["zeta"] == z and r["wh"] == wh and r["below"] == below]
                if vals and max(vals) <= BOUND:
                    best = wh
                else:
                    break
            print(f"  zeta {z:<5g}: {best}")


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--sets", type=int, default=20, help="random sets per model and grid point")
    ap.add_argument("--out", help="also write every set as a JSON line here")
    ap.add_argument("--seed", type=int, default=13)
    ap.add_argument("--zetas", help="run only these damping ratios (comma-separated; the other points' sets are "
                                    "drawn and skipped, so each set is the one a full run takes)")
    ap.add_argument("--tables", nargs="+", help="print the tables of these --out files and stop")
    a = ap.parse_args()
    if a.tables:
        return report([json.loads(line) for p in a.tables for line in open(p)])
    only = None if a.zetas is None else {float(z) for z in a.zetas.split(",")}
    rng = np.random.default_rng(a.seed)
    rows = []
    skipped = 0  # sets whose reference run failed (none expected)
    t0 = time.process_time()
    fh = open(a.out, "w") if a.out else None
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", RuntimeWarning)
        for z in ZETAS:
            for wh in OMEGA_H:
                for kind in ("lugre", "dahl"):
                    for j in range(a.sets):
                        law, m, dt, u = random_set(rng, kind, z, wh, below=j % 2 == 0)
                        if only is not None and z not in only:
                            continue
                        r = one(law, m, dt, u)
                        if r is None:
                            skipped += 1
                            continue
                        r.update(kind=kind, zeta=z, wh=wh, below=j % 2 == 0, m=m, dt=dt)
                        rows.append(r)
                        if fh:
                            fh.write(json.dumps(r) + "\n")
                if only is not None and z not in only:
                    continue
                print(f"zeta {z:g} omega h {wh:g}: {len(rows)} sets ({skipped} without a reference), "
                      f"{time.process_time() - t0:.0f} s CPU",
                      flush=True)
    report(rows)


def report(rows):
    for kind in ("lugre", "dahl"):
        table(rows, kind, "rms_x", "worst")
        table(rows, kind, "max_x", "worst")
        table(rows, kind, "rms_F", "worst")
        table(rows, kind, "rms_x", "median")
    limits(rows)
    odd = sum(abs(r["twin_rms_x"] - r["rms_x"]) > 1e-3 * r["rms_x"] for r in rows)
    print(f"\n{odd} of {len(rows)} sets whose twin's RMS x differs from the batch's by > 0.1 % (chaotic runs)")


if __name__ == "__main__":
    main()
