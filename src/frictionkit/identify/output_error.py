"""Output-error identification of dynamic friction by simulation (seed 002 §3.1, eq. 12).

The measured input force drives the model (mass + friction law) and the
parameters minimise the squared difference between the simulated and the
measured velocity (or position)::

    min_theta  sum_k ( y_k - y_hat_k(theta) )^2          (seed 002 eq. 12)

Any subset of the parameters can be freed: LuGre ``sigma0``, ``sigma1``; GMS
``k1 .. kM``, ``xi1 .. xiM``, ``C``; the static map ``Fc``, ``Fs``, ``vs``,
``delta``, ``sigma2`` (both directions, or ``Fc_pos``, ``Fc_neg`` ... per
direction); the mass ``m``; a constant force ``offset`` (``m a = u - F - offset``).

How the simulations are organised (measured, see ``benchmarks/identify.py``):

* the residual vector of one parameter set comes from :func:`frictionkit.simulate`
  (numba kernel, about 10 ms for 25,000 samples);
* the finite-difference Jacobian needs the residual *vectors* of the ``p``
  perturbed parameter sets. :func:`frictionkit.simulate_batch` returns only
  weighted SSEs, so it cannot give a Jacobian; instead the ``p`` runs go to a
  thread pool — the kernels release the GIL (``nogil=True``), so this is the
  same parallelism as the batch kernel's ``prange`` without touching the kernels;
* the multi-start screening needs only the cost of each start, so all starts go
  to **one** :func:`~frictionkit.simulate_batch` call and the optimiser is run
  from the best ones;
* the optimiser is :func:`scipy.optimize.least_squares` (trust-region
  reflective, bounds) on transformed parameters: logarithms of the strictly
  positive ones (stiffnesses, ``C``, ``vs``, ``delta``, mass), the others scaled
  by their start value.

Standard errors come from ``s^2 (J^T J)^-1`` with the Jacobian at the optimum.
"""

from __future__ import annotations

import math
import os
import warnings
from collections.abc import Callable, Mapping, Sequence
from concurrent.futures import ThreadPoolExecutor
from contextlib import nullcontext
from dataclasses import dataclass

import numpy as np
from scipy.optimize import least_squares

from .. import _validate as val
from ..data.recording import Recording
from ..errors import DataError, IdentificationError, ParameterError
from ..models.gms import GMS
from ..models.lugre import LuGre
from ..models.static import CoulombViscous, Directional, Stribeck
from ..plants.mass import Mass
from ..simulate.core import SimOptions, simulate, simulate_batch
from .result import IdentificationResult, parameter_statistics

__all__ = ["fit_output_error", "initial_guess_lugre", "OUTPUT_ERROR_OPTIONS"]

#: Integrator tolerances used by default during identification. Measured on the
#: 25,000-sample stick-slip run of ``benchmarks/identify.py``: max velocity error
#: 2.4e-6 m/s against a rtol = 1e-9 run (0.0006 % of the 0.39 m/s peak; the default
#: SimOptions give 4.5e-7) at 5 ms instead of 11.5 ms per simulation.
OUTPUT_ERROR_OPTIONS = SimOptions(rtol=1e-5, atol_v=1e-7, atol_F=1e-5)

_STATIC_FIELDS = ("Fc", "Fs", "vs", "delta", "sigma2")
_LOG = {"sigma0", "vs", "delta", "C", "m"}  # strictly positive: optimised as log
_NONNEG = {"sigma1", "Fc", "Fs", "sigma2"}


# --------------------------------------------------------------------------- parameter handling
def _stribeck_fields(law) -> dict:
    if isinstance(law, Stribeck):
        return {"Fc": law.Fc, "Fs": law.Fs, "vs": law.vs, "delta": law.delta, "sigma2": law.sigma2,
                "shape": law.shape}
    if isinstance(law, CoulombViscous):  # a flat Stribeck curve (same packed rows)
        return {"Fc": law.Fc, "Fs": law.Fc, "vs": 1.0, "delta": 1.0, "sigma2": law.sigma2,
                "shape": "exponential"}
    raise ParameterError(f"static law {type(law).__name__} is not supported")


