"""Seed 001 ball-screw stage on the machine core: the plant, sensors and Fig. 3 controller as a
:class:`~frictionkit.machines.Machine`.

This module builds the stage the private kernel ``kernels/ballscrew.py`` used to run, with
the machine API, so the stage can carry any friction law at the nut and the guide (issue 8,
part 6); that kernel is deleted and :func:`frictionkit.control.loop.simulate_closed_loop`
is now a thin wrapper over :func:`simulate_stage`.

Provenance
----------
* Zhu & Fujimoto, "High-precision control for ball-screw-driven stage in zero-speed region"
  (seed 001): eq. 1 (rigid model), Fig. 7 / Table 1 (elastic chain), Fig. 3 (PTC + PID + DOB),
  §2.1 sensors. The parameter values and every assumption live in
  :mod:`frictionkit.presets.zhu_fujimoto`; the plant objects in
  :mod:`frictionkit.plants.ballscrew`.

Mechanics (elastic stage, one DOF per chain coordinate)
-------------------------------------------------------
``theta_m`` (``J_m``), ``theta_s`` (``J_b``), ``x_l``, ``x_m``, ``x_r`` (``M_b / 3`` each),
``x_t`` (``M_t``); springs ``k_o`` on ``theta_m - theta_s``, ``k_bearing`` on ``x_l`` and
``x_r`` to ground, ``k_axial`` on ``x_l - x_m``, ``k_axial_right`` on ``x_r - x_m``,
``k_nut`` on the contact ``R theta_s + x_m - x_t``; each spring carries its Rayleigh damper
``c = beta k`` (``beta = 2 zeta / omega_1``, so ``D = diag(B_m, B_b, 0, 0, 0, C_t) + beta K``
exactly as :meth:`ElasticBallScrew.linear_chain`); viscosities ``B_m``, ``B_b``, ``C_t`` are
dampers to ground. Friction sites: ``"guide"`` on ``x_t`` and ``"nut"`` on ``R theta_s``
(linear equivalent of the nut torque), by default the Dahl laws of the private kernel
(``Dahl(Fc=level, sigma0=DAHL_SPAN level / presliding_length)``), or any law given as
``guide_law`` / ``nut_law``. The rigid stage (eq. 1): one DOF ``theta`` (``J``), damper
``B``, one site ``"nut"`` on ``R theta``.

Nut models (:class:`~frictionkit.plants.ballscrew.ElasticBallScrew` ``nut_model``):
``"sliding"`` as above. ``"flank"``: the site ``"nut"`` keeps the load-independent rest
``nut_friction - 2 mu_f P``; two sites ``"flank_pos"`` / ``"flank_neg"`` on ``R theta_s``
hold the flank law at the reference load ``P`` (default ``Dahl(Fc=mu_f P, ...)``, or
``flank_law``) with a :class:`~frictionkit.machines.NormalLoad` on the contact spring's force
``F_bn``: ``N = max(P + s F_bn / 2, s F_bn, 0)``. ``"hertz"``: the contact is a
:class:`~frictionkit.machines.HertzContact` compliance (``P``, ``k_nut``; damper
``beta k_nut``) and each flank's load is the Hertz load of its set, ``c (d0 + s d)_+^1.5``.

Actuator ``"motor"``: current -> torque ``K_tau`` on the motor, limit ``i_max``. Sensors:
``"encoder"`` on the motor angle (``2 pi / counts``), ``"scale"`` on ``x_t`` (resolution),
white noise before quantisation.

Controller (blocks, once per sample; input arrays ``theta_d``, ``u_ff`` [A], ``u_f`` [A])
--------------------------------------------------------------------------------------
::

    e     = theta_d - scale / R            ("table", "dual")  or  theta_d - encoder  ("motor")
    e_d   = theta_d - encoder              ("dual": the derivative on the encoder)
    u_pid = PID(e; derivative on e_d), integrator frozen while the motor current saturates
    d_hat = DOB(encoder, motor.applied, u_f)                         (StateSpace, see below)
    i_cmd = u_ff + u_pid + d_hat / K_tau_n + u_f      -> motor (clipped at i_max)

DOB (seed 001 §2.2; :class:`~frictionkit.control.dob.DisturbanceObserver`):
``omega_k = (enc_k - enc_{k-1}) / T``,
``raw_k = K_tau_n (i_{k-1} - u_f,{k-1}) - B_n omega_k - J_n (omega_k - omega_{k-1}) / T``,
``d_k = a d_{k-1} + (1 - a) raw_k`` — a 4-state :class:`~frictionkit.machines.StateSpace`
``x = [enc_{k-1}, omega_{k-1}, d_{k-1}, u_f,{k-1}]`` reading ``motor.applied`` before the
actuator writes it (last sample's applied current). One difference from the deleted private
kernel: it skipped the observer at ``k = 0`` (``enc_{-1} := enc_0``); here ``enc_{-1} = 0``,
which differs only if the first encoder sample is not 0 (noise at a stage at rest).
"""

