"""Exact Jacobians of the output-error fits from forward sensitivities (issue 11 part 6).

One augmented run of :mod:`frictionkit.kernels.sensitivity` gives the simulated signal and its
derivative with respect to every fitted parameter — the cost of about two plain simulations
instead of ``p`` (forward differences). Used by :mod:`.output_error` (force-driven, velocity or
position compared) and :mod:`.motion_error` (motion-driven, force compared) for the LuGre
family (LuGre, Dahl, a ``Directional`` of them); other laws (GMS) keep the finite differences.

How a fitted parameter reaches the kernel: the kernels read packed rows
(``frictionkit.models.pack``). The derivative of those rows with respect to each parameter is
taken by differencing the packing itself (:func:`row_coefficients`): the rows are linear in the
law's fields (a field is copied into one or both rows; Dahl's ``Fc`` into ``Fc`` and ``Fs``), so the
difference quotient is exact up to round-off and is rounded to the nearest integer when within
``1e-6`` of one. A law registered later whose packing is not linear still gets a (first-order)
coefficient.
"""

from __future__ import annotations

from collections.abc import Callable

import numpy as np

from ..errors import ParameterError
from ..kernels import sensitivity as _ks
from ..models.pack import kind_of, pack_lugre
from ..simulation.core import SimOptions, _atol_v, _f_scale


def supports(model) -> bool:
    """True when the law has sensitivity kernels (the LuGre family)."""
    try:
        return kind_of(model) == "lugre"
    except ParameterError:
        return False


def _packed(build: Callable, theta: np.ndarray):
    model, m, off = build(theta)
    pk = pack_lugre(model)
    return pk.static, pk.dyn, float(m), float(off)


def row_coefficients(build: Callable, theta: np.ndarray, cache: dict | None = None):
    """Packed rows at ``theta`` and their derivatives.

    ``build(theta) -> (law, mass, offset)``. Returns ``(static, dyn, m, off, coef, dm, doff)``
    with ``coef[j, row] = d[sigma0, sigma1, Fc, Fs, vs, delta, sigma2]_row / d theta_j``.
    ``cache`` (a dict kept by the caller for one problem): coefficients that all came out as
    integers (a linear packing, every law today) are kept there and not differenced again.
    """
    theta = np.asarray(theta, float)
    static, dyn, m, off = _packed(build, theta)
    if cache is not None and "coef" in cache:
        return (static, dyn, m, off, *cache["coef"])
    p = theta.size
    coef = np.zeros((p, 2, _ks.N_COEF))
    dm = np.zeros(p)
    doff = np.zeros(p)
    base = np.concatenate([dyn[:, :2], static[:, :5]], axis=1)
    for j in range(p):
        h = 1e-6 * abs(theta[j]) if theta[j] != 0.0 else 1e-6
        for sgn in (1.0, -1.0):
            q = theta.copy()
            q[j] += sgn * h
            try:
                st, dy, mj, oj = _packed(build, q)
            except ParameterError:
                continue
            step = q[j] - theta[j]
            break
        else:
            raise ParameterError(f"cannot perturb parameter {j} = {theta[j]!r} for its sensitivity")
        d = (np.concatenate([dy[:, :2], st[:, :5]], axis=1) - base) / step
        d = np.array([d[:, 0], d[:, 1], d[:, 2], d[:, 3], d[:, 4], d[:, 5], d[:, 6]]).T
        coef[j] = _snap(d)
        dm[j] = _snap(np.array([(mj - m) / step]))[0]
        doff[j] = _snap(np.array([(oj - off) / step]))[0]
    if cache is not None and all(np.array_equal(a, np.round(a)) for a in (coef, dm, doff)):
        cache["coef"] = (coef, dm, doff)
    return static, dyn, m, off, coef, dm, doff


def _snap(d: np.ndarray) -> np.ndarray:
    r = np.round(d)
    return np.where(np.abs(d - r) <= 1e-6 * np.maximum(1.0, np.abs(r)), r, d)


def force_driven(build: Callable, theta: np.ndarray, u: np.ndarray, dt: float, options: SimOptions,
                 segments, compare: str = "v", cache: dict | None = None):
    """Simulated ``x`` or ``v`` and ``d(.)/d theta`` (``N x p``) of the force-driven mass, each segment from rest.

    Returns ``(y, S, status)``; ``status`` is 0 when every segment integrated.
    """
    static, dyn, m, off, coef, dm, doff = row_coefficients(build, theta, cache)
    F_scale = _f_scale(static)
    sigma0 = float(dyn[:, 0].max())
    atol_v = _atol_v(options, F_scale, sigma0, m, float((dyn[:, 1] + static[:, 4]).max()))
    atol_z = options.atol_F * F_scale / sigma0
    N, p = u.size, theta.size
    x, v = np.empty(N), np.empty(N)
    Sx, Sv = np.empty((N, p)), np.empty((N, p))
    status = 0
    for a, b in segments:
        st, _ = _ks.lugre_force_sens(np.ascontiguousarray(u[a:b]), dt, m, off, static, dyn, coef, dm, doff,
                                     options.rtol, atol_v, atol_z, int(options.max_substeps),
                                     x[a:b], v[a:b], Sx[a:b], Sv[a:b])
        status = status or int(st)
    return (x, Sx, status) if compare == "x" else (v, Sv, status)


def motion_driven(build: Callable, theta: np.ndarray, x: np.ndarray, dt: float, cache: dict | None = None):
    """Force of the motion-driven law from ``z = 0`` and ``dF/d theta`` (``N x p``): ``(F, S, status)``."""
    static, dyn, _, _, coef, _, _ = row_coefficients(build, theta, cache)
    x = np.ascontiguousarray(x, dtype=float)
    F = np.empty(x.size)
    S = np.empty((x.size, theta.size))
    st = _ks.lugre_motion_sens(x, float(dt), static, dyn, coef, F, S)
    return F, S, int(st)
