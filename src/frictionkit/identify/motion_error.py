"""Motion-driven output error: the measured motion drives the law, the force is compared.

Drive logs are recorded under a controller: the motion is what the drive imposed,
the motor torque is what it took. So the natural output-error fit runs the friction
law **motion-driven** — :func:`frictionkit.simulate` with ``position=`` (or the
logged velocity integrated to a position) — and compares the predicted friction
force with the measured one::

    F_hat_k = F_law(x_0..k; theta) + J a_k + offset           (J and offset optional)
    min_theta  sum_k (F_k - F_hat_k)^2

over every sample where the drive is enabled. The force-driven direction (torque
drives a mass, velocity compared: :func:`.output_error.fit_output_error`) cannot
pin the bristle parameters of a position-controlled axis logged at tens of
milliseconds; this one at least says so (:mod:`.identifiability`).

Several records, and rests inside a record, are handled as **segments**: each run
of samples between rests (see :func:`frictionkit.data.find_rests`: torque logged
exactly zero over a run of samples, or a mask) is simulated from the unloaded state,
starting at the last rest sample; rest samples are not fitted.

Every dynamic law works (LuGre, Dahl, GMS, a ``Directional`` of one of them, a law
registered later): parameters are read from the law's fields
(:mod:`._law_params`), per direction with ``_pos`` / ``_neg``.
"""

from __future__ import annotations

import functools
import math
import warnings
from collections.abc import Mapping, Sequence

import numpy as np
from scipy.optimize import least_squares

from ..errors import DataError, IdentificationError, ParameterError
from ..models.gms import GMS
from ..models.lugre import Dahl, LuGre
from ..models.static import Directional
from . import _jacobian
from . import identifiability as idf
from ._advice import advisor, level, time_constants, unit
from ._law_params import LawTemplate, base_name, is_log
from .fit_options import MOTION_ERROR_FIT, FitOptions, fit_settings
from .motion_data import MotionData, _errors, _simulate_segments, _typical, evaluate_motion, motion_data
from .result import IdentificationResult
from typing import TYPE_CHECKING

if TYPE_CHECKING:
    from ..models.base import FrictionLaw
    from typing import Any

__all__ = ["MOTION_EXTRAS", "MotionData", "default_free", "evaluate_motion", "fit_motion_error", "motion_data",
           "motion_start"]

#: Parameters besides the law's: inertia ``J`` [kg or kg·m²] and a constant ``offset`` [N or N·m].
MOTION_EXTRAS = ("J", "offset")
_DYNAMIC = {"sigma0", "sigma1", "k", "C"}  # scaled together by the start grid
_START_FACTORS = (1e-2, 1e-1, 1.0, 1e1, 1e2, 1e3, 1e4)


def motion_start(kind: str, static: Any, data: Any, *, elements: int = 3, max_presliding: float | None = None,
                 drive: str = "auto", integration: str = "held", rests: Any="auto", min_rest: int = 3) -> FrictionLaw:
    """Start values of a motion-driven fit from the static map and the record.

    The dynamic stiffness is set so that the pre-sliding time constant
    ``|s(v)| / (sigma0 |v|)`` at the typical speed of the record equals one sample
    period — the edge of what the record can resolve (the fit's start grid then
    looks two decades slower and four faster) — unless that puts the pre-sliding
    displacement above ``max_presliding``.

    Parameters
    ----------
    kind : {"lugre", "gms", "dahl"}
    static : Stribeck | CoulombViscous | Directional
        The static map (e.g. ``identify static``'s result model).
    data, drive, integration, rests, min_rest
        As in :func:`motion_data`.
    elements : int
        GMS elements: equal weights ``1/M``, breakaway displacements a factor √10 apart.
    max_presliding : float, optional
        Largest pre-sliding displacement [m or rad] (see :func:`fit_motion_error`).

    Returns
    -------
    law
        ``LuGre(static, sigma0, sigma1)``, ``GMS(static, k, xi, C)`` or ``Dahl`` (a
        ``Directional`` of two for a direction-dependent map).
    """
    md = data if isinstance(data, MotionData) else motion_data(data, drive=drive, integration=integration,
                                                                rests=rests, min_rest=min_rest)
    v_typ, dt = _typical(md)
    s_typ = max(level(static, v_typ), 1e-300)
    s_max = max(s_typ, level(static, 1e-9 * v_typ))
    d_max = max_presliding if max_presliding is not None else math.inf
    if kind == "lugre":
        sigma0 = max(s_typ / (v_typ * dt), s_max / d_max)
        return LuGre(static, sigma0=sigma0, sigma1=0.01 * s_typ / v_typ)
    if kind == "gms":
        M = int(elements)
        if M < 1:
            raise ParameterError(f"elements = {elements!r}: must be >= 1")
        xi = np.full(M, 1.0 / M)
        top = min(v_typ * dt * 10.0 ** (0.25 * (M - 1)), d_max)  # the largest breakaway displacement
        disp = top * 10.0 ** (-0.5 * np.arange(M - 1, -1, -1))  # a factor sqrt(10) apart, largest last
        k = xi * s_max / disp
        return GMS(static, k=k.tolist(), xi=xi.tolist(), C=s_typ / dt)
    if kind == "dahl":
        def dahl(law):
            Fc = float(getattr(law, "Fc"))
            return Dahl(Fc=Fc, sigma0=max(Fc / (v_typ * dt), Fc / d_max), sigma2=float(getattr(law, "sigma2", 0.0)))
        if isinstance(static, Directional):
            return Directional(positive=dahl(static.positive), negative=dahl(static.negative))
        return dahl(static)
    raise ParameterError(f"kind = {kind!r}: must be 'lugre', 'gms' or 'dahl'")


