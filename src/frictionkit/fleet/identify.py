"""Identify every log of a fleet on Dask, resumably, into one Parquet table.

One task per log file (:func:`~frictionkit.fleet.task.identify_log`: segmentation, the
static map with intervals and model choice, LuGre σ0/σ1 through the reversals where the
data allow, SHA-256 and provenance). Each finished task
writes its row as a one-row Parquet part, atomically, into ``R.parquet.parts/`` beside
the results file ``R.parquet``; the results file is then consolidated from the parts.
Hence:

* **a failing file** gives a row with ``ok = False`` and its ``error``; the job goes on;
* **a rerun skips what is done**: a part named by the file's fingerprint (path, size,
  modification time, configuration, frictionkit version) exists → no task; only missing
  or stale parts are computed;
* **a killed worker loses nothing and duplicates nothing**: the parts already written
  stay; Dask reruns the lost task elsewhere, and its part has the same name, so it
  replaces itself; consolidation also drops duplicate ``(axis, period, file_sha256)``
  rows. A task the cluster gives up on (``KilledWorker`` after Dask's retries) is a row
  with its error but no part, so the next run computes it again.

Execution: a ``dask.distributed.LocalCluster`` by default (``threads_per_worker=1``,
worker processes started with ``OMP/OPENBLAS/MKL/NUMBA_NUM_THREADS=1``: the workers own
the parallelism), an existing cluster given its scheduler address, or a single process
(``scheduler="none"`` or ``workers=0``) running the same task function — the parameter
columns are identical either way.
"""

from __future__ import annotations

import glob as _glob

import logging
import os
import time
from contextlib import contextmanager
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

from ..errors import DataError, ParameterError
from .config import FleetConfig, load_config
from .dataset import LogFile, discover, parts_dir
from .task import _blank_row, identify_log, result_schema
from typing import TYPE_CHECKING

if TYPE_CHECKING:
    import numpy as np
    from matplotlib.axes import Axes

#: Environment of the worker processes of the default LocalCluster: one thread per library.
PIN_ENV = {name: "1" for name in ("OMP_NUM_THREADS", "OPENBLAS_NUM_THREADS", "MKL_NUM_THREADS",
                                   "NUMBA_NUM_THREADS", "VECLIB_MAXIMUM_THREADS", "NUMEXPR_NUM_THREADS")}

#: Name of the configuration file looked for in a dataset folder when none is given.
CONFIG_NAME = "fleet.toml"