from __future__ import annotations

import pickle
from collections import OrderedDict

import numpy as np

from .. import _validate as val
from .._lru import remember
from ..control.loop import ClosedLoopResult, Sensors, TwoDofController
from ..control.trajectories import Reference
from ..errors import DataError, ParameterError, SimulationError
from ..machines import PID, HertzContact, Machine, NormalLoad, StateSpace, Sum, simulate_machine
from ..models.lugre import Dahl
from ..plants.ballscrew import DAHL_SPAN, ElasticBallScrew, RigidBallScrew

__all__ = ["ballscrew_machine", "check_plant", "dob_block", "simulate_stage", "rayleigh_beta"]

ELASTIC_DOFS = ("theta_m", "theta_s", "x_l", "x_m", "x_r", "x_t")


def rayleigh_beta(plant: ElasticBallScrew) -> float:
    """``beta = 2 zeta / omega_1`` of the stiffness-proportional damping ``D = beta K``."""
    return 2.0 * plant.damping_ratio / plant.modes()[0]


#: Largest ratio of the chain's inertias (each DOF's, in its own unit: kg·m² or kg) the stage
#: accepts: the machine core refuses a mass matrix whose eigenvalues span 1e12 or more (singular in
#: double precision), so a wider span can never run; the seed 001 stage spans 2.7e5.
MAX_INERTIA_SPAN = 1e12


def check_plant(plant: ElasticBallScrew | RigidBallScrew, where: str = "ballscrew stage") -> None:
    """Refuse a plant the stage cannot simulate, naming the value (issue 13: a table mass of
    1e300 / 1e-300 kg failed every run as 'the mass matrix is singular' / 'coupling.c = nan').

    Elastic stage: the inertias ``J_m``, ``J_b`` [kg·m²], ``M_b / 3``, ``M_t`` [kg] must span less
    than :data:`MAX_INERTIA_SPAN` (the one farthest, in decades, from the median of the others is
    named), and the first elastic mode (Rayleigh damping ``beta = 2 zeta / omega_1``) must be
    finite and positive. Rigid stage: ``J`` and the friction level finite.
    """
    if isinstance(plant, RigidBallScrew):
        return
    if not isinstance(plant, ElasticBallScrew):
        raise ParameterError(f"{where}: plant = {type(plant).__name__}: must be ElasticBallScrew or RigidBallScrew")
    inertias = {"J_m": (plant.J_m, "kg·m²"), "J_b": (plant.J_b, "kg·m²"), "M_b": (plant.M_b, "kg"),
                "M_t": (plant.M_t, "kg")}
    per_dof = {k: (v / 3.0 if k == "M_b" else v) for k, (v, _) in inertias.items()}
    lo, hi = min(per_dof.values()), max(per_dof.values())
    if not hi < MAX_INERTIA_SPAN * lo:
        logs = {k: np.log10(v) for k, v in per_dof.items()}

        def off(k):
            return abs(logs[k] - float(np.median([x for j, x in logs.items() if j != k])))

        bad = max(logs, key=off)
        others = ", ".join(f"{k} = {inertias[k][0]:.4g} {inertias[k][1]}" for k in inertias if k != bad)
        raise ParameterError(
            f"{where}: {bad} = {inertias[bad][0]:.4g} {inertias[bad][1]} is not a plausible inertia beside "
            f"{others}: the chain's inertias would span {hi / lo:.3g} (at most {MAX_INERTIA_SPAN:.0e}; the mass "
            "matrix is singular in double precision beyond that)")
    w1 = float(plant.modes()[0]) if np.all(np.isfinite(plant.modes())) else float("nan")
    if not (np.isfinite(w1) and w1 > 0.0):
        raise ParameterError(f"{where}: the first elastic mode of the chain is {w1!r} rad/s (the Rayleigh damping "
                             "needs a finite, positive one); check the stiffnesses and inertias")


