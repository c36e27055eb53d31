"""Read recordings from CSV, MATLAB ``.mat`` (v5 and v7.3), HDF5, Parquet and NI ``.tdms`` files.

Columns are mapped explicitly to signals (``time=``, ``position=``, ``velocity=``,
``force=``, ...), and each may be multiplied by a scale factor to reach SI units,
e.g. the EMPS force ``F = gtau * vir`` with ``gtau = 35.15065188248547 N/V``::

    rec = load_recording("DATA_EMPS.csv", time="t_s", position="qm_m", force="vir_V",
                         scales={"force": 35.15065188248547})

National Instruments TDMS files (LabVIEW, DAQmx; read with npTDMS) name their columns
``"<group>/<channel>"``, like HDF5 dataset paths; a waveform channel (one with the
``wf_increment`` property) also gives its time track as ``"<group>/<channel>/time"`` [s]
(``wf_start_offset + i * wf_increment``); a timestamp channel becomes seconds since its
first sample.

Input files are opened read-only and never modified; the SHA-256 of the bytes read
is stored in ``Recording.provenance["sha256"]``.
"""

from __future__ import annotations

import hashlib
import re
from collections.abc import Mapping, Sequence
from pathlib import Path
from typing import Any

import numpy as np

from .._io import missing_reason
from .._validate import HUGE, typed_arguments
from ..errors import DataError, ParameterError
from .recording import Recording

#: Keyword of the loader → signal name of :class:`Recording`.
ROLE_TO_SIGNAL = {
    "time": "t",
    "position": "x",
    "velocity": "v",
    "force": "F",
    "current": "current",
    "command": "command",
    "reference": "reference",
}

#: File suffixes understood by :func:`load_recording` → reader name.
SUFFIXES = {
    ".csv": "csv",
    ".txt": "csv",
    ".tsv": "csv",
    ".mat": "mat",
    ".h5": "hdf5",
    ".hdf5": "hdf5",
    ".hdf": "hdf5",
    ".parquet": "parquet",
    ".pq": "parquet",
    ".tdms": "tdms",
}

#: Suffix of the time-track column of a TDMS waveform channel: ``"<group>/<channel>/time"``.
TDMS_TIME_SUFFIX = "/time"


# --------------------------------------------------------------------------- tables
def _sha256(path: Path) -> str:
    h = hashlib.sha256()
    with path.open("rb") as fh:
        for chunk in iter(lambda: fh.read(1 << 20), b""):
            h.update(chunk)
    return h.hexdigest()


def _check_path(path: str | Path) -> Path:
    p = Path(path)
    if not p.exists():
        raise DataError(f"file '{p}': {missing_reason(p)}")
    if p.is_dir():
        raise DataError(f"file '{p}' is a folder; give a data file")
    if not p.is_file():
        raise DataError(f"file '{p}': is not a regular file (a device, pipe or socket)")
    return p


def _file_kind(p: Path) -> str:
    kind = SUFFIXES.get(p.suffix.lower())
    if kind is None:
        raise DataError(
            f"file '{p}': unknown file type '{p.suffix or '(no suffix)'}'; supported: "
            + ", ".join(sorted(SUFFIXES))
        )
    return kind


class Table(dict):
    """Column name → array, plus the names the file's header holds more than once.

    ``duplicates`` maps such a name to its 0-based column positions; selecting it is
    refused (:func:`_column`) instead of silently taking the first.
    """

    duplicates: dict[str, list[int]]

    def __init__(self, *args: Any, duplicates: Mapping[str, list[int]] | None = None,
                 short_row: tuple[int, int, list[str]] | None = None, **kw: Any) -> None:
        super().__init__(*args, **kw)
        self.duplicates = dict(duplicates or {})
        #: ``(row, fields, missing column names)`` when a CSV's last row has fewer fields than its header
        self.short_row = short_row


class ShortRowWarning(UserWarning):
    """A CSV's last row has fewer fields than its header (a truncated file?) and only columns the
    load does not use are missing there; a used column missing there is an error (its value is NaN)."""


