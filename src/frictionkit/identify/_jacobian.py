"""Exact Jacobians of the output-error fits from forward sensitivities (issue 11 part 6).

One augmented run of :mod:`frictionkit.kernels.sensitivity` gives the simulated signal and its
derivative with respect to every fitted parameter — the cost of ~2.6 plain simulations for six
parameters (force-driven, 25,000 samples; ~1.2 for one) instead of ``p`` (forward differences).
The force-driven fit hands ``least_squares`` the ``(p + 1)``-row reduced problem
(:class:`ReducedProblem`, :func:`reduce_lsq`). Used by :mod:`.output_error` (force-driven, velocity or
position compared) and :mod:`.motion_error` (motion-driven, force compared) for the LuGre
family (LuGre, Dahl, a ``Directional`` of them), and GMS in the motion drive
(:func:`gms_motion_driven`, :mod:`frictionkit.kernels.sensitivity_gms`, its static fields too;
``benchmarks/identify.py``, 50,001 samples, k1..k3 and C free: 0.26 s CPU vs 0.42 s with
differences, final cost 25.7951 vs 25.8010). GMS in the force drive keeps the finite differences
by default; ``jacobian="sensitivity"`` takes :func:`gms_force_driven` (sensitivities along the
simulated trajectory, not of the kernel's discrete map: measured within 1e-4 ... 5e-3 of central
differences; over 48 paired fits from random starts they ended lower in 14, differences in 13,
equal in 21, the fits mostly dearer in CPU: a sweep costs ~25 plain runs — README, ``benchmarks/identify.py``).

How a fitted parameter reaches the kernel: the kernels read packed rows
(``frictionkit.models.pack``). The derivative of those rows with respect to each parameter is
taken by differencing the packing itself (:func:`row_coefficients`): the rows are linear in the
law's fields (a field is copied into one or both rows; Dahl's ``Fc`` into ``Fc`` and ``Fs``), so the
difference quotient is exact up to round-off and is rounded to the nearest integer when within
``1e-6`` of one. A law registered later whose packing is not linear still gets a (first-order)
coefficient.
"""

from __future__ import annotations

import math
import warnings
from collections.abc import Callable

import numpy as np

from ..errors import ParameterError
from ..kernels import sensitivity as _ks
from ..models.pack import kind_of, pack_lugre
from ..simulation.core import FAST_LIMIT, SimOptions, _atol_v, _f_scale, _v_floor

#: :func:`force_driven`'s status when the contact is faster than the samples (not run; see there).
UNRESOLVED = -1


def supports(model) -> bool:
    """True when the law has sensitivity kernels (the LuGre family)."""
    try:
        return kind_of(model) == "lugre"
    except ParameterError:
        return False


def supports_motion(model) -> bool:
    """True when the motion-driven reduced problem has a sensitivity kernel for the law (LuGre family, GMS)."""
    try:
        return kind_of(model) in ("lugre", "gms")
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