def default_free(model) -> tuple[str, ...]:
    """The dynamic parameters of a law: LuGre ``sigma0, sigma1``; Dahl ``sigma0``; GMS ``k, C``."""
    law = model.positive if isinstance(model, Directional) else model
    if isinstance(law, GMS):
        return ("k", "C")
    if isinstance(law, Dahl):
        return ("sigma0",)
    if isinstance(law, LuGre):
        return ("sigma0", "sigma1")
    tmpl = LawTemplate.of(model)
    dyn = [n for n in tmpl.fields if n not in tmpl.static_fields and base_name(n) in _DYNAMIC]
    if not dyn:
        raise ParameterError(f"{type(law).__name__}: name the parameters to fit (free=...)")
    return tuple(dyn)


# --------------------------------------------------------------------------- the problem
class _Problem:
    """Residuals of the transformed parameters (log scale for positive ones)."""

    def __init__(self, tmpl: LawTemplate, names: list[str], md: MotionData, fixed: dict, theta0: np.ndarray,
                 F_scale: float):
        self.tmpl, self.names, self.md, self.fixed = tmpl, names, md, dict(fixed)
        self.law_names = [n for n in names if n not in MOTION_EXTRAS]
        self.log = np.array([is_log(n) for n in names])
        self.scale = np.where(self.log, 1.0, np.where(np.abs(theta0) > 0, np.abs(theta0), F_scale))
        self.nsim = 0
        self.nfev = 0
        self.history: list[float] = []
        self.big = 10.0 * F_scale
        self.n = md.n_fit
        self._cache: tuple[bytes, np.ndarray] | None = None
        #: exact Jacobians (forward sensitivities of the LuGre family; set by the fitter)
        self.exact = False
        self.nsens = 0  # evaluations by augmented (sensitivity) runs: the reduced problem's and jac_exact's
        self._coef_cache: dict = {}  # parameter -> packed-row derivatives (_jacobian.row_coefficients)

    def to_nat(self, p):
        return np.where(self.log, np.exp(np.clip(p, -700, 700)), p * self.scale)

    def to_tr(self, theta):
        with np.errstate(divide="ignore"):
            return np.where(self.log, np.log(np.maximum(theta, 1e-300)), theta / self.scale)

    def parts(self, theta):
        vals = dict(zip(self.names, theta))
        model = self.tmpl.build(self.law_names, [vals[n] for n in self.law_names])
        return model, vals.get("J", self.fixed["J"]), vals.get("offset", self.fixed["offset"])

    def resid_nat(self, theta) -> np.ndarray:
        try:
            model, J, off = self.parts(theta)
        except ParameterError:
            return np.full(self.n, self.big)
        sims = _simulate_segments(model, self.md)
        self.nsim += len(self.md.segments)
        out = np.concatenate([(Fs + J * s.a + off - s.F)[s.fit] for s, Fs in zip(self.md.segments, sims)])
        bad = ~np.isfinite(out)
        if bad.any():
            out[bad] = self.big
        return out

    def fun(self, p):
        p = np.asarray(p, float)
        key = p.tobytes()
        if self._cache is not None and self._cache[0] == key:
            return self._cache[1]
        r = self.resid_nat(self.to_nat(p))
        self.nfev += 1
        self.history.append(0.5 * float(r @ r))
        self._cache = (key, r)
        return r

    def jac_exact(self, p) -> np.ndarray | None:
        """``d r / d p`` from the exact sensitivities of the motion-driven update (None: not available)."""
        theta = self.to_nat(np.asarray(p, float))
        law = [i for i, n in enumerate(self.names) if n not in MOTION_EXTRAS]

        def build(th):
            return self.tmpl.build(self.law_names, th), 1.0, 0.0
        try:
            if not _jacobian.supports(build(theta[law])[0]):
                return None
            self.nsens += 1
            rows = []
            for s in self.md.segments:
                _, S, status = _jacobian.motion_driven(build, theta[law], s.x, s.dt, self._coef_cache)
                if status != 0:
                    return None
                rows.append(S[s.fit])
        except ParameterError:
            return None
        J = np.zeros((self.n, len(self.names)))
        J[:, law] = np.concatenate(rows)
        for j, n in enumerate(self.names):
            if n == "J":
                J[:, j] = np.concatenate([s.a[s.fit] for s in self.md.segments])
            elif n == "offset":
                J[:, j] = 1.0
        if not np.all(np.isfinite(J)):
            return None
        return J * np.where(self.log, theta, self.scale)[None, :]

    def jac(self, p, h: float = 1e-4):
        if self.exact:
            J = self.jac_exact(p)
            if J is not None:
                return J
        p = np.asarray(p, float)
        r0 = self.fun(p)
        J = np.empty((r0.size, p.size))
        for j in range(p.size):
            hj = h if self.log[j] else h * max(1.0, abs(p[j]))
            q = p.copy()
            q[j] += hj
            J[:, j] = (self.resid_nat(self.to_nat(q)) - r0) / hj
        return J