def _last_row_fields(p: Path, delimiter: str) -> int | None:
    """Field count of the last non-blank line of a CSV (read from its last 64 kB), or None."""
    import csv

    if len(delimiter) != 1:
        return None
    with p.open("rb") as fh:
        fh.seek(0, 2)
        size = fh.tell()
        fh.seek(max(0, size - (1 << 16)))
        tail = fh.read().decode("utf-8", "replace")
    lines = [ln for ln in tail.splitlines() if ln.strip()]
    if not lines:
        return None
    try:
        return len(next(csv.reader([lines[-1]], delimiter=delimiter)))
    except (csv.Error, StopIteration):
        return None


def _note_short_row(table: Mapping[str, np.ndarray], p: Path, used: Sequence[str]) -> None:
    """Warn (:class:`ShortRowWarning`) when the last row lacks only unused columns. Was (issue 13, round 8
    leftover): a fleet log cut inside its last row read without a word when the lost field was the unused
    temperature column. Only the last row is looked at (a cut file); a short row inside a file is not."""
    import warnings

    short = getattr(table, "short_row", None)
    if short is None:
        return
    row, fields, missing = short
    if set(missing) & set(used):
        return  # the used column holds NaN there: the recording's own check names file, column and row
    names = ", ".join(f"'{m}'" for m in missing[:6]) + (" ..." if len(missing) > 6 else "")
    warnings.warn(f"file '{p}': its last row (row {row}) has {fields} of {fields + len(missing)} fields, a truncated "
                  f"file? column(s) {names} are empty there", ShortRowWarning, stacklevel=4)


def _duplicates(names: Sequence[str]) -> dict[str, list[int]]:
    pos: dict[str, list[int]] = {}
    for i, n in enumerate(names):
        pos.setdefault(str(n), []).append(i)
    return {n: ix for n, ix in pos.items() if len(ix) > 1}


#: Most columns a CSV row may have. A recording has a handful; a row of 30 million fields under a
#: 3-name header made pandas build a 30-million-level row index (13.5 GB, 9 minutes, then killed).
MAX_CSV_COLUMNS = 10_000


def _check_field_counts(p: Path, delimiter: str) -> None:
    """Refuse a header or first data row with more than :data:`MAX_CSV_COLUMNS` fields, counting
    delimiters in 64 kB chunks (nothing is parsed or held; a quoted delimiter counts too, which
    can only over-count)."""
    if len(delimiter) != 1:
        return
    counts = [1]
    with p.open("r", errors="replace", newline="") as fh:
        while len(counts) <= 2 and counts[-1] <= MAX_CSV_COLUMNS:
            chunk = fh.read(1 << 16)
            if not chunk:
                break
            for k, piece in enumerate(chunk.split("\n")):
                if k > 0:
                    counts.append(1)
                    if len(counts) > 2:
                        break
                counts[-1] += piece.count(delimiter)
                if counts[-1] > MAX_CSV_COLUMNS:
                    break
    for what, n in zip(("the header", "data row 1"), counts):
        if n > MAX_CSV_COLUMNS:
            raise DataError(f"file '{p}': {what} has more than {MAX_CSV_COLUMNS:,} fields (delimiter "
                            f"{delimiter!r}); a recording has one column per signal — is the delimiter right?")


def _more_fields_than_names(p: Path, delimiter: str) -> bool:
    """True when the first data row has more fields than the header (pandas' index of 0, 1, 2 ... then
    looks like its own row numbers)."""
    import csv

    if len(delimiter) != 1:
        return False
    with p.open("r", errors="replace", newline="") as fh:
        rows = csv.reader(fh, delimiter=delimiter)
        try:
            head, first = next(rows), next(rows)
        except (StopIteration, csv.Error):
            return False
    return len(first) > len(head)


def _csv_unshifted(p: Path, delimiter: str):
    """The table of a CSV whose rows have more fields than its header names, or a DataError."""
    import pandas as pd

    raw = pd.read_csv(p, sep=delimiter, header=None, skiprows=1, dtype=str, keep_default_na=False)
    names = pd.read_csv(p, sep=delimiter, nrows=0).columns
    extra = raw.iloc[:, len(names):]
    if extra.shape[1] == 0 or (extra != "").to_numpy().any():
        head = ", ".join(map(str, names[:8]))
        note = (" (a comment line above the header? remove it: the first line is the header)"
                if str(names[0]).lstrip().startswith(("#", "%", "//")) else "")
        raise DataError(f"file '{p}': the header names {len(names)} column(s) but the data rows have "
                        f"{raw.shape[1]} fields; every column needs a name (header: {head[:80]!r}){note}")
    return pd.read_csv(p, sep=delimiter, index_col=False)


