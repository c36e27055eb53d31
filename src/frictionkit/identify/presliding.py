"""GMS pre-sliding identification from a force–displacement curve (seed 000 §5.2.1, eq. 19).

In pre-sliding every GMS element sticks until its force reaches ``xi_i s(v)``, so
a monotone branch of the friction force over the displacement is piecewise
linear: it starts with slope ``sum k_i`` and loses ``k_i`` at the displacement
``dx_i`` where element ``i`` breaks away. Fitting a continuous piecewise-linear
curve with ``M`` breakpoints therefore gives

* ``k_i`` = slope before breakpoint ``i`` − slope after it,
* ``xi_i = k_i dx_i / s(v)`` (seed 000 eq. 19) on a virgin branch (all elements
  unloaded at the start), or ``xi_i = k_i dx_i / (|s(v_before)| + |s(v_after)|)``
  on a branch after a velocity reversal (each element travels from
  ``-xi_i s`` to ``+xi_i s``: the factor 2 of a symmetric map).

The breakpoints are found by least squares over their positions (coordinate
search on a logarithmic grid, then Nelder–Mead; the slopes follow by linear
least squares for given breakpoints). The estimates are then polished by
minimising the motion-driven simulation error ``F_sim(x) - F_meas`` of the GMS
model over the whole record, and ``C`` is chosen on a grid by the same error.
"""

from __future__ import annotations

import math
import warnings

import numpy as np
from scipy.optimize import least_squares, minimize

from .. import _validate as val
from ..errors import DataError, IdentificationError, ParameterError, warn_renamed
from ..models.gms import GMS
from ..models.static import CoulombViscous, check_static
from ..simulation.core import simulate
from .fit_options import FitOptions, fit_settings
from .motion_data import MotionData, motion_data
from .result import IdentificationResult, parameter_statistics
from typing import TYPE_CHECKING

if TYPE_CHECKING:
    from numpy.typing import ArrayLike
    from typing import Any

__all__ = ["PRESLIDING_FIT", "fit_presliding", "piecewise_linear_fit"]

#: Defaults of :func:`fit_presliding`'s polish (least squares on the simulation error):
#: 60 evaluations, forward-difference step 1e-5 of the log parameters, ``ftol = xtol = 1e-8``.
PRESLIDING_FIT = FitOptions(max_nfev=60, diff_step=1e-5)


# --------------------------------------------------------------------------- piecewise-linear fit
def _hinge(u: np.ndarray, d: np.ndarray) -> np.ndarray:
    return np.column_stack([np.ones_like(u), u] + [np.maximum(u - dj, 0.0) for dj in d])


def _pl_sse(u, f, d) -> tuple[float, np.ndarray]:
    """Least-squares error and coefficients of the hinge fit with breakpoints ``d``.

    Solved by the normal equations of the norm-scaled columns, formed with ``einsum``: the threaded BLAS
    behind ``lstsq`` busy-waits on a loaded machine (measured on 2 busy cores, 501 x 34: 4.6 ms CPU per
    ``lstsq``, 0.56 ms this way; the error agrees to 1e-13, being stationary at the solution). A solution
    that is not the least-squares one (two breakpoints together: a singular system) falls back to ``lstsq``.
    """
    A = _hinge(u, np.sort(d))
    scale = np.maximum(np.sqrt(np.einsum("ij,ij->j", A, A)), 1e-300)
    As = A / scale
    try:
        with np.errstate(all="ignore"):
            c = np.linalg.solve(np.einsum("ij,ik->jk", As, As), np.einsum("ij,i->j", As, f))
            r = f - np.einsum("ij,j->i", As, c)
            normal = np.einsum("ij,i->j", As, r)
        if np.all(np.isfinite(c)) and np.max(np.abs(normal)) <= _PL_NORMAL_TOL * max(float(np.linalg.norm(f)), 1e-300):
            return float(r @ r), c / scale
    except np.linalg.LinAlgError:
        pass
    coef, *_ = np.linalg.lstsq(A, f, rcond=None)
    r = f - A @ coef
    return float(r @ r), coef


