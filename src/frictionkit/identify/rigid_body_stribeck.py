"""Rigid body with a Stribeck map, per direction if asked, by inverse dynamics (nonlinear IDIM).

The signals are those of the IDIM-LS procedure (:func:`~frictionkit.identify.rigid_body_regressors`:
position low-passed, central differences, first samples dropped); the model

    F = M a + s(v) + sigma2 v (+ offset),    s(v) = sgn(v) [Fc + (Fs - Fc) phi(|v| / vs)]

is evaluated at the full sampling rate and **decimated like the IDIM-LS columns** (the
friction is nonlinear in ``v``, so it is decimated after evaluation, as IDIM-LS decimates
each column), then fitted to the decimated force by nonlinear least squares (scipy
``least_squares``, analytic Jacobian). ``phi = exp(-r^delta)`` (``"stribeck"``, seed 002
eq. 9b for ``delta = 2``) or ``1 / (1 + r^2)`` (``"lorentzian"``, eq. 9a).

With ``asymmetric`` each direction has its own ``Fc, Fs, vs, sigma2`` and there is no
offset: a constant force adds to ``Fc_pos`` and subtracts from ``Fc_neg``, so it cannot
be told apart from them (the published asymmetric model, EMPS description eq. 12, drops
it for the same reason). With ``Fs = Fc`` the map is the Coulomb–viscous model, so the
inverse error cannot exceed IDIM-LS's on the same regressors.

Named assumptions (the EMPS description gives no Stribeck model):

* :data:`DELTA_DEFAULT` — the exponent is fixed, not fitted: 2 (seed 002 eq. 9b). On the
  EMPS record a free exponent trades off against ``vs`` (flat valley); fix it and say so.
* :data:`VS_START_FRACTIONS` — ``vs`` is started at these fractions of the 95th percentile
  of ``|v|`` and the lowest cost is kept: the Stribeck valley is not convex in ``vs``, and
  the record's speed range is the only scale the data give.

Standard errors come from the Jacobian at the optimum (``s^2 (J^T J)^-1``); ``vs`` (which
must be positive) gets its interval on the log scale or, by default, from its likelihood
profile (:mod:`.identifiability`), never across zero; a parameter whose interval spans more
than a decade, or whose correlation with another exceeds 0.99, is flagged with the reason.
"""

from __future__ import annotations

import math

import numpy as np
from scipy import signal as _sig

from ..data.recording import Recording
from ..data.signals import decimate
from ..errors import IdentificationError, ParameterError
from ..models.static import Directional, Stribeck
from ..plants.rigid_body import RigidBody
from .identifiability import analyse

__all__ = ["DELTA_DEFAULT", "RIGID_BODY_LAWS", "VS_START_FRACTIONS", "fit_rigid_body_stribeck"]

#: Static laws of :func:`~frictionkit.identify.fit_rigid_body`: ``coulomb_viscous`` (linear,
#: IDIM-LS), ``stribeck`` (exponential shape) and ``lorentzian`` (nonlinear, this module).
RIGID_BODY_LAWS = ("coulomb_viscous", "stribeck", "lorentzian")

#: Stribeck exponent used when none is given (assumption, see the module docstring).
DELTA_DEFAULT = 2.0

#: Start values of ``vs`` as fractions of the 95th percentile of ``|v|`` (assumption).
VS_START_FRACTIONS = (0.03, 0.1, 0.3)

#: Trust-region solver of ``least_squares``: ``"lsmr"`` needs only products with the
#: Jacobian; the default ``"exact"`` factors the tall Jacobian (SVD) each iteration, which
#: multi-threaded OpenBLAS makes 100x slower on a loaded 2-core machine (measured: 90 ms
#: against 0.9 ms for a 2,480 x 9 SVD).
TR_SOLVER = "lsmr"

#: Bound on ``|log vs|`` inside the residuals (``exp`` of it stays a finite, normal float).
LOG_VS_CLIP = 700.0

#: Start value of ``Fs`` relative to the IDIM-LS Coulomb level (a 10 % Stribeck peak).
FS_START_RATIO = 1.1


def _phi(r: np.ndarray, shape: str, delta: float) -> tuple[np.ndarray, np.ndarray]:
    """``phi(r)`` and ``d phi / d log vs`` (``r = |v| / vs``)."""
    if shape == "lorentzian":
        phi = 1.0 / (1.0 + r**2)
        return phi, 2.0 * r**2 * phi**2
    with np.errstate(over="ignore"):  # r**delta = inf far above vs: phi = 0 and its derivative 0, not nan
        rd = r**delta
    phi = np.exp(-rd)
    return phi, np.where(phi > 0.0, phi * delta * np.where(np.isfinite(rd), rd, 0.0), 0.0)


