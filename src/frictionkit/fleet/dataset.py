"""Find the log files of a fleet and give each its axis, period and fingerprint.

A dataset is a folder (searched recursively), a glob (``"plant/*/2026-*.parquet"``), a
list of files or one file. Axis and period come from each path relative to the dataset folder
through the configuration's patterns (:attr:`FleetConfig.patterns`): by default
``AXIS/PERIOD.ext`` and Hive-style partitions ``axis=AXIS/date=PERIOD/part.parquet``;
or from columns of the file (``[layout] axis_column``, ``period_column``: one unpartitioned
file holding many axes and dates gives one task per value pair, :attr:`LogFile.select`),
or from constants (``[layout] axis``, ``period``).

The fingerprint of a file is a hash of its relative path, size, modification time, the
configuration and the frictionkit version: a result part carrying it is still valid
(the rerun skips the file); any change recomputes it. Checking it costs one ``stat`` per
file — no file is read to decide what is done (files split by columns have their key columns
read once, to list their tasks). The content hash (SHA-256, of the whole file) is computed
by the task that reads the file and stored with its result.
"""

from __future__ import annotations

import glob as _glob
import hashlib
import os
import re
from collections.abc import Iterable
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from ..data.loaders import SUFFIXES
from ..errors import DataError
from .config import FleetConfig

#: Suffix of the folder of per-task result parts beside a results file.
PARTS_SUFFIX = ".parts"


@dataclass(frozen=True, kw_only=True)
class LogFile:
    """One log file of the fleet: one task.

    Attributes
    ----------
    axis, period : str
        From the path (see :attr:`FleetConfig.patterns`).
    path : str
        Absolute path.
    file : str
        Path relative to the dataset folder (``/`` separated).
    size, mtime_ns : int
        From ``stat``.
    fingerprint : str
        Hash of ``file``, ``size``, ``mtime_ns``, ``select``, the configuration and the
        frictionkit version.
    select : tuple of (str, value)
        Rows of the file that are this task: ``(column, value)`` pairs all equal (empty: the
        whole file).
    """

    axis: str
    period: str
    path: str
    file: str
    size: int
    mtime_ns: int
    fingerprint: str
    select: tuple = ()

    @property
    def part_name(self) -> str:
        """File name of this task's result part (unique per axis, period and fingerprint)."""
        return f"{_safe(self.axis)}__{_safe(self.period)}__{self.fingerprint[:20]}.parquet"

    @property
    def key(self) -> str:
        """Dask task key."""
        return "fleet-identify-" + self.part_name[: -len(".parquet")]


def _safe(text: str) -> str:
    return re.sub(r"[^A-Za-z0-9._-]", "_", text)[:80]


def _magic(s: str) -> bool:
    return any(c in s for c in "*?[")


def _candidates(dataset) -> tuple[Path, list[Path]]:
    if isinstance(dataset, (list, tuple)):
        paths = [Path(p).absolute() for p in dataset]
        if not paths:
            raise DataError("fleet dataset: the list of files is empty")
        for p in paths:
            if not p.is_file():
                raise DataError(f"fleet dataset: file '{p}' not found")
        root = Path(os.path.commonpath([str(p.parent) for p in paths]))
        return root, paths
    text = str(dataset)
    if _magic(text):
        parts = Path(text).parts
        k = next(i for i, s in enumerate(parts) if _magic(s))
        root = Path(*parts[:k]) if k else Path(".")
        paths = [Path(p).absolute() for p in sorted(_glob.glob(text, recursive=True)) if Path(p).is_file()]
        _unreadable_folders(f"fleet dataset '{text}'", _glob_folders(text, k))
        if not paths:
            raise DataError(f"fleet dataset '{text}': the pattern matches no file")
        return root.absolute(), paths
    root = Path(text)
    if not root.exists():
        raise DataError(f"fleet dataset '{root}': not found")
    if root.is_file():  # one file (e.g. many axes and dates in one Parquet file)
        return root.parent.absolute(), [root.absolute()]
    paths, unreadable = [], []
    # os.walk skips a folder it cannot list without a word: an unreadable axis folder left that
    # axis out of the table silently (issue 13 round 6); such a folder is named instead
    for dirpath, dirnames, filenames in os.walk(root, onerror=unreadable.append):
        dirnames[:] = sorted(d for d in dirnames if not d.startswith(".") and not d.endswith(PARTS_SUFFIX))
        paths += [Path(dirpath, f).absolute() for f in sorted(filenames) if not f.startswith(".")]
    _unreadable_folders(f"fleet dataset '{root}'", unreadable)
    return root.absolute(), paths


