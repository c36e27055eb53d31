"""One TOML file that says, once for the whole fleet, how to read every log.

A fleet configuration maps file columns to signals, gives each column's unit (converted
to SI on loading), names the scheduling columns (temperature, load ...) that the drift
monitor regresses out, says how axis and period are read from the file path, and
carries the segmentation, fit and monitoring settings. It is read with the standard
library's :mod:`tomllib`; every mistake ends in one :class:`~frictionkit.DataError`
naming the file and the key.

Example (``frictionkit fleet simulate`` writes one like it beside the logs)::

    [layout]
    # regular expression on the path relative to the dataset folder, with the named
    # groups "axis" and "period"
    pattern = '(?P<axis>[^/]+)/(?P<period>\\d{4}-\\d{2}-\\d{2})\\.(csv|parquet)$'

    [columns]              # signal = column name in the files
    time = "t_s"
    velocity = "v_mm_s"
    force = "F_N"

    [units]                # unit of each column as logged; converted to SI
    time = "s"
    velocity = "mm/s"
    force = "N"

    [schedule.temperature] # a scheduling column: mean per log, regressed out by the monitor
    column = "temperature_C"
    unit = "degC"

    [segmentation]         # keywords of frictionkit.data.find_plateaus (SI units)
    min_speed = 2e-4
    min_duration = 0.3
    settle = 0.4           # and: fraction of each plateau dropped at its start (transient)

    [fit]                  # keywords of frictionkit.identify.fit_static_map
    model = "auto"
    criterion = "aic"

    [dynamic]              # LuGre sigma0, sigma1 through the reversals, where the data allow
    lugre = true

    [monitor]              # keywords of frictionkit.fleet.monitor_drift
    alpha = 0.01

**Many axis-periods in one file** (one unpartitioned Parquet/CSV file, or a long table of
records): ``[layout]`` names the columns that hold them, and a constant for what neither
the path nor a column gives::

    [layout]
    axis_column = "axis"       # rows are split into one task per (axis, period) value pair
    period_column = "date"
    # axis = "emps"            # a constant instead (a single-axis file)
    # period = "2018-11-06"
    # record_column = "source_file"  # within one task, records whose time restarts: each
    #                                # record is one steady-state point, averaged whole

A pattern is then needed only for what no column or constant gives. Discovering the tasks
reads those key columns of each such file (not the signals).

**Files that are not recordings** (a truth table, a list of known-bad files, notes) are named
in ``[layout] ignore``: shell-style patterns on the path relative to the dataset folder
(``/`` separated; ``*`` also crosses folders). They are left out without a word, while any other
data file that matches no pattern is reported (``fleet identify`` warns)::

    [layout]
    ignore = ["truth.csv", "truth_days.csv", "broken.csv", "broken.txt"]  # fleet simulate's side files
"""

from __future__ import annotations

import hashlib
import json
import math
import re
import tomllib
from dataclasses import dataclass, field
from fnmatch import fnmatchcase
from pathlib import Path
from typing import Any

from ..errors import DataError

#: Signals a column can be mapped to (keywords of :func:`frictionkit.data.load_recording`).
ROLES = ("time", "position", "velocity", "force", "current")

#: Unit strings understood in ``[units]`` → (factor to SI, SI unit label).
UNITS: dict[str, tuple[float, str]] = {
    "s": (1.0, "s"), "ms": (1e-3, "s"), "us": (1e-6, "s"),
    "m": (1.0, "m"), "mm": (1e-3, "m"), "um": (1e-6, "m"), "µm": (1e-6, "m"), "nm": (1e-9, "m"),
    "rad": (1.0, "rad"), "mrad": (1e-3, "rad"), "deg": (math.pi / 180.0, "rad"),
    "m/s": (1.0, "m/s"), "mm/s": (1e-3, "m/s"), "um/s": (1e-6, "m/s"), "µm/s": (1e-6, "m/s"),
    "m/min": (1.0 / 60.0, "m/s"), "mm/min": (1e-3 / 60.0, "m/s"),
    "rad/s": (1.0, "rad/s"), "deg/s": (math.pi / 180.0, "rad/s"), "rpm": (2.0 * math.pi / 60.0, "rad/s"),
    "N": (1.0, "N"), "kN": (1e3, "N"), "mN": (1e-3, "N"),
    "N·m": (1.0, "N·m"), "N*m": (1.0, "N·m"), "Nm": (1.0, "N·m"), "mN·m": (1e-3, "N·m"), "mNm": (1e-3, "N·m"),
    "A": (1.0, "A"), "mA": (1e-3, "A"),
}