@dataclass(frozen=True, kw_only=True)
class FleetRun:
    """What :func:`identify_fleet` did.

    Attributes
    ----------
    out : Path
        The results file.
    table : pandas.DataFrame
        Its rows (one per axis-period), as written.
    tasks, computed, skipped : int
        Log files found; computed in this run; skipped because their part was done.
    failed_tasks : int
        Tasks the cluster could not run (no part written; the next run retries them).
    ok, errors : int
        Rows with a fit; rows with an error (bad files and failed tasks).
    unmatched : tuple of str
        Data files whose path matched no layout pattern (not identified).
    scheduler : str
        ``"none"`` (single process), ``"local"`` (a LocalCluster) or the scheduler address.
    workers : int
        Worker processes used (1 for the single-process path).
    elapsed : float
        Wall time of the whole call [s].
    compute_seconds : float
        Wall time from the first task submitted to the last result [s].
    task_seconds : float
        Sum over the computed tasks of their own run time [s].
    other_version : int
        Tasks recomputed because their axis-period's part was written by another frictionkit
        version (the version is part of each part's fingerprint; a warning says so).
    """

    out: Path
    table: Any = field(repr=False)
    tasks: int
    computed: int
    skipped: int
    failed_tasks: int
    ok: int
    errors: int
    unmatched: tuple
    scheduler: str
    workers: int
    elapsed: float
    compute_seconds: float
    task_seconds: float
    monitored: bool = False
    other_version: int = 0

    @property
    def status(self) -> int:
        """0: every log identified; 1: some rows carry an error; 2: every row does (or none ran)."""
        return 0 if self.tasks and not self.errors else (2 if not self.ok else 1)

    @property
    def message(self) -> str:
        return "ok" if self.status == 0 else f"{self.errors} of {self.ok + self.errors} row(s) with an error"

    def summary(self) -> str:
        d = self.to_dict()
        text = (f"fleet identify: {self.tasks} log file(s), {self.computed} identified, {self.skipped} done before; "
                f"{self.ok} ok, {self.errors} with an error; status {self.status} ({self.message}); {self.out}")
        if self.other_version:
            text += f"\n  {self.other_version} recomputed: their parts were written by another frictionkit version"
        if "flagged_axes" in d:
            text += f"\n  drift flagged on {len(d['flagged_axes'])} axis/axes: {', '.join(d['flagged_axes'][:10])}"
        return text

    def plot(self, ax: Axes | None=None) -> Axes | np.ndarray:
        """Identified Coulomb level (mean of both directions) of each axis over its periods; axes
        flagged by the drift monitor drawn in red. Returns the Axes."""
        import matplotlib.pyplot as plt

        if ax is None:
            _, ax = plt.subplots(figsize=(7, 3.5))
        df = self.table
        if len(df) and {"Fc_pos", "Fc_neg"} <= set(df.columns):
            ok = df[df["ok"].astype(bool)]
            flag = ok["drift_flag"].fillna(False).astype(bool) if "drift_flag" in ok else None
            for axis, g in ok.groupby("axis", sort=True):
                g = g.sort_values("period")
                red = flag is not None and bool(flag.loc[g.index].any())
                ax.plot(g["period"].astype(str), 0.5 * (g["Fc_pos"] + g["Fc_neg"]), ".-",
                        color="C3" if red else "0.6", lw=1.2 if red else 0.6, label=str(axis) if red else None)
            if flag is not None and flag.any():
                ax.legend(title="drift flagged", fontsize=7)
        ax.set_xlabel("period")
        ax.set_ylabel("Fc (mean of both directions)")
        ax.set_title(f"fleet: {self.tasks} log file(s)")
        ax.tick_params(axis="x", labelrotation=60, labelsize=7)
        return ax

    def to_dict(self) -> dict[str, Any]:
        """Plain-data summary (the ``--json`` of ``frictionkit fleet identify``)."""
        out = {"out": str(self.out), "rows": int(len(self.table)), "tasks": self.tasks, "computed": self.computed,
               "skipped": self.skipped, "failed_tasks": self.failed_tasks, "ok": self.ok, "errors": self.errors,
               "unmatched_files": len(self.unmatched), "scheduler": self.scheduler, "workers": self.workers,
               "elapsed_s": round(self.elapsed, 3), "compute_s": round(self.compute_seconds, 3),
               "task_s_total": round(self.task_seconds, 3),
               "task_s_mean": round(self.task_seconds / self.computed, 4) if self.computed else None,
               "monitored": self.monitored, "other_version": self.other_version}
        if self.monitored and "drift_flag" in self.table:
            flagged = self.table.loc[self.table["drift_flag"].fillna(False).astype(bool), "axis"].unique()
            out["flagged_axes"] = sorted(map(str, flagged))
        return out


