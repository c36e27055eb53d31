"""One fleet task: read one log, find its plateaus, fit the static map, return one row.

:func:`identify_log` never raises for a bad file: whatever goes wrong reading,
segmenting or fitting it ends in a row with ``ok = False`` and the one-line ``error``.
With ``parts`` given, the row is also written there as a one-row Parquet file, atomically
(:mod:`frictionkit._io`), named by axis, period and fingerprint — so a task that runs
twice (a worker killed after writing, the task rescheduled) replaces its own part and
never duplicates it, and a part on disk is a finished task.

The result schema (:func:`result_schema`) is fixed, error rows included, so parts
concatenate and query (DuckDB, pandas) without type surprises.
"""

from __future__ import annotations

import datetime as _dt
import hashlib
import os
import time
import warnings
from pathlib import Path
from typing import Any

import numpy as np

from ..errors import DataError
from .config import FleetConfig
from .dataset import LogFile
from typing import TYPE_CHECKING

if TYPE_CHECKING:
    import pyarrow as pa

#: Static-map parameters reported per direction (NaN where the chosen structure has none).
PARAMS = ("Fc", "Fs", "vs", "delta", "sigma2")
DIRECTIONS = ("pos", "neg")

#: Static-map columns: ``Fc_pos``, ``Fc_pos_se``, ``Fc_pos_lo``, ``Fc_pos_hi`` ... (95 % intervals).
STATIC_COLUMNS = tuple(f"{p}_{d}{s}" for d in DIRECTIONS for p in PARAMS for s in ("", "_se", "_lo", "_hi"))
#: Dynamic (LuGre) columns, NaN where the data do not allow the fit.
DYNAMIC_COLUMNS = ("mass", "mass_se", *(f"{p}{s}" for p in ("sigma0", "sigma1") for s in ("", "_se", "_lo", "_hi")),
                   "lugre_rms")
#: Every identified parameter column.
PARAM_COLUMNS = STATIC_COLUMNS + DYNAMIC_COLUMNS


def result_schema(config: FleetConfig) -> pa.Schema:
    """The pyarrow schema of a results row for ``config`` (scheduling columns included)."""
    import pyarrow as pa

    f64, i64, s, b = pa.float64(), pa.int64(), pa.string(), pa.bool_()
    fields = [
        ("axis", s), ("period", s), ("ok", b), ("error", s), ("error_type", s),
        ("model_pos", s), ("model_neg", s),
        *[(c, f64) for c in PARAM_COLUMNS],
        ("n_reversals", i64),
        ("n_samples", i64), ("duration_s", f64), ("n_points_pos", i64), ("n_points_neg", i64),
        ("rms_pos", f64), ("rms_neg", f64), ("warnings", s),
        *[(name, f64) for name in config.schedule],
        ("unit_F", s), ("unit_v", s),
        ("file", s), ("file_sha256", s), ("file_size", i64), ("file_mtime_ns", i64), ("fingerprint", s),
        ("config_sha256", s), ("frictionkit_version", s), ("worker", s), ("task_seconds", f64),
        ("finished_utc", s),
    ]
    return pa.schema([pa.field(n, t) for n, t in fields])


def _blank_row(log: LogFile, config: FleetConfig) -> dict[str, Any]:
    from .. import __version__

    row: dict[str, Any] = {"axis": log.axis, "period": log.period, "ok": False, "error": None, "error_type": None,
                           "model_pos": None, "model_neg": None}
    row.update({c: float("nan") for c in PARAM_COLUMNS})
    row.update({"n_reversals": 0, "n_samples": None, "duration_s": float("nan"), "n_points_pos": 0, "n_points_neg": 0,
                "rms_pos": float("nan"), "rms_neg": float("nan"), "warnings": None})
    row.update({name: float("nan") for name in config.schedule})
    row.update({"unit_F": config.si_units.get("F"), "unit_v": config.si_units.get("v"),
                "file": log.file, "file_sha256": None, "file_size": log.size, "file_mtime_ns": log.mtime_ns,
                "fingerprint": log.fingerprint, "config_sha256": config.sha256, "frictionkit_version": __version__,
                "worker": None, "task_seconds": float("nan"), "finished_utc": None})
    return row


def _sha256(path: str) -> str:
    h = hashlib.sha256()
    with open(path, "rb") as fh:
        for chunk in iter(lambda: fh.read(1 << 20), b""):
            h.update(chunk)
    return h.hexdigest()