#: Units of scheduling columns: kept as logged (an offset-free factor would be wrong for °C).
SCHEDULE_UNITS = ("degC", "°C", "K", "degF", "%", "N", "kN", "kg", "1", "")

#: Default regular expressions for axis and period in a relative path: ``AXIS/PERIOD.ext``
#: and Hive-style partitions ``axis=AXIS/date=PERIOD/file``.
DEFAULT_PATTERNS = (
    r"(?:^|/)axis=(?P<axis>[^/]+)/(?:date|period|day)=(?P<period>[^/]+)/[^/]+$",
    r"(?:^|/)(?P<axis>[^/]+)/(?P<period>[^/]+)\.(?:csv|txt|tsv|parquet|pq|h5|hdf5|hdf|mat)$",
)

#: ``[layout]`` keys besides the patterns: axis/period from columns or constants, records.
LAYOUT_KEYS = ("axis", "period", "axis_column", "period_column", "record_column")

_SECTIONS = {"layout", "columns", "units", "scales", "schedule", "segmentation", "fit", "dynamic", "monitor"}
_SEGMENTATION_KEYS = {"window", "rel_tol", "abs_tol", "min_speed", "min_duration", "min_samples", "trim", "settle"}
_FIT_KEYS = {"model", "criterion", "loss", "f_scale", "delta", "direction"}
_MONITOR_KEYS = {"alpha", "min_periods", "parameters", "n_null", "seed", "se_floor", "method", "weights", "scale"}
_DYNAMIC_KEYS = {"lugre"}


