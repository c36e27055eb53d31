"""EMPS closed-loop simulation and friction beyond the published rigid-body model.

The EMPS benchmark (Janot, Gautier, Brunot 2019; ``../shared/data/emps/README.md``)
publishes a rigid-body model ``M q'' + Fv q' + Fc sgn(q') + offset = tau`` and its
closed-loop simulation errors on the estimation record (velocity 0.229 %, force
5.85 %). :func:`emps_closed_loop` reproduces that simulation for any static friction
map; :func:`emps_stribeck_fit` identifies a per-direction Stribeck map by inverse
dynamics on the same record, and :func:`emps_compare` reports both models' inverse
and closed-loop errors side by side.

Controller (README, ``Simulation_EMPS.m``): ``nu_k = kv (kp (qg_k - qm_k) - vf_k)``
with ``vf_k = (qf_k - qf_{k-1}) / dt``, ``qf_k = (qm_k + qm_{k-1}) / 2``, saturated at
±10 V; the plant receives ``tau = gtau nu_{k-1}`` during ``[t_k, t_{k+1})`` (one-sample
delay). The axis and its controller are the machine-core preset
:func:`frictionkit.presets.emps.emps_machine`.
"""

from __future__ import annotations

import numpy as np

from ..data.recording import Recording
from ..data.signals import derivative, lowpass
from ..errors import DataError, SimulationError
from ..machines import simulate_machine
from ..models.static import CoulombViscous, Directional
from ..presets.emps import EMPS_CONSTANTS, PUBLISHED, PUBLISHED_ASYMMETRIC, emps_machine
from .rigid_body import fit_rigid_body
from typing import TYPE_CHECKING

if TYPE_CHECKING:
    from ..models.base import FrictionLaw
    from numpy.typing import ArrayLike

__all__ = ["emps_closed_loop", "emps_closed_loop_errors", "emps_stribeck_fit", "emps_compare",
           "EMPS_CONSTANTS"]


def emps_closed_loop(qg: ArrayLike, *, M: float, friction: FrictionLaw, offset: float = 0.0, substeps: int = 40,
                     constants: dict | None = None, disturbance: ArrayLike | None=None, q0: float = 0.0,
                     v0: float = 0.0) -> dict[str, np.ndarray]:
    """Simulate the EMPS position loop with a rigid load and any friction law.

    Builds :func:`frictionkit.presets.emps.emps_machine` and runs it with
    :func:`~frictionkit.machines.simulate_machine` (the machine core: exact rigid-body
    update, implicit friction force per sub-step, so a static law sticks exactly when the
    holding force lies inside ``[-Fs, Fs]``).

    Parameters
    ----------
    qg : array_like
        Reference position [m] at 1 kHz.
    M : float
        Moving mass [kg].
    friction : CoulombViscous | Stribeck | Directional | Dahl | LuGre | GMS
        Friction law at the axis [N].
    offset : float
        Constant force [N] added to the friction (published model: −3.1648 N).
    substeps : int
        Plant sub-steps per 1 ms sample of the core (first order in the step). At 40
        (25 µs) the EMPS record's closed-loop errors are converged to about 0.001
        percentage points; 10 (0.1 ms, ``Simulation_EMPS.m``'s max step) leaves about
        0.005 pp, 5 about 0.007 pp (``tests/realdata/test_emps_dynamic.py``).
    constants : dict, optional
        Override :data:`EMPS_CONSTANTS`.
    disturbance : array_like, optional
        Voltage [V] added to the command ``nu`` after the controller's saturation, one value
        per sample, through the same one-sample delay and gain ``gtau`` (e.g. a pulse train
        that excites the axis beyond the reference's motion). ``tau`` then includes it.
    q0, v0 : float
        Initial position [m] and velocity [m/s] of the axis. The controller memories start
        at the initial position (the axis has been at ``q0``): the friction laws here do not
        depend on position, so the run from ``q0`` is the run from 0 with the reference
        shifted by ``-q0``, and ``q`` is shifted back. The velocity estimate starts at 0
        and catches up with ``v0`` within two samples (its FIR filter).

    Returns
    -------
    dict
        ``q`` [m], ``v`` [m/s] (plant state at the samples), ``nu`` [V] (controller
        output), ``tau`` [N] (``gtau (nu_{k-1} + d_{k-1})``: the force applied over
        ``[t_k, t_{k+1})``; compared with ``gtau vir_k`` it reproduces the published 5.85 %).

    Examples
    --------
    >>> import numpy as np
    >>> from frictionkit import CoulombViscous
    >>> from frictionkit.identify.emps_dynamic import emps_closed_loop
    >>> qg = np.r_[np.zeros(10), np.full(990, 1e-3)]
    >>> out = emps_closed_loop(qg, M=95.1, friction=CoulombViscous(Fc=20.4, sigma2=203.5))
    >>> bool(abs(out["q"][-1] - 1e-3) < 2e-4)
    True
    """
    import dataclasses

    from .. import _validate as val

    c = dict(EMPS_CONSTANTS, **(constants or {}))
    q0 = val.finite("emps_closed_loop", "q0", q0)
    v0 = val.finite("emps_closed_loop", "v0", v0)
    qg = val.signal("emps_closed_loop qg", qg, min_len=2)
    m = emps_machine(M=M, friction=friction, offset=offset, constants=c)
    inputs = {"qg": qg - q0}
    if v0 != 0.0:
        m.dofs[0] = dataclasses.replace(m.dofs[0], v0=v0)
    if disturbance is not None:
        d = val.signal("emps_closed_loop disturbance", disturbance, min_len=2)
        if d.size != qg.size:
            raise DataError(f"emps_closed_loop: disturbance has {d.size} samples, qg {qg.size}; give one per sample")
        # the same path as the controller output: gain gtau, one-sample delay (no saturation of its own)
        m.actuator("disturbance", m.coord("q"), gain=c["gtau"], delay=1, command="d")
        inputs["d"] = d
    res = simulate_machine(m, dt=c["dt"], inputs=inputs, substeps=substeps)
    if not res.success:
        raise SimulationError(f"emps_closed_loop: {res.message}")
    motor = res.actuator_names.index("motor")
    tau = c["gtau"] * res.u[:, motor]
    if disturbance is not None:
        tau = tau + c["gtau"] * res.u[:, res.actuator_names.index("disturbance")]
    return {"q": res.q[:, 0] + q0, "v": res.v[:, 0].copy(), "nu": res.signal("nu").copy(), "tau": tau}


