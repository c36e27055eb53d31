"""Records cut into motion segments, and the force a law predicts on them.

The data side of the motion-driven output error (:mod:`.motion_error`): one or
several records, each cut at its rests (:func:`frictionkit.data.find_rests`) into runs
that a dynamic law is simulated over from the unloaded state, and the error of a law
driven by that motion beside its static map's (:func:`evaluate_motion`, also used to
validate a fit on another record).
"""

from __future__ import annotations

import warnings
from collections.abc import Mapping, Sequence
from dataclasses import dataclass

import numpy as np

from .. import _validate as val
from ..data.recording import Recording
from ..data.rests import find_rests, motion_segments
from ..errors import DataError, ParameterError
from ..simulation.core import simulate
from typing import TYPE_CHECKING

if TYPE_CHECKING:
    from ..models.base import FrictionLaw
    from typing import Any

__all__ = ["INTEGRATIONS", "MotionData", "evaluate_motion", "motion_data"]

#: How a velocity log becomes a position (see :func:`motion_data`).
INTEGRATIONS = ("held", "trapezoidal")


@dataclass(frozen=True)
class _Segment:
    record: str
    dt: float
    x: np.ndarray  # drive position, from the last rest sample before the motion, starting at 0
    v: np.ndarray  # measured (or differentiated) velocity on the same samples
    F: np.ndarray  # measured force
    a: np.ndarray  # acceleration (central differences of the velocity)
    fit: np.ndarray  # bool: fitted samples (the leading rest sample is not)
    t: np.ndarray


@dataclass(frozen=True)
class MotionData:
    """Records cut into motion segments, ready for motion-driven simulation.

    Attributes
    ----------
    segments : tuple
        One entry per run between rests (record, sample period, drive position,
        velocity, force, acceleration, which samples are fitted, time).
    records : tuple of str
        Record names, in order.
    units : dict
        ``{"F": ..., "x": ..., "v": ...}`` of the first record.
    drive : str
        ``"position"`` or ``"velocity"``.
    integration : str
        How a velocity log became a position: ``"trapezoidal"`` or ``"held"``.
    summary : dict
        Per record: samples, rest samples, segments (first and last row of each).
    provenance : dict
        The records' provenance.
    rests : str
        How the rests were found (``"auto: ..."``, ``"mask"`` or ``"none"``).
    """

    segments: tuple
    records: tuple
    units: dict
    drive: str
    integration: str
    summary: dict
    provenance: dict
    rests: str = "auto"

    @property
    def n_fit(self) -> int:
        return int(sum(int(s.fit.sum()) for s in self.segments))


def _as_records(data) -> list[Recording]:
    def one(d, name):
        if isinstance(d, Recording):
            return d
        if isinstance(d, Mapping) and "t" in d:
            kw = dict(d)
            if "u" in kw and "F" not in kw:
                kw["F"] = kw.pop("u")
            unknown = set(kw) - {"t", "x", "v", "F"}
            if unknown:
                raise DataError(f"record '{name}': unknown signal(s) {sorted(unknown)}; use t, F (or u), x, v")
            return Recording(**kw, name=name)
        raise DataError(f"data: {type(d).__name__} is not a Recording or a mapping of arrays t, x|v, F")

    if isinstance(data, (Recording,)) or (isinstance(data, Mapping) and "t" in data):
        return [one(data, "arrays")]
    if isinstance(data, Mapping):
        recs = [one(d, str(k)) for k, d in data.items()]
    elif isinstance(data, Sequence) and not isinstance(data, (str, bytes)):
        recs = [one(d, f"record {i}") for i, d in enumerate(data)]
    else:
        raise DataError(f"data = {type(data).__name__}: give a Recording, a mapping of arrays, "
                        "or a list/dict of those (several records)")
    if not recs:
        raise DataError("data: no record given")
    return recs