@dataclass(frozen=True, kw_only=True)
class FleetConfig:
    """How to read and fit every log of a fleet (see the module docstring for the TOML form).

    Parameters
    ----------
    columns : dict
        Signal (``time``, ``position``, ``velocity``, ``force``, ``current``) → column name.
        ``time``, ``force`` (or ``current`` with ``scales["current_gain"]``) and one of
        ``velocity`` / ``position`` are required.
    scales : dict
        Signal → factor to SI (from ``[units]`` and ``[scales]``, multiplied).
    si_units : dict
        ``{"v": ..., "F": ...}`` SI unit labels after scaling (``m/s`` or ``rad/s``, ``N`` or ``N·m``).
    schedule : dict
        Scheduling variable name → ``{"column": ..., "unit": ...}``; each is averaged per log.
    patterns : tuple of str
        Regular expressions with the groups ``axis`` and ``period``, tried in order on the
        path relative to the dataset folder (``/`` separated).
    segmentation, fit, monitor : dict
        Keywords of :func:`~frictionkit.data.find_plateaus`,
        :func:`~frictionkit.identify.fit_static_map` and :func:`~frictionkit.fleet.monitor_drift`.
    dynamic : dict
        ``{"lugre": bool}``: fit LuGre σ0, σ1 through the reversals where the data allow
        (:mod:`frictionkit.fleet.dynamic`; default true).
    layout : dict
        Any of :data:`LAYOUT_KEYS`: ``axis_column`` / ``period_column`` split the rows of a
        file into one task per value pair; ``axis`` / ``period`` are constants used when
        neither the path nor a column gives them; ``record_column`` marks records (time
        restarting) inside one task, each averaged whole into one steady-state point.
    ignore : tuple of str
        ``[layout] ignore``: shell-style patterns (:func:`fnmatch.fnmatchcase`) on the path
        relative to the dataset folder of files that are not recordings (side files such as a
        truth table); :meth:`ignores` tells. They change no result, so not the fingerprint.
    source : str, optional
        File the configuration came from.
    """

    columns: dict = field(default_factory=dict)
    scales: dict = field(default_factory=dict)
    si_units: dict = field(default_factory=lambda: {"v": "m/s", "F": "N"})
    schedule: dict = field(default_factory=dict)
    patterns: tuple = DEFAULT_PATTERNS
    segmentation: dict = field(default_factory=dict)
    fit: dict = field(default_factory=dict)
    monitor: dict = field(default_factory=dict)
    dynamic: dict = field(default_factory=lambda: {"lugre": True})
    layout: dict = field(default_factory=dict)
    ignore: tuple = ()
    source: str | None = None

    def __post_init__(self) -> None:
        where = f"fleet config '{self.source}'" if self.source else "fleet config"
        cols = dict(self.columns)
        unknown = set(cols) - set(ROLES)
        if unknown:
            raise DataError(f"{where}: [columns] unknown signal(s) {sorted(unknown)}; use {list(ROLES)}")
        if "time" not in cols:
            raise DataError(f"{where}: [columns] needs time = \"<column>\"")
        if "force" not in cols and not ("current" in cols and "current_gain" in self.scales):
            raise DataError(f"{where}: [columns] needs force = \"<column>\" (or current with [scales] current_gain)")
        if "velocity" not in cols and "position" not in cols:
            raise DataError(f"{where}: [columns] needs velocity = \"<column>\" or position = \"<column>\"")
        for key, val in cols.items():
            if not isinstance(val, str) or not val:
                raise DataError(f"{where}: [columns] {key} = {val!r}: must be a column name (a string)")
        for key, val in self.scales.items():
            if isinstance(val, bool) or not isinstance(val, (int, float)) or not math.isfinite(val) or val == 0:
                raise DataError(f"{where}: [scales] {key} = {val!r}: must be a finite, non-zero number")
        for name, spec in self.schedule.items():
            if not re.fullmatch(r"[A-Za-z_][A-Za-z0-9_]*", name):
                raise DataError(f"{where}: [schedule] name {name!r}: use letters, digits and _ (it becomes a column)")
            if not isinstance(spec, dict) or not isinstance(spec.get("column"), str):
                raise DataError(f"{where}: [schedule.{name}] needs column = \"<column>\"")
        lay = dict(self.layout)
        bad = set(lay) - set(LAYOUT_KEYS)
        if bad:
            raise DataError(f"{where}: [layout] unknown key(s) {sorted(bad)}; use pattern, patterns or {list(LAYOUT_KEYS)}")
        for key, val in lay.items():
            if not isinstance(val, str) or not val:
                raise DataError(f"{where}: [layout] {key} = {val!r}: must be a non-empty string")
        for what in ("axis", "period"):
            if what in lay and f"{what}_column" in lay:
                raise DataError(f"{where}: [layout] gives both {what} and {what}_column; keep one")
        object.__setattr__(self, "layout", lay)
        ignore = (self.ignore,) if isinstance(self.ignore, str) else self.ignore
        if not isinstance(ignore, (list, tuple)) or not all(isinstance(g, str) and g.strip() for g in ignore):
            raise DataError(f"{where}: [layout] ignore = {self.ignore!r}: must be a list of file patterns "
                            "(strings such as \"truth.csv\" or \"notes/*\")")
        object.__setattr__(self, "ignore", tuple(ignore))
        need = {g for g in ("axis", "period") if g not in lay and f"{g}_column" not in lay}
        pats = tuple(self.patterns)
        for p in pats:
            try:
                rx = re.compile(p)
            except re.error as exc:
                raise DataError(f"{where}: [layout] pattern {p!r} is not a regular expression ({exc})") from None
            if not need <= set(rx.groupindex):
                raise DataError(f"{where}: [layout] pattern {p!r} needs the named group(s) "
                                + " and ".join(f"(?P<{g}>...)" for g in sorted(need))
                                + " (or give them as [layout] <name> / <name>_column)")
        object.__setattr__(self, "patterns", pats)
        if not isinstance(self.dynamic.get("lugre", True), bool):
            raise DataError(f"{where}: [dynamic] lugre = {self.dynamic.get('lugre')!r}: must be true or false")
        settle = self.segmentation.get("settle", 0.0)
        if isinstance(settle, bool) or not isinstance(settle, (int, float)) or not 0.0 <= settle < 0.9:
            raise DataError(f"{where}: [segmentation] settle = {settle!r}: must be a number in [0, 0.9)")
        for sec, keys in (("segmentation", _SEGMENTATION_KEYS), ("fit", _FIT_KEYS), ("monitor", _MONITOR_KEYS),
                          ("dynamic", _DYNAMIC_KEYS)):
            bad = set(getattr(self, sec)) - keys
            if bad:
                raise DataError(f"{where}: [{sec}] unknown key(s) {sorted(bad)}; allowed: {sorted(keys)}")
        # numbers checked here, naming the key (issue 13 round 4: min_duration = "m" failed in every log
        # as "TypeError: '>=' not supported"; monitor min_periods = "" as "invalid literal for int()")
        for sec, keys in (("segmentation", _SEGMENTATION_KEYS), ("fit", {"f_scale", "delta"}),
                          ("monitor", {"alpha", "min_periods", "n_null", "seed", "se_floor"})):
            for key in sorted(keys & set(getattr(self, sec))):
                val = getattr(self, sec)[key]
                whole = key in {"min_samples", "min_periods", "n_null", "seed", "window"}
                if (isinstance(val, bool) or not isinstance(val, (int, float)) or not math.isfinite(val)
                        or (whole and val != int(val))):
                    raise DataError(f"{where}: [{sec}] {key} = {val!r}: must be a finite "
                                    + ("whole number" if whole else "number"))

    # ------------------------------------------------------------------ identity
    def to_dict(self) -> dict[str, Any]:
        """The configuration as plain data (the fingerprint of results depends on it)."""
        d = {"columns": dict(self.columns), "scales": dict(self.scales), "si_units": dict(self.si_units),
             "schedule": {k: dict(v) for k, v in self.schedule.items()}, "patterns": list(self.patterns),
             "segmentation": dict(self.segmentation), "fit": dict(self.fit), "monitor": dict(self.monitor),
             "dynamic": dict(self.dynamic)}
        if self.layout:  # only when used: configurations without it keep their hash (and their parts)
            d["layout"] = dict(self.layout)
        if self.ignore:
            d["ignore"] = list(self.ignore)
        return d

    @property
    def key_columns(self) -> tuple[str, ...]:
        """Columns whose values split a file into tasks (``axis_column``, ``period_column``)."""
        return tuple(self.layout[k] for k in ("axis_column", "period_column") if k in self.layout)

    @property
    def sha256(self) -> str:
        """Hash of everything that changes a per-file result (not ``monitor`` nor ``source``)."""
        d = self.to_dict()
        d.pop("monitor")
        d.pop("ignore", None)  # which side files are left out changes no log's result
        return hashlib.sha256(json.dumps(d, sort_keys=True, default=str).encode()).hexdigest()

    def ignores(self, relpath: str) -> bool:
        """True when ``relpath`` (relative to the dataset folder, ``/`` separated) is an ``ignore`` file."""
        return any(fnmatchcase(relpath, g) for g in self.ignore)

    def match(self, relpath: str) -> tuple[str | None, str | None] | None:
        """``(axis, period)`` read from a relative path, or None when no pattern matches.

        A constant ``[layout] axis`` / ``period`` fills what the pattern lacks; what a
        column gives (``axis_column`` ...) is None here. When constants and columns give
        both and no pattern was set (the defaults), every path matches; a pattern set in
        the configuration always filters.
        """
        lay = self.layout
        for p in self.patterns:
            m = re.search(p, relpath)
            if m:
                g = m.groupdict()
                return tuple(None if f"{w}_column" in lay else lay.get(w, g.get(w)) for w in ("axis", "period"))
        if self.patterns == DEFAULT_PATTERNS and all(w in lay or f"{w}_column" in lay for w in ("axis", "period")):
            return tuple(lay.get(w) for w in ("axis", "period"))
        return None