def _read_csv(p: Path, delimiter: str | None) -> dict[str, np.ndarray]:
    import csv

    import pandas as pd

    with p.open("r", errors="replace") as fh:
        head = fh.readline()
    if delimiter is None:
        counts = {d: head.count(d) for d in (",", ";", "\t")}
        delimiter = max(counts, key=counts.get) if max(counts.values()) > 0 else ","
    _check_field_counts(p, delimiter)
    try:
        df = pd.read_csv(p, sep=delimiter)
    except (pd.errors.ParserError, pd.errors.EmptyDataError, UnicodeDecodeError) as exc:
        raise DataError(f"file '{p}': cannot be parsed as CSV ({str(exc).splitlines()[0]})") from None
    if not isinstance(df.index, pd.RangeIndex) or _more_fields_than_names(p, delimiter):
        # rows with more fields than the header has names: pandas took the first field(s) as an index and
        # shifted every name one column to the right ('t' read the positions), silently. A trailing
        # delimiter on every row (empty last field) is read without the shift; real extra values are refused
        df = _csv_unshifted(p, delimiter)
    try:  # pandas renames a repeated header name 'F' to 'F.1': find repeats in the raw header
        header = next(csv.reader([head], delimiter=delimiter)) if len(delimiter) == 1 else []
    except csv.Error:
        header = []
    short = None
    fields = _last_row_fields(p, delimiter) if len(df) else None
    if fields is not None and 0 < fields < len(df.columns):
        short = (len(df) - 1, fields, [str(c) for c in df.columns[fields:]])
    return Table({str(c): df[c].to_numpy() for c in df.columns}, duplicates=_duplicates([h.strip() for h in header]),
                 short_row=short)


def _read_parquet(p: Path) -> dict[str, np.ndarray]:
    import pandas as pd

    try:
        df = pd.read_parquet(p)
    except Exception as exc:  # pyarrow raises several unrelated types
        raise DataError(f"file '{p}': cannot be read as Parquet ({str(exc).splitlines()[0]})") from None
    dup = _duplicates([str(c) for c in df.columns])
    out = Table(duplicates=dup)
    for i, c in enumerate(df.columns):
        out.setdefault(str(c), df.iloc[:, i].to_numpy())
    return out


def _read_hdf5(p: Path) -> dict[str, np.ndarray]:
    import h5py

    out: dict[str, np.ndarray] = {}
    try:
        with h5py.File(p, "r") as f:

            def visit(name: str, obj: Any) -> None:
                if isinstance(obj, h5py.Dataset) and not name.startswith("#"):
                    out[name] = np.asarray(obj[()])

            f.visititems(visit)
    except OSError as exc:
        raise DataError(f"file '{p}': cannot be read as HDF5 ({str(exc).splitlines()[0]})") from None
    return out


def _read_mat(p: Path) -> dict[str, np.ndarray]:
    import h5py
    import scipy.io

    if h5py.is_hdf5(p):  # MATLAB v7.3 files are HDF5 with a 512-byte user block
        data = _read_hdf5(p)
        # MATLAB writes column-major arrays; vectors come out as (1, n) or (n, 1).
        return {k: np.asarray(v).T for k, v in data.items()}
    try:
        raw = scipy.io.loadmat(p, squeeze_me=False)
    except Exception as exc:  # noqa: BLE001 - scipy raises MatReadError, ValueError, struct.error ... on damaged files
        text = str(exc).splitlines()[0] if str(exc) else type(exc).__name__
        raise DataError(f"file '{p}': cannot be read as a MATLAB .mat file ({text})") from None
    return {k: v for k, v in raw.items() if not k.startswith("__")}


