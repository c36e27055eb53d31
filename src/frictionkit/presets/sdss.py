"""The three servo axes of the 2.5 m SDSS telescope (seed 002) on the machine core.

Seed 002 (*Friction Model of the 2.5 m SDSS Telescope*) gives the axis equations but **no
number** for any inertia, gain, ratio or friction parameter. Every value below is therefore
a named assumption with its reasoning; the paper's own facts are cited where they fix a value.

Equations (paper numbering; two equations carry the number 13, named 13a and 13b here):

* eq. 2 (azimuth, altitude): ``T = 2 n_c K_T i_ref`` — two DC motors in current mode, each
  driving a friction capstan on the axis disc. **Correction:** the paper *defines* ``n_c`` as
  "ratio between the capstan diameter and azimuth/altitude disc diameter" (< 1), which would
  divide the torque; the paper also calls the drive ratio "very low (25:1)". We use
  ``n_c = disc / capstan = 25`` (:data:`N_C_AZ_ALT`).
* eq. 11 (azimuth): ``T1 = J dω/dt + T_f`` (printed ``J_z1``/``J_zz1`` and ``T_l``: typos).
* eq. 13a (altitude): ``T2 = J dω/dt + T_f + G2(θ)``, ``G2 ≅ m g X θ`` "for small rotational
  angles". **Our convention** (the paper gives neither reference nor sign): θ is measured
  from the angle at which the out-of-balance mass hangs straight below the altitude axis,
  positive in the positive drive direction, ``G2 = m g X sin θ`` (:class:`~frictionkit.machines.SineLoad`,
  a *stable* equilibrium at θ = 0). Stable, because the paper drove the altitude axis in open
  loop with sine and triangle torques above breakaway and reports repeatable runs: around an
  unstable equilibrium the axis would run away as soon as it slides.
* eq. 3 (rotator), **re-derived** (the printed ``T_m = n_c K_T i`` lacks the harmonic-drive
  ratio ``n`` while the reflected inertia carries ``(n n_c)²``, so the printed set is not
  dimensionally consistent). Motor angle θ_m, HD ratio n, capstan ratio n_c (rotator disc /
  capstan, corrected as above), HD spring rate K at the HD output [N·m/rad], HD friction
  ``T_fHD`` expressed at the HD output but acting on the motor side of the flexspline,
  θ_s = θ_m / (n n_c) the motor reflected to the rotator frame::

      T_m = n n_c K_T i                                    (printed: n_c K_T i)
      T_3 = n_c² K(T_3) (θ_s − θ_3)                        (as printed)
      J_m (n n_c)² θ̈_s = T_m − T_3 − n_c T_fHD(n_c θ̇_s)   (as printed)
      J_3 θ̈_3 = T_3 − T_fb(θ̇_3)                           (bearing friction, rotator side)

  At constant velocity: ``T_m = T_fb + n_c T_fHD`` (eq. 13b). The machine is built in
  physical coordinates (motor DOF θ_m, rotator DOF θ_3; the HD compliance acts on
  ``θ_m / n − n_c θ_3``), which gives exactly these equations.
* HD spring rate: the paper writes that the HD "compliance [is] not constant. It increases as
  the torque developed by the actuator increases" (i.e. the drive softens). **Our choice:** the
  drive *stiffens* with torque (K1 < K2 < K3), the three-slope curve harmonic-drive catalogues
  publish (more teeth share the load as it rises; the soft start is the wave generator's
  clearance). The literal text contradicts every catalogue curve we know, and the rotator
  experiments of the paper (constant velocity, static map only) do not depend on the choice.

Friction: LuGre (eqs. 5–8) per axis over a Stribeck map per direction, eq. 9b with δ = 2 (the
form eq. 10 fits) by default; eq. 9a (``shape="lorentzian"``) or another exponent (the paper's
"generalised exponent 1/2 … 2") are options of :func:`stribeck_map`. σ0 and σ1 are *one* pair
per axis (decision: the bristle stiffness and damping are properties of the contact, and the
paper counts "six parameters" per axis: σ0, σ1, σ2, v_s, T_s, T_c); the static four are per
direction, as eq. 10 is run per direction.

Provenance
----------
* Seed 002, *Friction Model of the 2.5 m SDSS Telescope*: the axis equations (paper numbering
  above); it gives no number for any inertia, gain, ratio or friction parameter, so every value
  is a named assumption with its reasoning.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np

from .. import _validate as val
from ..errors import ParameterError
from ..machines import PID, Machine, PiecewiseLinearSpring, SineLoad, Sum
from ..models.lugre import LuGre
from ..models.static import Directional, Stribeck
from ..units import ARCSEC  # one arc second [rad], re-exported here for the telescope users
#: Sidereal rate: 15.041 arcsec/s = 2π / 86164.1 s [rad/s] (seed 002 §1: the telescope tracks at or below it).
SIDEREAL_RATE = 2.0 * math.pi / 86164.0905
#: Capstan drive ratio of azimuth and altitude, disc/capstan. Seed 002 eq. 2 defines n_c as
#: capstan/disc (< 1, which would divide the torque) and §2 calls the ratio "very low (25:1)":
#: corrected to disc/capstan = 25.
N_C_AZ_ALT = 25.0


# --------------------------------------------------------------------------- encoder
@dataclass(frozen=True, kw_only=True)
class Encoder:
    """An angle encoder: ``counts`` per revolution and white position noise ``noise`` [rad].

    The default is the HEIDENHAIN ERO 7001 graduated circle (2^15 = 32,768 lines) with its
    AWE 1024 interpolation to **2^25 counts per revolution** (0.0386 arcsec per count), as
    documented for the ESO La Silla telescope axes (ls.eso.org, electronics documentation,
    "HEIDENHAIN ERO7001 encoder part list"). The paper does not name its encoders. The
    noise (interpolation jitter) is not documented there: **assumption** half a count RMS
    (0.0193 arcsec), the usual size of interpolation noise of a well-adjusted sine/cosine
    interpolator.
    """

    counts: int = 2**25
    noise: float = 0.5 * 2.0 * math.pi / 2**25
    name: str = "HEIDENHAIN ERO 7001 + AWE 1024 (2^25 counts/rev)"

    def __post_init__(self) -> None:
        if isinstance(self.counts, bool) or not isinstance(self.counts, (int, np.integer)) or self.counts < 2:
            raise ParameterError(f"Encoder.counts = {self.counts!r}: must be an integer >= 2")
        object.__setattr__(self, "noise", val.nonnegative("Encoder", "noise", self.noise))

    @property
    def resolution(self) -> float:
        """One count [rad]."""
        return 2.0 * math.pi / self.counts


def stribeck_map(Tc: float, Ts: float, vs: float, sigma2: float, *, map: str = "9b",
                 delta: float = 2.0) -> Stribeck:
    """One direction's Stribeck map of seed 002: eq. 9b (``exp(-(v/vs)^delta)``, δ = 2 as eq. 10
    fixes it; another ``delta`` is the paper's generalised exponent) or eq. 9a (Lorentzian)."""
    if map not in ("9a", "9b"):
        raise ParameterError(f"stribeck_map.map = {map!r}: must be '9a' (Lorentzian) or '9b' (exponential)")
    shape = "lorentzian" if map == "9a" else "exponential"
    return Stribeck(Fc=Tc, Fs=Ts, vs=vs, delta=delta if map == "9b" else 2.0, sigma2=sigma2, shape=shape)