def _one_line(exc: BaseException) -> tuple[str, str]:
    from ..errors import FrictionKitError

    msg = " ".join(str(exc).split())
    if isinstance(exc, OSError) and exc.strerror:
        msg = f"'{exc.filename}': {exc.strerror}" if exc.filename else exc.strerror
    if not isinstance(exc, (FrictionKitError, ValueError, OSError)) or not msg:
        msg = f"{type(exc).__name__}: {msg}" if msg else type(exc).__name__
    return msg, type(exc).__name__


def _worker_name() -> str:
    try:
        from distributed import get_worker

        return get_worker().address
    except (ImportError, ValueError):
        return f"local:{os.getpid()}"


def _fill(row: dict[str, Any], res) -> None:
    for label, d in (("positive", "pos"), ("negative", "neg")):
        part = res.parts.get(label)
        if part is None:
            continue
        row[f"model_{d}"] = part.model_name
        row[f"n_points_{d}"] = int(part.n_obs)
        row[f"rms_{d}"] = float(part.rms)
        for name, val, se, ci in zip(part.names, part.values, part.stderr, part.ci95):
            row[f"{name}_{d}"] = float(val)
            row[f"{name}_{d}_se"] = float(se)
            row[f"{name}_{d}_lo"] = float(ci[0])
            row[f"{name}_{d}_hi"] = float(ci[1])


def _dynamic(row: dict[str, Any], rec, res) -> list[str]:
    """LuGre σ0, σ1 through the reversals into ``row``; what went wrong as notes (never an error row)."""
    from ..identify.static_map import stribeck_model
    from .dynamic import fit_lugre_reversals

    try:
        with np.errstate(all="ignore"):
            d = fit_lugre_reversals(rec, stribeck_model(res))
    except Exception as exc:  # noqa: BLE001 - the static map stands without the dynamics
        return [f"LuGre not fitted: {_one_line(exc)[0]}"]
    if not d["ok"]:
        return [f"LuGre not fitted: {d['message']}"]
    for c in DYNAMIC_COLUMNS:
        if c in d:
            row[c] = float(d[c])
    row["lugre_rms"] = float(d["rms"])
    row["n_reversals"] = int(d["n_reversals"])
    return list(d["warnings"])


def _recording(log: LogFile, config: FleetConfig, row: dict[str, Any], notes: list[str]):
    """The log's Recording; with ``[layout] record_column``, a dict of its records (name → Recording)."""
    from ..data.loaders import _build, _column, read_table
    from .dataset import select_rows

    table = read_table(log.path)
    p = Path(log.path)
    rows = select_rows(table, log.select, p)  # None: the whole file
    roles = {role: config.columns.get(role) for role in ("time", "position", "velocity", "force", "current")}
    scales = {k: v for k, v in config.scales.items() if k != "current_gain"}
    prov = {"sha256": row["file_sha256"], "axis": log.axis, "period": log.period}
    if log.select:
        prov["select"] = {c: v for c, v in log.select}

    def build(idx, name, **extra):
        return _build(table, p, roles, scales, idx, current_gain=config.scales.get("current_gain"),
                      units=dict(config.si_units), name=name, extra_prov={**prov, **extra})

    rcol = config.layout.get("record_column")
    if rcol is None:
        rec = build(rows, f"{log.axis} {log.period}")
    else:
        if rcol not in table:
            raise DataError(f"file '{p}': column '{rcol}' ([layout] record_column) not found")
        idx = np.arange(len(np.asarray(table[rcol]))) if rows is None else rows
        labels = np.asarray(table[rcol])[idx].astype(str)
        rec = {}
        for lab in dict.fromkeys(labels.tolist()):  # records in file order
            rec[lab] = build(idx[labels == lab], f"{log.axis} {log.period} {lab}", record=lab)
    for name, spec in config.schedule.items():
        col = spec["column"]
        if col not in table:
            notes.append(f"scheduling column '{col}' ({name}) not found")
            continue
        vals = _column(table, p, name, col)
        if rows is not None:
            vals = vals[rows]
        fin = np.isfinite(vals)
        if fin.any():
            row[name] = float(np.mean(vals[fin]))
        if not fin.all():
            notes.append(f"{int((~fin).sum())} non-finite sample(s) in scheduling column '{col}' ignored")
    return rec