@dataclass(frozen=True)
class _Template:
    """A model split into named scalar values and the recipe to rebuild it."""

    kind: str  # "lugre" or "gms"
    values: dict  # every adjustable scalar, by name
    static_free: bool
    orig_static: object
    M: int

    @classmethod
    def of(cls, model, mass: float, offset: float) -> _Template:
        if isinstance(model, Directional):
            raise ParameterError(
                "fit_output_error: a Directional of dynamic laws is not supported; put the direction "
                "dependence in the static map, e.g. LuGre(Directional(positive=..., negative=...), ...)"
            )
        if not isinstance(model, (LuGre, GMS)):
            raise ParameterError(f"fit_output_error: model0 = {type(model).__name__}: must be LuGre or GMS")
        vals: dict = {"m": float(mass), "offset": float(offset)}
        st = model.static
        pos, neg = (st.positive, st.negative) if isinstance(st, Directional) else (st, st)
        for side, law in (("pos", pos), ("neg", neg)):
            for f, v in _stribeck_fields(law).items():
                vals[f"{f}_{side}"] = v
        if isinstance(model, LuGre):
            vals.update(sigma0=model.sigma0, sigma1=model.sigma1)
            return cls("lugre", vals, False, st, 0)
        for i, (k, xi) in enumerate(zip(model.k, model.xi), start=1):
            vals[f"k{i}"] = float(k)
            vals[f"xi{i}"] = float(xi)
        vals["C"] = model.C
        return cls("gms", vals, False, st, model.M)

    def expand(self, free: Sequence[str]) -> list[str]:
        """Canonical names: ``Fc`` -> both directions tied, ``k`` -> every element."""
        out: list[str] = []
        for name in free:
            if not isinstance(name, str):
                raise ParameterError(f"fit_output_error: free = {free!r}: names must be strings")
            if name == "k" and self.kind == "gms":
                out += [f"k{i}" for i in range(1, self.M + 1)]
            elif name == "xi" and self.kind == "gms":
                out += [f"xi{i}" for i in range(1, self.M + 1)]
            elif name in _STATIC_FIELDS or name in self.values:
                out.append(name)
            else:
                known = sorted(set(self._public_names()))
                raise ParameterError(f"fit_output_error: unknown parameter {name!r}; known: {known}")
        if len(set(out)) != len(out):
            raise ParameterError(f"fit_output_error: free = {tuple(free)!r} names a parameter twice")
        for f in _STATIC_FIELDS:
            if f in out and (f"{f}_pos" in out or f"{f}_neg" in out):
                raise ParameterError(f"fit_output_error: free has both {f!r} and a per-direction {f}_pos/{f}_neg")
        if not out:
            raise ParameterError("fit_output_error: free is empty; name at least one parameter")
        return out

    def _public_names(self) -> list[str]:
        names = [n for n in self.values if not n.startswith("shape")] + list(_STATIC_FIELDS)
        return names + (["k", "xi"] if self.kind == "gms" else [])

    def get(self, name: str) -> float:
        if name in _STATIC_FIELDS:
            return float(self.values[f"{name}_pos"])
        return float(self.values[name])

    def build(self, free: Sequence[str], theta: np.ndarray):
        """``(model, mass, offset)`` with ``free`` set to ``theta``."""
        v = dict(self.values)
        for n, x in zip(free, theta):
            if n in _STATIC_FIELDS:
                v[f"{n}_pos"] = v[f"{n}_neg"] = float(x)
            else:
                v[n] = float(x)
        static_touched = any(n.split("_")[0] in _STATIC_FIELDS for n in free)
        if static_touched:
            laws = [Stribeck(**{f: v[f"{f}_{s}"] for f in (*_STATIC_FIELDS, "shape")}) for s in ("pos", "neg")]
            per_dir = any(n.endswith(("_pos", "_neg")) for n in free) or isinstance(self.orig_static, Directional)
            static = Directional(positive=laws[0], negative=laws[1]) if per_dir or laws[0] != laws[1] else laws[0]
        else:
            static = self.orig_static
        if self.kind == "lugre":
            model = LuGre(static, sigma0=v["sigma0"], sigma1=v["sigma1"])
        else:
            model = GMS(static, k=[v[f"k{i}"] for i in range(1, self.M + 1)],
                        xi=[v[f"xi{i}"] for i in range(1, self.M + 1)], C=v["C"])
        return model, v["m"], v["offset"]


def _is_log(name: str) -> bool:
    base = name.split("_")[0]
    return base in _LOG or (name[0] == "k" and name[1:].isdigit())