def _pid_gains(J: float, gain: float, bandwidth_hz: float) -> dict:
    """PID on position for an inertia ``J`` behind an actuator gain: ``(s + w)^3`` pole placement.

    ``Kp = 3 J w² / g``, ``Ki = J w³ / g``, ``Kd = 3 J w / g`` [command/rad ...]; derivative
    filter at 10 w. Used for the constant-velocity runs (the paper's controller is not given)."""
    w = 2.0 * math.pi * bandwidth_hz
    return {"Kp": 3.0 * J * w**2 / gain, "Ki": J * w**3 / gain, "Kd": 3.0 * J * w / gain, "tau_d": 0.1 / w}


def _positive(owner, name, value):
    return val.positive(owner, name, value)


# --------------------------------------------------------------------------- azimuth
def _az_friction() -> LuGre:
    # Levels: assumption, a few hundred N·m at the axis from the azimuth bearing and the four
    # tilt-restraint capstans (seed 002 Fig. 1: "lower azimuth bearing, upper azimuth bearings
    # (capstans)") - a few per cent of the drive's 1,000 N·m. vs = 5e-4 rad/s (~100 arcsec/s,
    # 7x sidereal): the Stribeck drop sits between tracking and slewing speeds. sigma2: viscous
    # torque ~50 N·m at a 2 deg/s slew. Direction asymmetry ~8 % (eq. 10 is run per direction).
    pos = stribeck_map(Tc=120.0, Ts=160.0, vs=5.0e-4, sigma2=1500.0)
    neg = stribeck_map(Tc=130.0, Ts=175.0, vs=4.0e-4, sigma2=1600.0)
    # sigma0: pre-sliding over "a few arc seconds" (seed 002 §2.2): Ts / sigma0 = 4 arcsec.
    # sigma1: damping ratio 0.5 of the pre-sliding oscillator J x'' + sigma1 x' + sigma0 x.
    s0 = 160.0 / (4.0 * ARCSEC)
    return LuGre(Directional(positive=pos, negative=neg), sigma0=s0, sigma1=2 * 0.5 * math.sqrt(s0 * 4.0e4))