def _bounds(prob: _Problem, p0: np.ndarray, bounds: Mapping | None, floors: Mapping[str, float]):
    """Transformed bounds: e^±35 around the start for log-scale parameters, ``floors``, then ``bounds``."""
    lo = np.where(prob.log, p0 - 35.0, -np.inf)
    hi = np.where(prob.log, p0 + 35.0, np.inf)
    for j, n in enumerate(prob.names):
        if bounds is not None and n in bounds:
            a, b = (float(x) for x in bounds[n])
            if not a < b:
                raise ParameterError(f"bounds[{n!r}] = {bounds[n]!r}: need low < high")
            if prob.log[j]:
                lo[j] = math.log(a) if a > 0 else lo[j]
                hi[j] = math.log(b) if math.isfinite(b) else np.inf
            else:
                lo[j], hi[j] = a / prob.scale[j], b / prob.scale[j]
        elif n in floors and prob.log[j]:
            lo[j] = max(lo[j], math.log(floors[n]))
    if bounds is not None:
        unknown = set(bounds) - set(prob.names)
        if unknown:
            raise ParameterError(f"bounds for {sorted(unknown)}: not among the fitted parameters {prob.names}")
    return lo, hi


def _floors(names, tmpl: LawTemplate, theta0, model0, v_typ: float, dt: float,
            max_presliding: float | None) -> dict[str, float]:
    """Default lower bounds of physical meaning (natural units).

    * GMS ``C``: the slip time constant ``|s(v)| / C`` at most 10 samples (at most the
      start value's): ``C -> 0`` would freeze slipping elements at their breakaway force.
    * With ``max_presliding = X``: LuGre/Dahl ``sigma0 >= s_max / X`` and GMS
      ``k_i >= xi_i s_max / X``, with ``s_max`` the larger of the breakaway and Coulomb
      levels — no bristle or element deflects more than ``X`` before it slides.
    """
    out: dict[str, float] = {}
    for j, n in enumerate(names):
        b = base_name(n)
        side = "neg" if n.endswith("_neg") else "pos"
        law = (model0.negative if side == "neg" else model0.positive) if isinstance(model0, Directional) else model0
        s_max = max(level(law, v_typ), level(law, 1e-9 * max(v_typ, 1e-300)))
        if b == "C":
            out[n] = min(level(law, v_typ) / (10.0 * dt), theta0[j])
        elif b in ("sigma0", "k") and max_presliding is not None:
            xi = 1.0
            if b == "k":
                core = n[:-4] if n.endswith(("_pos", "_neg")) else n
                xi = tmpl.get(core.replace("k", "xi", 1) + (n[len(core):] if n != core else ""))
            out[n] = xi * s_max / max_presliding
    return out