def _dahl(level: float, length: float):
    return Dahl(Fc=level, sigma0=DAHL_SPAN * level / length) if level > 0.0 else None


def dob_block(*, K_tau: float, J: float, B: float, a: float, T: float, encoder: str = "encoder",
              applied: str = "motor.applied", u_f: str = "u_f", out: str = "d_hat") -> StateSpace:
    """The seed 001 disturbance observer as a discrete state-space block (output ``d_hat`` [N·m]).

    State ``[enc_{k-1}, omega_{k-1}, d_{k-1}, u_f,{k-1}]``; inputs ``(encoder, applied, u_f)``
    where ``applied`` is read before the actuator writes it (last sample's current). The
    observer sees the applied current without the compensation ``u_f`` [A].
    """
    b = 1.0 - a
    a1 = B + J / T
    # d_k = a x2 + b (K (iapp - x3) - a1 (enc - x0) / T + (J / T) x1)
    c_row = [b * a1 / T, b * J / T, a, -b * K_tau]
    d_row = [-b * a1 / T, b * K_tau, 0.0]
    A = np.array([[0.0, 0.0, 0.0, 0.0],
                  [-1.0 / T, 0.0, 0.0, 0.0],
                  c_row,
                  [0.0, 0.0, 0.0, 0.0]])
    Bm = np.array([[1.0, 0.0, 0.0],
                   [1.0 / T, 0.0, 0.0],
                   d_row,
                   [0.0, 0.0, 1.0]])
    return StateSpace(outputs=(out,), inputs=(encoder, applied, u_f), A=A, B=Bm, C=[c_row], D=[d_row])