class _Problem:
    """Residuals and Jacobian of the decimated inverse-dynamics model, several records stacked."""

    def __init__(self, parts, *, asymmetric: bool, shape: str, delta: float, q: int):
        self.parts = parts  # [(a, v, y_decimated)] per record, a and v at the full rate
        self.asym, self.shape, self.delta, self.q = asymmetric, shape, delta, q
        self.y = np.concatenate([y for _, _, y in parts])
        self.sides = (("pos", True), ("neg", False)) if asymmetric else (("", None),)
        self.n_par = 1 + 4 * len(self.sides) + (0 if asymmetric else 1)

    def _dec(self, c: np.ndarray) -> np.ndarray:
        return decimate(c, self.q) if self.q > 1 else c

    def columns(self, p: np.ndarray, a: np.ndarray, v: np.ndarray) -> tuple[np.ndarray, list[np.ndarray]]:
        """Full-rate prediction and its derivative columns for one record."""
        out = p[0] * a
        cols = [a]
        s = np.sign(v)
        for i, (_, positive) in enumerate(self.sides):
            Fc, Fs, lvs, s2 = p[1 + 4 * i: 5 + 4 * i]
            sel = np.ones_like(v) if positive is None else ((v >= 0) if positive else (v < 0)).astype(float)
            # the solver may try any log vs: exp of it clipped to the float range (a step to
            # log vs > 709 raised OverflowError from --delta 100)
            phi, dphi = _phi(np.abs(v) / math.exp(min(max(lvs, -LOG_VS_CLIP), LOG_VS_CLIP)), self.shape, self.delta)
            sg = s * sel
            out = out + sg * (Fc + (Fs - Fc) * phi) + s2 * v * sel
            cols += [sg * (1.0 - phi), sg * phi, sg * (Fs - Fc) * dphi, v * sel]
        if not self.asym:
            out = out + p[-1]
            cols.append(np.ones_like(v))
        return out, cols

    def residual(self, p: np.ndarray) -> np.ndarray:
        return np.concatenate([self._dec(self.columns(p, a, v)[0]) for a, v, _ in self.parts]) - self.y

    def jacobian(self, p: np.ndarray) -> np.ndarray:
        blocks = []
        for a, v, _ in self.parts:
            cols = np.column_stack(self.columns(p, a, v)[1])
            # one zero-phase decimation of all columns (the filter of data.signals.decimate)
            blocks.append(_sig.decimate(cols, self.q, ftype="iir", zero_phase=True, axis=0) if self.q > 1 else cols)
        return np.vstack(blocks)


def _names(asymmetric: bool) -> tuple[str, ...]:
    if asymmetric:
        return ("M",) + tuple(f"{n}_{d}" for d in ("pos", "neg") for n in ("Fc", "Fs", "vs", "sigma2"))
    return ("M", "Fc", "Fs", "vs", "sigma2", "offset")


def _bounds(prob: _Problem) -> tuple[np.ndarray, np.ndarray]:
    lo = [1e-300] + [0.0, 0.0, -np.inf, 0.0] * len(prob.sides) + ([] if prob.asym else [-np.inf])
    return np.array(lo), np.full(prob.n_par, np.inf)


