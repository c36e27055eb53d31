"""Residuals, Jacobian, batched start costs, bounds and start points of the force-driven output-error fit.

Part of :mod:`.output_error` (split from it without a change of behaviour)."""

from __future__ import annotations

import math
import warnings
from types import SimpleNamespace
from concurrent.futures import ThreadPoolExecutor

import numpy as np

from ..errors import ParameterError
from ..plants.mass import Mass
from ..simulation.core import simulate, simulate_batch
from . import _jacobian
from ._oe_params import _NONNEG, _is_log

class _Problem:
    """Residuals of the transformed parameters; Jacobian by threaded simulations."""

    def __init__(self, tmpl, free, u, dt, y, compare, w, options, x0_nat, workers):
        self.tmpl, self.free, self.u, self.dt, self.y = tmpl, free, u, dt, y
        self.compare, self.w, self.options, self.workers = compare, w, options, workers
        self.is_log = np.array([_is_log(n) for n in free])
        self.scale = np.where(self.is_log, 1.0, np.where(np.abs(x0_nat) > 0, np.abs(x0_nat), 1.0))
        self.diff_step = 1e-3
        self.nfev = 0
        self.nsim = 0
        self.cost_history: list[float] = []
        self._cache: tuple[bytes, np.ndarray] | None = None
        self.big = 10.0 * (np.max(np.abs(y)) + 1e-300)
        self.progress = None
        #: exact Jacobians from forward sensitivities (set by the fitter when the law has them)
        self.exact = False
        self.nsens = 0  # augmented (sensitivity) runs
        self._coef_cache: dict = {}  # parameter -> packed-row derivatives (_jacobian.row_coefficients)
        #: ``[(start, stop), ...]``: the recordings concatenated in ``u``/``y``, each simulated from rest
        self.segments = [(0, u.size)]
        #: why the last :meth:`simulate_nat` gave no simulation (a parameter the law refused)
        self.last_failure = ""
        #: the sample period of each segment (records may be sampled differently)
        self.dts = [dt]

    def to_nat(self, p: np.ndarray) -> np.ndarray:
        return np.where(self.is_log, np.exp(np.clip(p, -700, 700)), p * self.scale)

    def to_tr(self, theta: np.ndarray) -> np.ndarray:
        with np.errstate(divide="ignore"):
            return np.where(self.is_log, np.log(np.maximum(theta, 1e-300)), theta / self.scale)

    def simulate_nat(self, theta):
        """The simulation at natural parameters, or None when they build no law/mass
        (the reason kept in ``self.last_failure``); several segments give one namespace whose
        ``status``/``message`` are the first failing segment's (named)."""
        try:
            model, m, off = self.tmpl.build(self.free, theta)
        except ParameterError as exc:
            self.last_failure = str(exc)
            return None
        with warnings.catch_warnings():
            warnings.simplefilter("ignore", RuntimeWarning)
            if len(self.segments) == 1:
                return simulate(model, plant=Mass(m), force=self.u - off, dt=self.dts[0], options=self.options)
            parts = [simulate(model, plant=Mass(m), force=self.u[a:b] - off, dt=h, options=self.options)
                     for (a, b), h in zip(self.segments, self.dts)]
        status, message = 0, "ok"
        for i, part in enumerate(parts):
            if getattr(part, "status", 0) != 0:
                status, message = part.status, f"record {i + 1} of {len(parts)}: {part.message}"
                break
        return SimpleNamespace(v=np.concatenate([p.v for p in parts]), x=np.concatenate([p.x for p in parts]),
                               status=status, message=message)

    def _resid_nat(self, theta) -> np.ndarray:
        res = self.simulate_nat(theta)
        if res is None:
            return np.full(self.y.size, self.big) * self.w
        yh = res.x if self.compare == "x" else res.v
        r = (yh - self.y) * self.w
        bad = ~np.isfinite(r)
        if bad.any():
            r[bad] = self.big
        return r

    def fun(self, p):
        key = np.asarray(p, float).tobytes()
        if self._cache is not None and self._cache[0] == key:
            return self._cache[1]
        r = self._resid_nat(self.to_nat(np.asarray(p, float)))
        self.nfev += 1
        self.nsim += 1
        self.cost_history.append(0.5 * float(r @ r))
        self._cache = (key, r)
        if self.progress is not None:
            self.progress(self.nfev, self.nsim, self.cost_history[-1])
        return r

    def jac_exact(self, p) -> np.ndarray | None:
        """``d r / d p`` from one augmented run per segment (None if it fails: the caller differences)."""
        theta = self.to_nat(np.asarray(p, float))
        try:
            with warnings.catch_warnings():
                warnings.simplefilter("ignore", RuntimeWarning)
                _, S, status = _jacobian.force_driven(lambda th: self.tmpl.build(self.free, th), theta, self.u,
                                                      self.dts, self.options, self.segments, self.compare,
                                                      self._coef_cache)
        except ParameterError:
            return None
        self.nsens += 1
        if status != 0 or not np.all(np.isfinite(S)):
            return None
        S *= self.w[:, None]
        S *= np.where(self.is_log, theta, self.scale)[None, :]  # d theta / d p
        return S

    def jac(self, p, h: float | None = None):
        if self.exact:
            J = self.jac_exact(p)
            if J is not None:
                return J
        h = self.diff_step if h is None else h
        p = np.asarray(p, float)
        r0 = self.fun(p)
        steps = []
        for j in range(p.size):
            q = p.copy()
            hj = h * max(1.0, abs(p[j])) if not self.is_log[j] else h
            q[j] += hj
            steps.append((q, hj))
        self.nsim += p.size
        with ThreadPoolExecutor(max_workers=self.workers) as ex:
            cols = list(ex.map(lambda s: self._resid_nat(self.to_nat(s[0])), steps))
        J = np.empty((r0.size, p.size))
        for j, (c, (_, hj)) in enumerate(zip(cols, steps)):
            J[:, j] = (c - r0) / hj
        return J