def _read_tdms(p: Path) -> dict[str, np.ndarray]:
    """Every channel of a TDMS file as ``"<group>/<channel>"``, plus the time tracks of waveforms.

    The file is read whole (``TdmsFile.read``, read-only; an ``.tdms_index`` beside it is
    used if present). A file whose last segment announces more data than it holds (a
    logger that stopped mid-write) is refused rather than read short, so a truncated
    log never passes for a shorter one.
    """
    import logging

    from nptdms import TdmsFile

    class _Catch(logging.Handler):  # npTDMS reports a short last segment by logging, not raising
        def __init__(self) -> None:
            super().__init__(logging.WARNING)
            self.messages: list[str] = []

        def emit(self, record: logging.LogRecord) -> None:
            self.messages.append(record.getMessage())

    with p.open("rb") as fh:
        lead = fh.read(4)
    if lead and lead != b"TDSm":  # every TDMS segment starts with the tag "TDSm"
        raise DataError(f"file '{p}': cannot be read as TDMS (it starts with {lead!r}, not b'TDSm')")
    catch = _Catch()
    loggers = [logging.getLogger(n) for n in ("nptdms", "nptdms.reader", "nptdms.tdms_segment")]
    # npTDMS gives its module loggers their own console handler: detach it while reading, else a
    # damaged file printed two "[nptdms.reader WARNING] ..." lines before the one error line
    saved = [(lg, lg.propagate, list(lg.handlers)) for lg in loggers]
    for lg in loggers:
        for h in list(lg.handlers):
            lg.removeHandler(h)
        lg.addHandler(catch)
        lg.propagate = False
    try:
        f = TdmsFile.read(p)
        channels = [(f"{g.name}/{c.name}", c, np.asarray(c[:])) for g in f.groups() for c in g.channels()]
    except Exception as exc:  # npTDMS raises many unrelated types on damaged files (struct.error, ...)
        text = str(exc).splitlines()[0] if str(exc) else type(exc).__name__
        raise DataError(f"file '{p}': cannot be read as TDMS ({text})") from None
    finally:
        for lg, prop, handlers in saved:
            lg.removeHandler(catch)
            for h in handlers:
                lg.addHandler(h)
            lg.propagate = prop
    short = [m for m in catch.messages if "less data than expected" in m or "not a multiple" in m]
    if short:
        raise DataError(f"file '{p}': truncated TDMS file ({short[0]}); the logger stopped mid-write — "
                        "repair or re-export it")
    out: dict[str, np.ndarray] = {}
    for name, c, data in channels:
        if data.dtype.kind == "M":  # timestamps: seconds since the channel's first sample
            data = (data - data[0]) / np.timedelta64(1, "ns") * 1e-9 if data.size else data.astype(float)
        out[name] = data
        if "wf_increment" in c.properties:
            try:
                out[name + TDMS_TIME_SUFFIX] = np.asarray(c.time_track(), dtype=float)
            except Exception as exc:  # noqa: BLE001 (bad property values of any type)
                raise DataError(f"file '{p}', column '{name}': waveform time properties unusable ({exc})") from None
    if not out:
        raise DataError(f"file '{p}': the TDMS file holds no channels")
    return out


def read_table(path: str | Path, *, delimiter: str | None = None) -> dict[str, np.ndarray]:
    """All columns (variables, datasets) of a data file as a name → array dict.

    Parameters
    ----------
    path : str or Path
        ``.csv``/``.txt``/``.tsv``, ``.mat`` (v5 or v7.3), ``.h5``/``.hdf5`` (dataset
        paths such as ``"axis/velocity"`` are the names), ``.parquet`` or ``.tdms``
        (``"<group>/<channel>"``; waveforms add ``"<group>/<channel>/time"``).
    delimiter : str, optional
        CSV field separator; default: detected.

    Returns
    -------
    dict of str to ndarray
        The file is read only; nothing is written.

    Examples
    --------
    >>> from frictionkit.data import read_table
    >>> cols = read_table("DATA_EMPS.csv")  # doctest: +SKIP
    >>> sorted(cols)  # doctest: +SKIP
    ['qg_m', 'qm_m', 't_s', 'vir_V']
    """
    p = _check_path(path)
    kind = _file_kind(p)
    if kind == "csv":
        return _read_csv(p, delimiter)
    if kind == "parquet":
        return _read_parquet(p)
    if kind == "hdf5":
        return _read_hdf5(p)
    if kind == "tdms":
        return _read_tdms(p)
    return _read_mat(p)


# --------------------------------------------------------------------------- mapping
def _unique(table: Mapping[str, np.ndarray], p: Path, role: str, col: str) -> None:
    """Refuse a selected column whose name the header repeats (the first one was used silently)."""
    dup = getattr(table, "duplicates", {}).get(col)
    if dup:
        raise DataError(f"file '{p}': column '{col}' (given for {role}) appears {len(dup)} times in the header "
                        f"(columns {', '.join(str(i + 1) for i in dup)}); rename them so the choice is unambiguous")


