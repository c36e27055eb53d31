"""TDMSSC: the corrected Stribeck curve of the two-axis differential micro-feed system.

Reference
---------
Seed 000 (Zhang et al., *Actuators* 2023), eq. 21 and Table 5. In differential-speed mode the
lumped friction of the nut motor, plotted against the **table speed** ``v``, is a Stribeck
curve whose Coulomb and static levels shift in proportion to the **base speed** ``s`` (the
speed the nut is held at), plus a term quadratic in the speed from the balls' centrifugal
force::

    F(v; s) = sgn(v) [Fc(s) + (Fs(s) - Fc(s)) exp(-|v / vs|^delta)] + sigma2 v - eps v |v|
    Fc(s) = Fc0 + Fc1 s,      Fs(s) = Fs0 + Fs1 s

Decisions on the paper's printing (recorded here, and next to the values in the tests):

* **Schedule variable.** Eq. 21 writes the levels as functions of ``theta2_dot``; Fig. 12
  labels the curves "Vbase = -4 mm/s, -0.1 mm/s" and §5.2.2 speaks of the nut "rotation
  speed" in mm/s, so ``theta2_dot`` is the nut's base speed as a *linear-equivalent* speed
  (``R theta2_dot``, R = P_h / 2 pi) in mm/s, signed by §2.3's convention (nut speed
  negative when both motors turn clockwise). In SI the schedule ``s`` is that speed in m/s,
  and the printed slope 6.45 N/(mm/s) becomes ``Fc1 = Fs1 = 6450 N·s/m``.
* **Levels are signed.** The nut's levels are negative at the paper's own base speeds
  (``Fc(s) < 0`` for ``s < 0.70 mm/s``, ``Fs(s) < 0`` for ``s < 3.03 mm/s``; Table 5's nut-
  column is -48.34 / -62.26 N). Read with eq. 20 (``T_n = T_fn - T_fbn``) and the text
  ("the friction created by the ball when the screw serves as the driving shaft helps the nut
  rotate"), a negative level is physical: the ball pair *drives* the nut. The law is applied
  as written: ``F = sgn(v) level``, so a negative level gives a force **along** the motion
  (it supplies energy). Nothing is clipped at zero; a level of exactly zero gives no force.
* **The quadratic term is odd.** Eq. 21 prints ``- eps v^2`` (even in ``v``); with the
  per-direction columns of Table 5 we use ``- eps v |v|``, which equals the printed term for
  ``v > 0`` and keeps the friction an odd function of ``v`` for symmetric parameters: the
  centrifugal effect strengthens the ball's drive on the nut in either direction (it adds to
  the negative levels' side), which is what §5.2.2 describes ("friction increases first and
  then reduces").
* **Units of sigma and eps.** Table 5 prints sigma in N·s/m and eps in N·s²/m with every
  speed in mm/s. Read in SI, the terms would be invisible (eps v² = 2e-4 N at 6 mm/s) and the
  curve could not "increase first and then reduce" as §5.2.2 says; read per mm/s, they are of
  the size of the Stribeck dip. We read them per mm/s: ``sigma2 [N·s/m] = 1e3 x printed``,
  ``eps [N·s²/m²] = 1e6 x printed``.
* **Stribeck speed.** Eq. 21 shares one symbol ``v_s3`` between the screw and nut lines,
  while Table 5 gives one per column: each law has its own ``vs`` (Table 5's value, its
  magnitude: the table prints it signed).
* **Directions.** One ``TDMSSC`` holds one parameter set; Table 5's two columns per shaft are
  ``Directional(positive=TDMSSC(...), negative=TDMSSC(...))``, as for every other law.

A TDMSSC is a static (memoryless) law of kernel family ``"static"``: in the machine core it
sticks and slips with the discrete Karnopp treatment of every static site, its levels
re-evaluated from the machine's schedule input at every sub-step (``Machine.friction(...,
schedule=<coordinate>.velocity)``), and negative levels are allowed there too (see
``kernels/machine.py``).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from .. import _validate as val
from ..errors import ParameterError
from .base import register_law
from typing import TYPE_CHECKING

if TYPE_CHECKING:
    from numpy.typing import ArrayLike

#: Columns of one row of :meth:`TDMSSC.schedule_rows` (and of every static law's, see
#: :func:`schedule_rows`): levels affine in the schedule, Stribeck shape, viscous, quadratic.
SCHEDULE_COLUMNS = ("Fc0", "Fc1", "Fs0", "Fs1", "vs", "delta", "sigma2", "shape", "eps")


@dataclass(frozen=True, kw_only=True)
class TDMSSC:
    """Seed 000 eq. 21: a Stribeck curve with levels affine in a scheduling variable ``s``.

    ``F(v; s) = sgn(v) [Fc(s) + (Fs(s) - Fc(s)) exp(-|v/vs|^delta)] + sigma2 v - eps v |v|``
    with ``Fc(s) = Fc0 + Fc1 s`` and ``Fs(s) = Fs0 + Fs1 s``. Levels may be negative (a force
    along the motion, see the module docstring); ``sigma2`` may be negative.

    Parameters
    ----------
    Fc0, Fs0 : float
        Coulomb and static levels at ``s = 0`` [N or N·m], any sign.
    vs : float
        Stribeck velocity [m/s or rad/s], > 0 (pass the magnitude of a signed print).
    delta : float
        Exponent of the Stribeck shape, > 0.
    Fc1, Fs1 : float
        Slopes of the levels in the schedule [N per unit of ``s``, e.g. N·s/m for a speed];
        default 0 (a plain Stribeck curve with signed levels).
    sigma2 : float
        Viscous coefficient [N·s/m], any sign (Table 5 has -1.12 for the nut).
    eps : float
        Coefficient of the ``- eps v |v|`` term [N·s²/m²], any sign.

    Examples
    --------
    Table 5, nut, positive direction, in SI (see the module docstring for the conversions):

    >>> import frictionkit as fk
    >>> nut = fk.TDMSSC(Fc0=-4.52, Fc1=6450.0, Fs0=-19.56, Fs1=6450.0, vs=0.065e-3,
    ...                 delta=1.7, sigma2=-1120.0, eps=5.852e6)
    >>> nut.levels(schedule=-4e-3)              # (Fc, Fs) at base speed -4 mm/s [N]
    (-30.32, -45.36)
    >>> float(nut.steady_state(1e-3, schedule=-4e-3).round(3))   # at 1 mm/s table speed [N]
    -37.292
    """

    Fc0: float
    Fs0: float
    vs: float
    delta: float = 1.0
    Fc1: float = 0.0
    Fs1: float = 0.0
    sigma2: float = 0.0
    eps: float = 0.0

    def __post_init__(self) -> None:
        o = type(self).__name__
        for f in ("Fc0", "Fs0", "Fc1", "Fs1", "sigma2", "eps"):
            object.__setattr__(self, f, val.finite(o, f, getattr(self, f)))
        object.__setattr__(self, "vs", val.positive(o, "vs", self.vs))
        object.__setattr__(self, "delta", val.positive(o, "delta", self.delta))
        if self.Fc0 == self.Fs0 == self.Fc1 == self.Fs1 == 0.0:
            raise ParameterError(f"{o}: Fc0 = Fs0 = Fc1 = Fs1 = 0 leaves no friction level to model")

    # ---------------------------------------------------------------- evaluation
    def levels(self, *, schedule: float) -> tuple[float, float]:
        """``(Fc(s), Fs(s))`` at the schedule value ``s`` [N]."""
        s = val.finite(type(self).__name__, "schedule", schedule)
        return (round(self.Fc0 + self.Fc1 * s, 12), round(self.Fs0 + self.Fs1 * s, 12))

    def schedule_rows(self) -> np.ndarray:
        """``(2, 9)`` rows (row 0: ``v >= 0``, row 1: ``v < 0``) in :data:`SCHEDULE_COLUMNS`."""
        row = [self.Fc0, self.Fc1, self.Fs0, self.Fs1, self.vs, self.delta, self.sigma2, 0.0, self.eps]
        return np.array([row, row], dtype=float)

    def steady_state(self, v: ArrayLike, *, schedule: ArrayLike | None=None) -> np.ndarray:
        """``F(v; s)`` for an array of velocities ``v`` at schedule ``s`` (scalar or broadcastable).

        ``schedule`` is required (a :class:`ParameterError` without it): a TDMSSC has no level
        without its scheduling variable, and no default is assumed (friction-law contract,
        item 4).
        """
        if schedule is None:
            raise ParameterError(f"{type(self).__name__}.steady_state: schedule = None: give the scheduling "
                                 "variable (the base speed [m/s] for seed 000's nut), e.g. schedule=-4e-3")
        return _schedule_eval(self.schedule_rows(), v, schedule, type(self).__name__)


def _schedule_eval(rows: np.ndarray, v, schedule, owner: str) -> np.ndarray:
    """NumPy reference evaluation of :data:`SCHEDULE_COLUMNS` rows (row 0: v >= 0, row 1: v < 0)."""
    v = val.velocities(f"{owner}.steady_state", v)
    try:
        s = np.asarray(schedule, dtype=float)
    except (TypeError, ValueError):
        raise ParameterError(f"{owner}.steady_state: schedule = {schedule!r}: must be real numbers") from None
    if not np.all(np.isfinite(s)):
        raise ParameterError(f"{owner}.steady_state: schedule = {schedule!r}: must be finite")
    v, s = np.broadcast_arrays(v, s)
    neg = v < 0.0
    p = np.where(neg[..., None], rows[1], rows[0])
    Fc0, Fc1, Fs0, Fs1, vs, delta, sigma2, shape, eps = (p[..., i] for i in range(len(SCHEDULE_COLUMNS)))
    Fc = Fc0 + Fc1 * s
    Fs = Fs0 + Fs1 * s
    r = np.abs(v) / vs
    with np.errstate(over="ignore", under="ignore"):
        phi = np.where(shape == 0.0, np.exp(-(r**delta)), 1.0 / (1.0 + r * r))
    return np.sign(v) * (Fc + (Fs - Fc) * phi) + sigma2 * v - eps * v * np.abs(v)


def schedule_rows(law) -> np.ndarray:
    """``(2, 9)`` :data:`SCHEDULE_COLUMNS` rows of any static law (the machine core's packing).

    ``TDMSSC`` and ``Directional`` of it give their own; ``Stribeck``, ``CoulombViscous`` and
    ``Directional`` of those give their levels with zero slopes and ``eps = 0``.
    """
    from .static import Directional

    if isinstance(law, Directional):
        return np.array([schedule_rows(law.positive)[0], schedule_rows(law.negative)[1]])
    if isinstance(law, TDMSSC):
        return law.schedule_rows()
    r = np.asarray(law.static_rows(), dtype=float)  # Fc, Fs, vs, delta, sigma2, shape
    z = np.zeros(2)
    return np.column_stack([r[:, 0], z, r[:, 1], z, r[:, 2], r[:, 3], r[:, 4], r[:, 5], z])


def is_scheduled(law) -> bool:
    """True for a law that reads a schedule input (``TDMSSC`` or ``Directional`` of it)."""
    from .static import Directional

    if isinstance(law, Directional):
        return isinstance(law.positive, TDMSSC)
    return isinstance(law, TDMSSC)


register_law("TDMSSC", TDMSSC, "static")
