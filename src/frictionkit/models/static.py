"""Static friction maps: Stribeck curves, Coulomb + viscous, and direction dependence.

References
----------
Seed 000 (Zhang et al., Actuators 2023) eq. 4: exponential Stribeck curve with free
exponent ``delta``. Seed 002 (SDSS telescope) eqs. 9a (Lorentzian) and 9b
(exponential, ``delta = 2``). Steady-state friction ``Fss(v) = s(v) + sigma2 * v``.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import Literal, Protocol, runtime_checkable

import numpy as np

from .. import _validate as val
from ..errors import ParameterError
from .base import kernel_family, register_law
from typing import TYPE_CHECKING

if TYPE_CHECKING:
    from numpy.typing import ArrayLike
    from typing import Any

#: Shape codes used by the kernels.
SHAPE_CODES = {"exponential": 0, "lorentzian": 1}

# Column layout of one packed static row (see ``static_rows``).
N_STATIC = 6


@runtime_checkable
class StaticLaw(Protocol):
    """What the dynamic models need from a static map."""

    def stribeck(self, v: np.ndarray) -> np.ndarray: ...

    def steady_state(self, v: np.ndarray) -> np.ndarray: ...

    def static_rows(self) -> np.ndarray: ...


def _stribeck_eval(rows: np.ndarray, v: np.ndarray, *, viscous: bool) -> np.ndarray:
    """NumPy reference evaluation of packed static rows (row 0: v >= 0, row 1: v < 0)."""
    v = np.asarray(v, dtype=float)
    neg = v < 0.0
    p = np.where(neg[..., None], rows[1], rows[0])
    Fc, Fs, vs, delta, sigma2, shape = (p[..., i] for i in range(N_STATIC))
    r = np.abs(v) / vs
    with np.errstate(over="ignore", under="ignore"):
        phi = np.where(shape == 0.0, np.exp(-(r**delta)), 1.0 / (1.0 + r * r))
    out = np.sign(v) * (Fc + (Fs - Fc) * phi)
    if viscous:
        out = out + sigma2 * v
    return out


@dataclass(frozen=True, kw_only=True)
class Stribeck:
    """Stribeck curve ``s(v) = sgn(v) [Fc + (Fs - Fc) phi(|v|/vs)]`` plus viscous ``sigma2 v``.

    Parameters
    ----------
    Fc : float
        Coulomb level [N or N·m], >= 0.
    Fs : float
        Static (breakaway) level [N or N·m], >= 0. ``Fs < Fc`` is allowed: seed 000
        Table 5 has corrected curves that rise with speed.
    vs : float
        Stribeck velocity [m/s or rad/s], > 0. Papers sometimes print it signed
        (seed 000 Table 3); pass its magnitude.
    delta : float
        Exponent of the exponential shape (seed 000 eq. 4), > 0. Ignored by the
        Lorentzian shape.
    sigma2 : float
        Viscous coefficient [N·s/m], >= 0, of ``Fss(v) = s(v) + sigma2 v``.
    shape : {"exponential", "lorentzian"}
        ``phi = exp(-(|v|/vs)**delta)`` (seed 002 eq. 9b for delta = 2) or
        ``phi = 1 / (1 + (v/vs)**2)`` (seed 002 eq. 9a).

    Examples
    --------
    >>> import frictionkit as fk
    >>> law = fk.Stribeck(Fc=1.0, Fs=1.5, vs=1e-3, sigma2=0.4)
    >>> law.steady_state([-1.0, 0.0, 1e-3]).round(4).tolist()
    [-1.4, 0.0, 1.1843]
    """

    Fc: float
    Fs: float
    vs: float
    delta: float = 2.0
    sigma2: float = 0.0
    shape: Literal["exponential", "lorentzian"] = "exponential"

    def __post_init__(self) -> None:
        o = type(self).__name__
        object.__setattr__(self, "Fc", val.nonnegative(o, "Fc", self.Fc))
        object.__setattr__(self, "Fs", val.nonnegative(o, "Fs", self.Fs))
        object.__setattr__(self, "vs", val.positive(o, "vs", self.vs))
        object.__setattr__(self, "delta", val.positive(o, "delta", self.delta))
        object.__setattr__(self, "sigma2", val.nonnegative(o, "sigma2", self.sigma2))
        if not isinstance(self.shape, str) or self.shape not in SHAPE_CODES:  # a list was "unhashable" (round 11)
            raise ParameterError(
                f"{o}.shape = {self.shape!r}: must be one of {sorted(SHAPE_CODES)}"
            )
        if self.Fc == 0.0 and self.Fs == 0.0:
            raise ParameterError(f"{o}: Fc = Fs = 0 leaves no friction to model; at least one must be > 0")

    def static_rows(self) -> np.ndarray:
        row = [self.Fc, self.Fs, self.vs, self.delta, self.sigma2, float(SHAPE_CODES[self.shape])]
        return np.array([row, row], dtype=float)

    def stribeck(self, v: ArrayLike) -> np.ndarray:
        """``s(v)`` without the viscous term."""
        return _stribeck_eval(self.static_rows(), v, viscous=False)

    def steady_state(self, v: ArrayLike) -> np.ndarray:
        """``Fss(v) = s(v) + sigma2 v`` for an array of velocities."""
        return _stribeck_eval(self.static_rows(), val.velocities("Stribeck.steady_state", v), viscous=True)


@dataclass(frozen=True, kw_only=True)
class CoulombViscous:
    """Coulomb plus viscous friction ``F = Fc sgn(v) + sigma2 v``.

    Parameters
    ----------
    Fc : float
        Coulomb level [N], > 0.
    sigma2 : float
        Viscous coefficient [N·s/m], >= 0.
    """

    Fc: float
    sigma2: float = 0.0

    def __post_init__(self) -> None:
        o = type(self).__name__
        object.__setattr__(self, "Fc", val.positive(o, "Fc", self.Fc))
        object.__setattr__(self, "sigma2", val.nonnegative(o, "sigma2", self.sigma2))

    def static_rows(self) -> np.ndarray:
        # A Stribeck curve with Fs = Fc is flat; vs and delta are then irrelevant.
        row = [self.Fc, self.Fc, 1.0, 1.0, self.sigma2, 0.0]
        return np.array([row, row], dtype=float)

    def stribeck(self, v: ArrayLike) -> np.ndarray:
        return _stribeck_eval(self.static_rows(), v, viscous=False)

    def steady_state(self, v: ArrayLike) -> np.ndarray:
        return _stribeck_eval(self.static_rows(), val.velocities("CoulombViscous.steady_state", v), viscous=True)


@dataclass(frozen=True, kw_only=True)
class Directional:
    """Separate parameter sets for positive and negative velocity.

    Works for any law: two static maps (``Stribeck``/``CoulombViscous``), two
    ``LuGre``, two ``GMS`` (same number of elements) or two ``Dahl``. The set for
    ``v >= 0`` is ``positive``; ``v < 0`` uses ``negative``. Papers identify each
    direction separately (seed 000 Tables 3-6, seed 002 §3.1).

    Examples
    --------
    >>> import frictionkit as fk
    >>> law = fk.Directional(positive=fk.Stribeck(Fc=1.0, Fs=1.2, vs=1e-3),
    ...                      negative=fk.Stribeck(Fc=1.5, Fs=1.8, vs=2e-3))
    >>> law.steady_state([1.0, -1.0]).tolist()
    [1.0, -1.5]
    """

    positive: object
    negative: object

    def __post_init__(self) -> None:
        if type(self.positive) is not type(self.negative):
            raise ParameterError(
                "Directional: positive and negative must be the same kind of law, got "
                f"{type(self.positive).__name__} and {type(self.negative).__name__}"
            )
        if isinstance(self.positive, Directional):
            raise ParameterError("Directional: positive/negative must not themselves be Directional")
        if not hasattr(self.positive, "steady_state"):
            raise ParameterError(
                f"Directional: {type(self.positive).__name__} is not a friction law"
            )
        kp = getattr(self.positive, "k", None)
        kn = getattr(self.negative, "k", None)
        if kp is not None and len(kp) != len(kn):
            raise ParameterError(
                f"Directional: GMS element counts differ (positive M={len(kp)}, negative M={len(kn)})"
            )

    @property
    def is_static(self) -> bool:
        """True for a pair of static maps usable inside LuGre/GMS (not a scheduled ``TDMSSC``)."""
        return isinstance(self.positive, (Stribeck, CoulombViscous))

    def static_rows(self) -> np.ndarray:
        return np.array([self.positive.static_rows()[0], self.negative.static_rows()[1]])

    def stribeck(self, v: ArrayLike) -> np.ndarray:
        return _stribeck_eval(self.static_rows(), v, viscous=False)

    def steady_state(self, v: ArrayLike, **kw: Any) -> np.ndarray:
        """Each side's ``steady_state``; keywords (``schedule=`` of a ``TDMSSC``) go to both."""
        v = val.velocities("Directional.steady_state", v)
        return np.where(v < 0.0, self.negative.steady_state(v, **kw), self.positive.steady_state(v, **kw))


def check_static(owner: str, static: object) -> None:
    """Raise unless ``static`` is a static map usable inside a dynamic model."""
    ok = isinstance(static, (Stribeck, CoulombViscous)) or (
        isinstance(static, Directional) and static.is_static
    )
    if not ok:
        raise ParameterError(
            f"{owner}.static = {type(static).__name__}: must be Stribeck, CoulombViscous "
            "or Directional(positive=..., negative=...) of those"
        )


register_law("Stribeck", Stribeck, "static")
register_law("CoulombViscous", CoulombViscous, "static")
register_law("Directional", Directional, lambda law: kernel_family(law.positive))