def _table(doc: dict, name: str, where: str) -> dict:
    val = doc.get(name, {})
    if not isinstance(val, dict):
        raise DataError(f"{where}: [{name}] must be a table")
    return dict(val)


def config_from_dict(doc: dict, *, source: str | None = None) -> FleetConfig:
    """Build a :class:`FleetConfig` from the parsed TOML document (see :func:`load_config`)."""
    where = f"fleet config '{source}'" if source else "fleet config"
    unknown = set(doc) - _SECTIONS
    if unknown:
        raise DataError(f"{where}: unknown section(s) {sorted(unknown)}; allowed: {sorted(_SECTIONS)}")
    layout = _table(doc, "layout", where)
    bad = set(layout) - {"pattern", "patterns", "ignore", *LAYOUT_KEYS}
    if bad:
        raise DataError(f"{where}: [layout] unknown key(s) {sorted(bad)}; use pattern, patterns, ignore or "
                        f"{list(LAYOUT_KEYS)}")
    if "pattern" in layout:
        patterns = (layout["pattern"],)
    elif "patterns" in layout:
        patterns = tuple(layout["patterns"])
    else:
        patterns = DEFAULT_PATTERNS
    for p in patterns:
        if not isinstance(p, str):
            raise DataError(f"{where}: [layout] pattern {p!r}: must be a string")
    columns = _table(doc, "columns", where)
    units = _table(doc, "units", where)
    scales: dict[str, float] = {}
    si = {"v": "m/s", "F": "N"}
    for role, unit in units.items():
        if role not in ROLES:
            raise DataError(f"{where}: [units] unknown signal {role!r}; use {list(ROLES)}")
        if unit not in UNITS:
            raise DataError(f"{where}: [units] {role} = {unit!r}: unknown unit; known: {', '.join(UNITS)}")
        factor, label = UNITS[unit]
        scales[role] = factor
        if role == "velocity" or (role == "position" and "velocity" not in units):
            si["v"] = label if role == "velocity" else label + "/s"
        elif role == "force":
            si["F"] = label
    for role, factor in _table(doc, "scales", where).items():
        if role not in ROLES and role != "current_gain":
            raise DataError(f"{where}: [scales] unknown key {role!r}; use {list(ROLES) + ['current_gain']}")
        if isinstance(factor, bool) or not isinstance(factor, (int, float)):
            raise DataError(f"{where}: [scales] {role} = {factor!r}: must be a number")
        scales[role] = float(scales.get(role, 1.0)) * float(factor)
    schedule = {}
    for name, spec in _table(doc, "schedule", where).items():
        if isinstance(spec, str):
            spec = {"column": spec}
        if not isinstance(spec, dict):
            raise DataError(f"{where}: [schedule] {name} must be a column name or a table with column = ...")
        bad = set(spec) - {"column", "unit"}
        if bad:
            raise DataError(f"{where}: [schedule.{name}] unknown key(s) {sorted(bad)}; use column, unit")
        schedule[name] = {"column": spec.get("column"), "unit": str(spec.get("unit", ""))}
    return FleetConfig(columns=columns, scales=scales, si_units=si, schedule=schedule, patterns=patterns,
                       segmentation=_table(doc, "segmentation", where), fit=_table(doc, "fit", where),
                       monitor=_table(doc, "monitor", where),
                       dynamic={"lugre": True, **_table(doc, "dynamic", where)},
                       layout={k: v for k, v in layout.items() if k in LAYOUT_KEYS}, ignore=layout.get("ignore", ()),
                       source=source)