@dataclass(frozen=True, kw_only=True)
class AzimuthAxis:
    """Azimuth (seed 002 eqs. 2, 11): ``J dω/dt = 2 n_c K_T i − T_f``.

    Parameters (all **assumptions** unless marked; SI units)
    ----------
    J : float — 4.0e4 kg·m². A rotating structure of ~20 t with a radius of gyration of
        ~1.4 m; the paper calls the structure "relatively light".
    K_T : float — 1.0 N·m/A per motor (a mid-size permanent-magnet DC torque motor).
    n_c : float — 25 (paper, corrected: disc/capstan, :data:`N_C_AZ_ALT`).
    i_max : float — 20 A per motor: 2·25·1.0·20 = 1,000 N·m peak axis torque.
    friction : LuGre — see ``_az_friction`` (levels, vs, σ2 assumed; σ0 from the paper's
        "a few arc seconds" of pre-sliding: Ts/σ0 = 4 arcsec; σ1 for damping ratio 0.5).
    encoder : Encoder — on the axis.
    dt : float — 1 ms servo period (assumption).
    bandwidth_hz : float — 2 Hz position loop of the constant-velocity runs (below the
        paper's > 10 Hz structural resonances). Not tuned per axis: on the light rotator the
        loop's derivative damping (3 J w = 4.0e4 N·m·s/rad) is below the combined map's steepest
        negative slope (6.2e4), so it hunts between about 1.1e-4 and 5.1e-4 rad/s; those runs are
        rejected by the two-step workflow's constant-velocity screen, not hidden by a gain change.
    """

    J: float = 4.0e4
    K_T: float = 1.0
    n_c: float = N_C_AZ_ALT
    i_max: float = 20.0
    friction: LuGre = field(default_factory=_az_friction)
    encoder: Encoder = field(default_factory=Encoder)
    dt: float = 1e-3
    bandwidth_hz: float = 2.0
    name: str = "azimuth"

    def __post_init__(self) -> None:
        o = type(self).__name__
        for f in ("J", "K_T", "n_c", "i_max", "dt", "bandwidth_hz"):
            object.__setattr__(self, f, _positive(o, f, getattr(self, f)))
        if self.n_c < 1.0:
            raise ParameterError(f"{o}.n_c = {self.n_c!r}: must be disc/capstan >= 1 (seed 002 eq. 2 prints the "
                                 "inverse ratio; 25 is the corrected value)")
        if not isinstance(self.friction, LuGre):
            raise ParameterError(f"{o}.friction = {type(self.friction).__name__}: must be a LuGre law")
        if not isinstance(self.encoder, Encoder):
            raise ParameterError(f"{o}.encoder = {type(self.encoder).__name__}: must be an Encoder")

    @property
    def torque_constant(self) -> float:
        """Axis torque per ampere of the common current reference, eq. 2: ``2 n_c K_T`` [N·m/A]."""
        return 2.0 * self.n_c * self.K_T

    @property
    def inertia(self) -> float:
        """Inertia the axis torque sees [kg·m²]."""
        return self.J

    def truth(self) -> dict:
        """The six (per direction: four static) friction parameters, by the fit's names."""
        return friction_truth(self.friction)

    def gravity(self, theta) -> np.ndarray:
        """Load torque at angle ``theta`` [N·m] (zero: balanced)."""
        return np.zeros_like(np.asarray(theta, dtype=float))

    def machine(self, *, loop: str = "open", theta0: float = 0.0) -> Machine:
        """The axis as a :class:`~frictionkit.Machine`.

        ``loop="open"``: current input ``"i"`` [A] (the torque experiments, §3.1).
        ``loop="position"``: PID on the encoder following the reference ``"r"`` [rad] (the
        constant-velocity runs; both motors driven by the one current, "in series").
        """
        m = Machine(f"SDSS {self.name}")
        th = m.dof("theta", inertia=self.J, kind="rotational", x0=theta0)
        m.friction("bearings", th, law=self.friction)
        self._loads(m, th)
        _drive(m, th, self, loop)
        return m

    def _loads(self, m, th) -> None:
        return None