def resolve_config(dataset, config) -> FleetConfig:
    """``config`` as a :class:`FleetConfig`: given, a TOML path, or ``fleet.toml`` in the dataset folder."""
    if isinstance(config, FleetConfig):
        return config
    if config is not None:
        return load_config(config)
    if isinstance(dataset, (str, Path)) and Path(dataset).is_dir() and (Path(dataset) / CONFIG_NAME).is_file():
        return load_config(Path(dataset) / CONFIG_NAME)
    from .simulate import UNFINISHED

    if isinstance(dataset, (str, Path)) and (Path(dataset) / UNFINISHED).is_file():  # said "no configuration"
        raise DataError(f"fleet dataset '{dataset}': an interrupted 'fleet simulate' ({UNFINISHED}, no "
                        f"{CONFIG_NAME} yet); run the same 'fleet simulate' again to finish it")
    if isinstance(dataset, (str, Path)) and any(c in str(dataset) for c in "*?[") and not _glob.glob(str(dataset)):
        raise DataError(f"fleet dataset '{dataset}': the pattern matches no file")  # before the missing config
    raise DataError(f"fleet dataset '{dataset}': no configuration; pass config= (--config fleet.toml) "
                    f"or put a {CONFIG_NAME} in the dataset folder")


def default_workers() -> int:
    """Cores this process may use."""
    try:
        return max(1, len(os.sched_getaffinity(0)))
    except AttributeError:  # pragma: no cover - not on Linux
        return max(1, os.cpu_count() or 1)


def local_cluster(workers: int | None = None, **kwargs: Any) -> Any:
    """A ``LocalCluster`` of single-threaded worker processes with BLAS/numba pinned to one thread."""
    from dask.distributed import LocalCluster

    opts = dict(n_workers=workers or default_workers(), threads_per_worker=1, processes=True,
                dashboard_address=":0", silence_logs=logging.ERROR, env=dict(PIN_ENV))
    opts.update(kwargs)
    return LocalCluster(**opts)


@contextmanager
def dask_client(scheduler=None, workers: int | None = None, *, timeout=None):
    """``(client, mode)`` for a job: a :func:`local_cluster` when ``scheduler`` is None, a
    cluster by scheduler address (str), or the given ``Client``; what is opened here is closed
    on leaving (a given client is left open)."""
    from dask.distributed import Client

    cluster = client = None
    try:
        if scheduler is None:
            cluster = local_cluster(workers)
            client = Client(cluster)
            mode = "local"
        elif isinstance(scheduler, str):
            client = Client(scheduler) if timeout is None else Client(scheduler, timeout=timeout)
            mode = scheduler
        else:
            client = scheduler
            mode = str(getattr(client, "scheduler", None) and client.scheduler.address)
        yield client, mode
    finally:
        if client is not None and client is not scheduler:
            client.close()
        if cluster is not None:
            cluster.close()


class _Progress:
    def __init__(self, enabled: bool, total: int, label: str) -> None:
        self.bar = None
        self.label = label
        if enabled and total:
            from rich.console import Console
            from rich.progress import BarColumn, MofNCompleteColumn, Progress, TextColumn, TimeElapsedColumn, \
                TimeRemainingColumn

            self.bar = Progress(TextColumn("{task.description}"), BarColumn(), MofNCompleteColumn(),
                                TimeElapsedColumn(), TextColumn("eta"), TimeRemainingColumn(),
                                console=Console(stderr=True), transient=False)
            self.task = self.bar.add_task(label, total=total)
            self.bar.start()

    def advance(self, errors: int) -> None:
        if self.bar is not None:
            self.bar.update(self.task, advance=1,
                            description=f"{self.label} ({errors} error(s))" if errors else self.label)

    def close(self) -> None:
        if self.bar is not None:
            self.bar.stop()


def _failed_row(log: LogFile, config: FleetConfig, exc: BaseException) -> dict[str, Any]:
    row = _blank_row(log, config)
    msg = " ".join(str(exc).split())
    row["error"] = f"task failed on the cluster ({type(exc).__name__}: {msg}); rerun to retry"
    row["error_type"] = type(exc).__name__
    return row


def _run_local(todo: list[LogFile], config: FleetConfig, parts: Path, bar: _Progress) -> tuple[list, list]:
    rows, errors = [], 0
    for log in todo:
        row = identify_log(log, config, str(parts))
        rows.append(row)
        errors += not row["ok"]
        bar.advance(errors)
    return rows, []


