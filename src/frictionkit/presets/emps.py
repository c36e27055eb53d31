"""EMPS preset: the Electro-Mechanical Positioning System axis and its position loop on the machine core.

Provenance
----------
* A. Janot, M. Gautier and M. Brunot, "Data Set and Reference Models of EMPS", 2019 Workshop
  on Nonlinear System Identification Benchmarks, Eindhoven (the benchmark's
  ``EMPS_Description.pdf``): rigid load-side model ``M q'' + Fv q' + Fc sgn(q') + offset =
  tau`` (eq. 1), cascaded P position / P velocity controller, ``tau = gtau nu``.
* ``../shared/data/emps/README.md`` (the dataset's curator notes): the constants below, the
  controller law checked against the logged ``vir`` (same-sample ``qm``, RMS residual
  0.0037 V) and the published parameters M = 95.1089 kg, Fv = 203.5034 N·s/m,
  Fc = 20.3935 N, offset = -3.1648 N.
* ``Simulation_EMPS.m`` (benchmark zip): the reference simulation — ±10 V saturation of the
  controller output (``viradm``), one-sample unit delay between control law and plant, the
  0.5/0.5 FIR position filter before the velocity difference, ode45 with 0.1 ms max step.

The closed loop, sample ``k`` (``dt`` = 1 ms)::

    qf_k  = (qm_k + qm_{k-1}) / 2                 FIR position filter
    vf_k  = (qf_k - qf_{k-1}) / dt                 backward difference
    nu_k  = sat_{±vmax}( kv (kp (qg_k - qm_k) - vf_k) )
    tau   = gtau nu_{k-1}   over [t_k, t_{k+1})    one-sample delay

All controller memories start at zero, the axis at rest at ``q = 0`` (as ``Simulation_EMPS.m``).
"""

from __future__ import annotations

from .. import _validate as val
from ..errors import ParameterError
from ..machines import Machine, Saturation, Sum
from typing import TYPE_CHECKING

if TYPE_CHECKING:
    from ..models.base import FrictionLaw

__all__ = ["EMPS_CONSTANTS", "PUBLISHED", "PUBLISHED_ASYMMETRIC", "emps_machine"]

#: Constants stored in ``DATA_EMPS.mat`` (README): drive gain ``gtau`` [N/V], position gain
#: ``kp`` [1/s], velocity gain ``kv`` [V/(m/s)]; ``Simulation_EMPS.m``: saturation ``vmax``
#: [V]; sample time ``dt`` [s].
EMPS_CONSTANTS = {"gtau": 35.15065188248547, "kp": 160.18, "kv": 243.45, "vmax": 10.0, "dt": 1e-3}

#: Published rigid-body parameters (``EMPS_Description.pdf`` §3.4, ``Simulation_EMPS.m``'s
#: ``M1, Fv1, Fc1, OF1``): mass [kg], viscous [N·s/m], Coulomb [N], offset [N].
PUBLISHED = {"M": 95.1089, "Fv": 203.5034, "Fc": 20.3935, "offset": -3.1648}

#: Published asymmetric-friction variant, no offset (``EMPS_Description.pdf`` §4.2, eq. 12,
#: ``Script_IDIM_LS_Asym_Fric.m``): mass [kg], viscous and Coulomb per direction.
PUBLISHED_ASYMMETRIC = {"M": 95.1540, "Fv_pos": 166.7061, "Fc_pos": 20.1440,
                        "Fv_neg": 240.4236, "Fc_neg": 20.6277}