def _drive(m: Machine, th, axis, loop: str) -> None:
    if loop not in ("open", "position"):
        raise ParameterError(f"{type(axis).__name__}.machine loop = {loop!r}: must be 'open' or 'position'")
    m.actuator("motors", th, gain=axis.torque_constant, limit=axis.i_max, command="i")
    m.sensor("encoder", th, resolution=axis.encoder.resolution, noise=axis.encoder.noise)
    if loop == "position":
        g = _pid_gains(axis.inertia, axis.torque_constant, axis.bandwidth_hz)
        m.add(Sum("e", {"r": 1.0, "encoder": -1.0}), PID("i", "e", antiwindup="motors", **g))


# --------------------------------------------------------------------------- altitude
def _alt_friction() -> LuGre:
    # Assumptions as for azimuth, altitude bearings + two capstans: lower levels (no tilt
    # restraint capstans), other asymmetry.
    pos = stribeck_map(Tc=90.0, Ts=120.0, vs=5.0e-4, sigma2=1000.0)
    neg = stribeck_map(Tc=85.0, Ts=112.0, vs=6.0e-4, sigma2=1100.0)
    s0 = 120.0 / (3.0 * ARCSEC)  # pre-sliding 3 arcsec (seed 002 §2.2 "a few arc seconds")
    return LuGre(Directional(positive=pos, negative=neg), sigma0=s0, sigma1=2 * 0.5 * math.sqrt(s0 * 2.5e4))


@dataclass(frozen=True, kw_only=True)
class AltitudeAxis(AzimuthAxis):
    """Altitude (seed 002 eqs. 2, 13a): ``J dω/dt = 2 n_c K_T i − T_f − m g X sin θ``.

    Extra parameters (assumptions)
    ----------
    J : float — 2.5e4 kg·m² (the tube and mirrors; lighter than the azimuth structure).
    imbalance : float — ``m g X`` = 600 N·m: the partially assembled telescope is out of
        balance (seed 002 §3.2); e.g. 30 kg missing 2 m from the axis. Angle convention in the
        module docstring (stable equilibrium at θ = 0, θ from the hanging position).
    theta_test : float — 0.3 rad: the open-loop runs start at this angle, held against
        G2(θ) = 177 N·m by a constant current (the operator balances the known load).
    """

    J: float = 2.5e4
    friction: LuGre = field(default_factory=_alt_friction)
    imbalance: float = 600.0
    theta_test: float = 0.3
    name: str = "altitude"

    def __post_init__(self) -> None:
        super().__post_init__()
        object.__setattr__(self, "imbalance", val.nonnegative(type(self).__name__, "imbalance", self.imbalance))
        object.__setattr__(self, "theta_test", val.finite(type(self).__name__, "theta_test", self.theta_test))

    def gravity(self, theta) -> np.ndarray:
        """``G2 = m g X sin θ`` [N·m] (eq. 13a, our sign and reference)."""
        return self.imbalance * np.sin(np.asarray(theta, dtype=float))

    def _loads(self, m, th) -> None:
        if self.imbalance > 0:
            m.load("gravity", th, law=SineLoad(amplitude=self.imbalance))