def _batch_costs(prob, points, w, options) -> np.ndarray:
    """``0.5 * SSE`` of each transformed point, from :func:`simulate_batch` (one call per offset value)."""
    costs = np.full(len(points), np.inf)
    built, idx = [], []
    for i, p in enumerate(points):
        try:
            mdl, m, off = prob.tmpl.build(prob.free, prob.to_nat(p))
        except ParameterError:
            continue
        built.append((mdl, m, off))
        idx.append(i)
    costs[idx] = 0.0
    for off_val in {b[2] for b in built}:
        sel = [j for j, b in enumerate(built) if b[2] == off_val]
        for (a, b), h in zip(prob.segments, prob.dts):  # each recording from rest, at its own period
            with warnings.catch_warnings():
                warnings.simplefilter("ignore", RuntimeWarning)
                br = simulate_batch([built[j][0] for j in sel], masses=[built[j][1] for j in sel],
                                    force=prob.u[a:b] - off_val, dt=h, target=prob.y[a:b],
                                    compare=prob.compare, weight=w[a:b], options=options)
            prob.nsim += len(sel)
            for j, sse in zip(sel, br.sse):
                costs[idx[j]] += 0.5 * sse
    return costs


def _bounds_tr(free, tmpl, bounds, prob):
    lo = np.empty(len(free))
    hi = np.empty(len(free))
    for j, n in enumerate(free):
        base = n.split("_")[0]
        if bounds is not None and n in bounds:
            a, b = bounds[n]
        else:
            a = 0.0 if (base in _NONNEG or base.startswith("xi") or prob.is_log[j]) else -np.inf
            b = np.inf
        if prob.is_log[j]:
            lo[j] = math.log(a) if a > 0 else -np.inf
            hi[j] = math.log(b) if np.isfinite(b) else np.inf
        else:
            lo[j] = a / prob.scale[j]
            hi[j] = b / prob.scale[j]
    return lo, hi


def _start_points(x0, lo, hi, is_log, starts, rng):
    pts = [x0.copy()]
    for _ in range(starts - 1):
        p = x0 + np.where(is_log, rng.uniform(-1.5, 1.5, x0.size), rng.uniform(-0.5, 0.5, x0.size))
        pts.append(p)
    with np.errstate(invalid="ignore"):
        a = np.where(np.isfinite(lo), lo + 1e-9 * np.maximum(1, np.abs(lo)), -np.inf)
        b = np.where(np.isfinite(hi), hi - 1e-9 * np.maximum(1, np.abs(hi)), np.inf)
    return [np.clip(p, a, b) for p in pts]


def _blas_limit():
    """One BLAS thread during the fit when ``threadpoolctl`` is installed (optional).

    OpenBLAS workers busy-wait after each call and steal the cores the simulation
    threads need: measured on 2 cores, the 25,000-sample benchmark fit takes 6.4 s
    CPU with default BLAS threading and 2.0 s with one BLAS thread.
    """
    from contextlib import nullcontext

    try:
        from threadpoolctl import threadpool_limits
    except ImportError:
        return nullcontext()
    return threadpool_limits(limits=1, user_api="blas")
