"""Interval coverage of the SDSS two-step estimation over noise seeds (issue 10).

    python benchmarks/sdss_coverage.py [--seeds 20] [--quick] [--triangle-only] [--max-ripple PCT|none] [--workers N]
                                       [--out DIR] [--json FILE]

Every identified parameter of the azimuth, altitude and rotator per seed (see
:func:`frictionkit.reproduce.sdss.coverage`); one seed per task of the study engine, with its
progress bar. Prints the coverage per axis and overall, the misses, and per parameter the mean
and RMS error in units of the interval's standard error (z).
"""

from __future__ import annotations

import argparse
import json
import time

from frictionkit.reproduce import sdss


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--seeds", type=int, default=20)
    ap.add_argument("--quick", action="store_true")
    ap.add_argument("--triangle-only", action="store_true", help="azimuth sigma0/sigma1 from the triangle alone")
    ap.add_argument("--max-ripple", default=str(sdss.MAX_RIPPLE_PERCENT),
                    help="constant-velocity screen threshold [%% RMS ripple]; 'none' keeps every run (the state before it)")
    ap.add_argument("--workers", type=int, default=0, help="0: this process; N: a LocalCluster of N processes")
    ap.add_argument("--out", default=None, help="directory for the per-seed Parquet parts (a rerun reuses them)")
    ap.add_argument("--json", default=None)
    a = ap.parse_args()
    t0 = time.perf_counter()
    mr = None if a.max_ripple.lower() == "none" else float(a.max_ripple)
    r = sdss.coverage(seeds=range(a.seeds), quick=a.quick, joint=not a.triangle_only, workers=a.workers, out=a.out,
                      max_ripple_percent=mr)
    wall = time.perf_counter() - t0
    print(f"{r['seeds']} seeds, quick={r['quick']}, joint={r['joint']}, max ripple {mr} %, workers={a.workers}: "
          f"{wall:.0f} s wall")
    for axis, s in r["axes"].items():
        print(f"  {axis:9s} {s['hits']:4d} / {s['n']:4d} = {s['percent']:5.1f} %")
        for k, p in s["parameters"].items():
            print(f"      {k:10s} {p['hits']:3d}/{p['n']:3d}  mean z {p['mean_z']:+6.2f}  rms z {p['rms_z']:5.2f}")
    print(f"  overall   {r['hits']:4d} / {r['n']:4d} = {r['percent']:5.1f} %  (issue 10: 85-99 %)")
    print("  misses:", r["misses"])
    if r["failed"]:
        print("  FAILED:", r["failed"])
    if a.json:
        with open(a.json, "w") as f:
            json.dump(r, f, indent=1)


if __name__ == "__main__":
    main()