def _inertia_start(md: MotionData, static, off: float) -> float:
    """Least-squares ``J`` of ``F - Fss(v) - offset = J a`` (floored at a tiny positive value)."""
    a = np.concatenate([s.a[s.fit] for s in md.segments])
    y = np.concatenate([(s.F - static.steady_state(s.v) - off)[s.fit] for s in md.segments])
    den = float(a @ a)
    J = float(a @ y) / den if den > 0 else 0.0
    F_scale = max(float(np.max(np.abs(y), initial=0.0)), 1e-300)
    a_scale = max(float(np.max(np.abs(a), initial=0.0)), 1e-300)
    return max(J, 1e-3 * F_scale / a_scale)


def _free_names(free, owner: str) -> tuple:
    """``free`` as a tuple of names (one string is one name)."""
    if isinstance(free, str):
        return (free,)
    if not isinstance(free, Sequence) and not hasattr(free, "__iter__"):
        raise ParameterError(f"{owner}: free = {free!r}: must be a sequence of parameter names")
    return tuple(free)


def _names_of_kind(kind: str, static, free, elements, initial, owner: str) -> None:
    """Check ``free`` against a stand-in of the start model ``kind`` would give (same fields, both
    directions equal, so only the names are judged); raises the ParameterError the fit would raise later."""
    from .start_values import static_law

    if kind not in ("lugre", "gms", "dahl"):
        return  # motion_error_start names the bad kind
    law = static_law(static, owner)
    law = law.positive if isinstance(law, Directional) else law
    if kind == "lugre":
        stand_in = LuGre(law, sigma0=1.0, sigma1=0.0)
    elif kind == "gms":
        given_k = initial.get("k") if isinstance(initial, Mapping) else None
        M = len(given_k) if isinstance(given_k, Sequence) and len(given_k) else elements
        if isinstance(M, bool) or not isinstance(M, (int, np.integer)) or M < 1:
            return  # motion_error_start names the bad count
        stand_in = GMS(law, k=[1.0] * M, xi=[1.0 / M] * M, C=1.0)
    else:
        stand_in = Dahl(Fc=1.0, sigma0=1.0, sigma2=0.0)
    LawTemplate.of(stand_in).expand(_free_names(free, owner), extra=MOTION_EXTRAS)