def _grid_input(table: Mapping[str, np.ndarray], p: Path, tcol: str, col: str, role: str,
                grid: tuple | None, time_role: str = "the time (first column)") -> tuple[np.ndarray, tuple]:
    """Column ``col`` of ``table`` as one input of a run whose inputs share one uniform time grid
    (``compensate --test`` specs, ``simulate MACHINE.json --input``): the time column ``tcol`` must
    be uniformly sampled and match ``grid`` (``(samples, step, file)`` of the first file, or None),
    the column numeric and finite. Returns the column and the grid."""
    _si_header(p, tcol, "s", time_role)
    _note_short_row(table, p, [tcol, col])
    t = _column(table, p, time_role, tcol)
    # the cause first: "not uniformly sampled" misled on an empty file, a NaN time or a time running backwards
    if t.size < 2:
        raise DataError(f"file '{p}': {t.size} row(s); a run's input needs at least 2 samples")
    if not np.all(np.isfinite(t)):
        raise DataError(f"file '{p}': time column {tcol!r} is not finite at row {int(np.flatnonzero(~np.isfinite(t))[0])}")
    steps = np.diff(t)
    if steps.min() <= 0:
        i = int(np.flatnonzero(steps <= 0)[0])
        raise DataError(f"file '{p}': time column {tcol!r} does not increase at row {i + 1} ({t[i]:.9g} -> "
                        f"{t[i + 1]:.9g} s)")
    if np.ptp(steps) > 1e-6 * steps.mean():
        raise DataError(f"file '{p}': time column {tcol!r} is not uniformly sampled (steps {steps.min():.6g} to "
                        f"{steps.max():.6g} s); the inputs of a run share one grid (resample first)")
    h = float(np.mean(steps))
    if grid is None:
        grid = (t.size, h, p)
    elif grid[0] != t.size or abs(grid[1] - h) > 1e-9 * h:
        raise DataError(f"{role}: '{p}' has {t.size} samples at {h:.6g} s, '{grid[2]}' {grid[0]} at "
                        f"{grid[1]:.6g} s; all inputs share one grid")
    _si_header(p, col, None, role)
    arr = _column(table, p, role, col)
    if not np.all(np.isfinite(arr)):
        bad = int(np.flatnonzero(~np.isfinite(arr))[0])
        raise DataError(f"file '{p}': column '{col}' (given for {role}) is not finite at row {bad}")
    huge = np.flatnonzero(np.abs(arr) > HUGE)
    if huge.size:  # one 1e300 sample in a reference ran with status 0 (campaign round 5)
        raise DataError(f"file '{p}': column '{col}' (given for {role}) = {arr[huge[0]]:.6g} at row {int(huge[0])}: "
                        f"beyond {HUGE:.0e}, a corrupt sample or a unit slip; remove or repair it")
    return arr, grid


#: Units in a column header (``"t [ms]"``, ``"qg [mm]"``) that are not SI: ``--input`` and
#: compensation-test inputs are read as SI, so such a column would be off by the prefix
#: (``t [ms]`` read as seconds ran 1,000x too slow with status 0; campaign round 5). Assumption:
#: the bracketed text of a header is its unit; only these common non-SI spellings are refused.
NON_SI_HEADER_UNITS = frozenset({"ms", "us", "µs", "ns", "min", "h", "mm", "cm", "um", "µm", "nm", "km", "deg",
                                 "°", "mrad", "urad", "µrad", "arcsec", "mm/s", "um/s", "µm/s", "deg/s", "°/s",
                                 "rpm", "mm/s^2", "mm/s²", "mn", "kn", "n·mm", "nmm", "ma", "mv", "g"})


def _si_header(p: Path, col: str, want: str | None, role: str) -> None:
    m = re.search(r"\[([^\]]*)\]\s*$", col)
    if m is None:
        return
    unit = m.group(1).strip()
    if (want is not None and unit not in (want, "")) or unit.lower() in NON_SI_HEADER_UNITS:
        raise DataError(f"file '{p}': column '{col}' (given for {role}) is in {unit}; this input is read in SI "
                        f"units{f' ({want})' if want else ''}: convert the column (its values are not rescaled)")


