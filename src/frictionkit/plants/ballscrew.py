"""Ball-screw-driven stage (seed 001): rigid model eq. 1 and the elastic chain of Fig. 7.

Both plants are frozen, keyword-only, validated parameter objects. They do not simulate by
themselves: :meth:`linear_chain` returns the mechanical chain as matrices
(``M q'' + D q' + K q = Bu u - sum_i c_i F_i``) that
:func:`frictionkit.control.loop.simulate_closed_loop` discretises exactly and runs in the
numba kernel :mod:`frictionkit.kernels.ballscrew`.

Elastic model (Fig. 7), generalised coordinates ``q = [theta_m, theta_s, x_l, x_m, x_r, x_t]``:

* ``theta_m`` motor (+ coupling hub) [rad]; ``theta_s`` screw at the nut [rad], joined by the
  series torsional stiffness ``k_o`` of coupling and screw (``k_coupling``, ``k_torsion``);
* ``x_l, x_m, x_r`` axial positions of the left, middle and right thirds of the screw
  (``M_b/3`` each), bearings ``k_bearing`` to ground at both ends, screw axial stiffness
  ``k_axial`` (left part) and ``k_axial_right``;
* screw-ball-nut contact ``F_bn = k_nut (R theta_s + x_m - x_t)``, the drive force on the
  table (eq. 2);
* table ``M_t x_t'' = F_bn - f_g - C_t x_t'`` (eq. 2 plus the Table 1 guide viscosity).

Friction sites (Dahl, rate form): the guide ``f_g`` acting on ``x_t`` and the nut
``f_n`` opposing screw rotation (linear-equivalent force on ``R theta_s``; its reaction is
a torque carried by the guide). Stiffness-proportional damping ``beta K`` with ``beta`` set
so the first elastic mode has ``damping_ratio``.

Nut friction models (``nut_model``)
-----------------------------------
``"sliding"`` (default, the original model): one Dahl site of constant level
``nut_friction``, driven by the screw rotation only — its state knows nothing of ``F_bn``.

``"flank"`` — seed 001 §3.1-3.2, Figs. 6, 8, 9: the balls are load-carrying contacts on two
groove flanks; which flank carries the load follows the sign of the drive force ``F_bn``
(Pattern I: the flank pushing the table forward; Pattern II: the other one). For a nut
preloaded with ``P = nut_preload`` (double nut / oversize balls, each flank set pressed with
``P`` at ``F_bn = 0``), the linearised equal-stiffness split gives the flank loads
``N_+ = max(P + F_bn/2, F_bn, 0)`` and ``N_- = max(P - F_bn/2, -F_bn, 0)`` (one flank set
unloads beyond ``|F_bn| = 2P``; Hertz contacts give ``2^1.5 P``). Each flank is its own
pre-rolling (Dahl) site, driven like the nut by the screw rotation, with a level
proportional to its ball load, ``mu_f N`` (``mu_f = flank_friction_coefficient``, the
linear-equivalent rolling-friction force per newton of flank load: catalogue preload-drag
torque law). When a flank unloads its contacts shrink and lose their tangential traction
(state scaled with the load, Mindlin); contacts that take up load start without traction.
So the nut's pre-rolling transition is tied to the *load transfer between flanks* — i.e.
to ``F_bn`` reversing, before zero speed in a fast deceleration — and not only to the
rolling displacement. The load-independent rest ``nut_friction - 2 mu_f P`` (support
bearings, seals, recirculation) stays an ordinary Dahl site. The contact stiffness stays the
linear ``k_nut`` (valid while both flanks are loaded, i.e. ``|F_bn| < 2P``).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from .. import _validate as val
from ..errors import ParameterError

#: ``sigma0 = DAHL_SPAN * Fc / presliding_length``: the Dahl curve goes from ``-Fc`` to
#: ``0.9 Fc`` over ``presliding_length`` (``1 - 2 exp(-u) = 0.9`` -> ``u = ln 20``).
DAHL_SPAN = math.log(20.0)

#: Nut friction models of :class:`ElasticBallScrew` (see the module docstring).
NUT_MODELS = ("sliding", "flank")


@dataclass(frozen=True)
class LinearChain:
    """A mechanical chain ``M q'' + D q' + K q = b u - C^T F`` with named outputs.

    Attributes
    ----------
    M, D, K : ndarray (n, n)
        Mass, damping and stiffness matrices (SI, mixed rotational/linear coordinates).
    b : ndarray (n,)
        Generalised force per ampere of motor current.
    C : ndarray (nf, n)
        Friction-site velocity rows: site ``j`` slides at ``C[j] @ q'`` [m/s] and its force
        ``F_j`` [N] acts through ``-C[j]``.
    Fc, sigma0 : ndarray (nf,)
        Dahl Coulomb levels [N] and pre-sliding stiffnesses [N/m].
    motor, table : ndarray (n,)
        Output rows: motor angle [rad] and table position [m] from ``q``.
    drive_force_q, drive_force_v : ndarray (n,)
        Output rows of the drive force on the table ``F_bn`` [N] from ``q`` and ``q'``.
    names : tuple of str
        Coordinate names.
    flank_sign, flank_mu, flank_preload : ndarray (nf,), optional
        Load-dependent (groove-flank) sites, nut model ``"flank"``: ``flank_sign[j] = +1``
        (flank loaded by ``F_bn > 0``) or ``-1``; 0 for an ordinary Dahl site. Such a site's
        Coulomb level is ``flank_mu[j] * max(P + s F_bn / 2, s F_bn, 0)`` with
        ``P = flank_preload[j]`` [N], and its Dahl transition spans ``presliding_length``.
        Default: no flank sites.
    presliding_length : float
        Dahl transition length of the flank sites [m] (unused without them).
    """

    M: np.ndarray
    D: np.ndarray
    K: np.ndarray
    b: np.ndarray
    C: np.ndarray
    Fc: np.ndarray
    sigma0: np.ndarray
    motor: np.ndarray
    table: np.ndarray
    drive_force_q: np.ndarray
    drive_force_v: np.ndarray
    names: tuple
    flank_sign: np.ndarray | None = None
    flank_mu: np.ndarray | None = None
    flank_preload: np.ndarray | None = None
    presliding_length: float = 10e-6

    def flank_arrays(self):
        """``(sign, mu, P, lam)`` per site for the kernel (zeros without flank sites)."""
        nf = self.C.shape[0]
        z = np.zeros(nf)
        if self.flank_sign is None:
            return z, z.copy(), z.copy(), z.copy()
        lam = np.where(np.asarray(self.flank_sign) != 0, DAHL_SPAN / self.presliding_length, 0.0)
        return (np.asarray(self.flank_sign, float), np.asarray(self.flank_mu, float),
                np.asarray(self.flank_preload, float), lam)

    def state_space(self):
        """Continuous ``(A, B)`` for ``X = [q, q']`` and inputs ``w = [u, F_1 .. F_nf]``."""
        n = self.M.shape[0]
        Minv = np.linalg.inv(self.M)
        A = np.zeros((2 * n, 2 * n))
        A[:n, n:] = np.eye(n)
        A[n:, :n] = -Minv @ self.K
        A[n:, n:] = -Minv @ self.D
        Bw = np.zeros((2 * n, 1 + self.C.shape[0]))
        Bw[n:, 0] = Minv @ self.b
        for j in range(self.C.shape[0]):
            Bw[n:, 1 + j] = -Minv @ self.C[j]
        return A, Bw

    def discretize(self, h: float):
        """Exact zero-order-hold pair ``(Phi, Gam)`` over ``h`` [s] (matrix exponential)."""
        from scipy.linalg import expm

        A, Bw = self.state_space()
        n2, m = Bw.shape
        aug = np.zeros((n2 + m, n2 + m))
        aug[:n2, :n2] = A * h
        aug[:n2, n2:] = Bw * h
        E = expm(aug)
        return np.ascontiguousarray(E[:n2, :n2]), np.ascontiguousarray(E[:n2, n2:])

    def lifted(self, T: float, n_sub: int):
        """Sub-stepping over one period ``T`` in lifted form, for the kernel.

        With ``(Phi, Gam) = discretize(T / n_sub)``, ``Cv`` the site-velocity rows on ``X``
        followed by one row giving the drive force ``F_bn`` (``drive_force_q``,
        ``drive_force_v``; used by flank sites):
        ``PhiN = Phi^n``, ``GN[s] = Phi^(n-1-s) Gam``, ``CvP[s] = Cv Phi^s``,
        ``CvG[s, r] = Cv Phi^(s-1-r) Gam`` (``r < s``, zero otherwise).
        """
        Phi, Gam = self.discretize(T / n_sub)
        n = self.M.shape[0]
        nf = self.C.shape[0]
        Cv = np.zeros((nf + 1, 2 * n))
        Cv[:nf, n:] = self.C
        Cv[nf, :n] = self.drive_force_q
        Cv[nf, n:] = self.drive_force_v
        P = [np.eye(2 * n)]
        for _ in range(n_sub):
            P.append(P[-1] @ Phi)
        GN = np.stack([P[n_sub - 1 - s] @ Gam for s in range(n_sub)])
        CvP = np.stack([Cv @ P[s] for s in range(n_sub)])
        CvG = np.zeros((n_sub, n_sub, nf + 1, Gam.shape[1]))
        for s in range(n_sub):
            for r in range(s):
                CvG[s, r] = Cv @ P[s - 1 - r] @ Gam
        c = np.ascontiguousarray
        return c(P[n_sub]), c(GN), c(CvP), c(CvG)


def _dahl_arrays(levels, length):
    Fc = np.array(levels, dtype=float)
    sig = np.where(Fc > 0.0, DAHL_SPAN * Fc / length, 0.0)
    return Fc, sig


@dataclass(frozen=True, kw_only=True)
class RigidBallScrew:
    """Seed 001 eq. 1: ``P_n(s) = K_tau / (J s^2 + B s)`` from current [A] to motor angle [rad].

    Parameters
    ----------
    K_tau : float — torque constant [N·m/A] (eq. 1: 0.715).
    J : float — total inertia at the motor [kg·m²] (eq. 1: 0.01).
    B : float — total viscosity at the motor [N·m·s/rad] (eq. 1: 0.1).
    L_p : float — screw lead [m/rev] (Table 1: 0.012); table position ``x_t = R theta``.
    friction : float — linear-equivalent Coulomb level of one Dahl site at the motor [N]
        (0 for none).
    presliding_length : float — Dahl transition length [m].

    Examples
    --------
    >>> from frictionkit.plants.ballscrew import RigidBallScrew
    >>> p = RigidBallScrew(K_tau=0.715, J=0.01, B=0.1)
    >>> round(p.R * 1e3, 4)
    1.9099
    """

    K_tau: float = 0.715
    J: float = 0.01
    B: float = 0.1
    L_p: float = 1.2e-2
    friction: float = 0.0
    presliding_length: float = 10e-6

    def __post_init__(self) -> None:
        o = "RigidBallScrew"
        for name in ("K_tau", "J", "L_p", "presliding_length"):
            object.__setattr__(self, name, val.positive(o, name, getattr(self, name)))
        for name in ("B", "friction"):
            object.__setattr__(self, name, val.nonnegative(o, name, getattr(self, name)))

    @property
    def R(self) -> float:
        """Screw ratio ``L_p / 2 pi`` [m/rad]."""
        return self.L_p / (2.0 * math.pi)

    def transfer_function(self):
        """``(num, den)`` of eq. 1 in descending powers of ``s``."""
        return np.array([self.K_tau]), np.array([self.J, self.B, 0.0])

    def linear_chain(self) -> LinearChain:
        R = self.R
        Fc, sig = _dahl_arrays([self.friction], self.presliding_length)
        one = np.ones(1)
        return LinearChain(
            M=np.array([[self.J]]), D=np.array([[self.B]]), K=np.zeros((1, 1)),
            b=np.array([self.K_tau]), C=np.array([[R]]), Fc=Fc, sigma0=sig,
            motor=one.copy(), table=R * one, drive_force_q=np.zeros(1), drive_force_v=np.zeros(1),
            names=("theta",),
        )


@dataclass(frozen=True, kw_only=True)
class ElasticBallScrew:
    """Elastic multi-mass ball-screw stage after seed 001 Fig. 7 / Table 1.

    Parameters
    ----------
    J_m, B_m : float — motor inertia [kg·m²] and viscosity [N·m·s/rad] (Table 1, ``B_m``
        corrected, see :mod:`frictionkit.presets.zhu_fujimoto`).
    J_b, B_b, M_b : float — screw inertia [kg·m²], viscosity [N·m·s/rad], mass [kg].
    M_t, C_t : float — table mass [kg] and guide viscosity [N·s/m].
    L_p : float — lead [m/rev].
    K_tau : float — torque constant [N·m/A].
    k_coupling, k_torsion : float — coupling and screw (motor -> nut) torsional stiffness
        [N·m/rad], in series.
    k_axial, k_axial_right : float — axial stiffness of the screw left/right of the nut [N/m]
        (``k_axial_right`` defaults to ``k_axial``).
    k_bearing : float — axial stiffness of each support bearing set [N/m].
    k_nut : float — screw-ball-nut axial stiffness [N/m].
    damping_ratio : float — damping ratio of the first elastic mode (Rayleigh, ``beta K``).
    guide_friction, nut_friction : float — Dahl Coulomb levels of guide and nut [N]
        (nut: linear equivalent of its torque, ``T / R``).
    presliding_length : float — Dahl transition length of both sites [m].
    nut_model : str — ``"sliding"`` (one Dahl site driven by screw rotation, default) or
        ``"flank"`` (flank load-transfer model, see the module docstring).
    nut_preload : float — per-flank ball preload ``P`` [N] (``"flank"`` only; > 0 there).
    flank_friction_coefficient : float — ``mu_f``: nut friction [N, linear equivalent] per
        newton of flank ball load (``"flank"`` only; ``2 mu_f P <= nut_friction``).

    Examples
    --------
    >>> from frictionkit.plants.ballscrew import ElasticBallScrew
    >>> from frictionkit.presets import zhu_fujimoto as zf
    >>> p = ElasticBallScrew(**zf.plant_kwargs())
    >>> bool(100 < p.modes()[0] / (2 * 3.141592653589793) < 400)   # first mode [Hz]
    True
    """

    J_m: float
    B_m: float
    J_b: float
    B_b: float
    M_b: float
    M_t: float
    C_t: float
    L_p: float
    K_tau: float
    k_coupling: float
    k_torsion: float
    k_axial: float
    k_axial_right: float | None = None
    k_bearing: float
    k_nut: float
    damping_ratio: float = 0.02
    guide_friction: float = 0.0
    nut_friction: float = 0.0
    presliding_length: float = 10e-6
    nut_model: str = "sliding"
    nut_preload: float = 0.0
    flank_friction_coefficient: float = 0.0

    def __post_init__(self) -> None:
        o = "ElasticBallScrew"
        if self.k_axial_right is None:
            object.__setattr__(self, "k_axial_right", self.k_axial)
        for name in ("J_m", "J_b", "M_b", "M_t", "L_p", "K_tau", "k_coupling", "k_torsion",
                     "k_axial", "k_axial_right", "k_bearing", "k_nut", "presliding_length"):
            object.__setattr__(self, name, val.positive(o, name, getattr(self, name)))
        for name in ("B_m", "B_b", "C_t", "damping_ratio", "guide_friction", "nut_friction"):
            object.__setattr__(self, name, val.nonnegative(o, name, getattr(self, name)))
        if self.damping_ratio >= 1.0:
            raise ParameterError(f"{o}.damping_ratio = {self.damping_ratio!r}: must be < 1")
        if self.nut_model not in NUT_MODELS:
            raise ParameterError(f"{o}.nut_model = {self.nut_model!r}: must be one of {NUT_MODELS}")
        for name in ("nut_preload", "flank_friction_coefficient"):
            object.__setattr__(self, name, val.nonnegative(o, name, getattr(self, name)))
        if self.nut_model == "flank":
            if self.nut_preload <= 0.0:
                raise ParameterError(f"{o}.nut_preload = {self.nut_preload!r}: must be > 0 with nut_model='flank'")
            if 2.0 * self.flank_friction_coefficient * self.nut_preload > self.nut_friction * (1 + 1e-12):
                raise ParameterError(
                    f"{o}: flank friction at zero load 2 * flank_friction_coefficient * nut_preload = "
                    f"{2.0 * self.flank_friction_coefficient * self.nut_preload!r} N exceeds "
                    f"nut_friction = {self.nut_friction!r} N")

    @property
    def R(self) -> float:
        """Screw ratio ``L_p / 2 pi`` [m/rad]."""
        return self.L_p / (2.0 * math.pi)

    @property
    def k_o(self) -> float:
        """Series torsional stiffness motor -> nut [N·m/rad]."""
        return 1.0 / (1.0 / self.k_coupling + 1.0 / self.k_torsion)

    def _mk(self):
        R = self.R
        n = 6
        M = np.diag([self.J_m, self.J_b, self.M_b / 3, self.M_b / 3, self.M_b / 3, self.M_t])
        K = np.zeros((n, n))

        def spring(k, g):
            g = np.asarray(g, dtype=float)
            K[:, :] += k * np.outer(g, g)

        spring(self.k_o, [1, -1, 0, 0, 0, 0])
        spring(self.k_bearing, [0, 0, 1, 0, 0, 0])
        spring(self.k_bearing, [0, 0, 0, 0, 1, 0])
        spring(self.k_axial, [0, 0, 1, -1, 0, 0])
        spring(self.k_axial_right, [0, 0, 0, -1, 1, 0])
        g_n = np.array([0, R, 0, 1, 0, -1], dtype=float)
        spring(self.k_nut, g_n)
        return M, K, g_n

    def modes(self) -> np.ndarray:
        """Undamped natural angular frequencies of the chain [rad/s], ascending (rigid mode dropped)."""
        from scipy.linalg import eigh

        M, K, _ = self._mk()
        lam = eigh(K, M, eigvals_only=True)
        lam = np.sort(lam)
        return np.sqrt(np.clip(lam[1:], 0.0, None))

    def linear_chain(self) -> LinearChain:
        R = self.R
        M, K, g_n = self._mk()
        w1 = self.modes()[0]
        beta = 2.0 * self.damping_ratio / w1
        D = np.diag([self.B_m, self.B_b, 0.0, 0.0, 0.0, self.C_t]) + beta * K
        flank = self.nut_model == "flank"
        fl0 = 2.0 * self.flank_friction_coefficient * self.nut_preload if flank else 0.0
        levels = [self.guide_friction, max(self.nut_friction - fl0, 0.0)]
        nf = 4 if flank else 2
        Fc, sig = _dahl_arrays(levels + [0.0] * (nf - 2), self.presliding_length)
        C = np.zeros((nf, 6))
        C[0, 5] = 1.0  # guide: table velocity
        C[1:, 1] = R  # nut (and its flanks): screw rotation (linear equivalent)
        extra = {}
        if flank:
            mu, P = self.flank_friction_coefficient, self.nut_preload
            extra = dict(flank_sign=np.array([0.0, 0.0, 1.0, -1.0]), flank_mu=np.array([0.0, 0.0, mu, mu]),
                         flank_preload=np.array([0.0, 0.0, P, P]), presliding_length=self.presliding_length)
        e = np.eye(6)
        return LinearChain(
            M=M, D=D, K=K, b=self.K_tau * e[0], C=C, Fc=Fc, sigma0=sig,
            motor=e[0].copy(), table=e[5].copy(),
            drive_force_q=self.k_nut * g_n,
            drive_force_v=beta * self.k_nut * g_n,
            names=("theta_m", "theta_s", "x_l", "x_m", "x_r", "x_t"), **extra,
        )

    @property
    def total_friction_torque(self) -> float:
        """Motor-side equivalent of both Coulomb levels [N·m]."""
        return (self.guide_friction + self.nut_friction) * self.R
