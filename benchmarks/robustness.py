"""The reproductions' robustness sweeps on the study engine: this process vs Dask workers.

Runs one robustness sweep (``--quick`` sized variants) three ways in the same run and prints
the wall times and ratios (JSON with ``--json PATH``):

* ``workers=0``: every variant in this process, no Dask (numba kernels warmed first by one
  variant, so compilation is not counted here);
* a LocalCluster of 1 and of 2 single-threaded workers, each from scratch (cluster start-up,
  the workers' imports and numba compilation included: what a user waits for), and the same
  with the start-up and a warm-up variant taken out (``tasks_s``).

The rows of every Dask run are checked equal to the ``workers=0`` rows.

Usage::

    python benchmarks/robustness.py [--sweep zhu-fujimoto|zhang2023] [--json out.json]

``zhang2023`` is 25 variants of about 30 s each (quick): about 13 min serially.
"""

from __future__ import annotations

import argparse
import json
import sys
import tempfile
import time
from pathlib import Path


def _sweep(name: str):
    if name == "zhu-fujimoto":
        from frictionkit.reproduce import zhu_fujimoto as rep

        return rep.robustness, {"quick": True}
    from frictionkit.reproduce import zhang2023 as rep

    return rep.robustness, {"quick": True}


def _warm(name: str) -> float:
    """One variant in this (worker) process: imports and numba compilation done."""
    t0 = time.perf_counter()
    fn, kw = _sweep(name)
    fn(**kw, seeds=(0,), factors=(), workers=0)
    return time.perf_counter() - t0


def _strip(out):
    return {k: v for k, v in out.items() if k not in ("runtime_s", "computed", "skipped", "out")} \
        if "runtime_s" in out else out


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--sweep", choices=("zhu-fujimoto", "zhang2023"), default="zhu-fujimoto")
    ap.add_argument("--json", type=Path, default=None)
    args = ap.parse_args(argv)

    from dask.distributed import Client

    from frictionkit.fleet import local_cluster

    fn, kw = _sweep(args.sweep)
    fn(**kw, seeds=(0,), factors=(), workers=0)  # warm this process's kernels
    t0 = time.perf_counter()
    ref = fn(**kw, workers=0)
    serial = time.perf_counter() - t0
    doc = {"sweep": args.sweep, "variants": len(ref.get("variants", ref)), "serial_s": serial, "cluster": {}}
    for n in (1, 2):
        with tempfile.TemporaryDirectory(prefix="robrun_bench_") as tmp:
            t0 = time.perf_counter()
            cluster = local_cluster(n)
            client = Client(cluster)
            try:
                start = time.perf_counter() - t0
                t1 = time.perf_counter()
                client.run(_warm, args.sweep)  # every worker: imports, numba compilation
                warm = time.perf_counter() - t1
                t2 = time.perf_counter()
                out = fn(**kw, scheduler=client, out=Path(tmp) / "r")
                tasks = time.perf_counter() - t2
            finally:
                client.close()
                cluster.close()
        same = _strip(out) == _strip(ref)
        doc["cluster"][n] = {"startup_s": start, "warmup_s": warm, "tasks_s": tasks,
                             "total_s": start + warm + tasks, "rows_equal_workers0": same}
        print(f"{n} worker(s): start-up {start:.1f} s, warm-up {warm:.1f} s, sweep {tasks:.1f} s "
              f"(rows equal to workers=0: {same})", file=sys.stderr)
    c1, c2 = doc["cluster"][1], doc["cluster"][2]
    doc["speedup_2_vs_1_tasks"] = c1["tasks_s"] / c2["tasks_s"]
    doc["speedup_2_vs_serial_total"] = serial / c2["total_s"]
    print(f"{args.sweep}: {doc['variants']} variants; serial {serial:.1f} s; 2 workers vs 1 (sweep only) "
          f"{doc['speedup_2_vs_1_tasks']:.2f}x; 2 workers incl. start-up vs serial "
          f"{doc['speedup_2_vs_serial_total']:.2f}x")
    if args.json is not None:
        args.json.write_text(json.dumps(doc, indent=2))
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