def identify_log(log: LogFile, config: FleetConfig, parts: str | None = None) -> dict[str, Any]:
    """Identify the static friction map (and LuGre σ0, σ1 where the data allow) of one log; one
    results row, never an exception for bad data.

    Parameters
    ----------
    log : LogFile
        The file (from :func:`~frictionkit.fleet.dataset.discover`).
    config : FleetConfig
        Columns, units, segmentation and fit settings.
    parts : str, optional
        Folder to write the row to as ``log.part_name`` (atomically).

    Returns
    -------
    dict
        One row of :func:`result_schema`: axis, period, ok, error, the static-map parameters per
        direction with standard errors and 95 % intervals, the chosen structures, the means of
        the scheduling columns, the file's SHA-256 and the provenance.
    """
    from ..data.segmentation import steady_state_points
    from ..identify.static_map import fit_static_map

    t0 = time.perf_counter()
    row = _blank_row(log, config)
    notes: list[str] = []
    try:
        _pin_threads()
        row["file_sha256"] = _sha256(log.path)
        with warnings.catch_warnings(record=True) as caught:
            warnings.simplefilter("always")
            rec = _recording(log, config, row, notes)
            records = rec if isinstance(rec, dict) else None
            pieces = list(records.values()) if records else [rec]
            row["n_samples"] = int(sum(r.n for r in pieces))
            row["duration_s"] = float(sum(r.duration for r in pieces))
            with np.errstate(all="ignore"):
                if records:  # one steady-state point per record, averaged whole (trim: [segmentation])
                    pts = steady_state_points(records, trim=config.segmentation.get("trim"))
                else:
                    pts = _plateau_points(rec, config.segmentation)
                res = fit_static_map(pts, units=dict(config.si_units), **config.fit)
        _fill(row, res)
        if config.dynamic.get("lugre", True) and records:
            notes.append("LuGre not fitted: the log is separate steady-state records, not one continuous run")
        elif config.dynamic.get("lugre", True):
            notes += _dynamic(row, rec, res)
        notes += [" ".join(str(w.message).split()) for w in caught
                  if not issubclass(w.category, RuntimeWarning) or "encountered" not in str(w.message)]
        notes += list(res.warnings)
        row["ok"] = True
    except (KeyboardInterrupt, SystemExit, MemoryError):
        raise
    except Exception as exc:  # noqa: BLE001 - every failure of a file becomes its row
        row["error"], row["error_type"] = _one_line(exc)
    row["warnings"] = "; ".join(dict.fromkeys(notes)) or None
    row["worker"] = _worker_name()
    row["task_seconds"] = time.perf_counter() - t0
    row["finished_utc"] = _dt.datetime.now(_dt.timezone.utc).isoformat(timespec="milliseconds")
    if parts is not None:
        write_part(row, Path(parts) / log.part_name, config)
    return row


def _plateau_points(rec, segmentation: dict):
    """Steady-state points of one log: :func:`~frictionkit.data.steady_state_points` with the
    ``[segmentation]`` keywords; ``settle`` (a fraction) drops that much more of each plateau
    at its start, where the friction is still settling from the previous speed (the
    pre-sliding state of a LuGre-like contact lags by ``~g(v)/(σ0·|v|)``: 30-120 ms at
    0.5 mm/s on the simulated fleet)."""
    from ..data.segmentation import Segment, _velocity, find_plateaus, steady_state_points

    seg = dict(segmentation)
    settle = float(seg.pop("settle", 0.0))
    if settle <= 0.0:
        return steady_state_points(rec, **seg)
    plateaus = find_plateaus(_velocity(rec), rec.dt, **seg)
    kept = []
    for s in plateaus:
        start = s.start + int(settle * len(s))
        if s.stop - start >= max(2, int(seg.get("min_samples", 10))):
            kept.append(Segment(start=start, stop=s.stop, direction=s.direction, kind=s.kind, amplitude=s.amplitude))
    return steady_state_points(rec, plateaus=kept)


def write_part(row: dict[str, Any], path: Path, config: FleetConfig) -> None:
    """One row as a one-row Parquet file, written atomically."""
    import pyarrow as pa
    import pyarrow.parquet as pq

    from .._io import atomic_open

    table = pa.Table.from_pylist([row], schema=result_schema(config))
    with atomic_open(path, "wb") as f:
        pq.write_table(table, f)


_PINNED = False


def _pin_threads() -> None:
    """One thread per task: the workers own the parallelism (numba's pool; BLAS via the worker env)."""
    global _PINNED
    if _PINNED or _worker_name().startswith("local:"):  # never change the caller's own process
        return
    _PINNED = True
    try:
        from .._jit import set_threads

        set_threads(1)
    except ValueError:  # pragma: no cover
        pass


__all__ = ["DIRECTIONS", "DYNAMIC_COLUMNS", "PARAMS", "PARAM_COLUMNS", "STATIC_COLUMNS", "identify_log",
           "result_schema", "write_part"]
