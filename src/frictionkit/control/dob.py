"""Inverse-model disturbance observer on motor velocity (seed 001 §2.2, ref. 6).

``d_hat = Q(s) [K_tau i - (J_n s + B_n) omega]`` with ``Q`` a first-order low-pass (80 Hz in
seed 001), discretised at ``T``: ``d_k = a d_{k-1} + (1 - a) raw_k``, ``a = exp(-2 pi f T)``,
``omega`` the backward difference of the encoder angle. ``d_hat / K_tau`` is added to the
current. The observer sees the applied current *without* the friction compensation ``u_f``,
so it estimates the friction left after compensation (DOB and compensator coexist).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

from .. import _validate as val


@dataclass(frozen=True, kw_only=True)
class DisturbanceObserver:
    """Parameters of the DOB.

    Parameters
    ----------
    K_tau : float — nominal torque constant [N·m/A].
    J : float — nominal inertia [kg·m²].
    B : float — nominal viscosity [N·m·s/rad].
    cutoff_hz : float — low-pass cut-off [Hz].
    T : float — sampling period [s].

    Examples
    --------
    >>> from frictionkit.control.dob import DisturbanceObserver
    >>> round(DisturbanceObserver(K_tau=0.715, J=0.01, B=0.1, cutoff_hz=80.0).a, 4)
    0.7778
    """

    K_tau: float
    J: float
    B: float
    cutoff_hz: float = 80.0
    T: float = 0.5e-3

    def __post_init__(self) -> None:
        o = "DisturbanceObserver"
        for name in ("K_tau", "J", "cutoff_hz", "T"):
            object.__setattr__(self, name, val.positive(o, name, getattr(self, name)))
        object.__setattr__(self, "B", val.nonnegative(o, "B", self.B))

    @property
    def a(self) -> float:
        """Discrete low-pass pole ``exp(-2 pi f T)``."""
        return math.exp(-2.0 * math.pi * self.cutoff_hz * self.T)
