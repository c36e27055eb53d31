"""Rolling-friction compensation laws for velocity reversals (seed 001 eqs. 5-7).

All three are functions of the displacement ``x`` [m] from the reversal (zero-speed)
point, written for a reversal from negative to positive velocity; for the other
direction pass ``-x`` and negate the result.

Corrections to seed 001 recorded here:

* eq. 5 prints ``sigma = 2`` without a unit; ``x / sigma`` must be dimensionless, so
  ``sigma`` is a length. We read it as 2 µm, consistent with the ~10 µm pre-sliding
  length of Figs. 12-13 (an assumption, documented in the ballscrew preset).
* ``F0`` is printed in N·m (2.431 and 2.65 N·m, Figs. 13, §5.3): a motor torque,
  not a force.
"""

from __future__ import annotations

import numpy as np

from .. import _validate as _check
from typing import TYPE_CHECKING

if TYPE_CHECKING:
    from numpy.typing import ArrayLike


def sigmoid_compensation(x: ArrayLike, *, F0: float, sigma: float) -> np.ndarray:
    """Seed 001 eq. 5: ``F0 (x/sigma) / sqrt(1 + (x/sigma)^2)``.

    Parameters
    ----------
    x : array_like
        Displacement from the reversal point [m].
    F0 : float
        Coulomb level [N or N·m], >= 0.
    sigma : float
        Transition length [m], > 0.

    Examples
    --------
    >>> from frictionkit.models.rolling import sigmoid_compensation
    >>> sigmoid_compensation([0.0, 2e-6, 1.0], F0=2.0, sigma=2e-6).round(4).tolist()
    [0.0, 1.4142, 2.0]
    """
    F0 = _check.nonnegative("sigmoid_compensation", "F0", F0)
    sigma = _check.positive("sigmoid_compensation", "sigma", sigma)
    r = _check.real_values("sigmoid_compensation", "x", x, "displacements from the reversal [m or rad]") / sigma
    return F0 * r / np.sqrt(1.0 + r * r)


def sinc_compensation(x: ArrayLike, *, F0: float, xs: float) -> np.ndarray:
    """Seed 001 eq. 6: sinc-shaped rise from ``-F0`` at ``x = 0`` to ``F0`` at ``x = xs``.

    ``-F0`` for ``x < 0``; ``2 F0 sinc(sqrt(x/xs) - 1) - F0`` on ``[0, xs)`` (normalised
    ``sinc(y) = sin(pi y)/(pi y)``, i.e. the paper's ``sin(pi sqrt(x/xs) - pi)/(pi sqrt(x/xs) - pi)``);
    ``F0`` for ``x >= xs``.

    Examples
    --------
    >>> from frictionkit.models.rolling import sinc_compensation
    >>> sinc_compensation([-1e-6, 0.0, 10e-6], F0=2.431, xs=10e-6).tolist()
    [-2.431, -2.431, 2.431]
    """
    F0 = _check.nonnegative("sinc_compensation", "F0", F0)
    xs = _check.positive("sinc_compensation", "xs", xs)
    x = _check.real_values("sinc_compensation", "x", x, "displacements from the reversal [m or rad]")
    y = np.sqrt(np.clip(x / xs, 0.0, 1.0)) - 1.0
    mid = 2.0 * F0 * np.sinc(y) - F0
    return np.where(x < 0.0, -F0, np.where(x >= xs, F0, mid))


def coulomb_compensation(v: ArrayLike, *, F0: float) -> np.ndarray:
    """Seed 001 eq. 7 with the sign of a friction *compensation*: ``F0 sgn(v)``.

    The paper prints ``u = F0`` for ``v < 0`` and ``-F0`` for ``v >= 0``, which is the
    friction force itself (it opposes motion); a compensating input has the opposite
    sign. We return the compensating input ``+F0`` for ``v >= 0`` and ``-F0`` for
    ``v < 0`` (correction recorded here).
    """
    F0 = _check.nonnegative("coulomb_compensation", "F0", F0)
    v = _check.real_values("coulomb_compensation", "v", v, "velocities [m/s or rad/s]")
    return np.where(v >= 0.0, F0, -F0)
