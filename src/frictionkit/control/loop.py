"""Closed-loop simulation of a ball-screw stage with the seed 001 controller (Fig. 3).

``i = u_ptc + PID(theta_d - y) + d_hat / K_tau + u_f / K_tau``, saturated at ``i_max``, every
``T`` = 0.5 ms. The stage and this controller run on the machine core
(:func:`frictionkit.presets.ballscrew.simulate_stage`); :func:`simulate_closed_loop` is a thin
wrapper over it kept for existing callers. The PID
acts on the table position from the linear scale divided by ``R`` (``feedback = "table"``),
on the motor encoder angle (``"motor"``), or on the scale for P and I and the encoder for D
(``"dual"``, the seed 001 preset: collocated damping of the elastic chain). The DOB always
uses the motor encoder; it sees the current without ``u_f``.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from .. import _validate as val
from ..errors import ParameterError
from .dob import DisturbanceObserver
from .pid import PID
from .ptc import PerfectTrackingControl
from .trajectories import Reference
from typing import TYPE_CHECKING

if TYPE_CHECKING:
    from matplotlib.axes import Axes
    from numpy.typing import ArrayLike
    from typing import Any


@dataclass(frozen=True, kw_only=True)
class Sensors:
    """Encoder and linear scale: resolution and white noise before quantisation.

    Parameters
    ----------
    encoder_counts : int — pulses per revolution (seed 001: 2**20); 0 = ideal.
    scale_resolution : float — linear-scale step [m] (seed 001: 100 nm); 0 = ideal.
    encoder_noise_counts : float — noise std [counts].
    scale_noise : float — noise std [m].
    """

    encoder_counts: int = 2**20
    scale_resolution: float = 100e-9
    encoder_noise_counts: float = 0.0
    scale_noise: float = 0.0

    def __post_init__(self) -> None:
        o = "Sensors"
        n = val.nonnegative(o, "encoder_counts", self.encoder_counts)
        if n != int(n):
            raise ParameterError(f"{o}.encoder_counts = {self.encoder_counts!r}: must be an integer")
        object.__setattr__(self, "encoder_counts", int(n))
        for name in ("scale_resolution", "encoder_noise_counts", "scale_noise"):
            object.__setattr__(self, name, val.nonnegative(o, name, getattr(self, name)))

    @property
    def encoder_step(self) -> float:
        return 2.0 * math.pi / self.encoder_counts if self.encoder_counts else 0.0


@dataclass(frozen=True, kw_only=True)
class TwoDofController:
    """Seed 001 Fig. 3: PTC feed-forward + PID feedback + DOB, current limit.

    Parameters
    ----------
    ptc : PerfectTrackingControl
    pid : PID
    dob : DisturbanceObserver or None
    R : float — screw ratio used to express table positions as motor angles [m/rad].
    i_max : float — current limit [A].
    feedback : str — ``"table"`` (linear scale), ``"motor"`` (encoder) or ``"dual"`` (P, I on
        the scale, D on the encoder).
    """

    ptc: PerfectTrackingControl
    pid: PID
    dob: DisturbanceObserver | None
    R: float
    i_max: float = 30.0
    feedback: str = "table"

    def __post_init__(self) -> None:
        o = "TwoDofController"
        object.__setattr__(self, "R", val.positive(o, "R", self.R))
        object.__setattr__(self, "i_max", val.positive(o, "i_max", self.i_max))
        if self.feedback not in ("table", "motor", "dual"):
            raise ParameterError(f"{o}.feedback = {self.feedback!r}: must be 'table', 'motor' or 'dual'")
        if not isinstance(self.pid, PID) or not isinstance(self.ptc, PerfectTrackingControl):
            raise ParameterError(f"{o}: pid must be a PID and ptc a PerfectTrackingControl")
        if self.dob is not None and abs(self.dob.T - self.pid.T) > 1e-15:
            raise ParameterError(f"{o}: dob.T = {self.dob.T!r} must equal pid.T = {self.pid.T!r}")
        if abs(self.ptc.T_input - self.pid.T) > 1e-15:
            raise ParameterError(f"{o}: ptc.T_frame / ptc.n = {self.ptc.T_input!r} must equal pid.T = {self.pid.T!r}")

    @property
    def T(self) -> float:
        return self.pid.T


@dataclass(frozen=True, eq=False)
class ClosedLoopResult:
    """Time series of one closed-loop run (SI). ``status`` 0 = ok; else ``message`` says why.

    Attributes: ``t``, ``r`` (reference), ``x_t`` / ``theta_m`` (true), ``x_t_meas`` /
    ``theta_m_meas`` (sensors), ``i`` (current), ``drive_force`` (``F_bn``, with the
    Hertz contact's nonlinear part for nut model ``"hertz"``),
    ``friction`` (friction sites x samples; the Hertz contact correction is not one) [N],
    ``u_f`` (compensation torque) [N·m].
    """

    t: np.ndarray
    r: np.ndarray
    x_t: np.ndarray
    theta_m: np.ndarray
    x_t_meas: np.ndarray
    theta_m_meas: np.ndarray
    i: np.ndarray
    drive_force: np.ndarray
    friction: np.ndarray
    u_f: np.ndarray
    status: int
    message: str

    @property
    def success(self) -> bool:
        return self.status == 0

    @property
    def error(self) -> np.ndarray:
        """Measured tracking error ``r - x_t_meas`` [m] (what the linear scale shows)."""
        return self.r - self.x_t_meas

    @property
    def true_error(self) -> np.ndarray:
        return self.r - self.x_t

    def summary(self) -> str:
        """Run length, status, and the true and measured tracking errors [µm]."""
        n = int(self.t.size)
        head = (f"closed loop: {n} samples over {float(self.t[-1]) if n else 0.0:.6g} s; status {self.status} "
                f"({self.message})")
        e, m = self.true_error, self.error
        if not (n and np.isfinite(e).any()):
            return head
        return (head + f"\n  true error r - x_t: max |e| {float(np.nanmax(np.abs(e))) * 1e6:.4g} µm, "
                f"RMS {float(np.sqrt(np.nanmean(e * e))) * 1e6:.4g} µm; measured: max |e| "
                f"{float(np.nanmax(np.abs(m))) * 1e6:.4g} µm")

    def plot(self, ax: Axes | None=None) -> Axes | np.ndarray:
        """True and measured tracking error [µm] over time; returns the Axes."""
        import matplotlib.pyplot as plt

        if ax is None:
            _, ax = plt.subplots(figsize=(7, 3.5))
        ax.plot(self.t, self.true_error * 1e6, lw=0.9, label="true r - x_t")
        ax.plot(self.t, self.error * 1e6, lw=0.6, alpha=0.7, label="measured r - x_t,meas")
        ax.set_xlabel("t [s]")
        ax.set_ylabel("tracking error [µm]")
        ax.set_title("closed loop")
        ax.legend(fontsize=8)
        return ax


def simulate_closed_loop(plant: Any, controller: TwoDofController, reference: Reference, *,
                         compensation: ArrayLike | None=None, sensors: Sensors | None = None, seed: int | None = 0,
                         n_substeps: int = 10, raise_on_failure: bool = False) -> ClosedLoopResult:
    """Run ``plant`` under ``controller`` along ``reference`` (sampled at ``controller.T``).

    A thin wrapper over :func:`frictionkit.presets.ballscrew.simulate_stage` (the stage on the
    machine core; ``n_substeps`` is its ``substeps``), kept for existing callers.

    Parameters
    ----------
    plant : RigidBallScrew or ElasticBallScrew
    controller : TwoDofController
    reference : Reference — table position reference, sample period = ``controller.T``.
    compensation : array_like, optional — friction compensation torque ``u_f`` [N·m] per sample.
    sensors : Sensors, optional — default: ideal sensors.
    seed : int — seed of the measurement noise (``numpy.random.default_rng``).
    n_substeps : int — plant sub-steps per control period.
    raise_on_failure : bool — raise :class:`SimulationError` instead of returning a failed result.

    Examples
    --------
    >>> from frictionkit.reproduce.zhu_fujimoto import paper_controller
    >>> from frictionkit.plants.ballscrew import RigidBallScrew
    >>> from frictionkit.control.trajectories import cosine_reference
    >>> res = simulate_closed_loop(RigidBallScrew(), paper_controller(), cosine_reference(duration=0.2))
    >>> res.success, bool(abs(res.error).max() < 1e-6)
    (True, True)
    """
    from ..presets.ballscrew import simulate_stage

    nsub = val.positive("simulate_closed_loop", "n_substeps", n_substeps)
    if nsub != int(nsub):
        raise ParameterError(f"simulate_closed_loop n_substeps = {n_substeps!r}: must be an integer")
    return simulate_stage(plant, controller, reference, compensation=compensation, sensors=sensors, seed=seed,
                          substeps=int(nsub), raise_on_failure=raise_on_failure)