def force_driven(build: Callable, theta: np.ndarray, u: np.ndarray, dt, options: SimOptions,
                 segments, compare: str = "v", cache: dict | None = None, spare: int = 0, work: dict | None = None,
                 S_out: np.ndarray | None = None):
    """Simulated ``x`` or ``v`` and ``d(.)/d theta`` (``N x p``) of the force-driven mass, each segment from rest.

    ``dt``: the sample period, or one per segment.

    The state is integrated with the steps of :func:`frictionkit.simulate` (same tolerances), the
    sensitivities ride on them (:func:`frictionkit.kernels.sensitivity.lugre_force_sens`).
    ``spare`` extra columns (left unset) are appended to ``S`` for the caller. ``work`` (a dict
    the caller keeps) holds the state buffers from call to call, and ``S_out`` (``N x (p + spare)``)
    receives ``S`` (for the velocity): an optimiser's evaluations then touch no fresh memory
    (fresh pages cost ~0.3 ms per 25,000-sample run). The returned ``y`` is then a buffer
    the next call overwrites.
    Returns ``(y, S, status)``; ``status`` is 0 when every segment integrated, :data:`UNRESOLVED`
    (nothing run) when the contact is faster than a segment's samples (below).

    A contact ringing or relaxing faster than the samples — ``max(sqrt(sigma0/m), c/m) dt`` above
    :data:`frictionkit.simulation.core.FAST_LIMIT`, ``c = sigma1 + sigma2`` — is not run here: there
    :func:`frictionkit.simulate` may repeat the run at tighter tolerances and flag it (its accuracy
    check, issue 13), which this kernel does not, so the exact fit would minimise another cost than the
    difference fit; and the sensitivities riding on the state's steps there can grow without bound
    while the state stays bounded (measured: a Dahl, sigma0 = 7.4e7 N/m on 1 kg, sigma2 = 1.32, at
    dt = 5e-4, omega dt = 4.3, damping ratio 7.6e-5: the columns grew 1.8x per sample in pre-sliding
    to 1e79 over 1,000 samples, the velocity within 2e-7 m/s; the fit from a poor start stepped there
    and stopped at sigma0 = 7.4e7). The caller then uses plain simulations (differences).
    """
    if cache is not None and cache.get("kind") is None:
        cache["kind"] = kind_of(build(np.asarray(theta, float))[0])
    if (cache["kind"] if cache is not None else kind_of(build(np.asarray(theta, float))[0])) == "gms":
        return gms_force_driven(build, theta, u, dt, options, segments, compare, cache, spare=spare, S_out=S_out)
    static, dyn, m, off, coef, dm, doff = row_coefficients(build, theta, cache)
    F_scale = _f_scale(static)
    sigma0 = float(dyn[:, 0].max())
    atol_v = _atol_v(options, F_scale, sigma0, m, float((dyn[:, 1] + static[:, 4]).max()))
    atol_z = options.atol_F * F_scale / sigma0
    N, p = u.size, theta.size
    want_x = compare == "x"
    work = {} if work is None else work
    if work.get("N") != N:
        work.update(N=N, x=np.empty(N), v=np.empty(N), z=np.empty(N), off=None)
    x, v, z = work["x"], work["v"], work["z"]
    Sv = np.empty((N, p + spare)) if S_out is None or want_x else S_out
    Sx = (np.empty((N, p + spare)) if S_out is None else S_out) if want_x else np.empty((1, p))
    if work["off"] != off:  # simulate is given u - offset
        work.update(off=off, ue=np.ascontiguousarray(u - off, dtype=float))
    ue = work["ue"]
    status = 0
    dts = [float(dt)] * len(segments) if np.ndim(dt) == 0 else [float(h) for h in dt]
    c_max = float((dyn[:, 1] + static[:, 4]).max())
    if max(math.sqrt(sigma0 / m), c_max / m) * max(dts) > FAST_LIMIT:
        return (x, Sx, UNRESOLVED) if want_x else (v, Sv, UNRESOLVED)
    for (a, b), h in zip(segments, dts):
        st, _, _ = _ks.lugre_force_sens(ue[a:b], h, m, static, dyn, coef, dm, doff, options.rtol, atol_v, atol_z,
                                        int(options.max_substeps), _v_floor(options), want_x,
                                        x[a:b], v[a:b], z[a:b], Sx[a:b] if want_x else Sx, Sv[a:b])
        status = status or int(st)
    return (x, Sx, status) if want_x else (v, Sv, status)


def motion_driven(build: Callable, theta: np.ndarray, x: np.ndarray, dt: float, cache: dict | None = None):
    """Force of the motion-driven law from ``z = 0`` and ``dF/d theta`` (``N x p``): ``(F, S, status)``."""
    static, dyn, _, _, coef, _, _ = row_coefficients(build, theta, cache)
    x = np.ascontiguousarray(x, dtype=float)
    F = np.empty(x.size)
    S = np.empty((x.size, theta.size))
    st = _ks.lugre_motion_sens(x, float(dt), static, dyn, coef, F, S)
    return F, S, int(st)