def identify_batch(logs: list[LogFile], config: FleetConfig, parts: str) -> list[dict[str, Any]]:
    """:func:`~frictionkit.fleet.task.identify_log` on several files in turn (one Dask task)."""
    return [identify_log(g, config, parts) for g in logs]


def _run_dask(todo: list[LogFile], config: FleetConfig, parts: Path, bar: _Progress, client,
              batch: int = 1) -> tuple[list, list]:
    from dask.distributed import as_completed

    groups = [todo[i:i + batch] for i in range(0, len(todo), batch)]
    futures = [client.submit(identify_batch, g, config, str(parts), key=g[0].key + (f"-x{len(g)}" if len(g) > 1 else ""),
                             pure=False) for g in groups]
    by_key = {f.key: g for f, g in zip(futures, groups)}
    done, failed, errors = [], [], 0
    for fut in as_completed(futures):
        if fut.status == "finished":
            rows = fut.result()
            done += rows
            errors += sum(not r["ok"] for r in rows)
            n = len(rows)
        else:
            exc = fut.exception()
            failed += [_failed_row(g, config, exc) for g in by_key[fut.key]]
            errors += len(by_key[fut.key])
            n = len(by_key[fut.key])
        fut.release()
        for _ in range(n):
            bar.advance(errors)
    return done, failed


def consolidate(logs: list[LogFile], parts: Path, config: FleetConfig, extra_rows: list[dict] = (),
                previous: Path | None = None) -> Any:
    """The results table of ``logs``, deduplicated and sorted.

    Rows come from ``extra_rows`` (this run's results and its failed tasks), then from the
    ``previous`` results file (rows whose fingerprint is still current), then from the parts
    on disk for whatever is left: a rerun reads only what it cannot get otherwise.
    """
    import pandas as pd
    import pyarrow as pa
    import pyarrow.parquet as pq

    schema = result_schema(config)
    tables = []
    have = {r["fingerprint"] for r in extra_rows}
    if extra_rows:
        tables.append(pa.Table.from_pylist(list(extra_rows), schema=schema))
    current = {log.fingerprint for log in logs}
    if previous is not None and Path(previous).is_file() and len(have) < len(current):
        try:
            prev = pq.read_table(previous, columns=schema.names)
        except Exception:  # noqa: BLE001 - unreadable or foreign: fall back to the parts
            prev = None
        if prev is not None:
            fps = prev.column("fingerprint").to_pylist()
            ok_parts = {log.fingerprint for log in logs if (parts / log.part_name).is_file()}
            keep = [fp in current and fp not in have and fp in ok_parts for fp in fps]
            if any(keep):
                t = prev.filter(pa.array(keep)).cast(schema)
                tables.append(t)
                have |= set(t.column("fingerprint").to_pylist())
    for log in logs:
        f = parts / log.part_name
        if log.fingerprint not in have and f.is_file():
            try:
                tables.append(pq.read_table(f, schema=schema))
            except (OSError, ValueError, pa.ArrowException) as exc:  # e.g. a part of another schema
                raise DataError(f"result part '{f}' cannot be read ({' '.join(str(exc).split())[:200]}); delete it "
                                "and rerun: its log is then identified again") from None
    if not tables:
        return schema.empty_table().to_pandas()
    df = pa.concat_tables(tables).to_pandas()
    # a task done twice (identical data) is one row: dedupe by axis, period and content hash
    has_hash = df["file_sha256"].notna()
    dedup = df[has_hash].sort_values("finished_utc").drop_duplicates(["axis", "period", "file_sha256"], keep="last")
    df = pd.concat([dedup, df[~has_hash]], ignore_index=True)
    df = df.sort_values(["axis", "period", "file"], kind="stable").reset_index(drop=True)
    return df