def _glob_folders(text: str, k: int) -> list[OSError]:
    """The folders a glob would descend into but cannot list (``glob`` skips them without a word:
    issue 13 round 6 left over — ``fleet/axis-*/*.csv`` left out an unreadable axis folder)."""
    parts = Path(text).parts
    if any("**" in s for s in parts):  # recursive: every folder under the pattern's fixed prefix
        errors: list[OSError] = []
        for _dirpath, dirnames, _f in os.walk(Path(*parts[:k]) if k else Path("."), onerror=errors.append):
            dirnames[:] = [d for d in dirnames if not d.startswith(".")]
        return errors
    errors = []
    for i in range(k + 1, len(parts)):  # each folder level at or below the first wildcard
        for d in sorted(_glob.glob(str(Path(*parts[:i])))):
            if os.path.isdir(d):
                try:
                    with os.scandir(d):
                        pass
                except OSError as exc:
                    errors.append(exc)
    return errors


def _unreadable_folders(where: str, unreadable: list[OSError]) -> None:
    if unreadable:
        named = ", ".join(f"'{e.filename}' ({e.strerror or type(e).__name__})" for e in unreadable[:3])
        raise DataError(f"{where}: {len(unreadable)} folder(s) cannot be read: {named}"
                        + (" ..." if len(unreadable) > 3 else "") + "; their logs would be left out — make them "
                        "readable, or give the other folders or a glob")


def discover(dataset: str | Path, config: FleetConfig, *, exclude: Iterable[str | Path] = ()) -> tuple[list[LogFile], list[str]]:
    """Log files of a dataset with axis, period and fingerprint.

    Parameters
    ----------
    dataset : str, Path or list of paths
        Folder, glob or files.
    config : FleetConfig
        Patterns for axis and period.
    exclude : iterable of paths
        Files never taken as logs (the results file of the run).

    Returns
    -------
    logs : list of LogFile
        Sorted by axis, period, file.
    unmatched : list of str
        Data files (by suffix) whose path matches no pattern, relative to the folder; files
        the configuration ignores (:attr:`FleetConfig.ignore`) are in neither list.

    Raises
    ------
    DataError
        The dataset does not exist, or no file in it matches the patterns.
    """
    from .. import __version__

    root, paths = _candidates(dataset)
    skip = {os.path.realpath(p) for p in exclude if p is not None}
    cfg_hash = config.sha256
    logs, unmatched = [], []
    for p in paths:
        if p.suffix.lower() not in SUFFIXES or os.path.realpath(p) in skip:
            continue
        if any(part.endswith(PARTS_SUFFIX) for part in p.parts):
            continue
        try:
            rel = p.relative_to(root).as_posix()
        except ValueError:
            rel = p.as_posix()
        if config.ignores(rel):  # a side file beside the recordings (fleet simulate's truth.csv ...)
            continue
        hit = config.match(rel) or config.match(p.as_posix())  # e.g. a list of one axis's files
        if hit is None:
            unmatched.append(rel)
            continue
        st = p.stat()
        for axis, period, select in _tasks_of(p, hit, config):
            key = f"{rel}\0{st.st_size}\0{st.st_mtime_ns}\0{cfg_hash}\0{__version__}"
            if select:
                key += "\0" + repr(select)
            fp = hashlib.sha256(key.encode()).hexdigest()
            logs.append(LogFile(axis=axis, period=period, path=str(p), file=rel, size=int(st.st_size),
                                mtime_ns=int(st.st_mtime_ns), fingerprint=fp, select=select))
    if not logs:
        shown = ", ".join(unmatched[:3]) + (" ..." if len(unmatched) > 3 else "")
        why = f"; {len(unmatched)} data file(s) match no [layout] pattern (e.g. {shown})" if unmatched else ""
        raise DataError(f"fleet dataset '{dataset}': no log file found{why}; patterns: {list(config.patterns)}")
    logs.sort(key=lambda g: (g.axis, g.period, g.file))
    return logs, unmatched