def gms_motion_driven(build: Callable, theta: np.ndarray, x: np.ndarray, dt: float, cache: dict | None = None):
    """Force of the motion-driven GMS from the unloaded state and ``dF/d theta``: ``(F, S, status)``.

    The parameters reach ``k``, ``xi``, ``C`` and the static rows ``[Fc, Fs, vs, delta, sigma2]``
    (coefficients by differencing the packing, as :func:`row_coefficients` does). None when one
    moves the Stribeck shape (not a parameter of any law today). Kernel:
    :func:`frictionkit.kernels.sensitivity_gms.gms_motion_sens`.
    """
    from ..kernels import sensitivity_gms as _kg
    from ..models.pack import pack_gms

    theta = np.asarray(theta, float)
    pk = pack_gms(build(theta)[0])
    if cache is None or "gms" not in cache:
        p = theta.size
        dk = np.zeros((p,) + pk.k.shape)
        dxi = np.zeros((p,) + pk.xi.shape)
        dC = np.zeros((p,) + pk.C.shape)
        dst = np.zeros((p, 2, 5))
        for j in range(p):
            h = 1e-6 * abs(theta[j]) if theta[j] != 0.0 else 1e-6
            q = theta.copy()
            q[j] += h
            try:
                pj = pack_gms(build(q)[0])
            except ParameterError:
                q[j] = theta[j] - h
                pj = pack_gms(build(q)[0])
            step = q[j] - theta[j]
            if not np.array_equal(pj.static[:, 5], pk.static[:, 5]):
                return None
            dk[j], dxi[j], dC[j] = ((pj.k - pk.k) / step, (pj.xi - pk.xi) / step, (pj.C - pk.C) / step)
            dst[j] = (pj.static[:, :5] - pk.static[:, :5]) / step
        coef = tuple(_snap(a.ravel()).reshape(a.shape) for a in (dk, dxi, dC, dst))
        if cache is not None and all(np.array_equal(a, np.round(a)) for a in coef):
            cache["gms"] = coef
    else:
        coef = cache["gms"]
    x = np.ascontiguousarray(x, dtype=float)
    F = np.empty(x.size)
    S = np.empty((x.size, theta.size))
    st = _kg.gms_motion_sens(x, float(dt), pk.static, pk.k, pk.xi, pk.C, *coef, F, S)
    return F, S, int(st)


def _gms_coefficients(build: Callable, theta: np.ndarray, cache: dict | None):
    """``(law, m, off, packed, (dk, dxi, dC, dst), dm, doff)``: the packed GMS rows at ``theta`` and
    their derivatives by differencing the packing (exact for the linear packings; cached when
    integral), or None when a parameter moves the Stribeck shape."""
    from ..models.pack import pack_gms

    theta = np.asarray(theta, float)
    law, m, off = build(theta)
    pk = pack_gms(law)
    if cache is not None and "gms_force" in cache:
        return law, float(m), float(off), pk, *cache["gms_force"]
    p = theta.size
    dk = np.zeros((p,) + pk.k.shape)
    dxi = np.zeros((p,) + pk.xi.shape)
    dC = np.zeros((p,) + pk.C.shape)
    dst = np.zeros((p, 2, 5))
    dm = np.zeros(p)
    doff = np.zeros(p)
    for j in range(p):
        h = 1e-6 * abs(theta[j]) if theta[j] != 0.0 else 1e-6
        q = theta.copy()
        q[j] += h
        try:
            lj, mj, oj = build(q)
        except ParameterError:
            q[j] = theta[j] - h
            lj, mj, oj = build(q)
        pj = pack_gms(lj)
        step = q[j] - theta[j]
        if not np.array_equal(pj.static[:, 5], pk.static[:, 5]):
            return None
        dk[j], dxi[j], dC[j] = ((pj.k - pk.k) / step, (pj.xi - pk.xi) / step, (pj.C - pk.C) / step)
        dst[j] = (pj.static[:, :5] - pk.static[:, :5]) / step
        dm[j] = (float(mj) - float(m)) / step
        doff[j] = (float(oj) - float(off)) / step
    coef = tuple(_snap(a.ravel()).reshape(a.shape) for a in (dk, dxi, dC, dst))
    dmo = tuple(_snap(a) for a in (dm, doff))
    if cache is not None and all(np.array_equal(a, np.round(a)) for a in coef + dmo):
        cache["gms_force"] = (coef, *dmo)
    return law, float(m), float(off), pk, coef, *dmo


