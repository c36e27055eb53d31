"""Find constant-velocity plateaus, velocity reversals and pre-sliding cycles.

Everything is automatic with documented defaults and can be overridden: pass your
own segments (``Segment(start=..., stop=..., direction=...)``) wherever a list of
plateaus is accepted.
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from dataclasses import dataclass, field
from typing import Any

import numpy as np
from scipy.ndimage import uniform_filter1d

from .. import _validate as val
from ..errors import DataError, ParameterError
from .recording import Recording
from .signals import derivative
from typing import TYPE_CHECKING

if TYPE_CHECKING:
    from numpy.typing import ArrayLike


@dataclass(frozen=True, kw_only=True)
class Segment:
    """Samples ``start:stop`` (stop exclusive) of a recording.

    Parameters
    ----------
    start, stop : int
        Sample indices, ``0 <= start < stop``.
    direction : int
        +1 (moving in the positive direction) or -1.
    kind : str
        ``"plateau"``, ``"cycle"`` or ``"record"``.
    amplitude : float, optional
        Peak-to-peak displacement of a cycle [m or rad].
    """

    start: int
    stop: int
    direction: int
    kind: str = "plateau"
    amplitude: float | None = None

    def __post_init__(self) -> None:
        if not 0 <= self.start < self.stop:
            raise ParameterError(f"Segment(start={self.start}, stop={self.stop}): need 0 <= start < stop")
        if self.direction not in (-1, 1):
            raise ParameterError(f"Segment.direction = {self.direction!r}: must be +1 or -1")

    @property
    def slice(self) -> slice:
        return slice(self.start, self.stop)

    def __len__(self) -> int:
        return self.stop - self.start


def _runs(mask: np.ndarray) -> list[tuple[int, int]]:
    """Start/stop pairs of the True runs of a boolean array."""
    d = np.diff(np.concatenate([[0], mask.astype(np.int8), [0]]))
    return list(zip(np.flatnonzero(d == 1).tolist(), np.flatnonzero(d == -1).tolist()))


@val.typed_arguments  # argument types named at the boundary (issue 13 round 11)
def find_plateaus(
    v: ArrayLike,
    dt: float,
    *,
    window: int = 11,
    rel_tol: float = 0.02,
    abs_tol: float | None = None,
    min_speed: float | None = None,
    min_duration: float = 0.0,
    min_samples: int = 10,
    trim: float = 0.1,
) -> list[Segment]:
    """Constant-velocity plateaus in both directions.

    A sample belongs to a plateau when the moving average of ``v`` over ``window``
    samples changes by at most ``max(abs_tol, rel_tol * |v|)`` across the window and
    ``|v| > min_speed``. Runs of such samples with one sign are cut again wherever
    the average drifts by more than twice that tolerance from the start of the run
    (so slow ramps are not mistaken for plateaus), then kept when they last at least
    ``min_duration`` and ``min_samples``; finally ``trim`` of each end is dropped.

    Parameters
    ----------
    v : array_like
        Velocity [m/s or rad/s], uniformly sampled.
    dt : float
        Sampling step [s].
    window : int
        Moving-average length [samples] (default 11).
    rel_tol : float
        Allowed relative change of the velocity across one window (default 2 %).
    abs_tol : float, optional
        Absolute floor of the tolerance [m/s]; default the larger of 0.01 % of
        ``max |v|`` and four standard deviations of the windowed change caused by
        noise (noise estimated robustly from the median absolute first difference).
    min_speed : float, optional
        Plateaus slower than this are ignored [m/s]; default 1 % of ``max |v|``.
    min_duration : float
        Shortest plateau kept [s], before trimming (default 0).
    min_samples : int
        Fewest samples kept after trimming (default 10).
    trim : float
        Fraction of each plateau dropped at both ends (default 0.1, i.e. 10 %),
        ``0 <= trim < 0.5``.

    Returns
    -------
    list of Segment
        In time order, ``kind="plateau"``.

    Examples
    --------
    >>> import numpy as np
    >>> from frictionkit.data import find_plateaus
    >>> v = np.concatenate([np.linspace(0, 1, 50), np.ones(200), np.linspace(1, -1, 100), -np.ones(200)])
    >>> [(s.direction, len(s)) for s in find_plateaus(v, 1e-3, trim=0.0)]
    [(1, 190), (-1, 195)]
    """
    return _find_plateaus(v, dt, window=window, rel_tol=rel_tol, abs_tol=abs_tol, min_speed=min_speed,
                          min_duration=min_duration, min_samples=min_samples, trim=trim)[0]


def _find_plateaus(
    v, dt, *, window=11, rel_tol=0.02, abs_tol=None, min_speed=None, min_duration=0.0,
    min_samples=10, trim=0.1,
) -> tuple[list[Segment], list[Segment], float]:
    """:func:`find_plateaus`, plus the plateaus left out only for being slower than
    ``min_speed`` (still above the noise floor ``abs_tol``, so not rests) and the
    ``min_speed`` used — so that callers can say what was dropped and why."""
    x = val.signal("v", v, min_len=3)
    dt = val.positive("find_plateaus", "dt", dt)
    if not 0.0 <= trim < 0.5:
        raise ParameterError(f"find_plateaus.trim = {trim!r}: must be in [0, 0.5)")
    window = val.integer("find_plateaus", "window", window, minimum=1)
    vmax = float(np.max(np.abs(x)))
    if vmax == 0.0:
        return [], [], 0.0
    if abs_tol is None:
        # noise floor: robust std of v from first differences, carried through the moving average
        sigma_v = 1.4826 * float(np.median(np.abs(np.diff(x)))) / np.sqrt(2.0)
        abs_tol = max(1e-4 * vmax, 4.0 * np.sqrt(2.0) * sigma_v / np.sqrt(window))
    else:
        abs_tol = val.nonnegative("find_plateaus", "abs_tol", abs_tol)
    min_speed = 0.01 * vmax if min_speed is None else val.nonnegative("find_plateaus", "min_speed", min_speed)
    m = uniform_filter1d(x, window, mode="nearest") if window > 1 else x
    h = max(window // 2, 1)
    mp = np.pad(m, h, mode="edge")
    change = np.abs(mp[2 * h:] - mp[: -2 * h])
    tol = np.maximum(abs_tol, rel_tol * np.abs(m))
    calm = change <= tol
    found = []
    for fast in (True, False):
        speed_ok = (np.abs(m) > min_speed) if fast else ((np.abs(m) <= min_speed) & (np.abs(m) > abs_tol))
        steady = calm & speed_ok
        out: list[Segment] = []
        for sign in (1, -1):
            for a, b in _runs(steady & (np.sign(m) == sign)):
                start = a
                ref = m[a]
                for i in range(a, b + 1):
                    if i == b or abs(m[i] - ref) > 2.0 * max(abs_tol, rel_tol * abs(ref)):
                        n = i - start
                        k = int(np.floor(trim * n))
                        s0, s1 = start + k, i - k
                        if n * dt >= min_duration and s1 - s0 >= min_samples:
                            out.append(Segment(start=s0, stop=s1, direction=sign))
                        if i < b:
                            start, ref = i, m[i]
        out.sort(key=lambda s: s.start)
        found.append(out)
    return found[0], found[1], float(min_speed)


@val.typed_arguments  # argument types named at the boundary (issue 13 round 11)
def find_reversals(v: ArrayLike, *, deadband: float = 0.0) -> np.ndarray:
    """Indices where the velocity changes sign.

    Samples with ``|v| <= deadband`` keep the previous sign, so noise around zero
    does not create spurious reversals.

    Parameters
    ----------
    v : array_like
        Velocity [m/s or rad/s].
    deadband : float
        Half-width of the band around zero ignored [m/s] (default 0).

    Returns
    -------
    ndarray of int
        First sample of each new direction.

    Examples
    --------
    >>> from frictionkit.data import find_reversals
    >>> find_reversals([1.0, 0.5, -0.5, -1.0, 0.0, 2.0]).tolist()
    [2, 5]
    """
    x = val.signal("v", v, min_len=2)
    deadband = val.nonnegative("find_reversals", "deadband", deadband)
    s = np.where(np.abs(x) > deadband, np.sign(x), 0.0)
    nz = np.flatnonzero(s != 0.0)
    if nz.size < 2:
        return np.zeros(0, dtype=int)
    changes = np.flatnonzero(np.diff(s[nz]) != 0.0) + 1
    return nz[changes].astype(int)


@val.typed_arguments  # argument types named at the boundary (issue 13 round 11)
def find_cycles(x: ArrayLike, dt: float, *, v: ArrayLike | None=None, deadband: float = 0.0,
                max_amplitude: float | None = None) -> list[Segment]:
    """Back-and-forth cycles between every other reversal (pre-sliding cycles).

    A cycle runs from one reversal to the reversal after next (there and back);
    consecutive cycles do not overlap. With
    ``max_amplitude``, only cycles whose peak-to-peak displacement is at most that
    value are kept — the small-stroke (pre-sliding) cycles of seed 000 §5.2.

    Parameters
    ----------
    x : array_like
        Position [m or rad].
    dt : float
        Sampling step [s].
    v : array_like, optional
        Velocity [m/s]; default central differences of ``x``.
    deadband : float
        Passed to :func:`find_reversals` [m/s].
    max_amplitude : float, optional
        Largest peak-to-peak displacement of a kept cycle [m or rad].

    Returns
    -------
    list of Segment
        ``kind="cycle"``, ``direction`` of the first half, ``amplitude`` set.

    Examples
    --------
    >>> import numpy as np
    >>> from frictionkit.data import find_cycles
    >>> t = np.arange(4000) * 1e-3
    >>> x = 1e-6 * np.sin(2 * np.pi * t)
    >>> len(find_cycles(x, 1e-3, max_amplitude=5e-6))
    3
    """
    pos = val.signal("x", x, min_len=3)
    dt = val.positive("find_cycles", "dt", dt)
    vel = derivative(pos, dt) if v is None else val.signal("v", v, min_len=3)
    if vel.size != pos.size:
        raise DataError(f"find_cycles: v has {vel.size} samples, x has {pos.size}")
    rev = find_reversals(vel, deadband=deadband)
    out = []
    for a, b in zip(rev[:-2:2], rev[2::2]):
        amp = float(np.ptp(pos[a:b + 1]))
        if max_amplitude is None or amp <= max_amplitude:
            out.append(Segment(start=int(a), stop=int(b), direction=int(np.sign(vel[a]) or 1),
                               kind="cycle", amplitude=amp))
    return out


@dataclass(frozen=True, kw_only=True, eq=False)
class SteadyStatePoints:
    """Averaged (velocity, force) pairs, one per constant-velocity segment or record.

    Parameters
    ----------
    v, F : ndarray
        Mean velocity [m/s or rad/s] and mean force/torque [N or N·m].
    v_std, F_std : ndarray
        Sample standard deviations inside each segment (ddof = 1).
    n : ndarray of int
        Samples averaged.
    labels : tuple of str
        Name of each point (record name or ``"start:stop"``).
    units : mapping
        ``{"v": ..., "F": ...}``.
    dropped : tuple of str
        What the automatic segmentation left out and why (plateaus slower than
        ``min_speed``); empty when nothing was dropped. Fits carry these notes into
        their warnings.
    """

    v: np.ndarray
    F: np.ndarray
    v_std: np.ndarray
    F_std: np.ndarray
    n: np.ndarray
    labels: tuple[str, ...]
    units: Mapping[str, str] = field(default_factory=lambda: {"v": "m/s", "F": "N"})
    dropped: tuple[str, ...] = ()

    def __len__(self) -> int:
        return int(self.v.size)

    def select(self, direction: int) -> SteadyStatePoints:
        """Points with ``sign(v) == direction`` (+1 or -1)."""
        keep = np.sign(self.v) == direction
        return SteadyStatePoints(v=self.v[keep], F=self.F[keep], v_std=self.v_std[keep],
                                 F_std=self.F_std[keep], n=self.n[keep],
                                 labels=tuple(lab for lab, k in zip(self.labels, keep) if k),
                                 units=self.units, dropped=self.dropped)


def _velocity(rec: Recording) -> np.ndarray:
    if rec.v is not None:
        return rec.v
    if rec.x is not None:
        return derivative(rec.x, rec.dt)
    raise DataError(f"recording '{rec.name}': needs velocity v or position x to find constant-velocity segments")


def _mean_std(a: np.ndarray) -> tuple[float, float]:
    return float(np.mean(a)), (float(np.std(a, ddof=1)) if a.size > 1 else 0.0)


def _from_file(rec: Recording) -> str:
    src = (rec.provenance or {}).get("file")
    return f" (file '{src}')" if src else ""


def steady_state_points(
    source: Recording | Mapping[str, Recording],
    *,
    plateaus: Sequence[Segment] | None = None,
    trim: float | None = None,
    **find_kw: Any,
) -> SteadyStatePoints:
    """Average velocity and force over constant-velocity segments.

    Parameters
    ----------
    source : Recording or mapping of str to Recording
        One recording: its plateaus are found with :func:`find_plateaus` (or taken
        from ``plateaus``). A mapping (e.g. from :func:`~frictionkit.data.load_groups`):
        each record is one steady-state point, averaged whole.
    plateaus : sequence of Segment, optional
        Override the automatic segmentation of a single recording.
    trim : float, optional
        Fraction dropped at both ends of each segment. Default: 0.1 for automatically
        found plateaus (applied by :func:`find_plateaus`), 0 for whole records
        (so whole-record means are exact).
    **find_kw
        Passed to :func:`find_plateaus`.

    Returns
    -------
    SteadyStatePoints

    Raises
    ------
    DataError
        No force signal, no velocity/position, or no constant-velocity segment found.

    Examples
    --------
    >>> import numpy as np
    >>> from frictionkit.data import Recording, steady_state_points
    >>> t = np.arange(300) * 1e-3
    >>> rec = Recording(t=t, v=np.r_[np.full(150, 0.1), np.full(150, -0.1)],
    ...                 F=np.r_[np.full(150, 2.0), np.full(150, -3.0)])
    >>> steady_state_points(rec).F.tolist()
    [2.0, -3.0]
    """
    rows = []
    dropped: tuple[str, ...] = ()
    if isinstance(source, Recording):
        source.require("F")
        v = _velocity(source)
        F = source.force()
        if plateaus is None and source.n < 3:  # said "v has 2 samples: need at least 3", naming no file (round 9)
            raise DataError(f"recording '{source.name}'{_from_file(source)}: {source.n} samples; finding "
                            "constant-velocity segments needs at least 3")
        if plateaus is None:
            if trim is not None:
                find_kw["trim"] = trim
            find_plateaus(v, source.dt, **find_kw)  # checks the keywords by its signature
            plateaus, slow, min_speed = _find_plateaus(v, source.dt, **find_kw)
            # a plateau straddling min_speed (its noisy samples cut into pieces on both sides)
            # is kept in part: report only plateaus clearly below it
            slow = [s for s in slow if abs(float(np.mean(v[s.slice]))) < 0.8 * min_speed]
            if slow:
                dropped = (_dropped_note(v, slow, min_speed, "min_speed" in find_kw, source.units["v"]),)
        if not plateaus:
            vmax = float(np.max(np.abs(v))) if v.size else 0.0
            imax = int(np.argmax(np.abs(v))) if v.size else 0
            why = (f" ({dropped[0]})" if dropped else
                   f"; the largest |v| is {vmax:.6g} {source.units['v']} at sample {imax}")
            raise DataError(
                f"recording '{source.name}': no constant-velocity segment found{why}; check the velocity "
                "signal or pass plateaus=[Segment(...)] / adjust rel_tol, window, min_speed"
            )
        for s in plateaus:
            if s.stop > source.n:
                raise DataError(f"{s}: stop beyond the {source.n} samples of recording '{source.name}'")
            vm, vs = _mean_std(v[s.slice])
            fm, fsd = _mean_std(F[s.slice])
            rows.append((vm, fm, vs, fsd, len(s), f"{s.start}:{s.stop}"))
        units = {"v": source.units["v"], "F": source.units["F"]}
    else:
        # a list, text or any object was "'list' object has no attribute 'items'" (issue 13 round 11)
        if not isinstance(source, Mapping):
            raise ParameterError(f"steady_state_points.source = {val.short(source)}: must be a Recording or a "
                                 "mapping of name -> Recording (e.g. from load_groups)")
        bad = next((k for k, r in source.items() if not isinstance(r, Recording)), None)
        if bad is not None:
            raise ParameterError(f"steady_state_points.source[{bad!r}] = {val.short(source[bad])}: must be a "
                                 "Recording")
        if not source:
            raise DataError("steady_state_points: no records given")
        tr = 0.0 if trim is None else float(trim)
        if not 0.0 <= tr < 0.5:
            raise ParameterError(f"steady_state_points.trim = {trim!r}: must be in [0, 0.5)")
        units = None
        for label, rec in source.items():
            rec.require("F")
            v = _velocity(rec)
            F = rec.force()
            k = int(np.floor(tr * rec.n))
            sl = slice(k, rec.n - k)
            vm, vs = _mean_std(v[sl])
            fm, fsd = _mean_std(F[sl])
            rows.append((vm, fm, vs, fsd, sl.stop - sl.start, str(label)))
            units = units or {"v": rec.units["v"], "F": rec.units["F"]}
    a = np.array([r[:5] for r in rows], dtype=float)
    return SteadyStatePoints(v=a[:, 0], F=a[:, 1], v_std=a[:, 2], F_std=a[:, 3],
                             n=a[:, 4].astype(int), labels=tuple(r[5] for r in rows), units=units,
                             dropped=dropped)


def _dropped_note(v: np.ndarray, slow: Sequence[Segment], min_speed: float, given: bool, vu: str) -> str:
    """One sentence: which slow plateaus were left out, at which speeds, and how to keep them."""
    speeds = np.array([abs(float(np.mean(v[s.slice]))) for s in slow])
    rule = "min_speed" if given else "min_speed, by default 1 % of the top speed,"
    where = ", ".join(f"{s.start}:{s.stop}" for s in slow[:6]) + (", ..." if len(slow) > 6 else "")
    return (
        f"{len(slow)} constant-velocity plateau(s) at |v| = {speeds.min():.3g} … {speeds.max():.3g} {vu} "
        f"(samples {where}) were left out: slower than {rule} = {min_speed:.3g} {vu}; the Stribeck "
        "region lies at low speed, pass min_speed=0 (CLI: identify static --min-speed 0) to keep them"
    )