def _key_array(vals) -> np.ndarray:
    """A key column as numbers or strings (dates as ISO text: ``2026-01-05``, or with the time
    of day when there is one)."""
    vals = np.asarray(vals)
    if vals.dtype.kind == "M":
        day = vals.astype("datetime64[D]")
        unit = "D" if (vals == day).all() else "s"
        return np.datetime_as_string(vals, unit=unit)
    if vals.dtype.kind in "biuf":
        return vals
    return vals.astype(str)


def _plain(v):
    """A key value as a plain Python scalar (str, int, float) for selection and hashing."""
    v = v.item() if hasattr(v, "item") else v
    if isinstance(v, float) and v.is_integer():
        return int(v)
    return v if isinstance(v, (str, int, float)) else str(v)


def read_key_columns(path: str | Path, columns: Iterable[str]) -> dict:
    """The given columns of a data file (only those are read from Parquet)."""
    from ..data.loaders import read_table

    columns = list(columns)
    p = Path(path)
    if p.suffix.lower() in (".parquet", ".pq"):
        import pyarrow.parquet as pq

        try:
            t = pq.read_table(p, columns=columns)
        except Exception as exc:  # noqa: BLE001 - one line naming the file
            raise DataError(f"file '{p}': cannot read the key column(s) {columns}: {' '.join(str(exc).split())}") from None
        return {c: _key_array(t.column(c).to_numpy(zero_copy_only=False)) for c in columns}
    table = read_table(p)
    missing = [c for c in columns if c not in table]
    if missing:
        raise DataError(f"file '{p}': key column(s) {missing} ([layout] axis_column/period_column) not found; "
                        f"available columns: {', '.join(list(table)[:20])}")
    return {c: _key_array(table[c]) for c in columns}


def _tasks_of(p: Path, hit: tuple, config: FleetConfig) -> list[tuple[str, str, tuple]]:
    """``(axis, period, select)`` of every task in one file."""
    lay = config.layout
    cols = config.key_columns
    if not cols:
        return [(hit[0], hit[1], ())]
    keys = read_key_columns(p, cols)
    if len(cols) == 1:
        uniq = [(_plain(v),) for v in dict.fromkeys(keys[cols[0]].tolist())]
    else:
        uniq = [tuple(_plain(v) for v in row) for row in dict.fromkeys(zip(*(keys[c].tolist() for c in cols)))]
    seen = dict.fromkeys(uniq)
    out = []
    for vals in seen:
        by = dict(zip(cols, vals))
        axis = str(by[lay["axis_column"]]) if "axis_column" in lay else hit[0]
        period = str(by[lay["period_column"]]) if "period_column" in lay else hit[1]
        out.append((axis, period, tuple(zip(cols, vals))))
    return out


def select_rows(table, select: tuple, path: str | Path) -> np.ndarray | None:
    """Indices of the rows of ``table`` (name → array) where every ``(column, value)`` of
    ``select`` holds; None for an empty selection (the whole file)."""
    if not select:
        return None
    mask = None
    for col, want in select:
        if col not in table:
            raise DataError(f"file '{path}': key column '{col}' not found")
        vals = _key_array(table[col])
        if vals.dtype.kind in "biuf":
            m = vals == want if isinstance(want, (int, float)) else np.zeros(vals.shape, bool)
        else:
            m = vals == str(want)
        mask = m if mask is None else mask & m
    rows = np.flatnonzero(mask)
    if rows.size == 0:
        raise DataError(f"file '{path}': no row has {dict(select)}")
    return rows


def parts_dir(out: str | Path) -> Path:
    """Folder of the result parts of a results file: ``R.parquet`` → ``R.parquet.parts``."""
    out = Path(out)
    return out.with_name(out.name + PARTS_SUFFIX)


__all__ = ["LogFile", "PARTS_SUFFIX", "discover", "parts_dir", "read_key_columns", "select_rows"]