#: Evaluation budget of the Nelder-Mead polish of the breakpoints. Up to 8 breakpoints it converges within
#: it (measured: about 3,500 evaluations at 8 on a 501-sample branch, results unchanged); at 16 and 32 the
#: polish ran to its 400·M iteration limit (42,000 evaluations at 16: 12 s of CPU, minutes under load) for an
#: error 10-35 % below the sweep's. With the budget, 32 breakpoints take about 2 s of CPU.
_PL_POLISH_MAXFEV = 4000
#: Relative singular-value cut-off of the fixed columns in :func:`_sweep_sse` (two breakpoints on one
#: candidate make two equal hinge columns: their common direction is projected out once).
_PL_RANK_RTOL = 1e-10
#: A normal-equation solution of :func:`_pl_sse` is kept when its residual is orthogonal to every column to
#: this fraction of |f| (a least-squares solution; measured 1e-15 when the columns are independent).
_PL_NORMAL_TOL = 1e-9


def _sweep_sse(u, f, others, hinges) -> np.ndarray:
    """Error of the fit with breakpoints ``others`` plus each candidate hinge column, all candidates at once.

    Projects ``f`` and the candidates' columns off the span of the fixed columns (one SVD); the error with
    candidate ``h`` added is then ``|f_r|² - (h_r·f_r)² / |h_r|²``. Replaces one least-squares solve per
    candidate (80 per breakpoint and sweep: 22,000 solves at 32 breakpoints).
    """
    A = _hinge(u, np.sort(others))
    A = A / np.maximum(np.linalg.norm(A, axis=0), 1e-300)
    U, sv, _ = np.linalg.svd(A, full_matrices=False)
    U = U[:, sv > sv[0] * _PL_RANK_RTOL]
    fr = f - U @ (U.T @ f)
    hr = hinges - U @ (U.T @ hinges)
    den = np.einsum("ij,ij->j", hr, hr)
    own = np.einsum("ij,ij->j", hinges, hinges)
    usable = den > _PL_RANK_RTOL * np.maximum(own, 1e-300)  # a candidate already in the span adds nothing
    gain = np.zeros(den.size)
    gain[usable] = (hr[:, usable].T @ fr) ** 2 / den[usable]
    return float(fr @ fr) - gain


def piecewise_linear_fit(u: ArrayLike, f: ArrayLike, n_breaks: int, *, grid: int = 80) -> dict:
    """Continuous piecewise-linear least-squares fit with ``n_breaks`` free breakpoints.

    Parameters
    ----------
    u : array_like
        Abscissa (displacement from the branch start [m]), >= 0.
    f : array_like
        Ordinate (force change along the branch [N]).
    n_breaks : int
        Number of breakpoints (>= 1); the curve has ``n_breaks + 1`` segments.
    grid : int
        Candidate breakpoints per coordinate sweep (logarithmically spaced).

    Returns
    -------
    dict
        ``breaks`` (sorted, [m]), ``slopes`` (``n_breaks + 1`` segment slopes [N/m]),
        ``intercept`` [N], ``sse`` [N²].

    Examples
    --------
    >>> import numpy as np
    >>> from frictionkit.identify.presliding import piecewise_linear_fit
    >>> u = np.linspace(0, 10, 201)
    >>> f = np.minimum(3 * u, 6 + 0.5 * (u - 2))
    >>> fit = piecewise_linear_fit(u, f, 1)
    >>> np.round(fit["breaks"], 3).tolist(), np.round(fit["slopes"], 3).tolist()
    ([2.0], [3.0, 0.5])
    """
    u = val.signal("piecewise_linear_fit: u", u)
    f = val.signal("piecewise_linear_fit: f", f)
    if u.size != f.size:
        raise DataError(f"piecewise_linear_fit: u has {u.size} samples, f has {f.size}: one force per abscissa")
    if isinstance(n_breaks, bool) or not isinstance(n_breaks, (int, np.integer)) or n_breaks < 1:
        raise ParameterError(f"piecewise_linear_fit: n_breaks = {n_breaks!r}: must be an integer >= 1")
    n_breaks = int(n_breaks)
    if isinstance(grid, bool) or not isinstance(grid, (int, np.integer)) or grid < 2:
        raise ParameterError(f"piecewise_linear_fit: grid = {grid!r}: must be an integer >= 2 (candidate breakpoints "
                             "per sweep)")
    pos = u[u > 0]
    if pos.size == 0 or np.unique(u).size < 2 * n_breaks + 2:
        raise DataError(
            f"piecewise_linear_fit: {np.unique(u).size} distinct abscissae are too few for {n_breaks} breakpoint(s)"
        )
    lo, hi = float(np.min(pos)), float(np.max(u))
    cand = np.geomspace(max(lo, hi * 1e-4), hi, grid)[:-1]
    # start: geometric spacing
    d = np.geomspace(max(lo, hi * 1e-3), hi * 0.8, n_breaks) if n_breaks > 1 else np.array([hi * 0.1])
    best, _ = _pl_sse(u, f, d)
    hinges = np.maximum(u[:, None] - cand[None, :], 0.0)  # every candidate's hinge column, once
    for _ in range(6):
        improved = False
        for j in range(n_breaks):
            trial = d.copy()
            trial[j] = cand[int(np.argmin(_sweep_sse(u, f, np.delete(d, j), hinges)))]
            s, _ = _pl_sse(u, f, trial)  # the exact error decides, as before
            if s < best * (1 - 1e-12):
                best, d, improved = s, trial, True
        if not improved:
            break
    # polish in log coordinates
    res = minimize(lambda q: _pl_sse(u, f, np.exp(q))[0], np.log(np.sort(d)), method="Nelder-Mead",
                   options={"xatol": 1e-6, "fatol": 1e-14 * max(best, 1e-300), "maxiter": 400 * n_breaks,
                            "maxfev": _PL_POLISH_MAXFEV})
    if res.fun < best:
        d = np.exp(res.x)
    d = np.sort(d)
    sse, coef = _pl_sse(u, f, d)
    slopes = coef[1] + np.r_[0.0, np.cumsum(coef[2:])]
    return {"breaks": d, "slopes": slopes, "intercept": float(coef[0]), "sse": sse}