def fit_motion_error(
    data: Any,
    model0: str | FrictionLaw,
    *,
    static: Any=None,
    initial: Any="auto",
    elements: int = 3,
    free: Sequence[str] | None = None,
    drive: str = "auto",
    integration: str = "held",
    rests: Any="auto",
    min_rest: int = 3,
    inertia: float = 0.0,
    offset: float = 0.0,
    bounds: Mapping[str, tuple[float, float]] | None = None,
    max_presliding: float | None = None,
    fit: FitOptions | None = None,
    **settings: Any,
) -> IdentificationResult:
    """Fit a dynamic friction law with the recorded motion as input and the force as output.

    Parameters
    ----------
    data : Recording, mapping of arrays, or a list / dict of them
        One or several records: ``t`` [s], force ``F`` [N or N·m] and position ``x``
        or velocity ``v``. Each run between rests is simulated from the unloaded state.
    model0 : dynamic law, or "lugre" / "gms" / "dahl"
        Structure and start values: ``LuGre``, ``Dahl``, ``GMS``, a ``Directional``
        of one of them, or any registered law. A name: the structure, with ``static``
        the map and ``initial`` the start values (the same words as
        :func:`~.output_error.fit_output_error`).
    static : law, static-map result, or path, optional
        With a model name: the static map (a law, the result of ``fit_static_map``, or
        the JSON file ``identify static --json`` wrote).
    initial : "auto" or mapping
        With a model name: ``"auto"`` computes every start value
        (:func:`motion_start`); a mapping gives some of them (LuGre ``sigma0``,
        ``sigma1``; GMS ``k``, ``xi``, ``C``; Dahl ``sigma0``), see
        :func:`.start_values.motion_error_start`.
    elements : int
        GMS elements when ``model0="gms"`` and ``k``, ``xi`` are not given.
    free : sequence of str, optional
        Parameters to fit (default: the law's dynamic ones, LuGre ``sigma0, sigma1``,
        Dahl ``sigma0``, GMS ``k, C``). Any field of the law by name (``Fc``, ``xi``, ``k2``),
        per direction with ``_pos`` / ``_neg`` (``sigma0_pos``, ``sigma0_neg``: the fitted
        model is then a ``Directional``), and ``J`` (inertia), ``offset``.
    drive, integration, rests, min_rest
        How the records become motion segments, see :func:`motion_data`.
    inertia : float
        ``J`` [kg or kg·m²]: fixed value, or start value with ``"J"`` in ``free``
        (0 there means: start from the least-squares ``J`` of the static residual).
    offset : float
        Constant force [N or N·m]: fixed value or start value.
    bounds : mapping, optional
        ``{name: (low, high)}`` in natural units. Defaults: positive parameters within
        e^±35 of their start; GMS ``C`` at least ``|s(v)| / (10 dt)`` (slip time
        constant at most 10 samples at the typical speed: ``C -> 0`` would freeze the
        slipping elements at their breakaway force for the rest of the record).
    max_presliding : float, optional
        Largest pre-sliding displacement the axis can have [m or rad], e.g. one
        encoder count when the logs show none: bounds ``sigma0 >= s_max / X`` and
        ``k_i >= xi_i s_max / X`` (``s_max`` the larger of breakaway and Coulomb
        level). A record sampled far slower than the bristle dynamics cannot bound
        the stiffness from below by itself; without this bound a fit may explain a
        logger's one-sample lag by half a radian of "bristle" deflection.
    fit : FitOptions, optional
        How the search runs (default :data:`.fit_options.MOTION_ERROR_FIT`), the same
        object as the force-driven fit's; ``workers`` is the force drive's only.
    **settings
        Single :class:`~.fit_options.FitOptions` fields replacing those of ``fit``:

        * ``starts``: ``"auto"`` (default) the start model with its dynamic parameters
          (``sigma0``, ``sigma1``, ``k``, ``C``) scaled together by 10^-2 … 10^4,
          screened by cost; an integer ``n``: the start and ``n - 1`` random log
          perturbations (factor e^±1.5);
        * ``refine`` (2): how many of the best-screened starts are optimised;
        * ``seed`` (0): seed of the random starts;
        * ``profile`` (True): profile every positive parameter (re-optimising the
          others) at factors 10^±0.25 … 10^±3: the intervals then come from the profile
          and a flat profile is reported. Costs about ``10 p`` small optimisations;
        * ``max_nfev`` (300), ``ftol``, ``xtol`` (1e-10), ``diff_step`` (1e-4):
          :func:`scipy.optimize.least_squares` settings per refined start and the
          forward-difference step;
        * ``raise_on_failure`` (False): raise :class:`~frictionkit.IdentificationError`
          when the optimiser does not converge; by default the result says
          ``success=False`` and why.

    Returns
    -------
    IdentificationResult
        ``kind="output_error"``; ``model`` the fitted law; ``rms`` the training force
        RMS; ``stderr`` and ``ci95`` (log-scale or profile intervals for positive
        parameters); ``warnings`` one sentence per parameter the data cannot pin —
        which, why, and what experiment would pin it (``flagged`` is then true);
        ``diagnostics`` holds ``static_rms`` (the start model's static map at the
        measured velocity, with the fitted ``J a + offset``), ``map_only_rms`` (the
        map alone), ``J``, ``offset``,
        ``identifiability``, ``segments``, ``time_constants``, ``nfev``, ``status``;
        ``data`` holds ``t``, ``y`` (measured force), ``y_pred``, ``y_static``.

    Raises
    ------
    ParameterError
        Unknown or repeated names, bad settings, a start value outside its bounds.
    DataError
        Missing signals, irregular sampling, no motion.
    IdentificationError
        Only with ``raise_on_failure``: no convergence, or every start fails.

    Examples
    --------
    >>> import numpy as np, frictionkit as fk
    >>> from frictionkit.identify import fit_motion_error
    >>> true = fk.LuGre(fk.Stribeck(Fc=1.0, Fs=1.5, vs=1e-3, sigma2=0.4), sigma0=1e5, sigma1=30.0)
    >>> dt = 1e-4; t = np.arange(4001) * dt; x = 20e-6 * np.sin(2 * np.pi * 5 * t)
    >>> F = fk.simulate(true, position=x, dt=dt).friction
    >>> res = fit_motion_error({"t": t, "x": x, "F": F}, fk.LuGre(true.static, sigma0=3e4, sigma1=5.0))
    >>> round(res["sigma0"] / 1e5, 3), res.success
    (1.0, True)
    """
    owner = "fit_motion_error"
    cfg = fit_settings(owner, MOTION_ERROR_FIT, fit, settings,
                       unused={"workers": "the motion-driven Jacobian runs in one thread"})
    starts, refine, seed, profile = cfg.starts, cfg.refine, cfg.seed, cfg.profile
    max_nfev, ftol, xtol, raise_on_failure = cfg.max_nfev, cfg.ftol, cfg.xtol, cfg.raise_on_failure
    md = data if isinstance(data, MotionData) else motion_data(data, drive=drive, integration=integration,
                                                                rests=rests, min_rest=min_rest)
    if isinstance(model0, str):
        from .start_values import motion_error_start

        if not (initial == "auto" or isinstance(initial, Mapping)):
            raise ParameterError(f"{owner}: initial = {initial!r}: must be 'auto' or a mapping of start values")
        if free is not None:  # names first: the start search below takes seconds to minutes
            _names_of_kind(model0.lower(), static, free, elements, initial, owner)
        model0 = motion_error_start(model0.lower(), static, md, given=initial if isinstance(initial, Mapping) else None,
                                    elements=elements, max_presliding=max_presliding)
    elif static is not None or initial != "auto":
        raise ParameterError(f"{owner}: static= and initial= are for a model name (model0='lugre', 'gms' or "
                             f"'dahl'); the {type(model0).__name__} given carries its own map and start values")
    tmpl = LawTemplate.of(model0)
    free = _free_names(free, owner) if free is not None else default_free(model0)
    names = tmpl.expand(free, extra=MOTION_EXTRAS)
    offset = float(offset)
    inertia = float(inertia)
    if not (math.isfinite(offset) and math.isfinite(inertia)) or inertia < 0:
        raise ParameterError(f"{owner}: inertia = {inertia!r} must be finite and >= 0, offset = {offset!r} finite")
    if "J" in names and inertia <= 0:
        inertia = _inertia_start(md, model0, offset if "offset" not in names else 0.0)
    F_scale = max(float(np.sqrt(np.mean(np.concatenate([s.F[s.fit] for s in md.segments]) ** 2))), 1e-300)
    theta0 = []
    for n in names:
        v = inertia if n == "J" else offset if n == "offset" else tmpl.get(n)
        if is_log(n) and v <= 0:
            raise ParameterError(f"{owner}: start value {n} = {v!r}: must be > 0 (it is fitted on a log scale)")
        theta0.append(v)
    theta0 = np.array(theta0, dtype=float)
    n_obs = md.n_fit
    dof = n_obs - len(names)
    if dof <= 0:
        raise DataError(f"{owner}: {n_obs} fitted samples for {len(names)} parameters")
    v_typ, dt_typ = _typical(md)
    if max_presliding is not None and not (math.isfinite(max_presliding) and max_presliding > 0):
        raise ParameterError(f"{owner}: max_presliding = {max_presliding!r}: must be finite and > 0")
    floors = _floors(names, tmpl, theta0, model0, v_typ, dt_typ, max_presliding)
    theta0 = np.array([max(th, floors.get(n, th)) if n not in (bounds or {}) else th
                       for n, th in zip(names, theta0)])  # starts below a floor move up to it
    prob = _Problem(tmpl, names, md, {"J": inertia, "offset": offset}, theta0, F_scale)
    prob.exact = cfg.jacobian in ("auto", "sensitivity")  # where the law has sensitivity kernels (else differences)
    p0 = prob.to_tr(theta0)
    lo, hi = _bounds(prob, p0, bounds, floors)
    if np.any(p0 < lo) or np.any(p0 > hi):
        j = int(np.flatnonzero((p0 < lo) | (p0 > hi))[0])
        raise ParameterError(f"{owner}: start value {names[j]} = {theta0[j]:.6g} lies outside its bounds")
    pts = _starts(prob, p0, lo, hi, starts, seed)
    screened = np.array([0.5 * float(np.sum(prob.fun(p) ** 2)) for p in pts]) if len(pts) > 1 else np.zeros(1)
    order = [int(i) for i in np.argsort(screened) if np.isfinite(screened[i])]
    refine = max(1, int(refine))
    best, runs = None, []
    reduced = prob.exact and _jacobian.supports_motion(model0)
    for i in order[:refine]:
        prob.history = []
        with warnings.catch_warnings():
            warnings.simplefilter("ignore", RuntimeWarning)
            if reduced:  # one augmented run per evaluation, handed to trf as the (p + 1)-row problem
                red = _jacobian.MotionReducedProblem(prob)
                fun, jac = red.fun, red.jac
            else:
                fun, jac = prob.fun, functools.partial(prob.jac, h=cfg.diff_step)
            sol = least_squares(fun, pts[i], jac=jac, bounds=(lo, hi), method="trf", x_scale=1.0,
                                max_nfev=max_nfev, ftol=ftol, xtol=xtol, gtol=1e-12)
        runs.append({"start": i, "cost": float(sol.cost), "status": int(sol.status), "nfev": int(sol.nfev),
                     "njev": int(sol.njev or 0), "message": str(sol.message)})
        if best is None or sol.cost < best.cost:
            best = sol
    sol = best
    failed_all = sol is None or not np.isfinite(sol.cost) or sol.cost >= 0.5 * n_obs * prob.big**2 * 0.99
    success = not failed_all and sol.status > 0
    if failed_all:
        message = "the simulation fails at every start point; check the start values and bounds"
    elif sol.status == 0:
        message = (f"least_squares did not converge within max_nfev = {max_nfev} evaluations "
                   f"(cost {runs[0]['cost']:.4g}); raise max_nfev or improve the start values")
    else:
        message = str(sol.message)
    if not success and raise_on_failure:
        raise IdentificationError(f"{owner}: {message}")
    p_best = sol.x if sol is not None else p0
    theta = prob.to_nat(p_best)
    r = prob.fun(p_best)
    Jt = prob.jac(p_best, h=cfg.diff_step)
    # columns with respect to log(theta) (log scale) or theta (linear): d/dtheta = d/dp / scale
    Jt = np.where(prob.log, Jt, Jt / prob.scale)
    model, J_fit, off_fit = prob.parts(theta) if success or not failed_all else (None, inertia, offset)

    prof_fn = _profile_fn(prob, p_best, lo, hi, max_nfev) if profile and success else None
    adv = advisor(model if model is not None else model0, names, theta, v_typ, dt_typ, md.units)
    ana = idf.analyse(names, theta, Jt, r, dof, log_scale=prob.log, profile=prof_fn, advice=adv)
    warns = list(ana.warnings)
    for j, n in enumerate(names):
        at_lo = np.isfinite(lo[j]) and abs(p_best[j] - lo[j]) < 1e-6 * max(1.0, abs(lo[j]))
        at_hi = np.isfinite(hi[j]) and abs(p_best[j] - hi[j]) < 1e-6 * max(1.0, abs(hi[j]))
        if at_lo or at_hi:
            why = ""
            if at_lo and n in floors and (bounds is None or n not in bounds):
                why = (" (slip time constant of 10 samples)" if base_name(n) == "C"
                       else f" (pre-sliding displacement at most max_presliding = {max_presliding:g} {md.units['x']})")
            warns.append(f"{n} = {theta[j]:.6g} sits on its {'lower' if at_lo else 'upper'} bound{why}")
    if not success:
        warns.append(f"not converged: {message}")
    err = _errors(md, _simulate_segments(model, md), model0, J_fit, off_fit) if model is not None else None
    units = tuple(unit(n, md.units) for n in names)
    taus = time_constants(model, v_typ) if model is not None else {}
    diagnostics = {
        "nfev": int(sum(rr["nfev"] for rr in runs)), "status": int(sol.status) if sol is not None else -1,
        "runs": runs, "start_costs": screened.tolist(), "simulations": int(prob.nsim),
        "sensitivity_runs": int(prob.nsens),
        "J": float(J_fit), "offset": float(off_fit),
        "static_rms": err["static_rms"] if err else math.nan,
        "static_relative_error_percent": err["static_relative_error_percent"] if err else math.nan,
        "map_only_rms": err["map_only_rms"] if err else math.nan,
        "identifiability": ana.details, "segments": md.summary, "sample_time": dt_typ,
        "typical_speed": v_typ, "time_constants": taus,
    }
    prov = dict(md.provenance)
    prov.update({"units": dict(md.units, F=md.units["F"]),
                 "procedure": {"method": "motion-driven output error", "drive": md.drive, "compare": "F",
                               "integration": md.integration, "rests": md.rests,
                               "free": list(names), "max_presliding": max_presliding, "fixed_J": None if "J" in names else inertia,
                               "fixed_offset": None if "offset" in names else offset,
                               "starts": starts if isinstance(starts, str) else int(starts), "profile": bool(profile),
                               "optimiser": "scipy.optimize.least_squares trf, log scale for positive parameters, "
                                            + ("exact Jacobian (forward sensitivities)"
                                               if reduced
                                               else "forward-difference Jacobian")}})
    law = model.positive if isinstance(model, Directional) else (model if model is not None else model0)
    law = law.positive if isinstance(law, Directional) else law
    return IdentificationResult(
        kind="output_error",
        model_name=type(law).__name__.lower(),
        model=model,
        names=tuple(names),
        values=theta,
        stderr=ana.stderr,
        ci95=ana.ci95,
        units=units,
        correlation=ana.correlation,
        rms=err["rms"] if err else math.nan,
        relative_error_percent=err["relative_error_percent"] if err else math.nan,
        n_obs=n_obs,
        dof=dof,
        success=bool(success),
        message=message,
        warnings=tuple(warns),
        diagnostics=diagnostics,
        provenance=prov,
        data={"t": err["t"], "y": err["F"], "y_pred": err["F_pred"], "y_static": err["F_static"]} if err else {},
    )


