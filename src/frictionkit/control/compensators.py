"""Zero-speed friction compensation signals along a reference (seed 001 eqs. 5-7).

The laws of :mod:`frictionkit.models.rolling` are written for one reversal from negative to
positive velocity as functions of the displacement from the reversal point. Along a
reference with several zero-speed points each sample belongs to the nearest crossing
(segments split halfway in time); with ``xi = sgn(t - t0) |x - x0|`` (negative while
approaching the zero-speed point, positive after) and ``d`` the new direction:

* ``sinc`` (eq. 6): ``d * sinc_compensation(xi)`` — previous-direction ``F0`` until zero
  speed, then the sinc rise over ``xs`` (compensation *after* the zero-speed point);
* ``sigmoid`` (eq. 5, Fig. 11): ``d * sigmoid_compensation(xi)`` — already falls to 0 while
  approaching zero speed ("helps brake"), then rises to ``F0`` (compensation *before*);
* ``sigmoid_post_only``: the sigmoid law with its pre-zero reduction removed — previous-direction
  ``F0`` until the zero-speed instant, then the sigmoid rise ``d * sigmoid_compensation(xi)``
  (a control experiment: does the reduction *before* zero speed, the paper's point, help?);
* ``coulomb`` (eq. 7, sign corrected): ``F0 sgn(v)``, switching at the zero-speed point;
* ``hold``: non-reverse crossing, friction keeps its direction: ``d * F0``;
* ``none``: no compensation.

For a non-reverse crossing ``sinc`` and ``coulomb`` reduce to ``hold``, ``sigmoid`` to
``d * |sigmoid(xi)|`` and ``sigmoid_post_only`` to ``d * F0`` before, ``d * sigmoid(xi)`` after. Samples at rest before the first motion get no compensation.
Values are torques [N·m] (``F0`` as the paper gives it); divide by ``K_tau`` for current.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from .. import _validate as val
from ..errors import ParameterError
from ..models.rolling import coulomb_compensation, sigmoid_compensation, sinc_compensation
from .zero_speed import find_crossings
from typing import TYPE_CHECKING

if TYPE_CHECKING:
    from ..control.trajectories import Reference
    from ..control.zero_speed import Crossing
    from collections.abc import Sequence

LAWS = ("sinc", "coulomb", "sigmoid", "sigmoid_post_only", "hold", "none")


@dataclass(frozen=True, kw_only=True)
class RollingCompensator:
    """Parameters of the three compensators of seed 001 §5.

    Parameters
    ----------
    F0 : float — Coulomb level [N·m] (§5.3: 2.65).
    xs : float — sinc pre-sliding length [m] (§5.3: 10 µm).
    sigma : float — sigmoid length [m] (§5.3: "2", read as 2 µm).
    """

    F0: float
    xs: float = 10e-6
    sigma: float = 2e-6

    def __post_init__(self) -> None:
        o = "RollingCompensator"
        object.__setattr__(self, "F0", val.nonnegative(o, "F0", self.F0))
        object.__setattr__(self, "xs", val.positive(o, "xs", self.xs))
        object.__setattr__(self, "sigma", val.positive(o, "sigma", self.sigma))

    def signal(self, reference: Reference, law: str="sinc", crossings: Sequence[Crossing] | None=None) -> np.ndarray:
        """Compensation torque [N·m] along ``reference``.

        Parameters
        ----------
        reference : Reference
        law : str or sequence of str — one law for every crossing, or one per crossing.
        crossings : list of Crossing, optional — default ``find_crossings(reference)``.

        Examples
        --------
        >>> from frictionkit.control.trajectories import cosine_reference
        >>> from frictionkit.control.compensators import RollingCompensator
        >>> ref = cosine_reference(duration=1.0)
        >>> u = RollingCompensator(F0=2.65).signal(ref, "coulomb")
        >>> float(u[500]), float(u[1500])
        (2.65, -2.65)
        """
        t, x, v = reference.t, reference.x, reference.v
        if crossings is None:
            crossings = find_crossings(t, v, x)
        laws = [law] * len(crossings) if isinstance(law, str) else list(law)
        if len(laws) != len(crossings):
            raise ParameterError(f"law has {len(laws)} entries: need one per crossing ({len(crossings)})")
        for name in laws:
            if name not in LAWS:
                raise ParameterError(f"law = {name!r}: must be one of {LAWS}")
        F0 = self.F0
        moving = np.flatnonzero(np.abs(v) > 1e-12)
        u = np.zeros(t.size)
        if moving.size == 0:
            return u
        if not crossings:
            return coulomb_compensation(v, F0=F0) * (np.abs(v) > 1e-12)
        t0s = np.array([c.t0 for c in crossings])
        edges = np.concatenate(([-np.inf], 0.5 * (t0s[1:] + t0s[:-1]), [np.inf]))
        seg = np.searchsorted(edges, t, side="right") - 1
        for j, (c, name) in enumerate(zip(crossings, laws)):
            sel = seg == j
            if not sel.any():
                continue
            xi = np.sign(t[sel] - c.t0) * np.abs(x[sel] - c.x0)
            d = c.after
            if name == "none":
                val_ = np.zeros(xi.size)
            elif name == "hold" or (not c.reverse and name in ("sinc", "coulomb")):
                val_ = np.full(xi.size, d * F0)
            elif name == "sigmoid":
                s = sigmoid_compensation(xi, F0=F0, sigma=self.sigma)
                val_ = d * (s if c.reverse else np.abs(s))
            elif name == "sigmoid_post_only":
                s = sigmoid_compensation(np.maximum(xi, 0.0), F0=F0, sigma=self.sigma)
                val_ = d * np.where(xi < 0.0, -F0 if c.reverse else F0, s)
            elif name == "sinc":
                val_ = d * sinc_compensation(xi, F0=F0, xs=self.xs)
            else:  # coulomb
                vv = v[sel]
                val_ = np.where(vv > 1e-12, F0, np.where(vv < -1e-12, -F0, d * F0))
            u[sel] = val_
        u[: moving[0]] = 0.0
        return u