def _complete_part(f: Path) -> bool:
    """A part ends with Parquet's ``PAR1`` trailer; an empty, truncated or foreign file is not done.

    Such a part made every later run fail ("Parquet magic bytes not found") until it was deleted
    by hand (campaign round 5); now its log is identified again and the part rewritten (atomically).
    Reads 4 bytes per part.
    """
    try:
        with open(f, "rb") as fh:
            if fh.seek(0, 2) < 12:
                return False
            fh.seek(-4, 2)
            return fh.read(4) == b"PAR1"
    except OSError:
        return False


def _other_versions(todo: list[LogFile], parts: Path, done: set[str]) -> dict[str, str]:
    """Tasks to run whose axis-period has a part written by another frictionkit version:
    part name -> that part's version (read from its ``frictionkit_version`` column)."""
    import pyarrow.parquet as pq

    from .. import __version__

    out: dict[str, str] = {}
    for log in todo:
        prefix = log.part_name.rsplit("__", 1)[0] + "__"
        for name in done:
            if not name.startswith(prefix) or name == log.part_name:
                continue
            try:
                ver = pq.read_table(parts / name, columns=["frictionkit_version"]).column(0)[0].as_py()
            except Exception:  # noqa: BLE001 - unreadable or foreign part: stale either way, not a version change
                continue
            if ver != __version__:
                out[log.part_name] = str(ver)
    return out


def _remove_stale(parts: Path, logs: list[LogFile]) -> None:
    """Delete parts of the same axis-period made from an older version of a file or configuration."""
    current = {log.part_name for log in logs}
    prefixes = {name.rsplit("__", 1)[0] + "__" for name in current}
    for f in parts.glob("*.parquet"):
        if f.name not in current and f.name.rsplit("__", 1)[0] + "__" in prefixes:
            try:
                f.unlink()
            except OSError:  # pragma: no cover - a concurrent run removed it
                pass


def write_table(df, out: Path) -> None:
    """A DataFrame as Parquet, atomically."""
    import pyarrow as pa
    import pyarrow.parquet as pq

    from .._io import atomic_open

    table = pa.Table.from_pandas(df, preserve_index=False)
    with atomic_open(out, "wb") as f:
        pq.write_table(table, f)


