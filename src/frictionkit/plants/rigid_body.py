"""A rigid axis with steady-state friction and a constant offset: ``F = M a + friction(v) + offset``.

The plant identified by IDIM-LS (:func:`frictionkit.identify.fit_rigid_body`, the EMPS
benchmark's reference model, description eqs. 1 and 12).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from .. import _validate as val
from ..errors import ParameterError
from typing import TYPE_CHECKING

if TYPE_CHECKING:
    from numpy.typing import ArrayLike


@dataclass(frozen=True, kw_only=True)
class RigidBody:
    """Rigid axis with friction: ``F = M a + friction(v) + offset``.

    Parameters
    ----------
    M : float
        Mass [kg] (or inertia [kg·m²] for a rotary axis), > 0.
    friction : CoulombViscous or Directional
        Friction law evaluated with ``steady_state(v)``.
    offset : float
        Constant force [N] (gravity, cable drag, amplifier offset).

    Examples
    --------
    >>> from frictionkit import CoulombViscous, RigidBody
    >>> body = RigidBody(M=95.0, friction=CoulombViscous(Fc=20.0, sigma2=200.0), offset=-3.0)
    >>> body.force([0.0], [0.1]).tolist()
    [37.0]
    """

    M: float
    friction: object
    offset: float = 0.0

    def __post_init__(self) -> None:
        object.__setattr__(self, "M", val.positive("RigidBody", "M", self.M))
        object.__setattr__(self, "offset", val.finite("RigidBody", "offset", self.offset))
        if not hasattr(self.friction, "steady_state"):
            raise ParameterError(f"RigidBody.friction = {type(self.friction).__name__}: must be a friction law")

    def force(self, a: ArrayLike, v: ArrayLike) -> np.ndarray:
        """Actuator force [N] for acceleration ``a`` [m/s²] and velocity ``v`` [m/s]."""
        a = np.asarray(a, dtype=float)
        v = np.asarray(v, dtype=float)
        return self.M * a + self.friction.steady_state(v) + self.offset