# --------------------------------------------------------------------------- branches
def _branches(x: np.ndarray) -> list[tuple[int, int]]:
    """Index ranges ``[a, b]`` (inclusive) of the monotone runs of ``x``."""
    dx = np.diff(x)
    s = np.sign(dx)
    nz = np.flatnonzero(s)
    if nz.size == 0:
        return []
    last = s[nz[0]]
    for i in range(s.size):
        if s[i] == 0:
            s[i] = last
        else:
            last = s[i]
    cuts = np.flatnonzero(np.diff(s) != 0) + 1
    edges = np.r_[0, cuts, dx.size]
    return [(int(a), int(b)) for a, b in zip(edges[:-1], edges[1:])]


def _s_abs(static, v: float) -> float:
    return float(abs(static.stribeck(np.array([v]))[0]))


def _times(md: MotionData) -> np.ndarray:
    """Time of every fitted sample, the records one after the other."""
    out, shift, last, rec = [], 0.0, None, None
    for sg in md.segments:
        if rec is not None and sg.record != rec:
            shift = last + sg.dt - float(sg.t[0])
        rec = sg.record
        out.append(sg.t[sg.fit] + shift)
        last = float(out[-1][-1]) if out[-1].size else last
    return np.concatenate(out)


#: Most elements :func:`fit_presliding` takes (the CLI's ``--elements`` bound is the same).
#: One branch rarely resolves more than a dozen breakpoints — so larger requests are refused, not
#: run. The breakpoint search (:func:`piecewise_linear_fit`) takes 5 s of CPU at 32 on a 501-sample
#: branch and 14 s on a 2,001-sample one (2 busy cores, round 10; 9 min before its sweep was one
#: projection per breakpoint and its polish got an evaluation budget).
MAX_ELEMENTS = 32


