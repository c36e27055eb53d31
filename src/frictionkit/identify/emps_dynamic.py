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
from ..data.signals import decimate, derivative, lowpass
from ..errors import DataError, SimulationError
from ..machines import simulate_machine
from ..models.static import CoulombViscous, Directional, Stribeck
from ..presets.emps import EMPS_CONSTANTS, PUBLISHED, PUBLISHED_ASYMMETRIC, emps_machine
from .rigid_body import fit_rigid_body, rigid_body_regressors

__all__ = ["emps_closed_loop", "emps_closed_loop_errors", "emps_stribeck_fit", "emps_compare",
           "EMPS_CONSTANTS"]


def emps_closed_loop(qg, *, M: float, friction, offset: float = 0.0, substeps: int = 40,
                     constants: dict | None = None) -> dict[str, np.ndarray]:
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

    Returns
    -------
    dict
        ``q`` [m], ``v`` [m/s] (plant state at the samples), ``nu`` [V] (controller
        output), ``tau`` [N] (``gtau nu_{k-1}``: the force applied over ``[t_k, t_{k+1})``;
        compared with ``gtau vir_k`` it reproduces the published 5.85 %).

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
    c = dict(EMPS_CONSTANTS, **(constants or {}))
    m = emps_machine(M=M, friction=friction, offset=offset, constants=c)
    res = simulate_machine(m, dt=c["dt"], inputs={"qg": qg}, substeps=substeps)
    if not res.success:
        raise SimulationError(f"emps_closed_loop: {res.message}")
    motor = res.actuator_names.index("motor")
    return {"q": res.q[:, 0].copy(), "v": res.v[:, 0].copy(), "nu": res.signal("nu").copy(),
            "tau": c["gtau"] * res.u[:, motor]}


def _measured(rec: Recording, skip: int = 49):
    xf = lowpass(rec.x, rec.fs, 100.0, order=4)
    v = derivative(xf, rec.dt)
    return v


def _rel(meas, sim) -> float:
    return float(100.0 * np.linalg.norm(meas - sim) / np.linalg.norm(meas))


def emps_stribeck_fit(rec: Recording, *, delta: float = 2.0) -> dict:
    """Per-direction Stribeck map of the EMPS axis by inverse dynamics (nonlinear IDIM).

    The signals of the published IDIM-LS procedure (filtered, differentiated;
    :func:`~frictionkit.identify.rigid_body_regressors`) feed a nonlinear
    least-squares fit, the model being evaluated at 1 kHz and decimated by 10 like
    the IDIM-LS columns, of ``tau = M a + s_dir(v) + sigma2_dir v`` with
    ``s(v) = sgn(v) [Fc + (Fs - Fc) exp(-(|v|/vs)^delta)]`` per direction
    (parameters ``M, Fc+, Fs+, vs+, sigma2+, Fc-, Fs-, vs-, sigma2-``), started from
    the asymmetric IDIM-LS estimates. With ``Fs = Fc`` the map is the asymmetric
    Coulomb–viscous model, so the inverse error cannot be worse than IDIM-LS's.

    Returns
    -------
    dict
        ``M`` [kg], ``friction`` (Directional of Stribeck), ``params`` (dict),
        ``inverse_error_percent`` (relative force error on the IDIM regressors),
        ``rigid_asym_error_percent`` (asymmetric IDIM-LS on the same regressors).

    Examples
    --------
    >>> fit = emps_stribeck_fit(rec)  # doctest: +SKIP
    >>> fit["inverse_error_percent"] < fit["rigid_asym_error_percent"]  # doctest: +SKIP
    True
    """
    from scipy.optimize import least_squares

    asym = fit_rigid_body(rec, asymmetric=True)
    reg = rigid_body_regressors(rec, asymmetric=True)
    y = reg["y"]
    full = rigid_body_regressors(rec, asymmetric=True, q=1)  # 1 kHz: the friction is nonlinear in v,
    a = full["X"][:, 0]                                         # so it is decimated after evaluation,
    v = full["X"][:, 1] + full["X"][:, 3]                       # as IDIM-LS decimates its columns
    pos = v >= 0

    def unpack(p):
        M, Fcp, Fsp, lvp, s2p, Fcn, Fsn, lvn, s2n = p
        return M, (Fcp, Fsp, np.exp(lvp), s2p), (Fcn, Fsn, np.exp(lvn), s2n)

    def pred(p):
        M, P, N = unpack(p)
        out = M * a
        for sel, (Fc, Fs, vs, s2) in ((pos, P), (~pos, N)):
            vv = v[sel]
            out[sel] += np.sign(vv) * (Fc + (Fs - Fc) * np.exp(-(np.abs(vv) / vs) ** delta)) + s2 * vv
        return decimate(out, 10)

    def jac(p):
        M, P, N = unpack(p)
        cols = [a]
        for sel, (Fc, Fs, vs, s2) in ((pos, P), (~pos, N)):
            r = np.abs(v) / vs
            phi = np.exp(-(r**delta))
            sg = np.sign(v) * sel
            cols += [sg * (1 - phi), sg * phi, sg * (Fs - Fc) * phi * delta * r**delta, v * sel]
        return np.column_stack([decimate(c, 10) for c in cols])

    p0 = np.array([asym["M"], asym["Fc_pos"], 1.1 * asym["Fc_pos"], np.log(0.01), asym["Fv_pos"],
                   asym["Fc_neg"], 1.1 * asym["Fc_neg"], np.log(0.01), asym["Fv_neg"]])
    sol = least_squares(lambda p: pred(p) - y, p0, jac=jac, method="trf", x_scale="jac")
    M, P, N = unpack(sol.x)
    law = Directional(positive=Stribeck(Fc=P[0], Fs=P[1], vs=P[2], delta=delta, sigma2=P[3]),
                      negative=Stribeck(Fc=N[0], Fs=N[1], vs=N[2], delta=delta, sigma2=N[3]))
    names = ("M", "Fc_pos", "Fs_pos", "vs_pos", "sigma2_pos", "Fc_neg", "Fs_neg", "vs_neg", "sigma2_neg")
    vals = (M, *P, *N)
    return {"M": float(M), "friction": law, "params": dict(zip(names, map(float, vals))),
            "inverse_error_percent": _rel(y, pred(sol.x)),
            "rigid_asym_error_percent": asym.relative_error_percent}


def emps_closed_loop_errors(rec: Recording, *, M: float, friction, offset: float = 0.0,
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