def _starts(prob: _Problem, p0, lo, hi, starts, seed) -> list[np.ndarray]:
    with np.errstate(invalid="ignore"):
        a = np.where(np.isfinite(lo), lo + 1e-9 * np.maximum(1, np.abs(lo)), -np.inf)
        b = np.where(np.isfinite(hi), hi - 1e-9 * np.maximum(1, np.abs(hi)), np.inf)
    if isinstance(starts, str):
        if starts != "auto":
            raise ParameterError(f"starts = {starts!r}: must be 'auto' or an integer >= 1")
        dyn = np.array([base_name(n) in _DYNAMIC for n in prob.names])
        if not dyn.any():
            return [p0.copy()]
        return [np.clip(p0 + np.where(dyn, math.log(f), 0.0), a, b) for f in _START_FACTORS]
    if isinstance(starts, bool) or not isinstance(starts, (int, np.integer)) or starts < 1:
        raise ParameterError(f"starts = {starts!r}: must be 'auto' or an integer >= 1")
    rng = np.random.default_rng(seed)
    pts = [p0.copy()]
    for _ in range(int(starts) - 1):
        pts.append(np.clip(p0 + np.where(prob.log, rng.uniform(-1.5, 1.5, p0.size),
                                         rng.uniform(-0.5, 0.5, p0.size)), a, b))
    return pts