#: Sub-steps per sample of :func:`gms_force_driven`'s sensitivity sweep: enough that the stiffest
#: sticking contact turns by at most ``GMS_SENS_OMEGA_H`` radians per sub-step (its load, taken
#: affine per sub-step from a cubic Hermite of the trajectory, is then within ~(omega h)^2 / 8).
GMS_SENS_OMEGA_H = 0.2

#: A sweep whose sensitivities say that a relative parameter change of ``1 / GMS_SENS_GROWTH`` moves
#: the simulated signal by more than its own largest value (``max |S_ij theta_j| > GMS_SENS_GROWTH
#: max |y|``, ``theta_j`` taken as 1 where it is 0) is refused (:data:`UNRESOLVED`: the caller
#: differences). Named assumption, measured: healthy sweeps of the fits in benchmarks/identify.py and
#: tests/kernels/test_sensitivity_gms.py stay below ~40; a switch crossed almost tangentially (an
#: element breaking away just after a reversal, under a fast-ringing stiff spring) gave a saltation
#: whose denominator nearly vanished and sensitivities growing to ~1e141, whose Jacobian stopped the
#: fit at once (``xtol``) at 6,500x the noise floor.
GMS_SENS_GROWTH = 1e4


def gms_force_driven(build: Callable, theta: np.ndarray, u: np.ndarray, dt, options: SimOptions, segments,
                     compare: str = "v", cache: dict | None = None, spare: int = 0, S_out: np.ndarray | None = None):
    """Simulated ``x`` or ``v`` of the force-driven GMS (:func:`frictionkit.simulate`, each segment from
    rest) and its sensitivities ``N x p``: ``(y, S, status)``.

    The signal is ``simulate``'s own (its accuracy check included); the sensitivities come from one
    sweep along that recorded trajectory (:func:`frictionkit.kernels.sensitivity_gms.gms_force_sens`):
    second order between switches, each switch the record shows located on the interpolated
    trajectory and its saltation applied there. They are the derivatives of the continuous model along
    the simulated trajectory, not of the kernel's discrete map (its spans and located switches are not
    differentiated): measured within 1e-4 ... 5e-3 of central differences of simulations at rtol 1e-9
    in stick-slip, the differences themselves scattering by as much for the stiffnesses
    (tests/kernels/test_sensitivity_gms.py). ``spare``/``S_out`` as :func:`force_driven`. ``status``
    as :func:`force_driven`; also :data:`UNRESOLVED` for a sweep beyond :data:`GMS_SENS_GROWTH`.
    """
    from ..kernels import sensitivity_gms as _kg
    from ..plants.mass import Mass
    from ..simulation.core import simulate

    out = _gms_coefficients(build, theta, cache)
    if out is None:
        return None, None, UNRESOLVED
    law, m, off, pk, (dk, dxi, dC, dst), dm, doff = out
    dts = [float(dt)] * len(segments) if np.ndim(dt) == 0 else [float(h) for h in dt]
    K = float(pk.k.sum(axis=1).max())
    c = float(pk.static[:, 4].max())
    if max(math.sqrt(K / m), c / m) * max(dts) > FAST_LIMIT:
        return None, None, UNRESOLVED
    N, P = u.size, np.asarray(theta).size
    y = np.empty(N)
    if S_out is not None:
        Sx = Sv = S_out  # the first P columns are written
    else:
        Sx = np.empty((N, P + spare))
        Sv = Sx
    for (a, b), h in zip(segments, dts):
        ue = np.ascontiguousarray(u[a:b] - off, dtype=float)
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")
            res = simulate(law, plant=Mass(m), force=ue, dt=h, options=options)
        if res.status != 0:
            return None, None, int(res.status)
        Fel = np.ascontiguousarray(res.states["F_elements"], dtype=float)
        stick = np.ascontiguousarray(res.states["stick"], dtype=np.bool_)
        nsub = max(1, int(math.ceil(math.sqrt(K / m) * h / GMS_SENS_OMEGA_H)))
        sx = np.empty((b - a, P))
        sv = np.empty((b - a, P))
        _kg.gms_force_sens(ue, h, m, pk.static, pk.k, pk.xi, pk.C, np.ascontiguousarray(res.x),
                           np.ascontiguousarray(res.v), Fel, stick, dk, dxi, dC, dst, dm, doff, nsub, sx, sv)
        ys = res.x if compare == "x" else res.v
        ss = sx if compare == "x" else sv
        scale = np.where(np.asarray(theta) != 0.0, np.abs(theta), 1.0)
        if not np.isfinite(ss).all() or np.max(np.abs(ss) * scale) > GMS_SENS_GROWTH * np.max(np.abs(ys)):
            return None, None, UNRESOLVED
        Sx[a:b, :P] = ss
        y[a:b] = ys
    return y, Sx, 0