def identify_fleet(
    dataset: str | Path,
    *,
    out: str | Path,
    config: FleetConfig | str | Path | None = None,
    scheduler: str | None=None,
    workers: int | None = None,
    progress: bool = True,
    monitor: bool = True,
    batch: int = 1,
) -> FleetRun:
    """Identify the static friction map of every log of a fleet; one row per axis-period.

    Parameters
    ----------
    dataset : str, Path or list of paths
        Folder of logs (recursive), a glob, or files (see :func:`~frictionkit.fleet.dataset.discover`).
    out : str or Path
        Results Parquet file. Parts go to ``<out>.parts/`` beside it and are kept (they
        make the next run resumable).
    config : FleetConfig, str or Path, optional
        Fleet configuration or its TOML file; default ``fleet.toml`` in the dataset folder.
    scheduler : None, "none", str or distributed.Client
        None: a new LocalCluster with ``workers`` single-threaded processes. ``"none"``:
        no Dask, everything in this process. A string: address of a running scheduler
        (``"tcp://10.0.0.5:8786"``). A ``Client``: use it.
    workers : int, optional
        Worker processes of the LocalCluster (default: the cores available); 0 means
        the single-process path. Not allowed with a scheduler address or client.
    progress : bool
        Show a progress bar on stderr (default True).
    monitor : bool
        Run :func:`~frictionkit.fleet.monitor_drift` on the table before writing it (adds
        ``drift_flag`` and the trend columns); default True.
    batch : int
        Files per Dask task (default 1). On large clusters, several files per task keep the
        scheduler's per-task cost (a few ms) small against the work; every file still
        writes its own part, so resumability is per file.

    Returns
    -------
    FleetRun

    Raises
    ------
    DataError
        No configuration, no log file found, unusable output path.
    ParameterError
        Bad ``workers`` / ``scheduler``.

    Examples
    --------
    >>> from frictionkit.fleet import identify_fleet, simulate_fleet
    >>> simulate_fleet("fleet", axes=6, days=3, seed=1)  # doctest: +SKIP
    >>> run = identify_fleet("fleet", out="results.parquet", workers=2)  # doctest: +SKIP
    >>> run.table[["axis", "period", "ok", "Fc_pos", "Fc_neg"]].head()  # doctest: +SKIP
    """
    t_start = time.perf_counter()
    if workers is not None and (isinstance(workers, bool) or int(workers) != workers or workers < 0):
        raise ParameterError(f"identify_fleet.workers = {workers!r}: must be an integer >= 0")
    if isinstance(batch, bool) or int(batch) != batch or batch < 1:
        raise ParameterError(f"identify_fleet.batch = {batch!r}: must be an integer >= 1")
    single = scheduler == "none" or workers == 0
    if not single and scheduler is not None and workers is not None:
        raise ParameterError("identify_fleet: workers= starts a local cluster; with a scheduler address or "
                             "client the cluster decides (drop workers=)")
    if scheduler is not None and not single and not isinstance(scheduler, str) and not hasattr(scheduler, "submit"):
        raise ParameterError(f"identify_fleet.scheduler = {scheduler!r}: must be None, 'none', an address or a Client")
    cfg = resolve_config(dataset, config)
    out = Path(out)
    if out.is_dir():
        raise DataError(f"out '{out}' is a folder; give a file name (e.g. results.parquet)")
    out.parent.mkdir(parents=True, exist_ok=True)
    logs, unmatched = discover(dataset, cfg, exclude=[out])
    parts = parts_dir(out)
    parts.mkdir(exist_ok=True)
    done = {f.name for f in parts.glob("*.parquet") if _complete_part(f)}
    todo = [log for log in logs if log.part_name not in done]
    other = _other_versions(todo, parts, done)
    if other:
        import warnings

        from .. import __version__

        vers = sorted(set(other.values()))
        warnings.warn(f"{len(other)} result(s) in '{parts}' were written by another frictionkit version "
                      f"({', '.join(vers[:3])}; this is {__version__}): not reused, recomputed", stacklevel=2)

    bar = _Progress(progress, len(todo), "identify")
    rows: list[dict] = []
    failed: list[dict] = []
    mode, n_workers = "none", 1
    t_compute = time.perf_counter()
    try:
        if todo and single:
            rows, failed = _run_local(todo, cfg, parts, bar)
        elif todo:
            with dask_client(scheduler, workers) as (client, mode):
                n_workers = len(client.nthreads())
                rows, failed = _run_dask(todo, cfg, parts, bar, client, int(batch))
    finally:
        bar.close()
    compute = time.perf_counter() - t_compute if todo else 0.0

    df = consolidate(logs, parts, cfg, rows + failed, previous=out)
    computed_names = {log.part_name for log in todo}
    task_s = float(df.loc[df["fingerprint"].isin({log.fingerprint for log in todo}), "task_seconds"].sum()) \
        if computed_names else 0.0
    _remove_stale(parts, logs)
    monitored = False
    if monitor:
        from .drift import monitor_drift

        df = monitor_drift(df, **cfg.monitor)
        monitored = True
    write_table(df, out)
    n_ok = int(df["ok"].sum())
    return FleetRun(out=out, table=df, tasks=len(logs), computed=len(todo) - len(failed), skipped=len(logs) - len(todo),
                    failed_tasks=len(failed), ok=n_ok, errors=int(len(df) - n_ok), unmatched=tuple(unmatched),
                    scheduler=mode, workers=n_workers, elapsed=time.perf_counter() - t_start,
                    compute_seconds=compute, task_seconds=task_s, monitored=monitored, other_version=len(other))


__all__ = ["CONFIG_NAME", "FleetRun", "PIN_ENV", "consolidate", "dask_client", "default_workers", "identify_batch", "identify_fleet",
           "local_cluster", "resolve_config", "write_table"]
