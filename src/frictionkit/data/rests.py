"""Rests where a drive is disabled, and the segments of motion between them.

Drive logs hold rests where the amplifier is off: the logged torque is exactly zero
over a run of samples (the TRO2021 start-stop runs: 0.0 % of nominal torque for
seconds, interrupted at most by a single 0.1 % sample). A dynamic friction model
run across such a rest would carry its bristle or element forces through it; the
identification restarts it from the unloaded state after every rest instead.
"""

from __future__ import annotations

import numpy as np

from ..errors import DataError, ParameterError
from typing import TYPE_CHECKING

if TYPE_CHECKING:
    from numpy.typing import ArrayLike

__all__ = ["find_rests", "motion_segments"]


def _runs(mask: np.ndarray) -> list[tuple[int, int]]:
    """``(start, stop)`` of every run of True."""
    m = np.concatenate([[False], np.asarray(mask, bool), [False]])
    d = np.diff(m.astype(np.int8))
    return list(zip(np.flatnonzero(d == 1).tolist(), np.flatnonzero(d == -1).tolist()))


def find_rests(F: ArrayLike, *, min_run: int = 3, max_blip: int = 1, tol: float = 0.0) -> np.ndarray:
    """Samples where the drive is disabled: ``|F| <= tol`` over at least ``min_run`` samples.

    A burst of at most ``max_blip`` non-zero samples between two rests (or between a
    rest and the end of the record) belongs to the rest: a logger's last-digit flicker
    (drive 2 of TRO2021 logs single 0.1 % samples inside its rests) is not a motion.

    Parameters
    ----------
    F : array_like
        Logged force or torque.
    min_run : int
        Shortest run of (near-)zero samples taken as a rest (default 3; a controlled
        axis at standstill holds a non-zero torque, an exact zero over three samples
        is a disabled drive).
    max_blip : int
        Longest burst of non-zero samples absorbed into the surrounding rest (default 1).
    tol : float
        Largest ``|F|`` counted as zero (default 0: exactly zero).

    Returns
    -------
    ndarray of bool
        True at rest samples.

    Examples
    --------
    >>> from frictionkit.data import find_rests
    >>> find_rests([0, 0, 0, 1.0, 2.0, 0, 0, 0, 0.1, 0, 0, 0]).astype(int).tolist()
    [1, 1, 1, 0, 0, 1, 1, 1, 1, 1, 1, 1]
    >>> find_rests([0, 0, 0, 1.0, 0, 0, 0]).astype(int).tolist()
    [1, 1, 1, 1, 1, 1, 1]
    """
    F = np.asarray(F, dtype=float)
    if F.ndim != 1:
        raise DataError(f"find_rests: F has shape {F.shape}; expected one signal")
    if int(min_run) != min_run or min_run < 1:
        raise ParameterError(f"find_rests: min_run = {min_run!r}: must be an integer >= 1")
    if int(max_blip) != max_blip or max_blip < 0:
        raise ParameterError(f"find_rests: max_blip = {max_blip!r}: must be an integer >= 0")
    if not np.isfinite(tol) or tol < 0:
        raise ParameterError(f"find_rests: tol = {tol!r}: must be finite and >= 0")
    zero = np.abs(F) <= tol
    rest = np.zeros(F.size, bool)
    for a, b in _runs(zero):
        if b - a >= min_run:
            rest[a:b] = True
    if not rest.any():
        return rest
    for a, b in _runs(~rest):  # short bursts touching a rest on both sides (or a rest and an end)
        if b - a <= max_blip:
            rest[a:b] = True
    return rest


def motion_segments(rest: ArrayLike, *, min_length: int = 2) -> list[tuple[int, int]]:
    """``(start, stop)`` of the runs between rests, each at least ``min_length`` samples long.

    Examples
    --------
    >>> import numpy as np
    >>> from frictionkit.data import motion_segments
    >>> motion_segments(np.array([1, 1, 0, 0, 0, 1, 0, 0], bool))
    [(2, 5), (6, 8)]
    """
    rest = np.asarray(rest, dtype=bool)
    return [(a, b) for a, b in _runs(~rest) if b - a >= min_length]