def ballscrew_machine(plant: ElasticBallScrew | RigidBallScrew, controller: TwoDofController | None = None,
                      sensors: Sensors | None = None, *, nut_law=None, guide_law=None,
                      flank_law=None) -> Machine:
    """The seed 001 ball-screw stage (elastic Fig. 7 or rigid eq. 1) as a machine.

    Parameters
    ----------
    plant : ElasticBallScrew or RigidBallScrew — masses, stiffnesses, viscosities, friction levels.
    controller : TwoDofController, optional — adds the Fig. 3 controller blocks (inputs
        ``theta_d`` [rad], ``u_ff`` [A], ``u_f`` [A] at simulation). Without it the actuator
        ``"motor"`` follows an input array ``"i"`` [A] (open loop), limit ``inf``.
    sensors : Sensors, optional — default: ideal (no quantisation, no noise).
    nut_law, guide_law : friction law, optional — replace the Dahl site at the nut (on
        ``R theta_s``, linear-equivalent force [N]) / the guide (on ``x_t``). Any law the core
        accepts (Stribeck, CoulombViscous, Directional, Dahl, LuGre, GMS). The rigid stage has
        only the nut site. With nut models ``"flank"``/``"hertz"``, ``nut_law`` is the
        load-independent rest of the nut friction.
    flank_law : friction law, optional — nut models ``"flank"``/``"hertz"``: the law of each
        groove flank at the reference load ``nut_preload`` (scaled with the flank's ball load).

    Returns
    -------
    Machine — DOFs as in the module docstring; sites ``"guide"``, ``"nut"`` (absent when the
    level is 0 and no law is given) and, for ``"flank"``/``"hertz"``, ``"flank_pos"``,
    ``"flank_neg"`` (and the compliance ``"nut_contact"`` for ``"hertz"``); actuator
    ``"motor"``; sensors ``"encoder"``, ``"scale"``.

    Examples
    --------
    >>> import frictionkit as fk
    >>> from frictionkit.presets.ballscrew import ballscrew_machine
    >>> from frictionkit.reproduce.zhu_fujimoto import paper_plant
    >>> gms = fk.GMS(fk.Stribeck(Fc=1270.0, Fs=1400.0, vs=1e-3), k=[5e7, 2e8], xi=[0.5, 0.5], C=20.0)
    >>> ballscrew_machine(paper_plant(), nut_law=gms)
    Machine('ballscrew (elastic, sliding nut)': 6 dofs, 9 springs, 2 sites, 1 actuator, 2 sensors, 0 blocks)
    """
    sensors = Sensors(encoder_counts=0, scale_resolution=0.0) if sensors is None else sensors
    if not isinstance(sensors, Sensors):
        raise ParameterError(f"ballscrew_machine sensors = {type(sensors).__name__}: must be a Sensors")
    if controller is not None and not isinstance(controller, TwoDofController):
        raise ParameterError(f"ballscrew_machine controller = {type(controller).__name__}: must be a TwoDofController")

    check_plant(plant, "ballscrew_machine")
    if isinstance(plant, ElasticBallScrew):
        R = plant.R
        m = Machine(f"ballscrew (elastic, {plant.nut_model} nut)")
        th_m = m.dof("theta_m", inertia=plant.J_m, kind="rotational")
        th_s = m.dof("theta_s", inertia=plant.J_b, kind="rotational")
        x_l = m.dof("x_l", inertia=plant.M_b / 3.0)
        x_m = m.dof("x_m", inertia=plant.M_b / 3.0)
        x_r = m.dof("x_r", inertia=plant.M_b / 3.0)
        x_t = m.dof("x_t", inertia=plant.M_t)
        beta = rayleigh_beta(plant)
        contact = R * th_s + x_m - x_t
        for name, at, k in (("coupling", th_m - th_s, plant.k_o),
                            ("bearing_left", x_l, plant.k_bearing),
                            ("bearing_right", x_r, plant.k_bearing),
                            ("screw_left", x_l - x_m, plant.k_axial),
                            ("screw_right", x_m - x_r, plant.k_axial_right)):
            m.spring(at, k=k, c=beta * k, name=name)
        if plant.nut_model == "hertz":
            m.compliance("nut_contact", contact, law=HertzContact(preload=plant.nut_preload, stiffness=plant.k_nut),
                         c=beta * plant.k_nut)
        else:
            m.spring(contact, k=plant.k_nut, c=beta * plant.k_nut, name="nut_contact")
        for name, at, c in (("B_m", th_m, plant.B_m), ("B_b", th_s, plant.B_b), ("C_t", x_t, plant.C_t)):
            if c > 0.0:
                m.damper(at, c=c, name=name)
        flank = plant.nut_model in ("flank", "hertz")
        mu, P = plant.flank_friction_coefficient, plant.nut_preload
        rest = max(plant.nut_friction - 2.0 * mu * P, 0.0) if flank else plant.nut_friction
        glaw = guide_law if guide_law is not None else _dahl(plant.guide_friction, plant.presliding_length)
        nlaw = nut_law if nut_law is not None else _dahl(rest, plant.presliding_length)
        if glaw is not None:
            m.friction("guide", x_t, law=glaw)
        if nlaw is not None:
            m.friction("nut", R * th_s, law=nlaw)
        if flank:
            flaw = flank_law if flank_law is not None else _dahl(mu * P, plant.presliding_length)
            if flaw is not None:
                for name, sgn in (("flank_pos", 1), ("flank_neg", -1)):
                    if plant.nut_model == "hertz":
                        load = NormalLoad(on="nut_contact", reference=P, hertz_set=sgn)
                    else:  # linearised equal-stiffness split of the drive force F_bn
                        load = NormalLoad(on="nut_contact", reference=P, preload=P, gain=0.5 * sgn, floor_gain=sgn)
                    m.friction(name, R * th_s, law=flaw, load=load)
        elif flank_law is not None:
            raise ParameterError("ballscrew_machine: flank_law needs nut_model 'flank' or 'hertz'")
        motor, table = th_m, x_t
    elif isinstance(plant, RigidBallScrew):
        if guide_law is not None or flank_law is not None:
            raise ParameterError("ballscrew_machine: the rigid stage (eq. 1) has one friction site, 'nut'; "
                                 "give its law as nut_law, not guide_law")
        R = plant.R
        m = Machine("ballscrew (rigid, eq. 1)")
        th = m.dof("theta", inertia=plant.J, kind="rotational")
        if plant.B > 0.0:
            m.damper(th, c=plant.B, name="B")
        nlaw = nut_law if nut_law is not None else _dahl(plant.friction, plant.presliding_length)
        if nlaw is not None:
            m.friction("nut", R * th, law=nlaw)
        motor, table = th, R * th
    else:
        raise ParameterError(f"ballscrew_machine plant = {type(plant).__name__}: must be ElasticBallScrew "
                             "or RigidBallScrew")

    q_enc = sensors.encoder_step
    m.sensor("encoder", motor, resolution=q_enc, noise=sensors.encoder_noise_counts * q_enc)
    m.sensor("scale", table, resolution=sensors.scale_resolution, noise=sensors.scale_noise)
    if controller is None:
        m.actuator("motor", motor, gain=plant.K_tau, command="i")
        return m

    c = controller
    m.actuator("motor", motor, gain=plant.K_tau, limit=c.i_max, command="i_cmd")
    if c.feedback == "motor":
        m.add(Sum("e", {"theta_d": 1.0, "encoder": -1.0}))
    else:
        m.add(Sum("e", {"theta_d": 1.0, "scale": -1.0 / c.R}))
    ed = None
    if c.feedback == "dual":
        m.add(Sum("e_d", {"theta_d": 1.0, "encoder": -1.0}))
        ed = "e_d"
    p = c.pid
    m.add(PID("u_pid", "e", Kp=p.Kp, Ki=p.Ki, Kd=p.Kd, tau_d=p.tau_d, derivative_error=ed, antiwindup="motor"))
    terms = {"u_ff": 1.0, "u_pid": 1.0}
    if c.dob is not None:
        d = c.dob
        m.add(dob_block(K_tau=d.K_tau, J=d.J, B=d.B, a=d.a, T=d.T))
        terms["d_hat"] = 1.0 / d.K_tau
    terms["u_f"] = 1.0
    m.add(Sum("i_cmd", terms))
    return m