def _unit(name: str, Fu: str, xu: str) -> str:
    base = name.split("_")[0]
    vu = f"{xu}/s"
    if base in ("sigma0",) or (name[0] == "k" and name[1:].isdigit()):
        return f"{Fu}/{xu}"
    if base in ("sigma1", "sigma2"):
        return f"{Fu}·s/{xu}"
    if base in ("Fc", "Fs", "offset"):
        return Fu
    if base == "vs":
        return vu
    if base == "C":
        return f"{Fu}/s"
    if base == "m":
        return "kg" if xu == "m" else f"{Fu}·s²/{xu}"
    return "-"


# --------------------------------------------------------------------------- data
def _arrays(data) -> tuple[np.ndarray, np.ndarray, np.ndarray | None, np.ndarray | None, dict, str]:
    """``t, u, x, v, provenance, name`` from a Recording or a mapping of arrays."""
    if isinstance(data, Recording):
        rec = data
    elif isinstance(data, Mapping):
        d = dict(data)
        if "u" in d and "F" not in d:
            d["F"] = d.pop("u")
        unknown = set(d) - {"t", "x", "v", "F"}
        if unknown:
            raise DataError(f"fit_output_error: unknown signal(s) {sorted(unknown)}; use t, F (or u), x, v")
        rec = Recording(**d, name="arrays")
    else:
        raise DataError(f"fit_output_error: data = {type(data).__name__}: give a Recording or a mapping of arrays")
    if not rec.is_regular:
        raise DataError(f"recording '{rec.name}': irregular sampling; call Recording.resample() first")
    return rec.t, np.asarray(rec.force(), dtype=float), rec.x, rec.v, dict(rec.provenance), rec.name


# --------------------------------------------------------------------------- initial guess
def initial_guess_lugre(data, *, mass: float = 0.0, zeta: float = 1.0, sigma2: float = 0.0,
                        load_fraction: float = 0.3) -> dict[str, float]:
    """Initial ``sigma0``, ``sigma1`` of a LuGre model from a sub-breakaway test (seed 002 §3.1).

    With a driving force below the breakaway level the axis stays in pre-sliding and
    the friction force ``F = u - m a`` over the displacement ``x`` draws hysteresis
    branches. Where the bristle deflection is zero (the friction force crosses 0
    on a branch, or at the virgin start) the slope ``dF/dx`` equals ``sigma0``
    exactly; it is estimated by a straight-line fit over the samples of each
    monotone branch whose friction force lies within ``load_fraction`` of the
    branch's force range around zero, and the median over branches is returned.
    ``sigma1`` follows from a damping-ratio guess of the linearised pre-sliding
    oscillator ``m x'' + (sigma1 + sigma2) x' + sigma0 x = u``:
    ``sigma1 = max(2 zeta sqrt(sigma0 m) - sigma2, 0)``.

    Parameters
    ----------
    data : Recording or mapping
        Time ``t`` [s], position ``x`` [m] and force ``F`` (or ``u``) [N].
    mass : float
        Moving mass [kg] (>= 0) for the inertia correction and the damping guess.
        With 0 the inertia is ignored and ``sigma1`` is returned as 0.
    zeta : float
        Damping-ratio guess [-] (1 = critical).
    sigma2 : float
        Viscous coefficient [N·s/m] already known from the static map.
    load_fraction : float
        Half-width of the force window around zero, as a fraction of the branch's range.

    Returns
    -------
    dict
        ``sigma0`` [N/m], ``sigma1`` [N·s/m], ``branches`` (number of branches used).

    Raises
    ------
    DataError
        No position, or no branch with enough distinct positions.

    Examples
    --------
    >>> import numpy as np, frictionkit as fk
    >>> from frictionkit.identify.output_error import initial_guess_lugre
    >>> dt = 1e-3; t = np.arange(4001) * dt
    >>> u = 1.0 * (2 / np.pi) * np.arcsin(np.sin(2 * np.pi * 0.5 * t))  # 1 N triangle < Fs
    >>> res = fk.simulate(fk.LuGre(fk.Stribeck(Fc=1.0, Fs=1.5, vs=1e-3), sigma0=1e5, sigma1=63.2),
    ...                   plant=fk.Mass(1.0), force=u, dt=dt)
    >>> g = initial_guess_lugre({"t": t, "x": res.x, "F": u}, mass=1.0)
    >>> bool(abs(g["sigma0"] / 1e5 - 1) < 0.1)
    True
    """
    t, u, x, _, _, name = _arrays(data)
    if x is None:
        raise DataError(f"recording '{name}': initial_guess_lugre needs the position x")
    mass = val.nonnegative("initial_guess_lugre", "mass", mass)
    zeta = val.nonnegative("initial_guess_lugre", "zeta", zeta)
    dt = float(np.median(np.diff(t)))
    F = u.copy()
    if mass > 0:
        F = F - mass * np.gradient(np.gradient(x, dt), dt)
    # monotone branches of x (direction changes of the smoothed increments)
    dx = np.diff(x)
    sgn = np.sign(dx)
    nz = np.flatnonzero(sgn != 0)
    if nz.size < 2:
        raise DataError(f"recording '{name}': the position does not move; no pre-sliding branch to fit")
    # fill zero increments with the previous direction
    s_full = sgn.copy()
    last = sgn[nz[0]]
    for i in range(s_full.size):
        if s_full[i] == 0:
            s_full[i] = last
        else:
            last = s_full[i]
    cuts = np.flatnonzero(np.diff(s_full) != 0) + 1
    edges = np.r_[0, cuts, dx.size]
    slopes, weights = [], []
    for a, b in zip(edges[:-1], edges[1:]):
        seg = slice(a, b + 1)
        xs, Fs_ = x[seg], F[seg]
        rng = float(Fs_.max() - Fs_.min())
        if rng <= 0:
            continue
        sel = np.abs(Fs_) <= load_fraction * rng / 2.0 if a > 0 else np.abs(Fs_) <= load_fraction * rng
        if np.unique(xs[sel]).size < 3:
            continue
        A = np.column_stack([xs[sel], np.ones(sel.sum())])
        coef, *_ = np.linalg.lstsq(A, Fs_[sel], rcond=None)
        if coef[0] > 0:
            slopes.append(coef[0])
            weights.append(sel.sum())
    if not slopes:
        raise DataError(
            f"recording '{name}': no pre-sliding branch with at least 3 distinct positions near zero force; "
            "use a sub-breakaway triangle-wave test with a finer position resolution"
        )
    sigma0 = float(np.median(slopes))
    sigma1 = max(2.0 * zeta * math.sqrt(sigma0 * mass) - sigma2, 0.0) if mass > 0 else 0.0
    return {"sigma0": sigma0, "sigma1": sigma1, "branches": len(slopes)}


