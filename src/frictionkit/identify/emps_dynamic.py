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
delay) and is integrated with RK4 sub-steps.
"""

from __future__ import annotations

import numpy as np

from .._jit import njit
from ..data.recording import Recording
from ..data.signals import decimate, derivative, lowpass
from ..errors import DataError
from ..models.static import CoulombViscous, Directional, Stribeck
from .rigid_body import fit_rigid_body, rigid_body_regressors

__all__ = ["emps_closed_loop", "emps_stribeck_fit", "emps_compare", "EMPS_CONSTANTS"]

#: Constants of ``DATA_EMPS.mat`` (README): drive gain [N/V], position gain [1/s],
#: velocity gain [V/(m/s)], saturation [V], sample time [s].
EMPS_CONSTANTS = {"gtau": 35.15065188248547, "kp": 160.18, "kv": 243.45, "vmax": 10.0, "dt": 1e-3}


@njit(inline="always")
def _fric(v, rows, offset):
    r = 0 if v >= 0.0 else 1
    Fc, Fs, vs, delta, sigma2, shape = rows[r, 0], rows[r, 1], rows[r, 2], rows[r, 3], rows[r, 4], rows[r, 5]
    av = abs(v)
    u = av / vs
    if shape == 0.0:
        phi = np.exp(-(u ** delta))
    else:
        phi = 1.0 / (1.0 + u * u)
    sg = 1.0 if v > 0.0 else (-1.0 if v < 0.0 else 0.0)
    return sg * (Fc + (Fs - Fc) * phi) + sigma2 * v + offset


@njit
def _closed_loop(qg, dt, M, rows, offset, kp, kv, gtau, vmax, nsub, q_out, v_out, nu_out):
    h = dt / nsub
    q = 0.0
    v = 0.0
    qm_prev = 0.0
    qf_prev = 0.0
    nu_prev = 0.0
    for k in range(qg.size):
        qm = q
        qf = 0.5 * (qm + qm_prev)
        vf = (qf - qf_prev) / dt
        nu = kv * (kp * (qg[k] - qm) - vf)
        if nu > vmax:
            nu = vmax
        elif nu < -vmax:
            nu = -vmax
        q_out[k] = q
        v_out[k] = v
        nu_out[k] = nu
        tau = gtau * nu_prev  # one-sample delay
        for _ in range(nsub):
            k1q = v
            k1v = (tau - _fric(v, rows, offset)) / M
            v2 = v + 0.5 * h * k1v
            k2v = (tau - _fric(v2, rows, offset)) / M
            v3 = v + 0.5 * h * k2v
            k3v = (tau - _fric(v3, rows, offset)) / M
            v4 = v + h * k3v
            k4v = (tau - _fric(v4, rows, offset)) / M
            q += h / 6.0 * (k1q + 2.0 * v2 + 2.0 * v3 + v4)
            v += h / 6.0 * (k1v + 2.0 * k2v + 2.0 * k3v + k4v)
        qm_prev = qm
        qf_prev = qf
        nu_prev = nu
    return 0


def emps_closed_loop(qg, *, M: float, friction, offset: float = 0.0, substeps: int = 10,
                     constants: dict | None = None) -> dict[str, np.ndarray]:
    """Simulate the EMPS position loop with a rigid load and a static friction map.

    Parameters
    ----------
    qg : array_like
        Reference position [m] at 1 kHz.
    M : float
        Moving mass [kg].
    friction : CoulombViscous | Stribeck | Directional
        Static friction map ``F(v)`` (its ``steady_state``) [N].
    offset : float
        Constant force [N] added to the friction (published model: −3.1648 N).
    substeps : int
        RK4 sub-steps per 1 ms sample (10: 0.1 ms, as ``Simulation_EMPS.m``'s max step).
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
    qg = np.ascontiguousarray(qg, dtype=float)
    rows = np.ascontiguousarray(friction.static_rows(), dtype=float)
    n = qg.size
    q, v, nu = np.empty(n), np.empty(n), np.empty(n)
    _closed_loop(qg, c["dt"], float(M), rows, float(offset), c["kp"], c["kv"], c["gtau"], c["vmax"],
                 int(substeps), q, v, nu)
    tau = np.r_[0.0, c["gtau"] * nu[:-1]]  # the force the plant receives (after the unit delay)
    return {"q": q, "v": v, "nu": nu, "tau": tau}


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


def emps_compare(rec: Recording, *, substeps: int = 10) -> dict:
    """Closed-loop errors of the published model and of the identified Stribeck model.

    Returns
    -------
    dict
        For ``"published"``, ``"asymmetric"`` (published asymmetric IDIM-LS values)
        and ``"stribeck"``: ``velocity_error_percent`` and ``force_error_percent``
        (``100 ||meas - sim|| / ||meas||`` after the first 49 samples; measured
        velocity from the 100 Hz Butterworth-filtered position, force ``gtau vir``),
        plus ``inverse_error_percent`` where defined.
    """
    if rec.reference is None or rec.command is None:
        raise DataError("emps_compare: the recording needs reference (qg) and command (vir)")
    g = EMPS_CONSTANTS["gtau"]
    sl = slice(49, None)
    v_meas = _measured(rec)[sl]
    tau_meas = g * rec.command[sl]
    out = {}
    models = {
        "published": (95.1089, CoulombViscous(Fc=20.3935, sigma2=203.5034), -3.1648),
        "asymmetric": (95.1540, Directional(positive=CoulombViscous(Fc=20.1440, sigma2=166.7061),
                                            negative=CoulombViscous(Fc=20.6277, sigma2=240.4236)), 0.0),
    }
    st = emps_stribeck_fit(rec)
    models["stribeck"] = (st["M"], st["friction"], 0.0)
    for name, (M, fr, off) in models.items():
        sim = emps_closed_loop(rec.reference, M=M, friction=fr, offset=off, substeps=substeps)
        out[name] = {"velocity_error_percent": _rel(v_meas, sim["v"][sl]),
                     "force_error_percent": _rel(tau_meas, sim["tau"][sl])}
    out["stribeck"]["inverse_error_percent"] = st["inverse_error_percent"]
    out["asymmetric"]["inverse_error_percent"] = st["rigid_asym_error_percent"]
    out["stribeck"]["model"] = st["friction"]
    out["stribeck"]["M"] = st["M"]
    return out