def simulate_stage(plant: ElasticBallScrew | RigidBallScrew, controller: TwoDofController, reference: Reference, *,
                   compensation=None, sensors: Sensors | None = None, seed: int | None = 0, substeps: int = 10,
                   nut_law=None, guide_law=None, flank_law=None, raise_on_failure: bool = False) -> ClosedLoopResult:
    """Run the stage of :func:`ballscrew_machine` in closed loop on the machine core.

    :func:`frictionkit.control.loop.simulate_closed_loop` is a wrapper over this function
    (``compensation``: friction compensation torque ``u_f`` [N·m] per sample, divided by the
    PTC's ``K_tau`` into a current; ``substeps`` plant sub-steps per control period).
    ``ClosedLoopResult.friction`` has rows ``[guide, nut]`` (elastic, ``"sliding"``),
    ``[guide, nut, flank_pos, flank_neg]`` (``"flank"``/``"hertz"``) or ``[nut]`` (rigid); a
    site without friction is a row of zeros. ``drive_force`` is the contact force
    ``F(d) + beta k_nut d'`` (``F = k_nut d`` or the Hertz law; zeros for the rigid stage).
    ``nut_law``, ``guide_law``, ``flank_law``: see :func:`ballscrew_machine`.

    Sensor noise: the same draws as the deleted private loop (encoder first, then scale, one
    ``default_rng(seed)``) when both noises are non-zero; the core draws only for sensors
    with noise, so with a noiseless encoder and a noisy scale the scale's draws differ.

    Examples
    --------
    >>> from frictionkit.reproduce.zhu_fujimoto import paper_controller
    >>> from frictionkit.plants.ballscrew import RigidBallScrew
    >>> from frictionkit.control.trajectories import cosine_reference
    >>> res = simulate_stage(RigidBallScrew(), paper_controller(), cosine_reference(duration=0.2))
    >>> res.success, bool(abs(res.error).max() < 1e-6)
    (True, True)
    """
    if not isinstance(controller, TwoDofController):
        raise ParameterError(f"simulate_stage controller = {type(controller).__name__}: must be a TwoDofController")
    if not isinstance(reference, Reference):
        raise DataError("reference: must be a frictionkit.control.trajectories.Reference")
    T = controller.T
    if abs(reference.T - T) > 1e-12 * T:
        raise DataError(f"reference.T = {reference.T!r} s: must equal the control period {T!r} s")
    N = len(reference)
    uf = np.zeros(N) if compensation is None else val.signal("compensation", compensation)
    if uf.size != N:
        raise DataError(f"compensation has {uf.size} samples: must match the reference ({N})")
    m, beta = _stage_machine(plant, controller, sensors, nut_law, guide_law, flank_law)
    R = controller.R
    u_ff, theta_d = _feedforward(controller.ptc, reference.x / R, reference.v / R)
    inputs = {"theta_d": theta_d, "u_ff": u_ff, "u_f": uf / controller.ptc.K_tau}
    res = simulate_machine(m, dt=T, inputs=inputs, substeps=substeps, seed=seed)
    if not res.success and raise_on_failure:
        raise SimulationError(res.message)
    elastic = isinstance(plant, ElasticBallScrew)
    if elastic:
        x_t = res.position("x_t")
        theta_m = res.position("theta_m")
        g = R * m.coord("theta_s") + m.coord("x_m") - m.coord("x_t")
        k = plant.k_nut
        d = res.position(g)
        fbn = plant.contact_force(d) + beta * k * res.velocity(g)
        names = ("guide", "nut") if plant.nut_model == "sliding" else ("guide", "nut", "flank_pos", "flank_neg")
    else:
        theta_m = res.position("theta")
        x_t = R * theta_m
        fbn = np.zeros(N)
        names = ("nut",)
    fric = np.zeros((len(names), N))
    for j, s in enumerate(names):
        if s in res.site_names:
            fric[j] = res.force(s)
    return ClosedLoopResult(t=reference.t, r=reference.x, x_t=x_t, theta_m=theta_m,
                            x_t_meas=res.signal("scale"), theta_m_meas=res.signal("encoder"),
                            i=res.u[:, 0].copy(), drive_force=fbn, friction=fric, u_f=uf,
                            status=res.status, message=res.message)