def fit_rigid_body_stribeck(
    recordings: list[Recording],
    regs_full: list[dict],
    linear,
    *,
    asymmetric: bool,
    shape: str = "stribeck",
    delta: float = DELTA_DEFAULT,
    q: int = 10,
    profile: bool = True,
) -> dict:
    """The nonlinear fit; :func:`~frictionkit.identify.fit_rigid_body` wraps it in a result.

    Parameters
    ----------
    recordings : list of Recording
        The records (for names and messages).
    regs_full : list of dict
        Their IDIM-LS regressors at the full rate (``rigid_body_regressors(..., q=1)``).
    linear : IdentificationResult
        The Coulomb–viscous IDIM-LS fit of the same structure (start values).
    asymmetric, shape, delta, q, profile
        See :func:`~frictionkit.identify.fit_rigid_body`.

    Returns
    -------
    dict
        ``names``, ``values``, ``ident`` (:class:`~frictionkit.identify.identifiability.Identifiability`),
        ``residual``, ``y``, ``y_pred``, ``model``, ``success``, ``message``, ``nfev``, ``starts``,
        ``condition_number``.
    """
    from scipy.optimize import least_squares

    if shape not in ("stribeck", "lorentzian"):
        raise ParameterError(f"fit_rigid_body.law = {shape!r}: must be one of {list(RIGID_BODY_LAWS)}")
    parts = []
    for g in regs_full:
        X, y = g["X"], g["y"]
        a = X[:, 0]
        v = X[:, 1] if not asymmetric else X[:, 1] + X[:, 3]
        parts.append((a, v, decimate(y, q) if q > 1 else y))
    prob = _Problem(parts, asymmetric=asymmetric, shape=shape, delta=delta, q=q)
    v_all = np.concatenate([v for _, v, _ in parts])
    v95 = float(np.percentile(np.abs(v_all), 95))
    if not v95 > 0:
        raise IdentificationError(f"recording '{recordings[0].name}': no motion (95th percentile of |v| is 0); "
                                  "a Stribeck map needs the axis to move")
    lin = linear.params
    if asymmetric:
        sides = [(abs(lin["Fc_pos"]), max(lin["Fv_pos"], 0.0)), (abs(lin["Fc_neg"]), max(lin["Fv_neg"], 0.0))]
    else:
        sides = [(abs(lin["Fc"]), max(lin["Fv"], 0.0))]
    lo, hi = _bounds(prob)
    best, tried = None, []
    for frac in VS_START_FRACTIONS:
        p0 = [max(lin["M"], 1e-12)]
        for Fc, Fv in sides:
            p0 += [Fc, FS_START_RATIO * Fc, math.log(frac * v95), Fv]
        if not asymmetric:
            p0.append(lin["offset"])
        p0 = np.array(p0, dtype=float)
        fin = np.isfinite(lo)
        p0[fin] = np.maximum(p0[fin], lo[fin] + 1e-6 * np.maximum(np.abs(p0[fin]), 1e-3))  # strictly inside
        sol = least_squares(prob.residual, p0, jac=prob.jacobian, bounds=(lo, hi), method="trf", x_scale="jac",
                            tr_solver=TR_SOLVER)
        tried.append({"vs_start": frac * v95, "cost": float(sol.cost), "status": int(sol.status)})
        if best is None or sol.cost < best.cost:
            best = sol
    p = best.x
    r = prob.residual(p)
    J = prob.jacobian(p)
    names = _names(asymmetric)
    vs_idx = [i for i, n in enumerate(names) if n.startswith("vs")]
    values = p.copy()
    values[vs_idx] = np.exp(p[vs_idx])
    n_obs = r.size
    dof = n_obs - p.size

    def prof(j: int, value: float) -> float:
        """SSE with parameter j held at ``value`` (only ``vs`` is profiled: the log-scale ones)."""
        keep = [i for i in range(p.size) if i != j]
        fixed = math.log(value)

        def full(z):
            x = np.empty(p.size)
            x[keep] = z
            x[j] = fixed
            return x

        try:
            s = least_squares(lambda z: prob.residual(full(z)), p[keep], jac=lambda z: prob.jacobian(full(z))[:, keep],
                              bounds=(lo[keep], hi[keep]), method="trf", x_scale="jac",
                              tr_solver=TR_SOLVER)
        except (ValueError, FloatingPointError):
            return math.inf
        return float(2.0 * s.cost)

    ident = analyse(names, values, J, r, dof, log_scale=[n.startswith("vs") for n in names],
                    profile=prof if profile else None)
    try:
        if asymmetric:
            law = Directional(
                positive=Stribeck(Fc=values[1], Fs=values[2], vs=values[3], delta=delta, sigma2=values[4], shape=_SHAPE[shape]),
                negative=Stribeck(Fc=values[5], Fs=values[6], vs=values[7], delta=delta, sigma2=values[8], shape=_SHAPE[shape]))
            model = RigidBody(M=values[0], friction=law, offset=0.0)
        else:
            law = Stribeck(Fc=values[1], Fs=values[2], vs=values[3], delta=delta, sigma2=values[4], shape=_SHAPE[shape])
            model = RigidBody(M=values[0], friction=law, offset=values[5])
        bad = None
    except ParameterError as exc:
        model, bad = None, str(exc)
    at_bound = [names[i] for i in range(p.size) if np.isfinite(lo[i]) and p[i] <= lo[i] + 1e-12 * max(1.0, abs(p[i]))]
    return {"names": names, "values": values, "ident": ident, "residual": r, "y": prob.y, "y_pred": prob.y + r,
            "model": model, "invalid": bad, "success": bool(best.success), "message": str(best.message),
            "nfev": int(best.nfev), "starts": tried, "at_bound": at_bound, "dof": dof,
            "condition_number": float(np.linalg.cond(J / np.maximum(np.linalg.norm(J, axis=0), 1e-300))),
            "v95": v95}


_SHAPE = {"stribeck": "exponential", "lorentzian": "lorentzian"}