def _rest_masks(rests, recs: list[Recording], min_rest: int) -> list[np.ndarray]:
    if val.is_bool(min_rest) or not isinstance(min_rest, (int, np.integer)) or min_rest < 1:
        # checked whatever rests is (True was taken as 1)
        raise ParameterError(f"min_rest = {min_rest!r}: must be an integer >= 1 (samples)")
    if isinstance(rests, str):
        if rests != "auto":
            raise ParameterError(f"rests = {rests!r}: must be 'auto', None or boolean masks")
        return [find_rests(r.force(), min_run=min_rest) for r in recs]
    if rests is None:
        return [np.zeros(r.n, bool) for r in recs]
    if val.is_bool(rests) or np.isscalar(rests) or not (isinstance(rests, Mapping) or np.iterable(rests)):
        raise ParameterError(f"rests = {rests!r}: must be 'auto', None or boolean masks (one per record)")
    if isinstance(rests, Mapping):
        masks = [rests.get(r.name) for r in recs]
    elif len(recs) == 1 and np.ndim(rests) == 1 and not (len(rests) and np.ndim(rests[0]) == 1):
        masks = [rests]
    else:
        masks = list(rests)
    if len(masks) != len(recs):
        raise DataError(f"rests: {len(masks)} mask(s) for {len(recs)} record(s)")
    out = []
    for r, m in zip(recs, masks):
        m = np.zeros(r.n, bool) if m is None else np.asarray(m)
        if m.shape != (r.n,):
            raise DataError(f"record '{r.name}': the rest mask has {m.size} samples, the record {r.n}")
        if m.dtype.kind not in "biuf":
            raise DataError(f"record '{r.name}': the rest mask holds {m.dtype} values; give booleans or numbers "
                            "(non-zero = drive disabled)")
        if m.dtype.kind == "f" and not np.all(np.isfinite(m)):
            i = int(np.flatnonzero(~np.isfinite(m))[0])
            raise DataError(f"record '{r.name}': the rest mask is {m[i]} at sample {i}; a mask must be finite "
                            "(non-zero = drive disabled)")
        out.append(m.astype(bool))
    return out