def _measured(rec: Recording, skip: int = 49):
    xf = lowpass(rec.x, rec.fs, 100.0, order=4)
    v = derivative(xf, rec.dt)
    return v


def _rel(meas, sim) -> float:
    return float(100.0 * np.linalg.norm(meas - sim) / np.linalg.norm(meas))


def emps_stribeck_fit(rec: Recording, *, delta: float = 2.0) -> dict:
    """Per-direction Stribeck map of the EMPS axis by inverse dynamics (nonlinear IDIM), as a dict.

    Kept for :func:`emps_compare`; the first-class fit, with standard errors, intervals,
    identifiability flags and JSON, is ``fit_rigid_body(rec, law="stribeck",
    asymmetric=True)`` (:mod:`frictionkit.identify.rigid_body_stribeck`), which this calls.

    Returns
    -------
    dict
        ``M`` [kg], ``friction`` (Directional of Stribeck), ``params`` (dict),
        ``inverse_error_percent`` (relative force error on the IDIM regressors),
        ``rigid_asym_error_percent`` (asymmetric IDIM-LS on the same regressors),
        ``result`` (the :class:`~frictionkit.identify.IdentificationResult`).

    Examples
    --------
    >>> fit = emps_stribeck_fit(rec)  # doctest: +SKIP
    >>> fit["inverse_error_percent"] < fit["rigid_asym_error_percent"]  # doctest: +SKIP
    True
    """
    res = fit_rigid_body(rec, law="stribeck", asymmetric=True, delta=delta, profile=False)
    if res.model is None:
        raise SimulationError(f"emps_stribeck_fit: no valid model ({'; '.join(res.warnings)})")
    return {"M": float(res.model.M), "friction": res.model.friction, "params": res.params,
            "inverse_error_percent": res.relative_error_percent,
            "rigid_asym_error_percent": float(res.diagnostics["linear"]["relative_error_percent"]),
            "result": res}


def emps_closed_loop_errors(rec: Recording, *, M: float, friction: FrictionLaw, offset: float = 0.0,
                            substeps: int = 40) -> dict[str, float]:
    """Closed-loop simulation errors of one model on an EMPS record.

    Simulates :func:`emps_closed_loop` on ``rec.reference`` and compares, after the first
    49 samples (the benchmark's ``n_border``), the velocity with the one measured from the
    100 Hz Butterworth-filtered position and the applied force ``gtau nu_{k-1}`` with
    ``gtau vir``: ``100 ||meas - sim|| / ||meas||``.

    Returns
    -------
    dict
        ``velocity_error_percent``, ``force_error_percent``.
    """
    if rec.reference is None or rec.command is None:
        raise DataError("emps_closed_loop_errors: the recording needs reference (qg) and command (vir)")
    sl = slice(49, None)
    sim = emps_closed_loop(rec.reference, M=M, friction=friction, offset=offset, substeps=substeps)
    return {"velocity_error_percent": _rel(_measured(rec)[sl], sim["v"][sl]),
            "force_error_percent": _rel(EMPS_CONSTANTS["gtau"] * rec.command[sl], sim["tau"][sl])}


def emps_compare(rec: Recording, *, substeps: int = 40) -> dict:
    """Closed-loop errors of the published models and of the identified Stribeck model.

    ``substeps`` (plant sub-steps per 1 ms sample) defaults to 40, where the errors are
    converged to about 0.001 percentage points (they move by < 0.003 pp from 40 to 80).

    Returns
    -------
    dict
        For ``"published"``, ``"asymmetric"`` (published asymmetric IDIM-LS values)
        and ``"stribeck"``: ``velocity_error_percent`` and ``force_error_percent``
        (:func:`emps_closed_loop_errors`), plus ``inverse_error_percent`` where defined.
    """
    if rec.reference is None or rec.command is None:
        raise DataError("emps_compare: the recording needs reference (qg) and command (vir)")
    a = PUBLISHED_ASYMMETRIC
    models = {
        "published": (PUBLISHED["M"], CoulombViscous(Fc=PUBLISHED["Fc"], sigma2=PUBLISHED["Fv"]),
                      PUBLISHED["offset"]),
        "asymmetric": (a["M"], Directional(positive=CoulombViscous(Fc=a["Fc_pos"], sigma2=a["Fv_pos"]),
                                           negative=CoulombViscous(Fc=a["Fc_neg"], sigma2=a["Fv_neg"])), 0.0),
    }
    st = emps_stribeck_fit(rec)
    models["stribeck"] = (st["M"], st["friction"], 0.0)
    out = {name: emps_closed_loop_errors(rec, M=M, friction=fr, offset=off, substeps=substeps)
           for name, (M, fr, off) in models.items()}
    out["stribeck"]["inverse_error_percent"] = st["inverse_error_percent"]
    out["asymmetric"]["inverse_error_percent"] = st["rigid_asym_error_percent"]
    out["stribeck"]["model"] = st["friction"]
    out["stribeck"]["M"] = st["M"]
    return out
