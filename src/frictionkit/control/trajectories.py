"""Reference trajectories sampled at the control period: position, velocity, acceleration.

* :func:`cosine_reference` — seed 001 §5: ``x*(t) = 25 (1 - cos 2 pi t)`` mm, peak
  deceleration ``100 pi^2`` mm/s² at the reversals (a *fast* reversal for that stage).
* :func:`piecewise_reference` — exact integration of piecewise-constant acceleration
  (trapezoidal speed profiles).
* :func:`zero_speed_reference` — the four zero-speed cases of seed 001 Fig. 10 / Table 2:
  cruise, decelerate to zero, accelerate again in the opposite (reverse) or the same
  (non-reverse) direction, cruise.
* :func:`mixed_reference` — slow and fast reversals in one run (for the Table 2 selector).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from .. import _validate as val
from ..errors import DataError, ParameterError
from typing import TYPE_CHECKING

if TYPE_CHECKING:
    from collections.abc import Sequence


@dataclass(frozen=True, eq=False)
class Reference:
    """A sampled reference: ``t`` [s], ``x`` [m], ``v`` [m/s], ``a`` [m/s²] on a uniform grid ``T``."""

    t: np.ndarray
    x: np.ndarray
    v: np.ndarray
    a: np.ndarray
    T: float

    def __post_init__(self) -> None:
        n = None
        for name in ("t", "x", "v", "a"):
            arr = val.signal(f"Reference.{name}", getattr(self, name))
            if n is None:
                n = arr.size
            elif arr.size != n:
                raise DataError(f"Reference.{name} has {arr.size} samples: must match t ({n})")
            arr.setflags(write=False)
            object.__setattr__(self, name, arr)
        object.__setattr__(self, "T", val.positive("Reference", "T", self.T))

    def __len__(self) -> int:
        return self.t.size


def _grid(duration: float, T: float) -> np.ndarray:
    duration = val.positive("reference", "duration", duration)
    T = val.positive("reference", "T", T)
    n = int(round(duration / T)) + 1
    return np.arange(n) * T


def cosine_reference(*, amplitude: float = 25e-3, period: float = 1.0, duration: float = 1.25,
                     T: float = 0.5e-3) -> Reference:
    """``x = amplitude (1 - cos(2 pi t / period))`` — seed 001 §5 with the defaults.

    Examples
    --------
    >>> from frictionkit.control.trajectories import cosine_reference
    >>> ref = cosine_reference(duration=1.0)
    >>> round(float(ref.x.max()) * 1e3, 6), round(float(-ref.a.min()), 4)   # mm, m/s^2
    (50.0, 0.987)
    """
    A = val.positive("cosine_reference", "amplitude", amplitude)
    P = val.positive("cosine_reference", "period", period)
    t = _grid(duration, T)
    w = 2.0 * np.pi / P
    return Reference(t=t, x=A * (1.0 - np.cos(w * t)), v=A * w * np.sin(w * t),
                     a=A * w * w * np.cos(w * t), T=T)


def piecewise_reference(segments: Sequence[tuple[float, float]], *, x0: float = 0.0, v0: float = 0.0, T: float = 0.5e-3) -> Reference:
    """Exact position/velocity for piecewise-constant acceleration.

    Parameters
    ----------
    segments : sequence of (duration [s], acceleration [m/s²])
    x0, v0 : float — initial position [m] and velocity [m/s].

    Examples
    --------
    >>> from frictionkit.control.trajectories import piecewise_reference
    >>> ref = piecewise_reference([(0.1, 1.0), (0.1, -1.0)])
    >>> round(float(ref.x[-1]), 6), round(float(ref.v[-1]), 12)
    (0.01, 0.0)
    """
    segs = [(val.positive("piecewise_reference", "segment duration", d),
             val.finite("piecewise_reference", "segment acceleration", a)) for d, a in segments]
    if not segs:
        raise ParameterError("piecewise_reference segments = []: need at least one segment")
    t_edges = np.concatenate(([0.0], np.cumsum([d for d, _ in segs])))
    t = _grid(t_edges[-1], T)
    xs, vs = [float(x0)], [float(v0)]
    for d, a in segs:
        xs.append(xs[-1] + vs[-1] * d + 0.5 * a * d * d)
        vs.append(vs[-1] + a * d)
    k = np.clip(np.searchsorted(t_edges, t, side="right") - 1, 0, len(segs) - 1)
    acc = np.array([a for _, a in segs])[k]
    tau = t - t_edges[k]
    v = np.array(vs)[k] + acc * tau
    x = np.array(xs)[k] + np.array(vs)[k] * tau + 0.5 * acc * tau * tau
    return Reference(t=t, x=x, v=v, a=acc, T=T)


def zero_speed_reference(*, reverse: bool, speed: float, decel: float, accel: float | None = None,
                         direction: int = 1, t_cruise: float = 0.1, t_after: float = 0.1,
                         T: float = 0.5e-3) -> Reference:
    """Start from rest, cruise at ``direction * speed``, decelerate at ``decel`` to zero speed,
    accelerate at ``accel`` (default ``decel``) to ``speed`` again — in the opposite direction
    if ``reverse`` else in the same one — and cruise for ``t_after``.

    The run starts with an acceleration phase at ``accel`` from rest. Zero speed is reached at
    ``zero_speed_time(...)``.
    """
    speed = val.positive("zero_speed_reference", "speed", speed)
    decel = val.positive("zero_speed_reference", "decel", decel)
    accel = decel if accel is None else val.positive("zero_speed_reference", "accel", accel)
    if direction not in (1, -1):
        raise ParameterError(f"zero_speed_reference direction = {direction!r}: must be +1 or -1")
    d = float(direction)
    d2 = -d if reverse else d
    segs = [(speed / accel, d * accel), (t_cruise, 0.0), (speed / decel, -d * decel),
            (speed / accel, d2 * accel), (t_after, 0.0)]
    return piecewise_reference(segs, T=T)


def mixed_reference(*, speed: float, slow_decel: float, fast_decel: float, t_cruise: float = 0.1,
                    pattern: str = "sfsf", T: float = 0.5e-3) -> Reference:
    """Back-and-forth motion whose reversals are slow (``s``) or fast (``f``) per ``pattern``.

    Each reversal decelerates at the given rate and accelerates back at the same rate; the
    motion starts from rest (accelerating at ``fast_decel``) and ends with a cruise.
    """
    speed = val.positive("mixed_reference", "speed", speed)
    rates = {"s": val.positive("mixed_reference", "slow_decel", slow_decel),
             "f": val.positive("mixed_reference", "fast_decel", fast_decel)}
    if not pattern or set(pattern) - set("sf"):
        raise ParameterError(f"mixed_reference pattern = {pattern!r}: must be a non-empty string of 's'/'f'")
    d = 1.0
    segs = [(speed / rates["f"], d * rates["f"]), (t_cruise, 0.0)]
    for c in pattern:
        a = rates[c]
        segs += [(speed / a, -d * a), (speed / a, -d * a), (t_cruise, 0.0)]
        d = -d
    return piecewise_reference(segs, T=T)