def motion_data(data: Any, *, drive: str = "auto", integration: str = "held", rests: Any="auto",
                min_rest: int = 3) -> MotionData:
    """Cut one or several records into the motion segments a motion-driven fit simulates.

    Parameters
    ----------
    data : Recording, mapping of arrays, or a list / dict of them
        Uniformly sampled ``t`` [s], force ``F`` (or ``u``) and the position ``x`` or
        velocity ``v``. Records may have different sample periods.
    drive : {"auto", "position", "velocity"}
        Signal that drives the model (``"auto"``: the position when present).
    integration : {"held", "trapezoidal"}
        How a velocity log becomes a position. ``"held"`` (default): the logged
        value is the mean velocity over the preceding sample interval, which is
        what drives log (an encoder difference over one period, or an "averaged
        velocity"): ``x_k = x_{k-1} + v_k dt``, so the interval velocity equals the
        log and there is no half-sample lag. ``"trapezoidal"``: the logged value is
        the velocity *at* the sample, as ``fk.simulate(velocity=...)`` assumes
        (simulated data).
    rests : "auto", None, array of bool, or one per record
        Rest samples (drive disabled): ``"auto"`` finds runs of exactly zero force
        (:func:`frictionkit.data.find_rests`); a mask gives them (True = rest);
        None: no rests.
    min_rest : int
        Shortest run of zero force taken as a rest with ``rests="auto"``.

    Returns
    -------
    MotionData
    """
    if drive not in ("auto", "position", "velocity"):
        raise ParameterError(f"drive = {drive!r}: must be 'auto', 'position' or 'velocity'")
    if integration not in INTEGRATIONS:
        raise ParameterError(f"integration = {integration!r}: must be one of {', '.join(INTEGRATIONS)}")
    recs = _as_records(data)
    masks = _rest_masks(rests, recs, min_rest)
    segs: list[_Segment] = []
    summary: dict = {}
    drives = set()
    for rec, rest in zip(recs, masks):
        rec.require("F")
        if not rec.is_regular:
            raise irregular(rec)
        d = drive if drive != "auto" else ("position" if rec.x is not None else "velocity")
        if d == "position" and rec.x is None or d == "velocity" and rec.v is None:
            raise DataError(f"recording '{rec.name}': drive = {d!r} needs the {d} signal; "
                            f"present: {', '.join(rec.signals)}")
        drives.add(d)
        dt = rec.dt
        F = np.asarray(rec.force(), dtype=float)
        if d == "position":
            x = np.asarray(rec.x, dtype=float)
            v = np.asarray(rec.v, dtype=float) if rec.v is not None else np.gradient(x, dt)
        else:
            v = np.asarray(rec.v, dtype=float)
            inc = v[1:] * dt if integration == "held" else 0.5 * (v[1:] + v[:-1]) * dt
            x = np.concatenate([[0.0], np.cumsum(inc)])
        a = np.gradient(v, dt) if v.size > 1 else np.zeros_like(v)
        rec_segs = []
        for s0, start, stop in segment_bounds(rest):
            fit = np.ones(stop - s0, bool)
            if s0 < start:
                fit[0] = False
            sl = slice(s0, stop)
            segs.append(_Segment(rec.name, dt, x[sl] - x[s0], v[sl], F[sl], a[sl], fit, rec.t[sl]))
            rec_segs.append([int(start), int(stop)])
        summary[rec.name] = {"samples": rec.n, "rest_samples": int(rest.sum()), "segments": rec_segs,
                             "dt": dt, "drive": d}
    if not segs:
        raise DataError(f"no motion to fit: {no_motion_cause(rests, min_rest)}")
    r0 = recs[0]
    units = {"F": r0.units["F"], "x": r0.units["x"],
             "v": r0.units["v"] if r0.units["v"] != "m/s" or r0.units["x"] == "m" else f"{r0.units['x']}/s"}
    prov = {"records": [dict(rec.provenance, name=rec.name) for rec in recs]}
    return MotionData(tuple(segs), tuple(r.name for r in recs), units,
                      drives.pop() if len(drives) == 1 else "mixed", integration, summary, prov,
                      _describe_rests(rests, min_rest))


def irregular(rec: Recording) -> DataError:
    """The error for an irregularly sampled record, naming its worst step (a dropped or repeated row
    in a file was reported as "call Recording.resample() first" with no place)."""
    d = np.diff(rec.t)
    m = float(np.median(d))
    i = int(np.argmax(np.abs(d - m)))
    return DataError(f"recording '{rec.name}': irregular sampling: the step at t = {rec.t[i]:.6g} s (sample {i}) is "
                     f"{d[i]:.6g} s against a median of {m:.6g} s (a missing or repeated row?); resample it first "
                     "(Recording.resample)")


def no_motion_cause(rests, min_rest: int) -> str:
    """Why every sample was taken as a rest, in the words of the ``rests=`` the caller gave."""
    if isinstance(rests, str):
        return (f"every sample is at rest (rests='auto': the force is logged exactly 0 over runs of >= "
                f"{min_rest} samples everywhere, or the runs between them are shorter than 2 samples)")
    if rests is None:
        return "every record is shorter than 2 samples"
    return ("the rest mask marks every sample as at rest (or leaves runs of motion shorter than 2 samples); "
            "a mask is non-zero where the drive is disabled")


def segment_bounds(rest) -> list[tuple[int, int, int]]:
    """``(s0, start, stop)`` of every run of motion between rests, each simulated from the unloaded state.

    ``start:stop`` are the run's samples; ``s0`` is where its simulation starts: the last
    rest sample before the run (the drive was disabled there, so the axis holds no
    load), or ``start`` itself for a run at the beginning of the record. Sample ``s0`` is
    not fitted when ``s0 < start``. The force-driven fit
    (:func:`~frictionkit.identify.fit_output_error`) and the motion-driven one cut their
    records the same way.
    """
    return [(start - 1 if start > 0 else start, start, stop) for start, stop in motion_segments(rest, min_length=2)]