@val.typed_arguments  # argument types named at the boundary (issue 13 round 11)
def fit_presliding(
    data: Any,
    *,
    elements: int,
    static: Any=None,
    branch: str = "auto",
    C: float | None = None,
    polish: bool = True,
    rests: Any="auto",
    min_rest: int = 3,
    fit: FitOptions | None = None,
    **settings: Any,
) -> IdentificationResult:
    """Identify a GMS model's ``k_i``, ``xi_i`` (and ``C``) from pre-sliding data (seed 000 eq. 19).

    Parameters
    ----------
    data : Recording or mapping, or a list / dict of them
        Motion-driven test: uniformly sampled ``t`` [s], position ``x`` [m] and the
        friction force ``F`` [N] (e.g. a slow triangle of a few tens of µm). Several
        records, and the runs between rests inside a record, are cut into segments as
        in the motion-driven output error (:func:`.motion_data.motion_data`): the
        breakpoints come from the first segment with a suitable branch, the ``C`` grid
        and the polish use every segment, each simulated from the unloaded state at
        its record's own sample period.
    elements : int
        Number ``M`` of Maxwell-slip elements (breakpoints), 1 … :data:`MAX_ELEMENTS` (32).
    static : Stribeck | CoulombViscous | Directional, optional
        The static map ``s(v)`` identified before (seed 000 step 1). Default: a
        Coulomb level equal to the plateau of the branch (``xi`` then sum to ≈ 1).
    branch : {"auto", "virgin", "reversal"}
        Which monotone branch to fit: the first one starting from the unloaded state
        (``"virgin"``) or the first one after a velocity reversal (``"reversal"``,
        factor 2). ``"auto"`` picks virgin when ``|F[0]|`` is below 5 % of the peak force.
    C : float, optional
        Attraction constant [N/s]. Default: chosen on a grid by the simulation
        error over time constants ``|s|/C`` from ``10 dt`` to the record length; when
        the data cannot tell (constant-speed tests) the largest candidate within
        0.1 % of the best error — the fastest convergence to ``s(v)``, as seed 000
        §5.2.1 asks — is kept and a warning says so.
    polish : bool
        Polish ``k_i``, ``xi_i`` by least squares on the motion-driven simulation
        error over the whole record (standard errors come from this step). Was
        ``refine`` (a bool) before; ``refine=True/False`` still works for one release
        with a :class:`~frictionkit.errors.FrictionKitDeprecationWarning` —
        ``refine`` is :class:`~.fit_options.FitOptions`' count of optimised starts.
    rests, min_rest
        Where the records are cut (state reset, rest samples not fitted): ``"auto"``
        (force logged exactly 0 over ``min_rest`` samples), a mask, or None; see
        :func:`.motion_data.motion_data`. A force sensor quantised so coarsely that a
        slow zero crossing reads exactly 0 for ``min_rest`` samples would be cut there:
        give ``rests=None`` (or a larger ``min_rest``) for such records.
    fit : FitOptions, optional
        How the polish runs (default :data:`PRESLIDING_FIT`).
    **settings
        Single :class:`~.fit_options.FitOptions` fields replacing those of ``fit``:
        ``max_nfev``, ``ftol``, ``xtol``, ``diff_step``, ``raise_on_failure``.

    Returns
    -------
    IdentificationResult
        ``kind="presliding"``, ``model`` a :class:`~frictionkit.GMS`; parameters
        ``k1..kM`` [N/m] and ``xi1..xiM`` [-] ordered by breakaway displacement;
        ``diagnostics`` holds ``breakpoints`` [m], ``slopes`` [N/m],
        ``total_stiffness`` [N/m], ``s_level`` [N], ``factor``, ``C``,
        ``C_grid_rms``, ``initial_k``, ``initial_xi`` (eq. 19 before refinement);
        ``data`` holds ``t``, ``x`` (the fitted samples' positions), ``y`` (measured
        force) and ``y_pred`` (simulated); ``.plot()`` draws the fit over time and as
        the force–displacement loop.
        ``success`` is False, with the reason in ``message``, when the branch is not
        concave (a slope rises at a breakpoint: ``M`` too large or not pre-sliding
        data; ``model`` is then None and the values NaN), when the polish does not
        converge (the eq. 19 values are kept, without intervals) or when its Jacobian
        is singular (an element the record does not excite; no intervals);
        ``diagnostics["polish"]`` says which: "off", "converged", "stopped" (at
        ``max_nfev``, below its start cost: the values reached are kept, with
        intervals), "failed" (at ``max_nfev``, above its start: eq. 19 values kept),
        "singular", "not run" (not concave).

    Raises
    ------
    ParameterError
        Bad settings (``elements``, ``branch``, ``C``, a FitOptions field the fit does not read).
    DataError
        No position or force, no suitable branch, too few distinct positions.
    IdentificationError
        Only with ``raise_on_failure=True``: the failures above.

    Examples
    --------
    >>> import numpy as np, frictionkit as fk
    >>> from frictionkit.identify.presliding import fit_presliding
    >>> law = fk.Stribeck(Fc=1.0, Fs=1.5, vs=1e-3)
    >>> true = fk.GMS(law, k=[4e5, 1e5, 2e4], xi=[0.2, 0.3, 0.5], C=20.0)
    >>> x = np.r_[np.linspace(0, 50e-6, 2501), np.linspace(50e-6, -50e-6, 5001)[1:]]
    >>> t = np.arange(x.size) * 1e-3
    >>> F = fk.simulate(true, position=x, dt=1e-3).friction
    >>> res = fit_presliding({"t": t, "x": x, "F": F}, elements=3, static=law)
    >>> bool(abs(res.diagnostics["total_stiffness"] / 5.2e5 - 1) < 0.05)
    True
    """
    owner = "fit_presliding"
    if "refine" in settings and val.is_bool(settings["refine"]):  # the old bool of the polish
        warn_renamed(owner, "refine", "polish")
        polish = bool(settings.pop("refine"))
    if not val.is_bool(polish):
        raise ParameterError(f"{owner}: polish = {polish!r}: must be True or False")
    if static is not None:  # static="abc" was "'str' object has no attribute 'stribeck'" (issue 13 round 11)
        check_static(owner, static)
    why = "the pre-sliding fit has one start (the eq. 19 breakpoints)"
    cfg = fit_settings(owner, PRESLIDING_FIT, fit, settings,
                       unused={"starts": why, "refine": why, "seed": why, "workers": "the polish runs in one thread",
                               "jacobian": "the polish differences its Jacobian (GMS has no sensitivity kernel)",
                               "profile": "the pre-sliding fit has no likelihood profiles"})
    max_nfev = cfg.max_nfev
    if val.is_bool(elements) or not isinstance(elements, (int, np.integer)) or not 1 <= elements <= MAX_ELEMENTS:
        raise ParameterError(
            f"{owner}: elements = {elements!r}: must be an integer in 1 … {MAX_ELEMENTS} (the breakpoint "
            "search grows with M: 32 elements on a 2,000-sample branch take about 20 s)"
        )
    if branch not in ("auto", "virgin", "reversal"):
        raise ParameterError(f"{owner}: branch = {branch!r}: must be 'auto', 'virgin' or 'reversal'")
    if C is not None:
        C = val.positive(owner, "C", C)
    md = motion_data(data, drive="position", rests=rests, min_rest=min_rest)
    segs = md.segments
    want = 4
    pick = None
    for j, sg in enumerate(segs):  # the first segment with a usable branch
        brs_j = [b_ for b_ in _branches(sg.x) if b_[1] - b_[0] >= want]
        if brs_j and (branch != "reversal" or any(b_[0] > 0 for b_ in brs_j)):
            pick = j
            break
    if pick is None:
        name = md.records[0]
        if branch != "reversal" and len(segs) > 1 and any(np.ptp(sg.x) > 0 for sg in segs):
            # the position moves, but the rests cut it into runs too short for a branch (min_rest=1 on a
            # force logged 0 at every third sample was reported as "the position does not move")
            longest = max(sg.x.size for sg in segs)
            raise DataError(f"{owner}: no pre-sliding branch of {want} samples in any of the {len(segs)} runs between "
                            f"rests (longest {longest} samples); the rests cut the motion too finely: raise "
                            f"min_rest (now {min_rest}) or give rests=None / a mask")
        raise DataError(f"recording '{name}': the position does not move; no pre-sliding branch"
                        if branch != "reversal" else f"recording '{name}': no branch after a velocity reversal")
    seg = segs[pick]
    dt = seg.dt  # the branch's period (records may be sampled differently: each is simulated at its own)
    rec_name = seg.record
    x, F = seg.x, seg.F
    brs = [b_ for b_ in _branches(x) if b_[1] - b_[0] >= want]
    Fpk = float(np.max(np.abs(F)))
    if branch == "auto":
        branch = "virgin" if abs(F[0]) < 0.05 * Fpk and _branches(x)[0][0] == 0 else "reversal"
    if branch == "virgin":
        a, b = brs[0]
    else:
        later = [br for br in brs if br[0] > 0]
        if not later:
            raise DataError(f"recording '{rec_name}': no branch after a velocity reversal")
        a, b = later[0]
    sgn = 1.0 if x[b] > x[a] else -1.0
    uu = sgn * (x[a:b + 1] - x[a])
    ff = sgn * (F[a:b + 1] - F[a])
    v_new = sgn * float(np.median(np.abs(np.diff(x[a:b + 1])))) / dt
    fit = piecewise_linear_fit(uu, ff, int(elements))
    slopes = fit["slopes"]
    k0 = slopes[:-1] - slopes[1:]
    k0[-1] = slopes[-2] - max(slopes[-1], 0.0) if slopes.size >= 2 else k0[-1]
    M = int(elements)
    names = tuple([f"k{i}" for i in range(1, M + 1)] + [f"xi{i}" for i in range(1, M + 1)])
    Fu = md.units["F"]
    xu = md.units["x"]
    prov = dict(md.provenance["records"][0])
    prov.pop("name", None)
    if len(md.records) > 1:
        prov["records"] = list(md.records)
    prov.update({"recording": rec_name, "units": {"F": Fu, "x": xu},
                 "procedure": {"method": "GMS pre-sliding breakpoints (seed 000 eq. 19) + simulation error",
                               "branch": branch, "samples": [int(a), int(b)], "segment": int(pick),
                               "elements": M, "polish": bool(polish), "rests": md.rests,
                               "min_rest": int(min_rest), "fit": cfg.to_dict()}})
    from ._advice import DIMENSIONLESS

    units = tuple([f"{Fu}/{xu}"] * M + [DIMENSIONLESS] * M)
    if np.any(k0 <= 0):
        j = int(np.flatnonzero(k0 <= 0)[0])
        message = (f"the {branch} branch is not concave — the slope rises at breakpoint {j + 1} "
                   f"({slopes[j]:.4g} -> {slopes[j + 1]:.4g} {Fu}/{xu}); fewer elements (M = {elements}) or "
                   "pre-sliding data needed")
        if cfg.raise_on_failure:
            raise IdentificationError(f"{owner}: {message}")
        nan = np.full(2 * M, np.nan)
        return IdentificationResult(
            kind="presliding", model_name=f"gms_M{M}", model=None, names=names, values=nan, stderr=nan,
            ci95=np.column_stack([nan, nan]), units=units, correlation=np.full((2 * M, 2 * M), np.nan),
            rms=math.nan, relative_error_percent=math.nan, n_obs=int(sum(int(sg.fit.sum()) for sg in segs)),
            dof=int(sum(int(sg.fit.sum()) for sg in segs)) - 2 * M, success=False, message=message,
            warnings=(f"not identified: {message}",),
            diagnostics={"breakpoints": fit["breaks"].tolist(), "slopes": slopes.tolist(), "branch": branch,
                         "segments": md.summary, "polish": "not run"},
            provenance=prov, data={})
    plateau = float(ff.max())
    if static is None:
        level = plateau if branch == "virgin" else plateau / 2.0
        static = CoulombViscous(Fc=max(level, 1e-12))
    s_new = _s_abs(static, v_new)
    if branch == "virgin":
        factor_level = s_new
        factor = 1.0
    else:
        s_prev = _s_abs(static, -v_new)
        factor_level = s_prev + s_new
        factor = factor_level / s_new
    xi0 = k0 * fit["breaks"] / factor_level
    # the attraction constant: grid over the time constant |s|/C
    s_ref = max(_s_abs(static, v_new), 1e-12)
    if C is None:
        dts = [sg.dt for sg in segs]
        taus = np.geomspace(10 * min(dts), max(max(float(sg.t[-1] - sg.t[0]) for sg in segs), 100 * max(dts)), 13)
        C_grid = s_ref / taus
    else:
        C_grid = np.array([C])

    F_all = np.concatenate([sg.F[sg.fit] for sg in segs])  # every fitted sample of every segment
    x_all = np.concatenate([sg.x[sg.fit] for sg in segs])  # their positions: the plot's F(x) loop
    t_all = _times(md)

    def sim_F(k, xi, Cv):
        with warnings.catch_warnings():
            warnings.simplefilter("ignore", RuntimeWarning)
            mdl = GMS(static, k=k, xi=xi, C=Cv)
            return np.concatenate([simulate(mdl, position=sg.x, dt=sg.dt).friction[sg.fit] for sg in segs])

    def rms_of(k, xi, Cv):
        r = sim_F(k, xi, Cv) - F_all
        return float(np.sqrt(np.mean(r**2))) if np.isfinite(r).all() else math.inf

    grid_rms = np.array([rms_of(k0, xi0, c) for c in C_grid])
    best_rms = float(np.min(grid_rms))
    ok = np.flatnonzero(grid_rms <= best_rms * 1.001 + 1e-300)
    C_sel = float(C_grid[ok].max())
    note = "" if ok.size == 1 or C is not None else (
        f"C is not determined by this record ({ok.size} of {C_grid.size} grid values within 0.1 % of the best "
        "error); the largest (fastest convergence to s(v), seed 000 §5.2.1) was kept")
    p0 = np.log(np.r_[k0, np.maximum(xi0, 1e-12)])
    theta = np.exp(p0)
    n = F_all.size
    dof = n - 2 * M
    message = "piecewise-linear fit (eq. 19), no polish"
    success = True
    polish_state = "off"
    cov = np.full((2 * M, 2 * M), np.nan)
    if polish:
        def resid(p):
            r = sim_F(np.exp(p[:M]), np.exp(p[M:]), C_sel) - F_all
            r[~np.isfinite(r)] = 10 * Fpk
            return r

        sol = least_squares(resid, p0, method="trf", diff_step=cfg.diff_step, max_nfev=max_nfev, x_scale=1.0,
                            ftol=cfg.ftol, xtol=cfg.xtol)
        cost0 = 0.5 * float(np.sum(resid(p0) ** 2)) if sol.status == 0 else math.inf
        if sol.status == 0 and sol.cost > cost0:
            success, polish_state = False, "failed"
            message = (f"the simulation-error polish did not converge within max_nfev = {max_nfev} evaluations "
                       f"and ended above its start ({sol.message}); the eq. 19 values are kept, without intervals")
        else:
            theta = np.exp(sol.x)
            Jn = sol.jac / theta  # d r / d theta
            r = sol.fun
            s2 = float(r @ r) / dof
            JtJ = Jn.T @ Jn
            if np.linalg.matrix_rank(JtJ) < 2 * M:
                success, polish_state = False, "singular"
                message = (f"unidentifiable — the simulation-error Jacobian is singular; the record does not "
                           f"excite every one of the {M} elements (use fewer elements or a longer stroke)")
            else:
                cov = s2 * np.linalg.pinv(JtJ)
                if sol.status == 0:  # stopped by the evaluation limit, below its start
                    success, polish_state = False, "stopped"
                    message = (f"the simulation-error polish did not converge within max_nfev = {max_nfev} "
                               f"evaluations (cost {cost0:.4g} -> {sol.cost:.4g}); raise max_nfev")
                else:
                    polish_state = "converged"
                    message = f"polished by simulation error: {sol.message}"
        if not success and cfg.raise_on_failure:
            raise IdentificationError(f"{owner}: {message}")
    st = parameter_statistics(theta, cov, dof)
    k, xi = theta[:M], theta[M:]
    model = GMS(static, k=k, xi=xi, C=C_sel)
    F_pred = sim_F(k, xi, C_sel)
    r = F_pred - F_all
    warns = [] if not note else [note]
    if not success:
        warns.append(f"not identified: {message}")
    return IdentificationResult(
        kind="presliding",
        model_name=f"gms_M{M}",
        model=model,
        names=names,
        values=theta,
        stderr=st["stderr"],
        ci95=st["ci"],
        units=units,
        correlation=st["correlation"],
        rms=float(np.sqrt(np.mean(r**2))),
        relative_error_percent=float(100 * np.linalg.norm(r) / max(np.linalg.norm(F_all), 1e-300)),
        n_obs=int(n),
        dof=int(dof),
        success=success,
        message=message,
        warnings=tuple(warns),
        diagnostics={"breakpoints": fit["breaks"].tolist(), "slopes": slopes.tolist(),
                     "total_stiffness": float(np.sum(k)), "initial_total_stiffness": float(np.sum(k0)),
                     "initial_k": k0.tolist(), "initial_xi": xi0.tolist(), "s_level": s_new,
                     "factor": factor, "C": C_sel, "C_grid": C_grid.tolist(), "C_grid_rms": grid_rms.tolist(),
                     "branch": branch, "segments": md.summary, "polish": polish_state},
        provenance=prov,
        data={"t": t_all, "x": x_all, "y": F_all, "y_pred": F_pred},
    )