def reduce_lsq(A: np.ndarray, col_scale: np.ndarray | None = None) -> tuple[np.ndarray, np.ndarray] | None:
    """The ``(p + 1)``-row least-squares problem with the same cost, gradient and Gauss–Newton matrix.

    ``A = [J r]`` (``N x (p + 1)``; with ``col_scale`` the Jacobian is ``A[:, :p] * col_scale``).
    With ``A = Q R`` (thin QR), ``R = [[R11, c], [0, rho]]``: ``f = [c, rho]``, ``Jr = [R11; 0]``
    give ``|f|^2 = |r|^2``, ``Jr^T Jr = J^T J`` and ``Jr^T f = J^T r`` — everything a trust-region
    step of :func:`scipy.optimize.least_squares` reads — from a ``(p + 1) x p`` matrix instead of
    an ``N x p`` one (the SVD per iteration of ``trf``'s exact solver, and its other passes over
    the ``N``-row arrays, were ~40 % of the fit's time with ``N = 25,000``). ``R`` comes from the
    Cholesky factor of the column-equilibrated Gram matrix (one BLAS pass over ``A``), or from a
    QR factorisation when that is ill-conditioned (a pivot below 1e-5 of the unit diagonal:
    ``cond(J)`` beyond ~1e5, where the Gram matrix would lose more than 1e-6 of relative
    accuracy). ``rho`` is set from ``|r|^2`` itself so that the cost is exact. None when ``A``
    holds a non-finite value.
    """
    p = A.shape[1] - 1
    sc = np.ones(p + 1) if col_scale is None else np.append(col_scale, 1.0)
    G = (A.T @ A) * np.outer(sc, sc)
    if not np.isfinite(G).all():
        return None  # a non-finite entry of A (checked here, not by a pass over A)
    rr = float(G[p, p])
    d = np.sqrt(np.diag(G))
    d = np.where(d > 0, d, 1.0)
    R = None
    try:
        L = np.linalg.cholesky(G / np.outer(d, d))
        if np.all(np.diag(L)[:p] > 1e-5):
            R = L.T * d[None, :]
    except np.linalg.LinAlgError:
        pass
    if R is None:
        R = np.linalg.qr(A * sc[None, :], mode="r")
    c = R[:p, p].copy()
    f = np.append(c, math.sqrt(max(rr - float(c @ c), 0.0)))
    Jr = np.zeros((p + 1, p))
    Jr[:p] = np.triu(R[:p, :p])
    return f, Jr