def emps_machine(*, M: float, friction: FrictionLaw, offset: float = 0.0, constants: dict | None = None,
                 encoder_resolution: float = 0.0) -> Machine:
    """The EMPS rigid axis in its position loop, as a :class:`~frictionkit.machines.Machine`.

    Parameters
    ----------
    M : float
        Moving mass, load side [kg].
    friction : friction law
        Any law the core accepts at a site (``CoulombViscous``, ``Stribeck``,
        ``Directional``, ``Dahl``, ``LuGre``, ``GMS``); the published model is
        ``CoulombViscous(Fc=20.3935, sigma2=203.5034)``.
    offset : float
        Constant force [N] opposing the actuator like the friction does (the published
        model's ``-3.1648`` N enters as ``... + offset = tau``). Zero: no offset part.
    constants : dict, optional
        Override :data:`EMPS_CONSTANTS` (``gtau``, ``kp``, ``kv``, ``vmax``, ``dt``).
    encoder_resolution : float
        Quantisation of the measured position ``qm`` [m] (the benchmark's encoder: one
        count = 5e-8 m on the load side). Default 0: unquantised, as ``Simulation_EMPS.m``.

    Returns
    -------
    Machine
        One DOF ``"q"``; friction site ``"friction"``; actuator ``"motor"`` (``gtau``,
        ±``vmax``, one-sample delay, follows ``"nu"``) and, if ``offset != 0``, actuator
        ``"offset"``; sensor ``"qm"``; controller signals ``"qf"``, ``"vf"``, ``"nu_c"``
        (before saturation), ``"nu"``. Simulate with
        ``simulate_machine(m, dt=constants["dt"], inputs={"qg": qg})``; the force the
        plant receives is ``res.signal("motor.applied") * gtau``.

    Examples
    --------
    >>> import numpy as np, frictionkit as fk
    >>> from frictionkit.presets.emps import emps_machine
    >>> m = emps_machine(M=95.1089, friction=fk.CoulombViscous(Fc=20.3935, sigma2=203.5034), offset=-3.1648)
    >>> m
    Machine('EMPS': 1 dof, 0 springs, 1 site, 2 actuators, 1 sensor, 7 blocks)
    >>> qg = np.r_[np.zeros(10), np.full(990, 1e-3)]
    >>> res = fk.simulate_machine(m, dt=1e-3, inputs={"qg": qg})
    >>> bool(abs(res.position("q")[-1] - 1e-3) < 2e-4)
    True
    """
    c = dict(EMPS_CONSTANTS, **(constants or {}))
    unknown = set(c) - set(EMPS_CONSTANTS)
    if unknown:
        raise ParameterError(f"emps_machine constants: unknown keys {sorted(unknown)}; "
                             f"known: {sorted(EMPS_CONSTANTS)}")
    o = "emps_machine"
    M = val.positive(o, "M", M)
    offset = val.finite(o, "offset", offset)
    gtau = val.positive(o, "constants['gtau']", c["gtau"])
    kp = val.positive(o, "constants['kp']", c["kp"])
    kv = val.positive(o, "constants['kv']", c["kv"])
    vmax = val.positive(o, "constants['vmax']", c["vmax"])
    dt = val.positive(o, "constants['dt']", c["dt"])

    m = Machine("EMPS")
    q = m.dof("q", inertia=M)
    m.friction("friction", q, law=friction)
    m.sensor("qm", q, resolution=encoder_resolution)
    # Controller, in order. A signal read before it is written this sample holds last
    # sample's value, so "qm_prev" / "qf_prev" below are qm_{k-1} / qf_{k-1} (zero at k = 0).
    m.add(
        Sum("qf", {"qm": 0.5, "qm_prev": 0.5}),                   # qf_k = (qm_k + qm_{k-1}) / 2
        Sum("vf", {"qf": 1.0 / dt, "qf_prev": -1.0 / dt}),        # vf_k = (qf_k - qf_{k-1}) / dt
        Sum("nu_c", {"qg": kv * kp, "qm": -kv * kp, "vf": -kv}),  # kv (kp (qg_k - qm_k) - vf_k)
        Saturation("nu", "nu_c", -vmax, vmax),                    # ±10 V (viradm)
        Sum("qm_prev", {"qm": 1.0}),                              # memories for the next sample
        Sum("qf_prev", {"qf": 1.0}),
    )
    # tau = gtau nu_{k-1}: the unit delay of Simulation_EMPS.m. The limit repeats the
    # controller's ±vmax (no effect after the Saturation block; kept if "nu" is rewired).
    m.actuator("motor", q, gain=gtau, limit=vmax, delay=1, command="nu")
    if offset != 0.0:
        # The offset opposes tau like the friction: M q'' = tau - F(q') - offset. The core has
        # no constant block, so a Sum with a zero-weight term carries the bias.
        m.add(Sum("offset_force", {"qg": 0.0}, bias=-offset))
        m.actuator("offset", q, gain=1.0, command="offset_force")
    return m