def _fd_columns(f, sub, h: float = 1e-4) -> np.ndarray:
    """Forward differences of ``f`` (fallback when an exact Jacobian fails at a point)."""
    r0 = f(sub)
    J = np.empty((r0.size, sub.size))
    for k in range(sub.size):
        q = sub.copy()
        hk = h * max(1.0, abs(q[k]))
        q[k] += hk
        J[:, k] = (f(q) - r0) / hk
    return J


def _profile_fn(prob: _Problem, p_best, lo, hi, max_nfev):
    """``profile(j, value) -> SSE`` minimised over the other parameters (warm-started outward)."""
    warm: dict[tuple[int, int], np.ndarray] = {}
    exact = prob.exact and prob.jac_exact(p_best) is not None

    def fn(j: int, value: float) -> float:
        pj = math.log(value) if prob.log[j] else value / prob.scale[j]
        if not lo[j] <= pj <= hi[j]:
            return math.inf
        others = [k for k in range(p_best.size) if k != j]
        side = 1 if pj > p_best[j] else -1
        if not others:
            q = p_best.copy()
            q[j] = pj
            r = prob.resid_nat(prob.to_nat(q))
            return float(r @ r)
        start = warm.get((j, side), p_best[others])

        def f(sub):
            q = p_best.copy()
            q[j] = pj
            q[others] = sub
            return prob.resid_nat(prob.to_nat(q))

        def jac(sub):  # exact columns of the other parameters (the law has sensitivities: checked below)
            q = p_best.copy()
            q[j] = pj
            q[others] = sub
            J = prob.jac_exact(q)
            return J[:, others] if J is not None else _fd_columns(f, sub)

        with warnings.catch_warnings():
            warnings.simplefilter("ignore", RuntimeWarning)
            sol = least_squares(f, np.clip(start, lo[others], hi[others]), bounds=(lo[others], hi[others]),
                                method="trf", diff_step=1e-4, max_nfev=max(30, 10 * len(others)),
                                ftol=1e-8, xtol=1e-8, jac=jac if exact else "2-point")
        warm[(j, side)] = sol.x
        return 2.0 * float(sol.cost)

    return fn

