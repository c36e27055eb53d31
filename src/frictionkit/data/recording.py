"""A validated, immutable time series recorded on a motion axis.

A :class:`Recording` holds the time stamps ``t`` and any of position ``x``,
velocity ``v``, force/torque ``F``, motor ``current`` (with its ``current_gain``),
controller ``command`` and ``reference``. Everything is stored in SI units;
conversions happen in the loaders (see :mod:`frictionkit.data.loaders`).

Validation happens once, at construction, and every message names the file,
the column and the row of the offending sample when the recording came from a
file (``provenance["file"]`` and ``provenance["columns"]``). Rows are 0-based sample
indices of the recording (for a CSV file with one header line, file line = row + 2).
"""

from __future__ import annotations

import math
import warnings
from collections.abc import Mapping
from dataclasses import dataclass, field, fields, replace
from types import MappingProxyType
from typing import Any

import numpy as np

from .. import _validate as _val
from ..errors import DataError

#: Names of the optional sampled signals, in the order they are reported.
SIGNALS = ("x", "v", "F", "current", "command", "reference")

#: SI unit assumed for each signal when ``units`` does not say otherwise.
DEFAULT_UNITS = {
    "t": "s",
    "x": "m",
    "v": "m/s",
    "F": "N",
    "current": "A",
    "command": "V",
    "reference": "m",
}

#: Relative spread of the sampling step above which a recording is called irregular.
IRREGULAR_RTOL = 1e-3


class IrregularSamplingWarning(UserWarning):
    """The time stamps of a recording are not equally spaced (see :meth:`Recording.resample`)."""


def _where(provenance: Mapping[str, Any], signal: str) -> str:
    """Human-readable location of ``signal``: ``file 'a.csv', column 'vir_V'`` or ``signal F``."""
    columns = provenance.get("columns", {}) or {}
    col = columns.get(signal)
    src = provenance.get("file")
    parts = []
    if src:
        parts.append(f"file '{src}'")
    grp = provenance.get("group")
    if grp:
        parts.append("record " + ", ".join(f"{k}={v}" for k, v in grp.items()))
    if col is not None:
        parts.append(f"column '{col}'")
    else:
        parts.append(f"signal '{signal}'")
    return ", ".join(parts)


def _as_signal(provenance: Mapping[str, Any], signal: str, value: Any, n: int | None) -> np.ndarray:
    where = _where(provenance, signal)
    try:
        arr = np.array(value, dtype=np.float64)
    except (TypeError, ValueError):
        raise DataError(f"{where}: cannot be read as numbers") from None
    if arr.ndim != 1:
        arr = arr.squeeze()
        if arr.ndim != 1:
            raise DataError(f"{where}: has shape {arr.shape}, must be 1-D (one sample per time step)")
    if n is not None and arr.size != n:
        raise DataError(f"{where}: has {arr.size} samples but t has {n}; every signal needs one sample per time stamp")
    bad = ~np.isfinite(arr)
    if bad.any():
        i = int(np.flatnonzero(bad)[0])
        raise DataError(
            f"{where}, row {i}: value {float(arr[i])!r} is not finite "
            f"({int(bad.sum())} bad sample(s) in total); remove or repair them before loading"
        )
    hit = _val.outlier(arr)
    if hit is not None:
        i, limit = hit
        raise DataError(
            f"{where}, row {i}: value {float(arr[i]):.6g} is beyond {limit:.3g}, "
            f"{_val.OUTLIER_FACTOR:.0e} times the 99th percentile of the column's magnitudes: "
            "a corrupt sample or a unit/scale slip; remove or repair it before loading"
        )
    arr = np.ascontiguousarray(arr)
    arr.setflags(write=False)
    return arr


#: The fields of :class:`Recording` checked against their annotations at construction (the signals are checked as
#: arrays by :func:`_as_signal`).
_TYPED_FIELDS = ("current_gain", "units", "name", "provenance")