# ---------------------------------------------------------------------- caches of simulate_stage
#: Stage machines and feed-forwards of recent :func:`simulate_stage` calls (oldest first), so a
#: study's, fit's or benchmark's many runs of one stage build its machine (~2.5 ms) and its PTC
#: feed-forward (~2.3 ms; scipy's matrix exponential inside took up to 24 ms on a loaded 2-core
#: machine, OpenBLAS threads waiting on each other) once.
_STAGE_CACHE: "OrderedDict[bytes, tuple]" = OrderedDict()
_FF_CACHE: "OrderedDict[tuple, tuple]" = OrderedDict()
STAGE_CACHE_SIZE = 8
FF_CACHE_SIZE = 4
#: Longest reference whose feed-forward is remembered (its key holds the reference's bytes:
#: at most FF_CACHE_SIZE x 4 arrays of this many float64 samples, 12.8 MB).
FF_CACHE_MAX_SAMPLES = 100_000


def _content_key(*objs) -> bytes | None:
    """The objects' content as bytes — their pickle, which rebuilds equal objects, floats bit
    for bit — or None when one cannot be pickled (then nothing is cached). An edited plant,
    controller, sensor set or law is another object with other content, so it can never meet
    a stale entry. Named assumption: a class is known by its module and name (a class
    redefined under the same name with the same fields, e.g. in a notebook, is not told apart)."""
    try:
        return pickle.dumps(objs, protocol=pickle.HIGHEST_PROTOCOL)
    except Exception:
        return None


def _stage_machine(plant, controller, sensors, nut_law, guide_law, flank_law) -> tuple:
    """``(machine, beta)`` of :func:`simulate_stage`: :func:`ballscrew_machine` and the
    Rayleigh ``beta`` (0 for the rigid stage), remembered by content. The machine never leaves
    :func:`simulate_stage` (its result holds arrays only), so no caller can edit a cached one."""
    def make():
        m = ballscrew_machine(plant, controller, sensors, nut_law=nut_law, guide_law=guide_law, flank_law=flank_law)
        return m, (rayleigh_beta(plant) if isinstance(plant, ElasticBallScrew) else 0.0)

    key = _content_key(plant, controller, sensors, nut_law, guide_law, flank_law)
    return remember(_STAGE_CACHE, key, make, STAGE_CACHE_SIZE)


def _feedforward(ptc, theta_ref: np.ndarray, omega_ref: np.ndarray) -> tuple:
    """``ptc.feedforward(theta_ref, omega_ref)``, remembered by content (the PTC's and the
    references' bytes) for references up to :data:`FF_CACHE_MAX_SAMPLES`. The arrays are
    read-only: they are only ever copied into the machine's inputs."""
    def make():
        out = ptc.feedforward(theta_ref, omega_ref)
        for a in out:
            a.setflags(write=False)
        return out

    th = np.ascontiguousarray(theta_ref, dtype=float)
    om = np.ascontiguousarray(omega_ref, dtype=float)
    key = None
    if th.size <= FF_CACHE_MAX_SAMPLES and om.size <= FF_CACHE_MAX_SAMPLES:
        k = _content_key(ptc)
        key = None if k is None else (k, th.shape, th.tobytes(), om.shape, om.tobytes())
    return remember(_FF_CACHE, key, make, FF_CACHE_SIZE)
