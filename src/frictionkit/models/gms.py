"""Generalized Maxwell-Slip (GMS) friction (seed 000 eqs. 1-3, 6, 9; Al-Bender et al. 2005).

``M`` elements in parallel, element ``i`` with stiffness ``k_i`` and weight ``xi_i``:

* sticking: ``dF_i/dt = k_i v``; it breaks away when ``F_i`` reaches ``xi_i s(v)``
  in the direction of motion (``F_i / s(v) >= xi_i``, ``s`` signed);
* slipping: ``dF_i/dt = sgn(v) C (xi_i - F_i / s(v))`` until the velocity reverses,
  then it sticks again.

``F = sum F_i + sigma2 v``. In steady sliding ``F = (sum xi) s(v) + sigma2 v``, so
the weights should sum to 1 for the model to settle on the static map.

Note on ``C``: in seed 000's form ``C (xi_i - F_i/s)`` the attraction constant has
the unit of force per second [N/s] (the time constant of the lag is ``|s| / C``).
"""

from __future__ import annotations

import warnings
from dataclasses import KW_ONLY, dataclass

import numpy as np

from .. import _validate as val
from ..errors import ParameterError
from .base import register_law
from .static import check_static
from typing import TYPE_CHECKING

if TYPE_CHECKING:
    from numpy.typing import ArrayLike


#: Weight sums outside this band draw a :class:`GMSWeightWarning` (assumption, issue 13:
#: within a factor 2 of 1 a sum is a fitted or printed imperfection — seed 000's Tables 4/6
#: print 0.45-1.37 — beyond it the model slides at a multiple of its static map,
#: almost always a mistake; not an error, because a fit may pass through such sums).
XI_SUM_BAND = (0.5, 2.0)


class GMSWeightWarning(UserWarning):
    """The GMS weights sum far from 1, so steady sliding is off the static map."""


@dataclass(frozen=True)
class GMS:
    """Generalized Maxwell-Slip model over a static map.

    Parameters
    ----------
    static : Stribeck | CoulombViscous | Directional
        The Stribeck curve ``s(v)`` and viscous ``sigma2``.
    k : sequence of float
        Element stiffnesses [N/m], each > 0.
    xi : sequence of float
        Element weights [-], each >= 0, same length as ``k``, not all zero. They
        should sum to 1; a sum outside ``XI_SUM_BAND`` (0.5 … 2) draws a
        :class:`GMSWeightWarning` naming the sum (steady sliding settles at
        ``sum(xi) s(v)``).
    C : float
        Attraction (lag) constant [N/s], > 0.

    Examples
    --------
    >>> import frictionkit as fk
    >>> law = fk.Stribeck(Fc=1.0, Fs=1.5, vs=1e-3, sigma2=0.4)
    >>> gms = fk.GMS(law, k=[1e4, 1e5, 1e6], xi=[0.5, 0.3, 0.2], C=20.0)
    >>> gms.M, gms.presliding_stiffness
    (3, 1110000.0)
    """

    static: object
    _: KW_ONLY
    k: tuple
    xi: tuple
    C: float

    def __post_init__(self) -> None:
        o = type(self).__name__
        check_static(o, self.static)
        k = val.vector(o, "k", self.k, rule="positive")
        xi = val.vector(o, "xi", self.xi, rule="nonnegative")
        if k.size != xi.size:
            raise ParameterError(
                f"{o}: k has {k.size} entries but xi has {xi.size}: one weight per element is required"
            )
        if not xi.any():
            raise ParameterError(f"{o}.xi = {xi.tolist()}: at least one weight must be > 0")
        object.__setattr__(self, "k", k)
        object.__setattr__(self, "xi", xi)
        object.__setattr__(self, "C", val.positive(o, "C", self.C))
        total = float(xi.sum())
        if not XI_SUM_BAND[0] <= total <= XI_SUM_BAND[1]:
            warnings.warn(
                f"{o}.xi sums to {total:.6g}, not 1: steady sliding settles at {total:.3g}·s(v), "
                f"off the static map (weights summing outside {XI_SUM_BAND[0]} … {XI_SUM_BAND[1]} "
                "are flagged)", GMSWeightWarning, stacklevel=3,
            )

    @property
    def M(self) -> int:
        """Number of elements."""
        return int(self.k.size)

    @property
    def presliding_stiffness(self) -> float:
        """Initial stiffness ``sum k_i`` [N/m] when every element sticks."""
        return float(self.k.sum())

    def steady_state(self, v: ArrayLike) -> np.ndarray:
        v = val.velocities("GMS.steady_state", v)
        s = self.static.stribeck(v)
        return float(self.xi.sum()) * s + (self.static.steady_state(v) - s)

    def __eq__(self, other) -> bool:  # arrays make the dataclass __eq__ ambiguous
        return (
            type(other) is GMS
            and self.static == other.static
            and np.array_equal(self.k, other.k)
            and np.array_equal(self.xi, other.xi)
            and self.C == other.C
        )

    __hash__ = None


register_law("GMS", GMS, "gms")
