"""Ball-screw-driven stage (seed 001): rigid model eq. 1 and the elastic chain of Fig. 7.

Both plants are frozen, keyword-only, validated parameter objects. They do not simulate by
themselves: :func:`frictionkit.presets.ballscrew.ballscrew_machine` builds them as a machine
of the core and :func:`frictionkit.presets.ballscrew.simulate_stage` runs it in closed loop.
:meth:`linear_chain` returns the same mechanical chain as matrices
(``M q'' + D q' + K q = Bu u - sum_i c_i F_i``) for the frequency response, the modes and
the tests' continuous-time twins.

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

``"hertz"`` — the ``"flank"`` friction sites on a *nonlinear* ball contact. Each flank set
is a Hertz point-contact law ``F = c delta^1.5`` (``delta >= 0``; zero when unloaded),
both pressed by the preload ``P = nut_preload`` at the preload deflection ``d0``. The net
drive force through the balls is
``F_bn(d) = c (d0 + d)_+^1.5 - c (d0 - d)_+^1.5`` with ``d = R theta_s + x_m - x_t``
(the contact deflection). ``c`` and ``d0`` follow from two conditions: ``c d0^1.5 = P``
and the net stiffness at zero external load ``dF_bn/dd(0) = 3 c d0^0.5 = k_nut`` (each set
``dF/ddelta = k_nut / 2`` at the preload; the catalogue ``k_nut`` is the axial stiffness of
the preloaded nut, both sets in parallel), so ``d0 = 3 P / k_nut`` and ``c = P / d0^1.5``.
Beyond ``|F_bn| = 2^1.5 P`` one set unloads: the stiffness drops from ``k_nut`` to that of
one set and the lost preload deflection appears as lost motion at the flank change.
The flank friction levels are ``mu_f`` times the Hertz loads ``c (d0 +- d)_+^1.5`` (instead
of the linearised split). In the chain the contact keeps its linear part ``k_nut d`` (and its
Rayleigh damping ``beta k_nut d'``); the rest ``F_bn(d) - k_nut d`` is a nonlinear
generalised force along the contact row (on the machine core: a
:class:`~frictionkit.machines.HertzContact` compliance).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from .. import _validate as val
from ..errors import ParameterError
from typing import TYPE_CHECKING

if TYPE_CHECKING:
    from numpy.typing import ArrayLike

#: ``sigma0 = DAHL_SPAN * Fc / presliding_length``: the Dahl curve goes from ``-Fc`` to
#: ``0.9 Fc`` over ``presliding_length`` (``1 - 2 exp(-u) = 0.9`` -> ``u = ln 20``).
DAHL_SPAN = math.log(20.0)

#: Nut friction models of :class:`ElasticBallScrew` (see the module docstring).
NUT_MODELS = ("sliding", "flank", "hertz")


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
    contact_q : ndarray (n,), optional
        Nut model ``"hertz"``: the contact-deflection row ``d = contact_q @ q`` [m].
    contact_site : int
        Index of the site that carries the nonlinear contact correction
        ``F_bn(d) - k_nut d`` (its ``C`` row is ``contact_q``: it acts along the contact);
        -1 without. It is the last site and not a friction site.
    hertz_c, hertz_d0, hertz_k : float
        Hertz constant ``c`` [N/m^1.5], preload deflection ``d0`` [m] and the linear
        stiffness ``k_nut`` kept in ``K`` [N/m] (nut model ``"hertz"``; unused otherwise).
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
    contact_q: np.ndarray | None = None
    contact_site: int = -1
    hertz_c: float = 0.0
    hertz_d0: float = 0.0
    hertz_k: float = 0.0

    @property
    def n_friction(self) -> int:
        """Number of friction sites (all sites but the contact correction)."""
        return self.C.shape[0] - (1 if self.contact_site >= 0 else 0)

    def flank_arrays(self):
        """``(sign, mu, P, lam)`` per site (zeros without flank sites): flank sign, ``mu_f``,
        preload [N] and the Dahl rate ``DAHL_SPAN / presliding_length`` [1/m]."""
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

    def transfer_function(self) -> tuple[np.ndarray, np.ndarray]:
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
    nut_model : str — ``"sliding"`` (one Dahl site driven by screw rotation, default),
        ``"flank"`` (flank load-transfer friction, linear contact) or ``"hertz"`` (flank
        friction on a preloaded Hertzian ball contact); see the module docstring.
    nut_preload : float — per-flank ball preload ``P`` [N] (``"flank"``/``"hertz"`` only;
        > 0 there).
    flank_friction_coefficient : float — ``mu_f``: nut friction [N, linear equivalent] per
        newton of flank ball load (``"flank"``/``"hertz"`` only; ``2 mu_f P <= nut_friction``).

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
        if self.nut_model in ("flank", "hertz"):
            if self.nut_preload <= 0.0:
                raise ParameterError(
                    f"{o}.nut_preload = {self.nut_preload!r}: must be > 0 with nut_model={self.nut_model!r}")
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

    @property
    def hertz_constants(self) -> tuple[float, float]:
        """``(c, d0)`` of the ``"hertz"`` contact: ``c`` [N/m^1.5] and the preload deflection
        ``d0 = 3 P / k_nut`` [m], from ``c d0^1.5 = P`` and ``dF_bn/dd(0) = 3 c d0^0.5 = k_nut``."""
        P = self.nut_preload
        if P <= 0.0:
            raise ParameterError(f"ElasticBallScrew.nut_preload = {P!r}: must be > 0 for the Hertz contact")
        d0 = 3.0 * P / self.k_nut
        return P / d0**1.5, d0

    def contact_force(self, d: ArrayLike) -> np.ndarray:
        """Static drive force through the balls ``F_bn`` [N] at contact deflection ``d`` [m].

        Linear ``k_nut d`` for ``"sliding"``/``"flank"``; for ``"hertz"``
        ``c (d0 + d)_+^1.5 - c (d0 - d)_+^1.5``.
        """
        d = np.asarray(d, dtype=float)
        if self.nut_model != "hertz":
            return self.k_nut * d
        c, d0 = self.hertz_constants
        return c * (np.maximum(d0 + d, 0.0) ** 1.5 - np.maximum(d0 - d, 0.0) ** 1.5)

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

    def antiresonances(self) -> np.ndarray:
        """Undamped anti-resonance angular frequencies [rad/s] of current -> motor angle,
        ascending: the natural frequencies of the chain with the motor clamped."""
        from scipy.linalg import eigh

        M, K, _ = self._mk()
        lam = eigh(K[1:, 1:], M[1:, 1:], eigvals_only=True)
        return np.sqrt(np.clip(np.sort(lam), 0.0, None))

    def frequency_response(self, f: ArrayLike, *, output: str = "motor", presliding: bool = False) -> np.ndarray:
        """Complex frequency response from motor current [A] at frequencies ``f`` [Hz].

        ``output = "motor"``: motor angle ``theta_m`` [rad/A] (what seed 001 Fig. 2 plots);
        ``"table"``: table position ``x_t`` [m/A]. The chain is linear with its viscosities
        and Rayleigh damping; the contact is linearised at zero load (stiffness ``k_nut`` for
        every nut model). Friction: ``presliding = False`` leaves it out (a large-amplitude
        measurement, the Coulomb level is a constant force that does not enter the small-signal
        response); ``True`` linearises each Dahl site about ``F = 0`` as a spring of its
        pre-sliding stiffness ``sigma0`` along its row (a small-amplitude measurement).
        """
        fv = val.vector("ElasticBallScrew.frequency_response", "f", f, rule="positive")
        if output not in ("motor", "table"):
            raise ParameterError(f"ElasticBallScrew.frequency_response output = {output!r}: must be 'motor' or 'table'")
        ch = self.linear_chain()
        Kf = ch.K.copy()
        if presliding:
            sign, mu, P, lam = ch.flank_arrays()
            stiff = np.where(sign != 0, lam * mu * P, ch.sigma0)
            for j in range(ch.n_friction):
                Kf += stiff[j] * np.outer(ch.C[j], ch.C[j])
        row = ch.motor if output == "motor" else ch.table
        out = np.empty(fv.size, dtype=complex)
        for i, fi in enumerate(fv):
            s = 2j * math.pi * fi
            out[i] = row @ np.linalg.solve(ch.M * s * s + ch.D * s + Kf, ch.b)
        return out

    def linear_chain(self) -> LinearChain:
        R = self.R
        M, K, g_n = self._mk()
        w1 = self.modes()[0]
        beta = 2.0 * self.damping_ratio / w1
        D = np.diag([self.B_m, self.B_b, 0.0, 0.0, 0.0, self.C_t]) + beta * K
        flank = self.nut_model in ("flank", "hertz")
        hertz = self.nut_model == "hertz"
        fl0 = 2.0 * self.flank_friction_coefficient * self.nut_preload if flank else 0.0
        levels = [self.guide_friction, max(self.nut_friction - fl0, 0.0)]
        nf = (4 if flank else 2) + int(hertz)
        Fc, sig = _dahl_arrays(levels + [0.0] * (nf - 2), self.presliding_length)
        C = np.zeros((nf, 6))
        C[0, 5] = 1.0  # guide: table velocity
        C[1:5, 1] = R  # nut (and its flanks): screw rotation (linear equivalent)
        extra = {}
        if flank:
            mu, P = self.flank_friction_coefficient, self.nut_preload
            pad = [0.0] * (nf - 4)
            extra = dict(flank_sign=np.array([0.0, 0.0, 1.0, -1.0] + pad),
                         flank_mu=np.array([0.0, 0.0, mu, mu] + pad),
                         flank_preload=np.array([0.0, 0.0, P, P] + pad), presliding_length=self.presliding_length)
        if hertz:
            C[4] = g_n  # contact correction acts along the contact (last site)
            c, d0 = self.hertz_constants
            extra.update(contact_q=g_n.copy(), contact_site=nf - 1, hertz_c=c, hertz_d0=d0, hertz_k=self.k_nut)
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