def _available(table: Mapping[str, np.ndarray], col: str) -> str:
    """The header names for a 'not found' message; names with surrounding spaces quoted and pointed
    out (round 7: ' t_s , v_ms ' listed as "t_s , v_ms" read as if 't_s' were there)."""
    names = [str(n) for n in table]
    spaced = any(n != n.strip() for n in names)
    shown = [repr(n) if spaced else n for n in names[:20]]
    avail = ", ".join(shown) + (" ..." if len(names) > 20 else "")
    if spaced and any(n.strip() == col.strip() for n in names):
        avail += f" (the header has {col.strip()!r} with surrounding spaces: remove them from the file's header)"
    return avail


def _first_text(arr: np.ndarray) -> str:
    """``": row K holds 'TEXT'"`` for the first value that is not a number (rows counted from 0 after the
    header, as in the other row messages), or ``""``. Was (campaign round 8): a unit row under the header
    ("s,m/s,N") or a NUL byte said only "is not numeric"."""
    for k, x in enumerate(arr.ravel()):
        try:
            float(x)
        except (TypeError, ValueError):
            text = x.decode("utf-8", "replace") if isinstance(x, bytes) else str(x)
            hint = " (a units row under the header? remove it)" if k == 0 and not any(c.isdigit() for c in text) else ""
            return f": row {k} holds {text[:40]!r}{hint}"
    return ""


def _column(table: Mapping[str, np.ndarray], p: Path, role: str, col: str) -> np.ndarray:
    if col not in table:
        raise DataError(f"file '{p}': column '{col}' (given for {role}) not found; available columns: "
                        f"{_available(table, col)}")
    _unique(table, p, role, col)
    arr = np.asarray(table[col])
    if arr.dtype.kind == "b" or (arr.dtype.kind == "O" and any(isinstance(x, (bool, np.bool_)) for x in arr.ravel()[:1000])):
        raise DataError(f"file '{p}': column '{col}' (given for {role}) holds true/false values, not numbers; "
                        "a flag column cannot be a signal (True/False would become 1/0)")
    if arr.dtype.kind == "c":  # complex: numpy dropped the imaginary part with only a ComplexWarning
        if np.any(arr.imag != 0):
            raise DataError(f"file '{p}': column '{col}' (given for {role}) holds complex values with a non-zero "
                            "imaginary part; a signal must be real")
        arr = arr.real
    if arr.dtype.kind not in "biuf":
        try:
            arr = arr.astype(np.float64)
        except (TypeError, ValueError):
            raise DataError(f"file '{p}': column '{col}' (given for {role}) is not numeric{_first_text(arr)}") from None
    arr = arr.astype(np.float64)
    if arr.ndim > 1:
        arr = arr.squeeze()
        if arr.ndim != 1:
            raise DataError(f"file '{p}': column '{col}' (given for {role}) has shape {arr.shape}, must be a vector")
    return arr


def _select_rows(
    table: Mapping[str, np.ndarray], p: Path, where: Mapping[str, Any] | None
) -> np.ndarray | None:
    if not where:
        return None
    mask = None
    for col, want in where.items():
        if col not in table:
            raise DataError(f"file '{p}': column '{col}' (given in where) not found; available columns: "
                            f"{_available(table, col)}")
        _unique(table, p, "where", col)
        vals = np.asarray(table[col])
        if mask is not None and vals.shape != mask.shape:
            raise DataError(f"file '{p}': column '{col}' (given in where) has {vals.size} rows, the other "
                            f"where column(s) {mask.size}; the columns differ in length")
        if vals.dtype.kind in "biuf":
            try:
                m = vals == float(want)
            except (TypeError, ValueError):
                m = np.zeros(vals.shape, bool)
        else:
            m = vals.astype(str) == str(want)
        mask = m if mask is None else (mask & m)
    if not mask.any():
        raise DataError(f"file '{p}': no row matches where={dict(where)}")
    return mask


