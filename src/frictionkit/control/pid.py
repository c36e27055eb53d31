"""Discrete PID with filtered derivative and anti-windup, designed by pole placement.

Seed 001 §2.2: "A PID compensator, designed by pole assignment approach, is applied as the
feedback controller. The resulting bandwidth of the closed loop is 20 Hz", at 0.5 ms.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

from .. import _validate as val


@dataclass(frozen=True, kw_only=True)
class PID:
    """``C(s) = Kp + Ki/s + Kd s/(tau_d s + 1)``, discretised by backward Euler at ``T``.

    Parameters
    ----------
    Kp : float — proportional gain [A/rad].
    Ki : float — integral gain [A/(rad·s)].
    Kd : float — derivative gain [A·s/rad].
    tau_d : float — derivative filter time constant [s] (>= 0).
    T : float — sampling period [s] (> 0).

    The integrator is frozen while the current saturates (conditional integration).
    """

    Kp: float
    Ki: float
    Kd: float
    tau_d: float = 0.0
    T: float = 0.5e-3

    def __post_init__(self) -> None:
        for name in ("Kp", "Ki", "Kd", "tau_d"):
            object.__setattr__(self, name, val.nonnegative("PID", name, getattr(self, name)))
        object.__setattr__(self, "T", val.positive("PID", "T", self.T))

    @classmethod
    def pole_placement(cls, *, K_tau: float, J: float, B: float, bandwidth_hz: float,
                       T: float = 0.5e-3, derivative_cutoff_hz: float | None = None) -> "PID":
        """Place the three closed-loop poles of ``PID x K_tau/(J s^2 + B s)`` at ``-2 pi bandwidth_hz``.

        ``J s^3 + (B + K_tau Kd) s^2 + K_tau Kp s + K_tau Ki = J (s + w)^3``, so
        ``Kp = 3 J w^2 / K_tau``, ``Ki = J w^3 / K_tau``, ``Kd = (3 J w - B) / K_tau``.

        Examples
        --------
        >>> from frictionkit.control.pid import PID
        >>> c = PID.pole_placement(K_tau=0.715, J=0.01, B=0.1, bandwidth_hz=20.0)
        >>> round(c.Kp, 1), round(c.Ki), round(c.Kd, 3)
        (662.6, 27754, 5.133)
        """
        K_tau = val.positive("PID.pole_placement", "K_tau", K_tau)
        J = val.positive("PID.pole_placement", "J", J)
        B = val.nonnegative("PID.pole_placement", "B", B)
        f = val.positive("PID.pole_placement", "bandwidth_hz", bandwidth_hz)
        w = 2.0 * math.pi * f
        Kd = (3.0 * J * w - B) / K_tau
        if Kd < 0.0:
            from ..errors import ParameterError

            raise ParameterError(
                f"PID.pole_placement bandwidth_hz = {f!r}: too low for B = {B!r} (needs 3 J w >= B)"
            )
        tau_d = 0.0
        if derivative_cutoff_hz is not None:
            tau_d = 1.0 / (2.0 * math.pi * val.positive("PID.pole_placement", "derivative_cutoff_hz",
                                                        derivative_cutoff_hz))
        return cls(Kp=3.0 * J * w * w / K_tau, Ki=J * w**3 / K_tau, Kd=Kd, tau_d=tau_d, T=T)
