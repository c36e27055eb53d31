"""LuGre and Dahl dynamic friction.

LuGre (seed 002 eqs. 5-8, after Canudas de Wit et al. 1995)::

    dz/dt = v - sigma0 |v| z / |s(v)|
    F     = sigma0 z + sigma1 dz/dt + sigma2 v

At constant velocity ``z -> sgn(v) |s(v)| / sigma0`` and ``F -> s(v) + sigma2 v``
exactly (seed 002 eq. 8 with ``sigma0 g(v) = |s(v)|``).

Dahl (1968) with exponent 1 is the special case ``s = Fc`` (no Stribeck dip),
``sigma1 = 0``: ``dF/dx = sigma0 (1 - F sgn(v) / Fc)``.
"""

from __future__ import annotations

from dataclasses import KW_ONLY, dataclass

import numpy as np

from .. import _validate as val
from .base import register_law
from .static import CoulombViscous, check_static
from typing import TYPE_CHECKING

if TYPE_CHECKING:
    from numpy.typing import ArrayLike


@dataclass(frozen=True)
class LuGre:
    """LuGre model over a static map.

    Parameters
    ----------
    static : Stribeck | CoulombViscous | Directional
        Steady-state map ``s(v) + sigma2 v``; its ``sigma2`` is the viscous term.
    sigma0 : float
        Bristle (pre-sliding) stiffness [N/m], > 0.
    sigma1 : float
        Micro-damping [N·s/m], >= 0.

    Examples
    --------
    >>> import frictionkit as fk
    >>> law = fk.Stribeck(Fc=1.0, Fs=1.5, vs=1e-3, sigma2=0.4)
    >>> model = fk.LuGre(law, sigma0=1e5, sigma1=63.2)
    >>> float(model.steady_state(0.01))
    1.004
    """

    static: object
    _: KW_ONLY
    sigma0: float
    sigma1: float = 0.0

    def __post_init__(self) -> None:
        o = type(self).__name__
        check_static(o, self.static)
        object.__setattr__(self, "sigma0", val.positive(o, "sigma0", self.sigma0))
        object.__setattr__(self, "sigma1", val.nonnegative(o, "sigma1", self.sigma1))

    def steady_state(self, v: ArrayLike) -> np.ndarray:
        return self.static.steady_state(val.velocities(f"{type(self).__name__}.steady_state", v))

    def dynamic_rows(self) -> np.ndarray:
        row = [self.sigma0, self.sigma1]
        return np.array([row, row], dtype=float)


@dataclass(frozen=True, kw_only=True)
class Dahl:
    """Dahl model (exponent 1): ``dF/dt = sigma0 v (1 - F sgn(v) / Fc)`` plus ``sigma2 v``.

    Parameters
    ----------
    Fc : float
        Coulomb level the force saturates at [N], > 0.
    sigma0 : float
        Initial (rest) stiffness [N/m], > 0.
    sigma2 : float
        Viscous coefficient [N·s/m], >= 0.
    """

    Fc: float
    sigma0: float
    sigma2: float = 0.0

    def __post_init__(self) -> None:
        o = type(self).__name__
        object.__setattr__(self, "Fc", val.positive(o, "Fc", self.Fc))
        object.__setattr__(self, "sigma0", val.positive(o, "sigma0", self.sigma0))
        object.__setattr__(self, "sigma2", val.nonnegative(o, "sigma2", self.sigma2))

    @property
    def static(self) -> CoulombViscous:
        return CoulombViscous(Fc=self.Fc, sigma2=self.sigma2)

    @property
    def sigma1(self) -> float:
        return 0.0

    def steady_state(self, v: ArrayLike) -> np.ndarray:
        return self.static.steady_state(val.velocities(f"{type(self).__name__}.steady_state", v))

    def dynamic_rows(self) -> np.ndarray:
        return np.array([[self.sigma0, 0.0], [self.sigma0, 0.0]], dtype=float)


register_law("LuGre", LuGre, "lugre")
register_law("Dahl", Dahl, "lugre")