# --------------------------------------------------------------------------- the fit
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

    def to_nat(self, p: np.ndarray) -> np.ndarray:
        return np.where(self.is_log, np.exp(np.clip(p, -700, 700)), p * self.scale)

    def to_tr(self, theta: np.ndarray) -> np.ndarray:
        with np.errstate(divide="ignore"):
            return np.where(self.is_log, np.log(np.maximum(theta, 1e-300)), theta / self.scale)

    def simulate_nat(self, theta):
        try:
            model, m, off = self.tmpl.build(self.free, theta)
        except ParameterError:
            return None
        with warnings.catch_warnings():
            warnings.simplefilter("ignore", RuntimeWarning)
            res = simulate(model, plant=Mass(m), force=self.u - off, dt=self.dt, options=self.options)
        return res

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

    def jac(self, p, h: float | None = None):
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
    for off_val in {b[2] for b in built}:
        sel = [j for j, b in enumerate(built) if b[2] == off_val]
        with warnings.catch_warnings():
            warnings.simplefilter("ignore", RuntimeWarning)
            br = simulate_batch([built[j][0] for j in sel], masses=[built[j][1] for j in sel],
                                force=prob.u - off_val, dt=prob.dt, target=prob.y, compare=prob.compare,
                                weight=w, options=options)
        prob.nsim += len(sel)
        for j, sse in zip(sel, br.sse):
            costs[idx[j]] = 0.5 * sse
    return costs


@dataclass
class _LMResult:
    x: np.ndarray
    cost: float
    status: int
    message: str
    nfev: int
    njev: int


_LM_MESSAGES = {
    0: "the iteration limit was reached",
    1: "the gradient vanished (first-order optimality)",
    2: "the relative cost reduction fell below ftol",
    3: "no trial step reduced the cost (converged to the resolution of the simulation)",
    4: "the step fell below step_tol standard errors of every parameter",
}


