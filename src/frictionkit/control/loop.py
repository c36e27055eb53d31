"""Closed-loop simulation of a ball-screw stage with the seed 001 controller (Fig. 3).

``i = u_ptc + PID(theta_d - y) + d_hat / K_tau + u_f / K_tau``, saturated at ``i_max``, every
``T`` = 0.5 ms; the plant is advanced by :mod:`frictionkit.kernels.ballscrew`. The PID
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
from ..errors import DataError, ParameterError, SimulationError
from ..kernels import ballscrew as _k
from .dob import DisturbanceObserver
from .pid import PID
from .ptc import PerfectTrackingControl
from .trajectories import Reference


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

    def ctrl_vector(self, sensors: Sensors) -> np.ndarray:
        c = np.zeros(_k.N_CTRL)
        c[_k.C_KP], c[_k.C_KI], c[_k.C_KD], c[_k.C_TAUD], c[_k.C_T] = (
            self.pid.Kp, self.pid.Ki, self.pid.Kd, self.pid.tau_d, self.pid.T)
        if self.dob is not None:
            c[_k.C_DOB] = 1.0
            c[_k.C_AQ] = self.dob.a
            c[_k.C_JN], c[_k.C_BN] = self.dob.J, self.dob.B
            c[_k.C_KTAU] = self.dob.K_tau
        else:
            c[_k.C_KTAU] = self.ptc.K_tau
        c[_k.C_IMAX] = self.i_max
        c[_k.C_FBMODE] = {"motor": 0.0, "table": 1.0, "dual": 2.0}[self.feedback]
        c[_k.C_R] = self.R
        c[_k.C_QENC] = sensors.encoder_step
        c[_k.C_QSCALE] = sensors.scale_resolution
        return c


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


def _flank_arrays(chain):
    if hasattr(chain, "flank_arrays"):
        return chain.flank_arrays()
    z = np.zeros(chain.Fc.size)
    return z, z, z, z


def _hertz_array(chain):
    if hasattr(chain, "hertz_array"):
        return chain.hertz_array()
    return np.array([-1.0, 0.0, 0.0, 0.0])


def simulate_closed_loop(plant, controller: TwoDofController, reference: Reference, *,
                         compensation=None, sensors: Sensors | None = None, seed: int | None = 0,
                         n_substeps: int = 10, raise_on_failure: bool = False) -> ClosedLoopResult:
    """Run ``plant`` under ``controller`` along ``reference`` (sampled at ``controller.T``).

    Parameters
    ----------
    plant : RigidBallScrew or ElasticBallScrew (anything with ``linear_chain()``).
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
    if not isinstance(reference, Reference):
        raise DataError("reference: must be a frictionkit.control.trajectories.Reference")
    T = controller.T
    if abs(reference.T - T) > 1e-12 * T:
        raise DataError(f"reference.T = {reference.T!r} s: must equal the control period {T!r} s")
    nsub = val.positive("simulate_closed_loop", "n_substeps", n_substeps)
    if nsub != int(nsub):
        raise ParameterError(f"simulate_closed_loop n_substeps = {n_substeps!r}: must be an integer")
    nsub = int(nsub)
    sensors = Sensors(encoder_counts=0, scale_resolution=0.0) if sensors is None else sensors
    N = len(reference)
    uf = np.zeros(N) if compensation is None else val.signal("compensation", compensation)
    if uf.size != N:
        raise DataError(f"compensation has {uf.size} samples: must match the reference ({N})")

    R = controller.R
    u_ff, theta_d = controller.ptc.feedforward(reference.x / R, reference.v / R)
    K_tau = controller.ptc.K_tau
    chain = plant.linear_chain()
    h = T / nsub
    PhiN, GN, CvP, CvG = chain.lifted(T, nsub)
    n = chain.M.shape[0]
    c_mot = np.concatenate((chain.motor, np.zeros(n)))
    c_tab = np.concatenate((chain.table, np.zeros(n)))
    c_frc = np.concatenate((chain.drive_force_q, chain.drive_force_v))
    X = np.zeros(2 * n)
    F = np.zeros(chain.Fc.size)
    rng = np.random.default_rng(seed)
    noise_enc = rng.standard_normal(N) * sensors.encoder_noise_counts * sensors.encoder_step
    noise_scale = rng.standard_normal(N) * sensors.scale_noise
    out = {k: np.full(N, np.nan) for k in ("xt", "thm", "xtm", "thmm", "i", "fbn")}
    fric = np.full((chain.Fc.size, N), np.nan)
    status, k_end = _k.closed_loop(
        PhiN, GN, CvP, CvG, h, chain.Fc.astype(float), chain.sigma0.astype(float),
        *(np.ascontiguousarray(a, dtype=float) for a in _flank_arrays(chain)), _hertz_array(chain), F, X,
        c_mot, c_tab, c_frc, theta_d, u_ff, uf / K_tau, noise_enc, noise_scale,
        controller.ctrl_vector(sensors),
        out["xt"], out["thm"], out["xtm"], out["thmm"], out["i"], out["fbn"], fric)
    message = "ok"
    if status == _k.STATUS_NONFINITE:
        message = (f"non-finite plant state after step {k_end} (t = {(k_end) * T:.6g} s); "
                   f"samples from there on are NaN")
        if raise_on_failure:
            raise SimulationError(message)
    return ClosedLoopResult(t=reference.t, r=reference.x, x_t=out["xt"], theta_m=out["thm"],
                            x_t_meas=out["xtm"], theta_m_meas=out["thmm"], i=out["i"],
                            drive_force=out["fbn"], friction=fric[:getattr(chain, "n_friction", chain.Fc.size)],
                            u_f=uf, status=int(status),
                            message=message)