def load_config(path: str | Path) -> FleetConfig:
    """Read a fleet configuration TOML file.

    Parameters
    ----------
    path : str or Path
        The TOML file.

    Returns
    -------
    FleetConfig

    Raises
    ------
    DataError
        Missing file, not TOML, unknown section or key, unknown unit, missing column role.

    Examples
    --------
    >>> from frictionkit.fleet import load_config
    >>> cfg = load_config("fleet/fleet.toml")  # doctest: +SKIP
    >>> cfg.columns["force"]  # doctest: +SKIP
    'F_N'
    """
    from .._io import read_input_bytes

    p = Path(path)
    raw = read_input_bytes(p, f"fleet config '{p}'", missing="not found")  # a FIFO or /dev/zero was "not found" (round 11)
    try:
        doc = tomllib.loads(raw.decode("utf-8-sig"))  # a BOM is read as the JSON loaders read it
    except UnicodeDecodeError as exc:
        raise DataError(f"fleet config '{p}': not UTF-8 text (byte {exc.start})") from None
    except tomllib.TOMLDecodeError as exc:
        raise DataError(f"fleet config '{p}': not valid TOML ({exc})") from None
    return config_from_dict(doc, source=str(p))


def _toml_value(v: Any) -> str:
    if isinstance(v, str):
        return "'" + v + "'" if "'" not in v and "\n" not in v else json.dumps(v)
    if isinstance(v, bool):
        return "true" if v else "false"
    if isinstance(v, (list, tuple)):
        return "[" + ", ".join(_toml_value(x) for x in v) + "]"
    return repr(v)


def config_toml(sections: dict[str, dict], *, header: str = "") -> str:
    """TOML text of a configuration document (flat tables, one level of sub-tables)."""
    lines = [f"# {ln}" if ln else "#" for ln in header.splitlines()]
    for sec, body in sections.items():
        flat = {k: v for k, v in body.items() if not isinstance(v, dict)}
        subs = {k: v for k, v in body.items() if isinstance(v, dict)}
        if flat or not subs:
            lines += ["", f"[{sec}]"] + [f"{k} = {_toml_value(v)}" for k, v in flat.items()]
        for name, sub in subs.items():
            lines += ["", f"[{sec}.{name}]"] + [f"{k} = {_toml_value(v)}" for k, v in sub.items()]
    return "\n".join(lines).lstrip("\n") + "\n"


__all__ = ["FleetConfig", "LAYOUT_KEYS", "ROLES", "UNITS", "config_from_dict", "config_toml", "load_config"]