def _levenberg_marquardt(prob, p0, lo, hi, w, options, *, max_iter, ftol, step_tol) -> _LMResult:
    """Levenberg–Marquardt with batched trial steps.

    Each iteration: the Jacobian from ``p`` threaded simulations; three damped
    Gauss–Newton steps (``lambda/10, lambda, 10 lambda``, Marquardt scaling by
    ``diag(J^T J)``) projected into the bounds and judged — together with the
    current point, so every cost comes from the same kernel — in **one**
    :func:`simulate_batch` call; the best decrease is accepted.
    """
    p = np.asarray(p0, float).copy()
    r = prob.fun(p)
    cost = 0.5 * float(r @ r)
    lam = 1e-3
    nfev, njev = 1, 0
    n = int((w > 0).sum())
    dof = max(n - p.size, 1)
    with np.errstate(invalid="ignore"):
        a_lo = np.where(np.isfinite(lo), lo + 1e-12 * np.maximum(1, np.abs(lo)), -np.inf)
        a_hi = np.where(np.isfinite(hi), hi - 1e-12 * np.maximum(1, np.abs(hi)), np.inf)
    status = 0
    for _ in range(max_iter):
        J = prob.jac(p)
        njev += 1
        g = J.T @ r
        A = J.T @ J
        d = np.diag(A).copy()
        d[d <= 0] = max(float(d.max()), 1e-300) * 1e-12
        if np.max(np.abs(g) / np.sqrt(d)) <= 1e-12 * max(np.sqrt(2 * cost), 1e-300):
            status = 1
            break
        accepted = False
        while lam < 1e12:
            lams = lam * np.array([0.1, 1.0, 10.0])
            trials = []
            for lm in lams:
                try:
                    step = np.linalg.solve(A + lm * np.diag(d), -g)
                except np.linalg.LinAlgError:
                    step = np.linalg.lstsq(A + lm * np.diag(d), -g, rcond=None)[0]
                trials.append(np.clip(p + step, a_lo, a_hi))
            costs = _batch_costs(prob, [p] + trials, w, options)
            nfev += len(trials)
            j = int(np.argmin(costs[1:]))
            if costs[1 + j] < costs[0]:
                accepted = True
                lam = max(0.3 * lams[j], 1e-12)
                break
            lam *= 100.0
        if not accepted:
            status = 3
            break
        step = trials[j] - p
        p = trials[j]
        r = prob.fun(p)
        nfev += 1
        new = 0.5 * float(r @ r)
        rel = (cost - new) / cost if cost > 0 else 0.0
        cost = new
        try:
            se = np.sqrt(np.abs(np.diag(np.linalg.inv(A))) * 2.0 * cost / dof)
        except np.linalg.LinAlgError:
            se = np.full(p.size, np.inf)
        if 0 <= rel < ftol:
            status = 2
            break
        if rel < 1e-3 and np.all(np.abs(step) <= step_tol * se):  # only near the optimum is se meaningful
            status = 4
            break
    return _LMResult(p, cost, status, _LM_MESSAGES[status], nfev, njev)


def _blas_limit():
    """One BLAS thread during the fit when ``threadpoolctl`` is installed (optional).

    OpenBLAS workers busy-wait after each call and steal the cores the simulation
    threads need: measured on 2 cores, the 25,000-sample benchmark fit takes 6.4 s
    CPU with default BLAS threading and 2.0 s with one BLAS thread.
    """
    try:
        from threadpoolctl import threadpool_limits
    except ImportError:
        return nullcontext()
    return threadpool_limits(limits=1, user_api="blas")


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