@dataclass(frozen=True, kw_only=True, eq=False)
class Recording:
    """Sampled signals of one experiment on one axis, validated at construction.

    Parameters
    ----------
    t : array_like
        Time stamps [s], strictly increasing, at least :attr:`MIN_SAMPLES` samples.
    x : array_like, optional
        Position [m or rad].
    v : array_like, optional
        Velocity [m/s or rad/s].
    F : array_like, optional
        Force or torque [N or N·m] acting on the axis (motor side).
    current : array_like, optional
        Motor current [A]; with ``current_gain`` it gives the force when ``F`` is absent.
    current_gain : float, optional
        Force (torque) per ampere [N/A or N·m/A].
    command : array_like, optional
        Controller output as logged [V or any unit].
    reference : array_like, optional
        Reference (set-point) position [m or rad].
    units : mapping, optional
        Unit string per signal name; missing entries take :data:`DEFAULT_UNITS`.
    name : str
        Short label used in plots and reports.
    provenance : mapping, optional
        Where the data came from. Loaders store ``file``, ``columns`` (signal → column
        name), ``scales`` and ``sha256``; error messages use ``file`` and ``columns``.

    Raises
    ------
    DataError
        NaN or inf samples, signals of different lengths, time stamps that are not
        strictly increasing (repeated or going backwards), too few samples.

    Warns
    -----
    IrregularSamplingWarning
        When the sampling step varies by more than :data:`IRREGULAR_RTOL` (relative).
        Call :meth:`resample` to get a uniformly sampled copy.

    Examples
    --------
    >>> import numpy as np
    >>> from frictionkit.data import Recording
    >>> t = np.arange(5) * 1e-3
    >>> rec = Recording(t=t, v=np.full(5, 0.1), F=np.full(5, 2.0))
    >>> rec.n, rec.dt
    (5, 0.001)
    """

    t: np.ndarray
    x: np.ndarray | None = None
    v: np.ndarray | None = None
    F: np.ndarray | None = None
    current: np.ndarray | None = None
    current_gain: float | None = None
    command: np.ndarray | None = None
    reference: np.ndarray | None = None
    units: Mapping[str, str] = field(default_factory=dict)
    name: str = "recording"
    provenance: Mapping[str, Any] = field(default_factory=dict)

    #: Smallest number of samples a recording may have.
    MIN_SAMPLES = 2

    def __post_init__(self) -> None:
        # the scalar and mapping fields keep their annotations (issue 13 round 11: current_gain="abc" was
        # float()'s ValueError, units="abc" "dictionary update sequence ...", name=None accepted)
        for f in fields(self):
            if f.name in _TYPED_FIELDS:
                _val.annotated("Recording", f.name, getattr(self, f.name), f.type)
        prov = MappingProxyType(dict(self.provenance or {}))
        object.__setattr__(self, "provenance", prov)
        t = _as_signal(prov, "t", self.t, None)
        if t.size < self.MIN_SAMPLES:
            raise DataError(
                f"{_where(prov, 't')}: has {t.size} sample(s); a recording needs at least "
                f"{self.MIN_SAMPLES} samples"
            )
        dt = np.diff(t)
        if (dt <= 0.0).any():
            i = int(np.flatnonzero(dt <= 0.0)[0]) + 1
            what = "repeats the previous time stamp" if dt[i - 1] == 0.0 else "goes backwards"
            raise DataError(
                f"{_where(prov, 't')}, row {i}: time {float(t[i])!r} {what} ({float(t[i - 1])!r} at row {i - 1}); "
                "time stamps must be strictly increasing"
            )
        object.__setattr__(self, "t", t)
        present = []
        for s in SIGNALS:
            val = getattr(self, s)
            if val is not None:
                object.__setattr__(self, s, _as_signal(prov, s, val, t.size))
                present.append(s)
        if self.current_gain is not None:
            g = float(self.current_gain)
            if not math.isfinite(g) or g == 0.0:
                raise DataError(f"Recording.current_gain = {self.current_gain!r}: must be finite and non-zero")
            object.__setattr__(self, "current_gain", g)
        units = dict(DEFAULT_UNITS)
        units.update(self.units or {})
        object.__setattr__(self, "units", MappingProxyType(units))
        step = np.median(dt)
        spread = float(np.max(np.abs(dt - step)) / step)
        if spread > IRREGULAR_RTOL:
            k = int(np.argmax(np.abs(dt - step))) + 1
            warnings.warn(
                f"{_where(prov, 't')}: irregular sampling, step at row {k} is {dt[k - 1]:.6g} s "
                f"against a median of {step:.6g} s (relative deviation {spread:.3g} > {IRREGULAR_RTOL:g}); "
                "call Recording.resample() for a uniform grid",
                IrregularSamplingWarning,
                stacklevel=3,
            )

    # ------------------------------------------------------------------ properties
    @property
    def n(self) -> int:
        """Number of samples."""
        return int(self.t.size)

    @property
    def dt(self) -> float:
        """Median sampling step [s]."""
        return float(np.median(np.diff(self.t)))

    @property
    def fs(self) -> float:
        """Sampling rate [Hz] from the median step."""
        return 1.0 / self.dt

    @property
    def duration(self) -> float:
        """``t[-1] - t[0]`` [s]."""
        return float(self.t[-1] - self.t[0])

    @property
    def signals(self) -> tuple[str, ...]:
        """Names of the signals present (besides ``t``)."""
        return tuple(s for s in SIGNALS if getattr(self, s) is not None)

    @property
    def is_regular(self) -> bool:
        """True when every step is within :data:`IRREGULAR_RTOL` of the median step."""
        d = np.diff(self.t)
        m = np.median(d)
        return bool(np.max(np.abs(d - m)) / m <= IRREGULAR_RTOL)

    # ------------------------------------------------------------------ access
    def require(self, *names: str) -> None:
        """Raise :class:`DataError` unless every named signal is present."""
        missing = [s for s in names if s != "F" and getattr(self, s) is None]
        if "F" in names and self.F is None and (self.current is None or self.current_gain is None):
            missing.append("F (or current with current_gain)")
        if missing:
            raise DataError(
                f"recording '{self.name}': missing signal(s) {', '.join(missing)}; "
                f"present: {', '.join(self.signals) or 'only t'}"
            )

    def force(self) -> np.ndarray:
        """Force/torque [N or N·m]: ``F`` if present, else ``current_gain * current``."""
        self.require("F")
        if self.F is not None:
            return self.F
        out = self.current * self.current_gain
        out.setflags(write=False)
        return out

    def segment(self, start: int, stop: int, *, name: str | None = None) -> Recording:
        """Samples ``start:stop`` as a new recording (provenance records the slice)."""
        if not 0 <= start < stop <= self.n:
            raise DataError(f"segment({start}, {stop}): need 0 <= start < stop <= {self.n}")
        prov = dict(self.provenance)
        prov["segment"] = [int(start), int(stop)]
        kw = {s: getattr(self, s)[start:stop] for s in self.signals}
        return replace(self, t=self.t[start:stop], name=name or self.name, provenance=prov, **kw)

    def resample(self, dt: float | None = None) -> Recording:
        """Linearly interpolate every signal onto a uniform grid.

        Parameters
        ----------
        dt : float, optional
            New sampling step [s]; default the median step of the recording.

        Returns
        -------
        Recording
            A new, uniformly sampled recording starting at ``t[0]``; its provenance
            records ``resampled_dt``.

        Examples
        --------
        >>> import numpy as np, warnings
        >>> from frictionkit.data import Recording
        >>> with warnings.catch_warnings():
        ...     warnings.simplefilter("ignore")
        ...     rec = Recording(t=[0.0, 0.1, 0.3, 0.4], x=[0.0, 1.0, 3.0, 4.0])
        >>> rec.resample(0.1).x.round(12).tolist()
        [0.0, 1.0, 2.0, 3.0, 4.0]
        """
        step = self.dt if dt is None else float(dt)
        if not math.isfinite(step) or step <= 0.0:
            raise DataError(f"resample: dt = {dt!r}: must be finite and > 0")
        n = int(math.floor(self.duration / step * (1.0 + 1e-12))) + 1
        tn = self.t[0] + step * np.arange(n)
        kw = {s: np.interp(tn, self.t, getattr(self, s)) for s in self.signals}
        prov = dict(self.provenance)
        prov["resampled_dt"] = step
        return replace(self, t=tn, provenance=prov, **kw)

    def __repr__(self) -> str:
        sig = ", ".join(self.signals) or "no signals"
        return f"Recording(name={self.name!r}, n={self.n}, dt={self.dt:.6g} s, signals: {sig})"