def _build(
    table: Mapping[str, np.ndarray],
    p: Path,
    roles: Mapping[str, str | None],
    scales: Mapping[str, float] | None,
    rows: np.ndarray | None,
    *,
    current_gain: float | None,
    units: Mapping[str, str] | None,
    name: str,
    extra_prov: Mapping[str, Any],
) -> Recording:
    scales = dict(scales or {})
    _note_short_row(table, p, [c for c in roles.values() if c is not None])
    unknown = set(scales) - set(ROLE_TO_SIGNAL)
    if unknown:
        raise DataError(f"scales: unknown key(s) {sorted(unknown)}; use {sorted(ROLE_TO_SIGNAL)}")
    if roles.get("time") is None:
        raise DataError("time column must be given (time='...')")
    kw: dict[str, np.ndarray] = {}
    columns: dict[str, str] = {}
    for role, col in roles.items():
        if col is None:
            continue
        arr = _column(table, p, role, col)
        if rows is not None:
            need = rows.size if rows.dtype == bool else (int(rows.max()) + 1 if rows.size else 0)
            if (arr.size != need) if rows.dtype == bool else (arr.size < need):
                raise DataError(f"file '{p}': column '{col}' (given for {role}) has {arr.size} rows but the "
                                f"row selection (where/group) spans {need}; the columns differ in length")
            arr = arr[rows]
        arr = arr * float(scales.get(role, 1.0))
        sig = ROLE_TO_SIGNAL[role]
        kw[sig] = arr
        columns[sig] = col
    prov = {"file": str(p), "columns": columns, "scales": scales, **extra_prov}
    return Recording(**kw, current_gain=current_gain, units=dict(units or {}), name=name, provenance=prov)


@typed_arguments  # argument types named at the boundary (issue 13 round 11)
def load_recording(
    path: str | Path,
    *,
    time: str,
    position: str | None = None,
    velocity: str | None = None,
    force: str | None = None,
    current: str | None = None,
    current_gain: float | None = None,
    command: str | None = None,
    reference: str | None = None,
    scales: Mapping[str, float] | None = None,
    units: Mapping[str, str] | None = None,
    where: Mapping[str, Any] | None = None,
    name: str | None = None,
    delimiter: str | None = None,
) -> Recording:
    """Load one :class:`Recording` from a CSV, ``.mat``, HDF5, Parquet or TDMS file.

    Parameters
    ----------
    path : str or Path
        Data file; the type is taken from the suffix (see :data:`SUFFIXES`).
    time, position, velocity, force, current, command, reference : str, optional
        Column (variable, dataset) name for each signal; ``time`` is required.
    current_gain : float, optional
        Force per ampere [N/A or N·m/A], used when ``force`` is absent.
    scales : mapping, optional
        Factor per role (keys as the keyword names: ``"force"``, ``"velocity"`` ...)
        that converts the stored numbers to SI, e.g. ``{"force": 35.15065188248547}``
        (EMPS: N per V) or ``{"velocity": frictionkit.units.RPM}``.
    units : mapping, optional
        Unit strings per signal name (``"F": "N·m"``, ``"v": "rad/s"``) after scaling.
    where : mapping, optional
        Keep only rows whose column equals the value, e.g. ``{"drive_id": 1}``.
    name : str, optional
        Label of the recording; default the file stem.
    delimiter : str, optional
        CSV separator; default detected.

    Returns
    -------
    Recording
        ``provenance`` holds ``file``, ``columns``, ``scales``, ``sha256``.

    Raises
    ------
    DataError
        Unknown file type, missing column, non-numeric column, NaN/inf values,
        non-monotonic or repeated time stamps, too few samples.

    Examples
    --------
    >>> from frictionkit.data import load_recording
    >>> rec = load_recording("DATA_EMPS.csv", time="t_s", position="qm_m", force="vir_V",
    ...                      scales={"force": 35.15065188248547})  # doctest: +SKIP
    >>> rec.n  # doctest: +SKIP
    24841
    """
    p = _check_path(path)
    digest = _sha256(p)
    table = read_table(p, delimiter=delimiter)
    rows = _select_rows(table, p, where)
    roles = dict(time=time, position=position, velocity=velocity, force=force,
                 current=current, command=command, reference=reference)
    extra = {"sha256": digest}
    if where:
        extra["where"] = {k: (v.item() if hasattr(v, "item") else v) for k, v in where.items()}
    return _build(table, p, roles, scales, rows, current_gain=current_gain, units=units,
                  name=name or p.stem, extra_prov=extra)