def fit_output_error(
    data,
    model0,
    *,
    free: Sequence[str] = ("sigma0", "sigma1"),
    plant_mass: float,
    offset: float = 0.0,
    compare: str = "v",
    bounds: Mapping[str, tuple[float, float]] | None = None,
    starts: int = 1,
    refine: int = 1,
    seed: int = 0,
    weight=None,
    options: SimOptions | None = None,
    optimiser: str = "trf",
    max_nfev: int = 200,
    ftol: float = 1e-8,
    xtol: float = 1e-8,
    step_tol: float = 0.02,
    workers: int | None = None,
    diff_step: float = 1e-3,
    progress: Callable[[int, int, float], None] | None = None,
) -> IdentificationResult:
    """Fit dynamic-friction parameters by simulated-vs-measured output error (seed 002 eq. 12).

    The model ``m a = u - F(model) - offset`` is simulated from rest with the
    measured force ``u`` and the parameters named in ``free`` minimise
    ``sum_k w_k (y_k - y_hat_k)^2`` with ``y`` the velocity (``compare="v"``) or the
    position relative to its first sample (``compare="x"``).

    Parameters
    ----------
    data : Recording or mapping
        Uniformly sampled ``t`` [s], force ``F`` (or ``u``) [N] and the compared
        signal ``v`` [m/s] or ``x`` [m].
    model0 : LuGre or GMS
        Structure and start values (the parameters not in ``free`` stay fixed).
    free : sequence of str
        Parameters to fit: ``sigma0``, ``sigma1`` (LuGre); ``k1..kM``, ``xi1..xiM``,
        ``C``, or ``k``/``xi`` for all elements (GMS); ``Fc``, ``Fs``, ``vs``,
        ``delta``, ``sigma2`` (both directions) or with ``_pos``/``_neg``; ``m``;
        ``offset``.
    plant_mass : float
        Moving mass [kg] (start value when ``"m"`` is free).
    offset : float
        Constant force [N] (start value when ``"offset"`` is free).
    compare : {"v", "x"}
        Compared signal.
    bounds : mapping, optional
        ``{name: (low, high)}`` in natural units; default ``[0, inf)`` for
        non-negative parameters, ``(0, inf)`` for positive ones, unbounded ``offset``.
    starts : int
        Number of start points: the given values and ``starts - 1`` random
        perturbations (factor ``e^±1.5`` for log-parameters, ±50 % otherwise),
        screened by one :func:`~frictionkit.simulate_batch` call.
    refine : int
        How many of the best-screened starts are optimised to convergence.
    seed : int
        Random seed of the start perturbations.
    weight : array_like, optional
        Per-sample weights (default 1; sample 0 never counts).
    options : SimOptions, optional
        Integrator tolerances (default :data:`OUTPUT_ERROR_OPTIONS`).
    optimiser : {"trf", "lm"}
        ``"trf"`` (default): :func:`scipy.optimize.least_squares` trust-region
        reflective. ``"lm"``: Levenberg–Marquardt whose trial steps (three damping
        values) are judged in one :func:`~frictionkit.simulate_batch` call per
        iteration. Measured: on the 6-parameter LuGre benchmark ``"lm"`` needs
        ~190 simulations against ~260 for ``"trf"``, but on the GMS stiffness
        round trip it stalls on the non-smooth cost (4.7e-7 vs 2.6e-9), so
        ``"trf"`` is the default.
    max_nfev : int
        Iteration limit (``"lm"``) or evaluation limit (``"trf"``) per refined start.
    ftol, xtol
        Relative cost-reduction and (``"trf"`` only) step tolerances.
    step_tol : float
        ``"lm"`` stops when every step component is below ``step_tol`` times the
        parameter's standard error: further iterations cannot change the result
        by a statistically visible amount.
    workers : int, optional
        Threads for the Jacobian simulations (default: CPU count).
    diff_step : float
        Forward-difference step of the transformed parameters (relative for
        log-parameters). 1e-3 is large against the integrator noise (rtol 1e-6) yet
        small against the curvature; measured on GMS round trips, 1e-4 stalls in
        false minima and 1e-2 biases the result.
    progress : callable, optional
        Called after every residual evaluation as ``progress(nfev, simulations, cost)``
        (the CLI shows it as a live status line). Exceptions from it propagate.

    Returns
    -------
    IdentificationResult
        ``kind="output_error"``; ``model`` the fitted LuGre/GMS; ``diagnostics``
        holds ``nfev``, ``njev``, ``status``, ``cost_history``, ``start_costs``,
        ``mass``, ``offset``, ``condition_number``; ``data`` holds ``t``, ``y``, ``y_pred``.

    Raises
    ------
    ParameterError
        Unknown or repeated parameter names, bad settings.
    DataError
        Missing signals, irregular sampling.
    IdentificationError
        Every start fails to simulate, the optimiser stops without convergence
        (``max_nfev`` reached), or the Jacobian at the optimum is singular
        (a parameter has no effect on the output, or parameters are confounded).

    Examples
    --------
    >>> import numpy as np, frictionkit as fk
    >>> from frictionkit.identify.output_error import fit_output_error
    >>> true = fk.LuGre(fk.Stribeck(Fc=1.0, Fs=1.5, vs=1e-3, sigma2=0.4), sigma0=1e5, sigma1=63.2)
    >>> dt = 1e-3; t = np.arange(3001) * dt; u = 2.0 * np.sin(np.pi * t)
    >>> sim = fk.simulate(true, plant=fk.Mass(1.0), force=u, dt=dt)
    >>> start = fk.LuGre(true.static, sigma0=3e4, sigma1=100.0)
    >>> res = fit_output_error({"t": t, "F": u, "v": sim.v}, start, plant_mass=1.0)
    >>> round(res["sigma0"] / 1e5, 3)
    1.0
    """
    owner = "fit_output_error"
    if optimiser not in ("lm", "trf"):
        raise ParameterError(f"{owner}: optimiser = {optimiser!r}: must be 'lm' or 'trf'")
    if compare not in ("v", "x"):
        raise ParameterError(f"{owner}: compare = {compare!r}: must be 'v' or 'x'")
    plant_mass = val.positive(owner, "plant_mass", plant_mass)
    offset = val.finite(owner, "offset", offset)
    if not isinstance(starts, (int, np.integer)) or starts < 1:
        raise ParameterError(f"{owner}: starts = {starts!r}: must be an integer >= 1")
    refine = max(1, min(int(refine), int(starts)))
    t, u, x, v, prov, name = _arrays(data)
    y = x if compare == "x" else v
    if y is None:
        raise DataError(f"recording '{name}': compare = {compare!r} needs the signal {compare!r}")
    y = np.asarray(y, float)
    if compare == "x":
        y = y - y[0]
    dt = float(np.median(np.diff(t)))
    w = np.ones(u.size) if weight is None else val.signal("weight", weight)
    if w.size != u.size or (w < 0).any():
        raise DataError("weight must have one non-negative entry per sample")
    w = w.copy()
    w[0] = 0.0
    sw = np.sqrt(w)
    tmpl = _Template.of(model0, plant_mass, offset)
    names = tmpl.expand(free)
    theta0 = np.array([tmpl.get(n) for n in names])
    options = options or OUTPUT_ERROR_OPTIONS
    workers = workers or os.cpu_count() or 1
    prob = _Problem(tmpl, names, u, dt, y, compare, sw, options, theta0, workers)
    prob.diff_step = val.positive(owner, "diff_step", diff_step)
    if progress is not None and not callable(progress):
        raise ParameterError(f"{owner}: progress = {progress!r}: must be callable(nfev, simulations, cost) or None")
    prob.progress = progress
    lo, hi = _bounds_tr(names, tmpl, bounds, prob)
    p0 = prob.to_tr(theta0)
    if np.any(p0 < lo) or np.any(p0 > hi):
        j = int(np.flatnonzero((p0 < lo) | (p0 > hi))[0])
        raise ParameterError(f"{owner}: start value {names[j]} = {theta0[j]:.6g} lies outside its bounds")
    rng = np.random.default_rng(seed)
    pts = _start_points(p0, lo, hi, prob.is_log, int(starts), rng)

    # --- screening: one batched simulation for all starts (SSE only)
    start_costs = np.full(len(pts), np.inf)
    if len(pts) > 1:
        start_costs = _batch_costs(prob, pts, w, options)
        order = [int(i) for i in np.argsort(start_costs) if np.isfinite(start_costs[i])]
        if not order:
            raise IdentificationError(f"{owner}: the simulation failed at every one of the {len(pts)} start points")
    else:
        order = [0]

    best = None
    runs = []
    for i in order[:refine]:
        prob.cost_history = []
        with warnings.catch_warnings(), _blas_limit():
            warnings.simplefilter("ignore", RuntimeWarning)
            if optimiser == "lm":
                sol = _levenberg_marquardt(prob, pts[i], lo, hi, w, options, max_iter=max_nfev, ftol=ftol,
                                           step_tol=step_tol)
            else:
                sol = least_squares(prob.fun, pts[i], jac=prob.jac, bounds=(lo, hi), method="trf",
                                    x_scale=1.0, max_nfev=max_nfev, ftol=ftol, xtol=xtol, gtol=1e-12)
        runs.append({"start": i, "cost": float(sol.cost), "status": int(sol.status), "nfev": int(sol.nfev),
                     "njev": int(sol.njev or 0), "message": sol.message, "history": list(prob.cost_history)})
        if best is None or sol.cost < best[0].cost:
            best = (sol, runs[-1])
    sol, run = best
    if not np.isfinite(sol.cost) or sol.cost >= 0.5 * prob.big**2:
        raise IdentificationError(f"{owner}: the simulation fails at the optimum; check the start values and bounds")
    if sol.status == 0:
        raise IdentificationError(
            f"{owner}: {optimiser} did not converge within max_nfev = {max_nfev} "
            f"{'iterations' if optimiser == 'lm' else 'evaluations'} "
            f"(cost {run['history'][0]:.4g} -> {sol.cost:.4g}); raise max_nfev or improve the start values"
        )

    theta = prob.to_nat(sol.x)
    r = prob.fun(sol.x)
    J = prob.jac(sol.x)
    # natural-parameter Jacobian: d r / d theta = d r / d p * d p / d theta
    dpdth = np.where(prob.is_log, 1.0 / theta, 1.0 / prob.scale)
    n_obs = int((w > 0).sum())
    dof = n_obs - len(names)
    if dof <= 0:
        raise IdentificationError(f"{owner}: {n_obs} samples for {len(names)} parameters")
    colnorm = np.linalg.norm(J, axis=0)
    dead = [names[j] for j in range(len(names)) if colnorm[j] <= 1e-10 * max(colnorm.max(), 1e-300)]
    if dead:
        raise IdentificationError(
            f"{owner}: unidentifiable — {', '.join(dead)} has no effect on the simulated {compare} "
            "for this data (zero Jacobian column); fix it or use data that excite it"
        )
    Js = J / colnorm
    sv = np.linalg.svd(Js, compute_uv=False)
    cond = float(sv[0] / sv[-1]) if sv[-1] > 0 else math.inf
    if not np.isfinite(cond) or cond > 1e8:
        raise IdentificationError(
            f"{owner}: unidentifiable — the Jacobian is singular (condition number {cond:.3g}); "
            f"the parameters {names} are confounded on this data"
        )
    s2 = float(r @ r) / dof
    # covariance in column-normalised transformed coordinates (well conditioned), then
    # mapped to natural units: cov_theta = D C D with D = d theta / d p
    Ci = np.linalg.inv(Js.T @ Js) / np.outer(colnorm, colnorm)
    dthdp = 1.0 / dpdth
    cov = s2 * Ci * np.outer(dthdp, dthdp)
    st = parameter_statistics(theta, cov, dof)
    model, m_fit, off_fit = tmpl.build(names, theta)
    res_sim = prob.simulate_nat(theta)
    y_pred = res_sim.x if compare == "x" else res_sim.v
    warns = []
    for j, nm in enumerate(names):
        if np.isfinite(st["stderr"][j]) and st["stderr"][j] > 0.5 * abs(theta[j]):
            warns.append(f"{nm} is poorly determined (standard error {st['stderr'][j]:.3g} > 50 % of {theta[j]:.6g})")
        if np.isfinite(lo[j]) and abs(sol.x[j] - lo[j]) < 1e-6 * max(1, abs(lo[j])) or \
                np.isfinite(hi[j]) and abs(sol.x[j] - hi[j]) < 1e-6 * max(1, abs(hi[j])):
            warns.append(f"{nm} = {theta[j]:.6g} sits on its bound")
    resid = (y_pred - y)[w > 0]
    units_map = {"F": "N", "x": "m"}
    if isinstance(data, Recording):
        units_map = {"F": data.units["F"], "x": data.units["x"]}
    prov.update({"recording": name, "units": {"F": units_map["F"], "x": units_map["x"],
                                               compare: f"{units_map['x']}/s" if compare == "v" else units_map["x"]},
                 "procedure": {"method": "output error (seed 002 eq. 12)", "compare": compare,
                               "optimiser": ("Levenberg-Marquardt, batched trial steps" if optimiser == "lm"
                                             else "scipy.optimize.least_squares trf")
                                            + ", forward-difference Jacobian (threaded nogil simulations)",
                               "starts": int(starts), "refine": refine, "seed": int(seed),
                               "rtol": options.rtol, "atol_v": options.atol_v, "atol_F": options.atol_F}})
    return IdentificationResult(
        kind="output_error",
        model_name=tmpl.kind,
        model=model,
        names=tuple(names),
        values=theta,
        stderr=st["stderr"],
        ci95=st["ci"],
        units=tuple(_unit(n, units_map["F"], units_map["x"]) for n in names),
        correlation=st["correlation"],
        rms=float(np.sqrt(np.mean(resid**2))),
        relative_error_percent=float(100.0 * np.linalg.norm(resid) / max(np.linalg.norm(y[w > 0]), 1e-300)),
        n_obs=n_obs,
        dof=dof,
        success=True,
        message=str(sol.message),
        warnings=tuple(warns),
        diagnostics={"nfev": run["nfev"], "njev": run["njev"], "status": run["status"],
                     "iterations": run["njev"], "cost_history": run["history"],
                     "start_costs": start_costs.tolist(), "runs": [{k: v for k, v in rr.items() if k != "history"}
                                                                   for rr in runs],
                     "mass": float(m_fit), "offset": float(off_fit), "condition_number": cond,
                     "simulations": int(prob.nsim)},
        provenance=prov,
        data={"t": t, "y": y, "y_pred": y_pred},
    )