# --------------------------------------------------------------------------- rotator
def _bearing_friction() -> LuGre:
    # Rotator central bearing with its "very large initial pre-load" (seed 002 §4): levels
    # assumed; vs = 4e-4 rad/s at the rotator.
    st = stribeck_map(Tc=60.0, Ts=80.0, vs=4.0e-4, sigma2=800.0)
    s0 = 80.0 / (3.0 * ARCSEC)
    return LuGre(st, sigma0=s0, sigma1=2 * 0.5 * math.sqrt(s0 * 600.0))


def _hd_friction() -> LuGre:
    # Harmonic-drive friction at the HD output shaft (no-load running torque of a size-32 drive,
    # a few N·m). vs at the HD output = n_c * 4e-4 = 6e-3 rad/s: the same Stribeck velocity as
    # the bearing in the rotator frame, an assumption that makes the combined map of eq. 13b
    # exactly an eq. 9b curve (the model the paper fits in Fig. 8).
    st = stribeck_map(Tc=2.0, Ts=2.6, vs=15.0 * 4.0e-4, sigma2=2.0)
    return LuGre(st, sigma0=2.6 / 1e-4, sigma1=0.0)  # pre-sliding 1e-4 rad at the HD output


@dataclass(frozen=True, kw_only=True)
class RotatorAxis:
    """Instrument rotator (seed 002 eqs. 3, 13b, re-derived in the module docstring).

    Parameters (assumptions)
    ----------
    J3 : float — 600 kg·m², rotator with instrument (~1 t at a radius of gyration of 0.8 m).
    J_m : float — 2e-4 kg·m², motor rotor and wave generator.
    K_T : float — 0.1 N·m/A; ``i_max`` 5 A: 0.5 N·m at the motor, n n_c × = 750 N·m at the rotator.
    n : float — 100, harmonic-drive ratio (a common catalogue ratio).
    n_c : float — 15, rotator disc / capstan (corrected as eq. 2's n_c).
    hd_stiffness, hd_torques : the three-slope HD curve at the HD output, K1 = 5.4e4,
        K2 = 6.7e4, K3 = 8.8e4 N·m/rad with breaks at 29 and 108 N·m — the order of a
        size-32 cup-type harmonic drive catalogue; stiffening (module docstring). Rotator-side
        resonance: n_c² K1 = 1.2e7 N·m/rad against the reduced inertia of J3 and
        J_m (n n_c)² = 450 kg·m²: 36 Hz, above the paper's 10 Hz.
    hd_damping : float — 50 N·m·s/rad at the HD output across the flexspline: damping ratio ~0.1
        of the flexspline mode, the order of a harmonic drive's structural losses (the paper
        excludes the HD hysteresis; this viscous term stands in for its energy loss). Without it
        the undamped 36 Hz mode is kept ringing by the friction at both ends (measured: the
        combined map's Coulomb level read 57 % low, the friction dithered away).
    bearing, hd_friction : LuGre — bearing friction (rotator side), HD friction (motor side,
        in HD-output units).
    """

    J3: float = 600.0
    J_m: float = 2.0e-4
    K_T: float = 0.1
    i_max: float = 5.0
    n: float = 100.0
    n_c: float = 15.0
    hd_stiffness: tuple = (5.4e4, 6.7e4, 8.8e4)
    hd_torques: tuple = (29.0, 108.0)
    hd_damping: float = 50.0
    bearing: LuGre = field(default_factory=_bearing_friction)
    hd_friction: LuGre = field(default_factory=_hd_friction)
    encoder: Encoder = field(default_factory=Encoder)
    dt: float = 1e-3
    bandwidth_hz: float = 2.0
    name: str = "rotator"

    def __post_init__(self) -> None:
        o = type(self).__name__
        object.__setattr__(self, "hd_damping", val.nonnegative(o, "hd_damping", self.hd_damping))
        for f in ("J3", "J_m", "K_T", "i_max", "n", "n_c", "dt", "bandwidth_hz"):
            object.__setattr__(self, f, _positive(o, f, getattr(self, f)))
        for f in ("bearing", "hd_friction"):
            if not isinstance(getattr(self, f), LuGre):
                raise ParameterError(f"{o}.{f} = {type(getattr(self, f)).__name__}: must be a LuGre law")
        PiecewiseLinearSpring.from_torque_breaks(self.hd_stiffness, self.hd_torques)  # validates
        if not isinstance(self.encoder, Encoder):
            raise ParameterError(f"{o}.encoder = {type(self.encoder).__name__}: must be an Encoder")

    @property
    def ratio(self) -> float:
        """Motor to rotator ``n n_c``."""
        return self.n * self.n_c

    @property
    def torque_constant(self) -> float:
        """Rotator-frame torque per ampere, re-derived eq. 3: ``n n_c K_T`` [N·m/A]."""
        return self.ratio * self.K_T

    @property
    def inertia(self) -> float:
        """Rigid-body inertia in the rotator frame: ``J3 + J_m (n n_c)²`` [kg·m²]."""
        return self.J3 + self.J_m * self.ratio**2

    def combined_truth(self) -> dict:
        """Eq. 13b's combined map at the rotator, ``T_fb(ω) + n_c T_fHD(n_c ω)``, as one eq. 9b
        set (exact because both Stribeck velocities agree in the rotator frame)."""
        b, h, nc = self.bearing.static, self.hd_friction.static, self.n_c
        out = {}
        for side in ("pos", "neg"):
            out.update({f"Fc_{side}": b.Fc + nc * h.Fc, f"Fs_{side}": b.Fs + nc * h.Fs, f"vs_{side}": b.vs,
                        f"sigma2_{side}": b.sigma2 + nc**2 * h.sigma2})
        return out

    def truth(self) -> dict:
        return self.combined_truth()

    def machine(self, *, loop: str = "position", hd_only: bool = False) -> Machine:
        """Two-mass rotator: motor DOF ``theta_m`` (θ_m), rotator DOF ``theta`` (θ_3), HD compliance on ``θ_m/n − n_c θ_3``.

        ``loop="position"``: PID on the rotator encoder following ``"r"`` [rad at the rotator].
        ``hd_only=True``: the bench test of the separation attempt (ours): the capstan
        disengaged, the motor and HD alone, with the encoder reading the HD output scaled to
        the rotator frame (``θ_m / (n n_c)``).
        """
        m = Machine("SDSS rotator" + (" (HD bench)" if hd_only else ""))
        thm = m.dof("theta_m", inertia=self.J_m, kind="rotational")
        m.friction("harmonic drive", thm / self.n, law=self.hd_friction, unit="N·m")  # a geared angle
        m.actuator("motor", thm, gain=self.K_T, limit=self.i_max, command="i")
        if hd_only:
            at = thm / self.ratio
            J = self.J_m * self.ratio**2
        else:
            th3 = m.dof("theta", inertia=self.J3, kind="rotational")
            m.friction("bearing", th3, law=self.bearing)
            m.compliance("flexspline", thm / self.n, th3 * self.n_c,
                         law=PiecewiseLinearSpring.from_torque_breaks(self.hd_stiffness, self.hd_torques),
                         c=self.hd_damping, unit="N·m")
            at = th3
            J = self.inertia
        m.sensor("encoder", at, resolution=self.encoder.resolution, noise=self.encoder.noise)
        if loop == "position":
            g = _pid_gains(J, self.torque_constant, self.bandwidth_hz)
            m.add(Sum("e", {"r": 1.0, "encoder": -1.0}), PID("i", "e", antiwindup="motor", **g))
        elif loop != "open":
            raise ParameterError(f"RotatorAxis.machine loop = {loop!r}: must be 'open' or 'position'")
        return m


def friction_truth(law: LuGre) -> dict:
    """``{sigma0, sigma1, Fc_pos, Fs_pos, vs_pos, sigma2_pos, ... _neg}`` of a LuGre law."""
    st = law.static
    pos, neg = (st.positive, st.negative) if isinstance(st, Directional) else (st, st)
    out = {"sigma0": law.sigma0, "sigma1": law.sigma1}
    for side, s in (("pos", pos), ("neg", neg)):
        out.update({f"Fc_{side}": s.Fc, f"Fs_{side}": s.Fs, f"vs_{side}": s.vs, f"sigma2_{side}": s.sigma2})
    return out


AXES = ("azimuth", "altitude", "rotator")


def axis(name: str):
    """The default axis of that name (``"azimuth"``, ``"altitude"``, ``"rotator"``)."""
    if name not in AXES:
        raise ParameterError(f"sdss axis = {name!r}: must be one of {AXES}")
    return {"azimuth": AzimuthAxis, "altitude": AltitudeAxis, "rotator": RotatorAxis}[name]()
