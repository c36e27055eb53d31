"""Small validation helpers shared by the parameter objects and public functions.

Every message names the parameter, its value and the rule it breaks.
"""

from __future__ import annotations

import math
from typing import Any

import numpy as np

from .errors import DataError, ParameterError


def finite(owner: str, name: str, value: Any) -> float:
    """Return ``value`` as a float, or raise if it is not a finite real number."""
    try:
        out = float(value)
    except (TypeError, ValueError):
        raise ParameterError(f"{owner}.{name} = {value!r}: must be a real number") from None
    if not math.isfinite(out):
        raise ParameterError(f"{owner}.{name} = {out!r}: must be finite (not NaN or inf)")
    return out


def positive(owner: str, name: str, value: Any) -> float:
    out = finite(owner, name, value)
    if out <= 0.0:
        raise ParameterError(f"{owner}.{name} = {out!r}: must be > 0")
    return out


def nonnegative(owner: str, name: str, value: Any) -> float:
    out = finite(owner, name, value)
    if out < 0.0:
        raise ParameterError(f"{owner}.{name} = {out!r}: must be >= 0")
    return out


def vector(owner: str, name: str, value: Any, *, rule: str = "finite") -> np.ndarray:
    """A read-only 1-D float array whose entries obey ``rule`` (finite, positive, nonnegative)."""
    try:
        arr = np.array(value, dtype=float, ndmin=1)
    except (TypeError, ValueError):
        raise ParameterError(f"{owner}.{name} = {value!r}: must be a sequence of real numbers") from None
    if arr.ndim != 1 or arr.size == 0:
        raise ParameterError(f"{owner}.{name} has shape {arr.shape}: must be a non-empty 1-D sequence")
    bad = ~np.isfinite(arr)
    if rule == "positive":
        bad |= arr <= 0.0
    elif rule == "nonnegative":
        bad |= arr < 0.0
    if bad.any():
        i = int(np.flatnonzero(bad)[0])
        need = {"finite": "finite", "positive": "finite and > 0", "nonnegative": "finite and >= 0"}[rule]
        raise ParameterError(f"{owner}.{name}[{i}] = {float(arr[i])!r}: every entry must be {need}")
    arr.setflags(write=False)
    return arr


def signal(name: str, value: Any, *, min_len: int = 2) -> np.ndarray:
    """A contiguous 1-D float64 copy of a sampled signal, checked for NaN/inf and length."""
    try:
        arr = np.array(value, dtype=np.float64)
    except (TypeError, ValueError):
        raise DataError(f"{name}: cannot be read as an array of numbers") from None
    if arr.ndim != 1:
        raise DataError(f"{name} has shape {arr.shape}: must be 1-D (one sample per time step)")
    if arr.size < min_len:
        raise DataError(f"{name} has {arr.size} samples: need at least {min_len}")
    bad = ~np.isfinite(arr)
    if bad.any():
        i = int(np.flatnonzero(bad)[0])
        raise DataError(f"{name}[{i}] = {float(arr[i])!r}: samples must be finite (not NaN or inf)")
    return np.ascontiguousarray(arr)