class ReducedProblem:
    """The force-driven fit for :func:`scipy.optimize.least_squares` as a ``(p + 1)``-row problem.

    (:class:`MotionReducedProblem` is the same for the motion-driven fit.)

    Every evaluation is one augmented run (:func:`force_driven`: the residual *and* its
    Jacobian), reduced by :func:`reduce_lsq`; ``jac`` returns the Jacobian of the last ``fun``
    point (the trust-region method asks for it only at accepted points, right after ``fun``).
    The residual is the same as :meth:`prob.fun <._oe_problem._Problem.fun>`'s (the state steps are
    those of :func:`frictionkit.simulate`). Where the augmented run fails, the residual and a
    forward-difference Jacobian come from ``prob`` (plain simulations), reduced the same way.
    ``prob``'s counters (``nfev``, ``nsim``, ``nsens``, ``cost_history``, ``progress``) are kept.
    :meth:`full` gives the full ``(r, J)`` of the last point whose Jacobian was asked for (the
    fitter's statistics at the optimum).
    """

    def __init__(self, prob):
        self.prob = prob
        self._last = None  # (key, f, Jr, A, col_scale, buffer) of the last fun point
        self._accepted = None  # the same for the last jac point
        self._work: dict = {}  # state buffers of force_driven
        self._bufs = [None, None]  # two [J r] buffers: the last jac point's is never overwritten
        self._held = 1
        self._setup()

    def _setup(self) -> None:
        w = self.prob.w
        self._binary = bool(np.all((w == 0.0) | (w == 1.0)))  # the usual mask: zero rows, no product
        self._zero = np.flatnonzero(w == 0.0)

    def _buffer(self, shape: tuple[int, int]) -> np.ndarray:
        """The ``[J r]`` buffer not holding the last accepted point (reused from call to call)."""
        k = 1 - self._held
        if self._bufs[k] is None or self._bufs[k].shape != shape:
            self._bufs[k] = np.empty(shape)
        return self._bufs[k]

    def _record(self, cost: float) -> None:
        """Count one evaluation on the problem (its counters and progress callback)."""
        prob = self.prob
        prob.nfev += 1
        prob.cost_history.append(cost)
        if prob.progress is not None:
            prob.progress(prob.nfev, prob.nsim + prob.nsens, cost)

    def _exact(self, p: np.ndarray):
        """``([J r], d theta / d p)`` from one augmented run at transformed ``p`` (None if it fails)."""
        prob = self.prob
        theta = prob.to_nat(p)
        P = theta.size
        try:
            with warnings.catch_warnings():
                warnings.simplefilter("ignore", RuntimeWarning)
                buf = self._buffer((prob.u.size, P + 1))
                yh, A, status = force_driven(lambda th: prob.tmpl.build(prob.free, th), theta, prob.u, prob.dts,
                                             prob.options, prob.segments, prob.compare, prob._coef_cache, spare=1,
                                             work=self._work, S_out=buf)
        except ParameterError:
            return None
        finally:
            prob.nsens += 1
        if status != 0:
            return None
        A[:, P] = yh - prob.y
        if self._binary:
            A[self._zero] = 0.0
        else:
            A *= prob.w[:, None]
        return A, np.where(prob.is_log, theta, prob.scale)

    def _residual(self, nat: np.ndarray) -> np.ndarray:
        """The plain residual of ``prob`` at natural parameters ``nat`` (one simulation, counted)."""
        r = self.prob._resid_nat(nat)
        self.prob.nsim += 1
        return r

    def _fallback(self, p: np.ndarray):
        """``[J r]`` from plain simulations: the residual of ``prob`` and a difference Jacobian."""
        prob = self.prob
        exact, prob.exact = prob.exact, False
        try:
            r = self._residual(prob.to_nat(p))
            J = prob.jac(p)
        finally:
            prob.exact = exact
        return np.column_stack([J, r])

    def fun(self, p):
        p = np.asarray(p, float)
        key = p.tobytes()
        if self._last is not None and self._last[0] == key:
            return self._last[1]
        A, sc, red = None, None, None
        out = self._exact(p)
        if out is not None:
            A, sc = out
            red = reduce_lsq(A, sc)
        if red is None:
            A, sc = self._fallback(p), None
            red = reduce_lsq(A)
        f, Jr = red
        self._last = (key, f, Jr, A, sc, 1 - self._held if A is self._bufs[1 - self._held] else -1)
        self._record(0.5 * float(f @ f))
        return f

    def jac(self, p):
        p = np.asarray(p, float)
        if self._last is None or self._last[0] != p.tobytes():
            self.fun(p)
        self._accepted = self._last
        if self._last[5] >= 0:
            self._held = self._last[5]
        return self._last[2]

    def full(self, p) -> tuple[np.ndarray, np.ndarray] | None:
        """``(r, J)`` (``N``, ``N x p``) at ``p`` if it is the last point whose Jacobian was asked for."""
        acc = self._accepted
        if acc is None or acc[0] != np.asarray(p, float).tobytes():
            return None
        A, sc = acc[3], acc[4]
        P = A.shape[1] - 1
        J = A[:, :P] if sc is None else A[:, :P] * sc[None, :]
        return A[:, P].copy(), J