# --------------------------------------------------------------------------- prediction
def _simulate_segments(model, md: MotionData) -> list[np.ndarray] | None:
    out = []
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", RuntimeWarning)
        for s in md.segments:
            res = simulate(model, position=s.x, dt=s.dt)
            out.append(res.friction)
    return out


def evaluate_motion(model: FrictionLaw, data: Any, *, inertia: float = 0.0, offset: float = 0.0, drive: str = "auto",
                    integration: str = "held", rests: Any="auto", min_rest: int = 3,
                    static: Any=None) -> dict:
    """Error of a dynamic law driven by recorded motion, beside its static map's.

    The force predicted by ``model`` (motion-driven from the unloaded state after
    every rest, plus ``inertia · a + offset``) is compared with the measured force on
    every sample where the drive is enabled.

    Parameters
    ----------
    model : dynamic law
        LuGre, Dahl, GMS or a Directional of one.
    data, drive, integration, rests, min_rest
        As in :func:`motion_data` (``data`` may also be a :class:`MotionData`).
    inertia, offset : float
        The ``J a`` and constant terms [kg or kg·m²], [N or N·m].
    static : law, optional
        The static map of the comparison (default ``model``'s steady state).

    Returns
    -------
    dict
        ``rms``, ``relative_error_percent``, ``static_rms``, ``static_relative_error_percent``
        (the steady-state map at the measured velocity, same ``J a + offset``),
        ``n``, ``t``, ``F``, ``F_pred``, ``F_static`` (fitted samples, records one after another).
    """
    md = data if isinstance(data, MotionData) else motion_data(data, drive=drive, integration=integration,
                                                                rests=rests, min_rest=min_rest)
    sims = _simulate_segments(model, md)
    st = static if static is not None else model
    return _errors(md, sims, st, inertia, offset)


def _errors(md: MotionData, sims, static, J: float, off: float) -> dict:
    F, P, S, T = [], [], [], []
    t_shift = 0.0
    last_rec = None
    for s, Fs in zip(md.segments, sims):
        if last_rec is not None and s.record != last_rec:
            t_shift = T[-1][-1] + 2 * s.dt - s.t[0] if T else 0.0
        last_rec = s.record
        k = s.fit
        F.append(s.F[k])
        P.append(Fs[k] + J * s.a[k] + off)
        S.append(np.asarray(static.steady_state(s.v[k]), dtype=float) + J * s.a[k] + off)
        T.append(s.t[k] + t_shift)
    F, P, S, T = (np.concatenate(a) for a in (F, P, S, T))
    nF = max(float(np.linalg.norm(F)), 1e-300)
    r, rs = P - F, S - F
    r0 = (S - J * np.concatenate([s.a[s.fit] for s in md.segments]) - off) - F  # the map without J a + offset
    return {"rms": float(np.sqrt(np.mean(r**2))), "relative_error_percent": float(100 * np.linalg.norm(r) / nF),
            "static_rms": float(np.sqrt(np.mean(rs**2))), "map_only_rms": float(np.sqrt(np.mean(r0**2))),
            "static_relative_error_percent": float(100 * np.linalg.norm(rs) / nF),
            "n": int(F.size), "t": T, "F": F, "F_pred": P, "F_static": S}


def _typical(md: MotionData) -> tuple[float, float]:
    """Median |v| over moving fitted samples, and the median sample period."""
    v = np.concatenate([np.abs(s.v[s.fit]) for s in md.segments])
    moving = v[v > 0.05 * (v.max() if v.size else 0.0)]
    v_typ = float(np.median(moving)) if moving.size else float(max(v.max(initial=0.0), 1e-12))
    dt = float(np.median([s.dt for s in md.segments]))
    return max(v_typ, 1e-300), dt



def _describe_rests(rests, min_rest: int) -> str:
    if isinstance(rests, str):
        return f"auto: runs of >= {int(min_rest)} samples with the force exactly 0"
    return "none" if rests is None else "mask"