@typed_arguments  # argument types named at the boundary (issue 13 round 11)
def load_csv(
    path: str | Path,
    *,
    time: str,
    position: str | None = None,
    velocity: str | None = None,
    force: str | None = None,
    current: str | None = None,
    current_gain: float | None = None,
    command: str | None = None,
    reference: str | None = None,
    scales: Mapping[str, float] | None = None,
    units: Mapping[str, str] | None = None,
    where: Mapping[str, Any] | None = None,
    name: str | None = None,
    delimiter: str | None = None,
) -> Recording:
    """Load a :class:`Recording` from a CSV file (``.csv``, ``.txt``, ``.tsv``).

    Same keywords as :func:`load_recording`; refuses other file types.

    Examples
    --------
    >>> from frictionkit.data import load_csv
    >>> rec = load_csv("DATA_EMPS.csv", time="t_s", position="qm_m", force="vir_V",
    ...                scales={"force": 35.15065188248547})  # doctest: +SKIP
    """
    p = Path(path)
    if SUFFIXES.get(p.suffix.lower()) != "csv":
        raise DataError(f"file '{p}': load_csv needs a .csv/.txt/.tsv file, got '{p.suffix}'")
    return load_recording(p, time=time, position=position, velocity=velocity, force=force,
                          current=current, current_gain=current_gain, command=command,
                          reference=reference, scales=scales, units=units, where=where,
                          name=name, delimiter=delimiter)


@typed_arguments  # argument types named at the boundary (issue 13 round 11)
def load_groups(
    path: str | Path,
    *,
    group: str | Sequence[str],
    time: str,
    position: str | None = None,
    velocity: str | None = None,
    force: str | None = None,
    current: str | None = None,
    current_gain: float | None = None,
    command: str | None = None,
    reference: str | None = None,
    scales: Mapping[str, float] | None = None,
    units: Mapping[str, str] | None = None,
    where: Mapping[str, Any] | None = None,
    delimiter: str | None = None,
) -> dict[str, Recording]:
    """Split a long table into one :class:`Recording` per value of the ``group`` column(s).

    Used for files that stack many records, such as the screw-drive steady-state
    records (one group per ``source_file``; select a drive with ``where``).

    Parameters
    ----------
    group : str or sequence of str
        Column(s) whose values identify a record; the record name joins the values
        with ``"/"``. Rows keep their file order inside each group.
    time, position, ..., delimiter
        As in :func:`load_recording`.

    Returns
    -------
    dict of str to Recording
        In order of first appearance in the file.

    Examples
    --------
    >>> from frictionkit.data import load_groups
    >>> recs = load_groups("steady_state_records.csv", group="source_file", time="t_s",
    ...                    velocity="motor_velocity_rad_per_s", force="motor_torque_N_m",
    ...                    where={"drive_id": 1})  # doctest: +SKIP
    >>> len(recs)  # doctest: +SKIP
    32
    """
    p = _check_path(path)
    digest = _sha256(p)
    table = read_table(p, delimiter=delimiter)
    sel = _select_rows(table, p, where)
    # group=None or an object was "'NoneType' object is not iterable" (issue 13 round 11)
    if not (isinstance(group, str) or (np.iterable(group) and all(isinstance(k, str) for k in group))):
        raise ParameterError(f"load_groups.group = {group!r}: must be a column name or a list of column names")
    keys = [group] if isinstance(group, str) else list(group)
    if not keys:
        raise DataError("group: give at least one column")
    for k in keys:
        if k not in table:
            raise DataError(f"file '{p}': column '{k}' (given for group) not found; available columns: {', '.join(table)}")
        _unique(table, p, "group", k)
    n = len(next(iter(table.values())))
    idx = np.arange(n) if sel is None else np.flatnonzero(sel)
    labels = ["/".join(str(table[k][i]) for k in keys) for i in idx]
    order: dict[str, list[int]] = {}
    for i, lab in zip(idx, labels):
        order.setdefault(lab, []).append(int(i))
    roles = dict(time=time, position=position, velocity=velocity, force=force,
                 current=current, command=command, reference=reference)
    out: dict[str, Recording] = {}
    for lab, rows in order.items():
        extra = {"sha256": digest, "group": {k: str(table[k][rows[0]]) for k in keys}, "first_row": rows[0]}
        out[lab] = _build(table, p, roles, scales, np.asarray(rows), current_gain=current_gain,
                          units=units, name=lab, extra_prov=extra)
    return out