class MotionReducedProblem(ReducedProblem):
    """The motion-driven fit (:mod:`.motion_error`) as a ``(p + 1)``-row problem.

    Every evaluation is one run of :func:`motion_driven` per segment: the force (equal to
    :func:`frictionkit.simulate`'s ``position=`` run to round-off, tested) *and* its
    derivatives, plus the ``J a`` and ``offset`` columns. Where it fails (a law without
    sensitivity kernels, a parameter the law refuses, a non-finite value) the residual
    and a difference Jacobian come from ``prob`` (plain simulations).
    """

    def _setup(self) -> None:
        prob = self.prob
        md = prob.md
        self._law = [i for i, n in enumerate(prob.names) if n not in ("J", "offset")]
        self._a = np.concatenate([s.a[s.fit] for s in md.segments])
        self._F = np.concatenate([s.F[s.fit] for s in md.segments])
        self._rows = np.cumsum([0] + [int(s.fit.sum()) for s in md.segments])

    def _record(self, cost: float) -> None:
        self.prob.nfev += 1
        self.prob.history.append(cost)

    def _exact(self, p: np.ndarray):
        prob = self.prob
        theta = prob.to_nat(p)
        P = theta.size
        law = self._law

        def build(th):
            return prob.tmpl.build(prob.law_names, th), 1.0, 0.0
        try:
            with warnings.catch_warnings():
                warnings.simplefilter("ignore", RuntimeWarning)
                kind = kind_of(build(theta[law])[0])
                run = motion_driven if kind == "lugre" else gms_motion_driven
                A = self._buffer((prob.n, P + 1))
                for s, a, b in zip(prob.md.segments, self._rows[:-1], self._rows[1:]):
                    out = run(build, theta[law], s.x, s.dt, prob._coef_cache)
                    if out is None or out[2] != 0:
                        return None
                    F, S, _ = out
                    A[a:b, law] = S[s.fit]
                    A[a:b, P] = F[s.fit]
        except ParameterError:
            return None
        finally:
            prob.nsens += 1
        vals = dict(zip(prob.names, theta))
        J = vals.get("J", prob.fixed["J"])
        off = vals.get("offset", prob.fixed["offset"])
        A[:, P] += J * self._a + off - self._F
        for j, n in enumerate(prob.names):
            if n == "J":
                A[:, j] = self._a
            elif n == "offset":
                A[:, j] = 1.0
        return A, np.where(prob.log, theta, prob.scale)

    def _residual(self, nat: np.ndarray) -> np.ndarray:
        return self.prob.resid_nat(nat)  # the motion problem counts its own simulations
