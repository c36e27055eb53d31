"""A single rigid axis: ``m dv/dt = u - F``."""

from __future__ import annotations

from dataclasses import dataclass

from .. import _validate as val


@dataclass(frozen=True)
class Mass:
    """Rigid mass (or inertia) driven by a force (torque) ``u`` against friction ``F``.

    Parameters
    ----------
    m : float
        Mass [kg] (or inertia [kg·m²] for a rotary axis), > 0.
    """

    m: float

    def __post_init__(self) -> None:
        object.__setattr__(self, "m", val.positive("Mass", "m", self.m))
