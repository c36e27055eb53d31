"""Two-step LuGre identification of a slow, heavy rotary axis (seed 002 §3, eqs. 10 and 12).

The procedure the SDSS telescope paper ran on its three axes, as a workflow for any axis of
the kind (large inertia, low speed, friction-dominated near zero velocity):

1. **static map** (eq. 10): the steady-state points of closed-loop constant-velocity runs in
   both directions (mean velocity and mean torque per run) are fitted per direction with eq. 9b
   and a fixed exponent δ = 2 (or eq. 9a): ``Fc, Fs, vs, sigma2`` for each direction. Eq. 10
   needs the speed of each run to be constant: a run whose velocity ripple (from its encoder
   angle, :func:`constant_velocity_ripple`) exceeds :data:`MAX_RIPPLE_PERCENT` — a position loop
   hunting where the map falls faster than the loop damps — is not a constant-velocity point and
   is rejected by name (:func:`screen_constant_velocity`; our procedure, the paper has none);
2. **dynamic parameters** (eq. 12): ``sigma0, sigma1`` by output error on an open-loop,
   torque-driven run below breakaway, the static map held fixed. The start values come from
   the same sub-breakaway triangle run (:func:`~frictionkit.identify.initial_guess_lugre`,
   the pre-sliding slope), as the paper does.

``order="dynamic_first"`` is the paper's altitude procedure, where no constant-velocity runs
exist and all parameters come from torque-driven data: σ0, σ1 first from the sub-breakaway
triangle (over a rough static map: start values from the inverse dynamics of the run above
breakaway, ``F − load − J dω/dt`` against ω), then the static map per direction by output
error on a run above breakaway with σ0, σ1 fixed, then — one step beyond the paper, recorded in
``steps`` — σ0, σ1 once more over the identified static map (the first pass depended on the
rough breakaway level through the bristle saturation ``|s(0)| / sigma0``).

A known position-dependent load (gravity imbalance, seed 002 eq. 13a) is given per run as an
array evaluated on the measured position (``fit_output_error(external_load=...)``).

The force-driven simulations run on the single-axis kernels (:func:`frictionkit.simulate`), so
one axis takes seconds (``benchmarks/sdss.py``).
"""

from __future__ import annotations

from collections.abc import Callable, Mapping, Sequence
from dataclasses import dataclass, field

import numpy as np

from .. import _validate as val
from ..errors import DataError, IdentificationError, ParameterError
from ..models.lugre import LuGre
from ..models.static import Directional, Stribeck
from ..plants.mass import Mass
from .initial_guess import initial_guess_lugre
from .output_error import fit_output_error
from .result import IdentificationResult
from .static_map import COVARIANCES, fit_static_map
from typing import TYPE_CHECKING

if TYPE_CHECKING:
    from matplotlib.axes import Axes

__all__ = ["TwoStepResult", "ConstantVelocityScreen", "fit_two_step", "velocity_nrmse", "simulate_run",
           "constant_velocity_ripple", "screen_constant_velocity", "ripple_rejection_limit", "MAX_RIPPLE_PERCENT",
           "RIPPLE_CONFIDENCE"]

#: Largest velocity ripple [% of the mean speed, RMS] of a run that eq. 10 counts as a
#: constant-velocity point. Eq. 10 equates a run's mean torque with ``T_fss(mean speed)``, which
#: holds only for a constant speed. For an eq. 9b map (δ = 2) the averaging bias of a slow
#: (quasi-static) ripple of relative RMS ``r`` is ``½ T''(v) v² r²``, at most ``0.83 r² (Fs − Fc)``
#: (``max_u |u² (4u² − 2) e^{−u²}| / 2 = 0.83``, ``u = v / vs``), whatever the parameters: at 10 %
#: below 1 % of the Stribeck hump. A hunting or stick-slip limit cycle is not quasi-static
#: (the friction lags and sticks) and shows ripples of tens of per cent. Chosen from this
#: argument before its effect on the SDSS fits was looked at (robustness over 3-50 %: README).
MAX_RIPPLE_PERCENT = 10.0

#: Confidence at which a run's ripple must exceed the threshold to be rejected. The ripple is an
#: estimate from a few dozen windows; where the encoder's share dominates (2e-5 rad/s on the SDSS
#: axes: floor 15 %) its sampling error is several per cent, and a plain comparison rejected the
#: slowest runs of 3 of 20 noise seeds by chance (ripple 10.2-11.9 %, nothing hunting there).
RIPPLE_CONFIDENCE = 0.95

#: Inflation of the variance of a sample variance of window velocities: they are differences of
#: encoder readings, so white encoder noise gives them a lag-1 correlation of -1/2, and the
#: variance of their sample variance grows by ``1 + 2 rho^2 = 1.5`` (effective degrees of freedom
#: ``(m - 1) / 1.5`` for ``m`` windows).
_WINDOW_VARIANCE_INFLATION = 1.5

_SHAPES = {"9b": "exponential", "9a": "lorentzian"}
_STATIC = ("Fc", "Fs", "vs", "sigma2")


def _run_arrays(run, what: str):
    if not isinstance(run, Mapping):
        raise DataError(f"fit_two_step: {what} must be a mapping with t, F (torque), v and optionally x, load")
    for k in ("t", "F", "v"):
        if k not in run:
            raise DataError(f"fit_two_step: {what} has no {k!r}; it needs t, F, v (and x for the initial guess)")
    t = np.asarray(run["t"], float)
    n = t.size
    load = np.zeros(n) if run.get("load") is None else np.asarray(run["load"], float)
    for k in ("F", "v"):
        if np.asarray(run[k]).size != n:
            raise DataError(f"fit_two_step: {what}[{k!r}] has {np.asarray(run[k]).size} samples, t has {n}")
    if load.size != n:
        raise DataError(f"fit_two_step: {what}['load'] has {load.size} samples, t has {n}")
    return t, np.asarray(run["F"], float), np.asarray(run["v"], float), load


def simulate_run(model, run: Mapping, inertia: float):
    """The model's velocity on a torque run: ``J dω/dt = F − load − T_f`` from rest [rad/s]."""
    from ..simulation.core import simulate

    t, u, _, load = _run_arrays(run, "run")
    return simulate(model, plant=Mass(inertia), force=u - load, dt=float(np.median(np.diff(t)))).v


def velocity_nrmse(model, run: Mapping, inertia: float) -> float:
    """``100 · RMS(ω_model − ω_measured) / range(ω_measured)`` [%] on a torque run."""
    v = np.asarray(run["v"], float)
    vh = simulate_run(model, run, inertia)
    return float(100.0 * np.sqrt(np.mean((vh - v) ** 2)) / max(np.ptp(v), 1e-300))


def constant_velocity_ripple(t, angle, *, window: float, resolution: float = 0.0, noise: float = 0.0) -> dict:
    """Velocity ripple of one constant-velocity run from its encoder angle (the averaging window).

    The angle is cut into consecutive windows of ``window`` [s]; each window's velocity is its
    angle change / ``window``. The encoder's own share of their variance, ``2 (noise² +
    resolution²/12) / window²`` (``noise`` RMS [rad], one count ``resolution`` [rad], both from
    the data sheet), is subtracted. Choose ``window`` about a tenth of the period of the loop's
    bandwidth (a limit cycle of the loop lives near it and passes such a window nearly unattenuated).

    Returns ``{"v_mean": angle change / time [rad/s], "ripple_percent": sqrt(max(var − floor², 0))
    / |v_mean| · 100, "floor_percent": the encoder's share · 100, "windows": count}``.
    """
    t = np.asarray(t, float)
    x = np.asarray(angle, float)
    if t.ndim != 1 or t.size != x.size or t.size < 3:
        raise DataError(f"constant_velocity_ripple: t ({t.size} samples) and angle ({x.size}) must be "
                        "1-D of one length >= 3")
    if not (np.isfinite(window) and window > 0):
        raise ParameterError(f"constant_velocity_ripple: window = {window!r}: must be finite and > 0 [s]")
    for k, v in (("resolution", resolution), ("noise", noise)):
        if not (np.isfinite(v) and v >= 0):
            raise ParameterError(f"constant_velocity_ripple: {k} = {v!r}: must be finite and >= 0 [rad]")
    dt = float(np.median(np.diff(t)))
    k = max(int(round(window / dt)), 1)
    xs = x[::k]
    if xs.size < 3:
        raise DataError(f"constant_velocity_ripple: {t[-1] - t[0]:.3g} s of data holds fewer than 2 windows "
                        f"of {window:g} s")
    w = k * dt
    vw = np.diff(xs) / w
    v_mean = float((x[-1] - x[0]) / (t[-1] - t[0]))
    floor2 = 2.0 * (noise**2 + resolution**2 / 12.0) / w**2
    scale = max(abs(v_mean), 1e-300)
    return {"v_mean": v_mean, "ripple_percent": 100.0 * float(np.sqrt(max(np.var(vw) - floor2, 0.0))) / scale,
            "floor_percent": 100.0 * float(np.sqrt(floor2)) / scale, "windows": int(vw.size)}


def ripple_rejection_limit(max_ripple_percent: float, floor_percent, windows, *,
                           confidence: float = RIPPLE_CONFIDENCE) -> np.ndarray:
    """Ripple [%] above which a run is rejected: ``max_ripple_percent`` exceeded at ``confidence``.

    A run's window velocities have variance ``r² + floor²`` (relative to the mean speed², ``floor`` the
    encoder's share, :func:`constant_velocity_ripple`); with ``m`` windows its sample variance has
    about ``nu = (m − 1) / 1.5`` degrees of freedom (the windows are differences of encoder
    readings: lag-1 correlation −½ from white noise). Under ``r = max_ripple_percent`` the sample
    variance stays below ``(floor² + r_max²) χ²_conf(nu) / nu`` with probability ``confidence``;
    the limit is the ripple at that variance, ``sqrt((floor² + r_max²) χ²_conf(nu)/nu − floor²)``.
    """
    from scipy.stats import chi2

    floor = np.asarray(floor_percent, float)
    m = np.asarray(windows, float)
    nu = np.maximum(m - 1.0, 1.0) / _WINDOW_VARIANCE_INFLATION
    var = (floor**2 + max_ripple_percent**2) * chi2.ppf(confidence, nu) / nu
    return np.sqrt(np.maximum(var - floor**2, 0.0))


@dataclass(frozen=True, eq=False)
class ConstantVelocityScreen:
    """Outcome of :func:`screen_constant_velocity`: which runs eq. 10 may use.

    Attributes
    ----------
    status : int — 0 enough points kept in every direction; 1 fewer than ``min_points`` in one.
    message : str — names the rejected runs.
    v, F, ripple_percent : arrays — every run (mean speed, mean torque, ripple).
    accepted : bool array — runs kept.
    max_ripple_percent : float
    limit_percent : array or None — per run, the ripple above which it is rejected
        (:func:`ripple_rejection_limit`; ``None``: the plain threshold, no encoder data given).
    resolvable : bool array or None — whether the encoder's share (``floor_percent``) is below the
        threshold: where it is not, the screen cannot tell a ripple of the threshold from the
        encoder, and the run is kept and named "not resolvable".
    """

    status: int
    message: str
    v: np.ndarray
    F: np.ndarray
    ripple_percent: np.ndarray
    accepted: np.ndarray
    max_ripple_percent: float
    limit_percent: np.ndarray | None = None
    resolvable: np.ndarray | None = None

    @property
    def success(self) -> bool:
        return self.status == 0

    def steady(self) -> dict:
        """``{"v", "F"}`` of the accepted runs (the points eq. 10 fits)."""
        return {"v": self.v[self.accepted], "F": self.F[self.accepted]}

    def rejected(self) -> list:
        """``[{"speed_rad_s", "ripple_percent"}]`` of the rejected runs, in run order."""
        return [{"speed_rad_s": float(v), "ripple_percent": float(r)}
                for v, r, a in zip(self.v, self.ripple_percent, self.accepted) if not a]

    def summary(self) -> str:
        lines = [f"constant-velocity screen (ripple <= {self.max_ripple_percent:g} %): status {self.status} "
                 f"({self.message})"]
        lim = self.limit_percent if self.limit_percent is not None else np.full(self.v.size, np.nan)
        res = self.resolvable if self.resolvable is not None else np.ones(self.v.size, bool)
        for v, r, a, L, ok in zip(self.v, self.ripple_percent, self.accepted, lim, res):
            lines.append(f"  {v:+.4e} rad/s  ripple {r:7.2f} %" + (f" (limit {L:5.2f} %)" if np.isfinite(L) else "")
                         + f"  {'kept' if a else 'REJECTED'}" + ("" if ok else ", not resolvable"))
        return "\n".join(lines)

    def plot(self, ax: Axes | None=None) -> Axes | np.ndarray:
        """Ripple against |speed| per run, the threshold as a line."""
        import matplotlib.pyplot as plt

        new = ax is None
        if new:
            _, ax = plt.subplots(figsize=(6, 3.5))
        a = self.accepted
        ax.loglog(np.abs(self.v[a]), np.maximum(self.ripple_percent[a], 1e-3), "ko", ms=4, label="kept")
        ax.loglog(np.abs(self.v[~a]), np.maximum(self.ripple_percent[~a], 1e-3), "rx", ms=7, label="rejected")
        ax.axhline(self.max_ripple_percent, color="r", lw=0.8, ls="--")
        ax.set_xlabel("|mean speed| [rad/s]")
        ax.set_ylabel("velocity ripple [% RMS]")
        ax.legend(fontsize=8)
        if new:
            ax.figure.tight_layout()
        return ax


def screen_constant_velocity(steady: Mapping, *, max_ripple_percent: float = MAX_RIPPLE_PERCENT,
                             min_points: int = 5) -> ConstantVelocityScreen:
    """Keep the runs of a constant-velocity campaign whose speed was constant (eq. 10's premise).

    ``steady``: ``{"v", "F", "ripple_percent"}`` per run (:func:`constant_velocity_ripple` gives
    the ripple from each run's encoder angle), optionally with its ``floor_percent`` and
    ``windows``. A run whose ripple exceeds ``max_ripple_percent`` (:data:`MAX_RIPPLE_PERCENT`,
    argued there) is not a constant-velocity point: rejected and named. With ``floor_percent``
    and ``windows`` the ripple is read as the estimate it is: a run is rejected when it exceeds the
    threshold at :data:`RIPPLE_CONFIDENCE` (:func:`ripple_rejection_limit`), and a run whose
    encoder floor is above the threshold is named "not resolvable" (kept: no evidence against it).
    ``status`` 1 when a direction keeps fewer than ``min_points`` runs (eq. 10 fits four
    parameters per direction).
    """
    if "ripple_percent" not in steady:
        raise DataError("screen_constant_velocity: steady has no 'ripple_percent' (constant_velocity_ripple per run)")
    v = np.asarray(steady["v"], float)
    F = np.asarray(steady["F"], float)
    r = np.asarray(steady["ripple_percent"], float)
    if not (v.shape == F.shape == r.shape and v.ndim == 1):
        raise DataError(f"screen_constant_velocity: v, F, ripple_percent have {v.size}, {F.size}, {r.size} entries")
    max_ripple_percent = val.positive("screen_constant_velocity", "max_ripple_percent", max_ripple_percent)
    if isinstance(min_points, bool) or not isinstance(min_points, (int, np.integer)) or min_points < 1:
        raise ParameterError(f"screen_constant_velocity: min_points = {min_points!r}: must be an integer >= 1")
    limit = resolvable = None
    if "floor_percent" in steady and "windows" in steady:
        floor = np.asarray(steady["floor_percent"], float)
        m = np.asarray(steady["windows"], float)
        if not (floor.shape == m.shape == v.shape):
            raise DataError(f"screen_constant_velocity: floor_percent, windows have {floor.size}, {m.size} entries, "
                            f"v has {v.size}")
        limit = ripple_rejection_limit(max_ripple_percent, floor, m)
        resolvable = floor <= max_ripple_percent
    lim = np.full(v.size, max_ripple_percent) if limit is None else limit
    acc = np.isfinite(r) & (r <= lim)
    rej = [f"{x:+.3e} rad/s ({p:.1f} %)" for x, p, a in zip(v, r, acc) if not a]
    unres = [] if resolvable is None else [f"{x:+.3e} rad/s (floor {f:.1f} %)"
                                           for x, f, ok in zip(v, floor, resolvable) if not ok]
    short = [d for d, sel in (("positive", v > 0), ("negative", v < 0)) if sel.any() and (acc & sel).sum() < min_points]
    how = (f"ripple > {max_ripple_percent:g} %" if limit is None
           else f"ripple > {max_ripple_percent:g} % at {100 * RIPPLE_CONFIDENCE:g} % confidence")
    msg = (f"kept {int(acc.sum())} of {v.size} runs"
           + (f"; rejected ({how}): " + ", ".join(rej) if rej else "")
           + (f"; not resolvable (encoder floor > {max_ripple_percent:g} %, kept): " + ", ".join(unres) if unres else "")
           + (f"; too few points left in the {' and '.join(short)} direction (< {min_points})" if short else ""))
    return ConstantVelocityScreen(status=1 if short else 0, message=msg, v=v, F=F, ripple_percent=r, accepted=acc,
                                  max_ripple_percent=float(max_ripple_percent), limit_percent=limit,
                                  resolvable=resolvable)


def is_flagged(name: str, warnings) -> bool:
    """Whether a fit's warnings flag parameter ``name`` (``Fc_pos`` also matches a static-map
    warning ``"positive: Fc ..."``)."""
    side = {"_pos": "positive: ", "_neg": "negative: "}.get(name[-4:])
    base = name[:-4] if side else name
    for w in warnings:
        if w.startswith(name) or f" {name} " in w:
            return True
        if side and w.startswith(side) and (f" {base} " in w or w[len(side):].startswith(base + " ")):
            return True
    return False


@dataclass(frozen=True, eq=False)
class TwoStepResult:
    """Outcome of :func:`fit_two_step`.

    Attributes
    ----------
    status : int — 0 every step converged; 1 a step failed (``message`` says which and why).
    message : str
    model : LuGre or None — the identified law (static map per direction, one σ0/σ1 pair).
    static : IdentificationResult or None — the static parameters (eq. 10 or output error).
    dynamic : IdentificationResult or None — σ0, σ1 (eq. 12).
    steps : tuple of (label, IdentificationResult) — every fit in the order run.
    order : str — ``"static_first"`` or ``"dynamic_first"``.
    initial_guess : dict — σ0, σ1 start values from the triangle run.
    nrmse_percent : dict — velocity NRMSE of the identified model per named run.
    screen : ConstantVelocityScreen or None — the constant-velocity runs kept and rejected
        (when ``steady`` carried ``ripple_percent``).
    """

    status: int
    message: str
    model: LuGre | None
    static: IdentificationResult | None
    dynamic: IdentificationResult | None
    steps: tuple = ()
    order: str = "static_first"
    initial_guess: Mapping = field(default_factory=dict)
    nrmse_percent: Mapping = field(default_factory=dict)
    inertia: float = 1.0
    screen: ConstantVelocityScreen | None = None

    @property
    def success(self) -> bool:
        return self.status == 0

    def parameters(self) -> dict:
        """``{name: {"value", "ci95", "unit", "flagged"}}`` of the final estimates (rotary units)."""
        rotary = {"N": "N·m", "N/m": "N·m/rad", "N·s/m": "N·m·s/rad", "m/s": "rad/s"}
        out = {}
        for res in (self.static, self.dynamic):
            if res is None:
                continue
            for n in res.names:
                p = res.parameter(n)
                flag = is_flagged(n, res.warnings)
                out[n] = {"value": p["value"], "ci95": p["ci95"], "unit": rotary.get(p["unit"], p["unit"]),
                          "flagged": bool(flag)}
        return out

    def summary(self) -> str:
        lines = [f"two-step LuGre identification ({self.order}): status {self.status} ({self.message})"]
        for n, p in self.parameters().items():
            lines.append(f"  {n:<10s} {p['value']:>12.5g}  95 % [{p['ci95'][0]:.5g}, {p['ci95'][1]:.5g}] {p['unit']}"
                         + ("  FLAGGED" if p["flagged"] else ""))
        if self.initial_guess:
            lines.append("  start from the triangle: " + ", ".join(f"{k} = {v:.4g}" for k, v in self.initial_guess.items()
                                                                if k in ("sigma0", "sigma1")))
        for k, v in self.nrmse_percent.items():
            lines.append(f"  velocity NRMSE {k}: {v:.3g} %")
        if self.screen is not None:
            lines.append(f"  {self.screen.message}")
        for label, res in self.steps:
            for w in res.warnings:
                lines.append(f"  [{label}] {w}")
        return "\n".join(lines)

    def plot(self, ax: Axes | None=None) -> Axes | np.ndarray:
        """The identified steady-state map over the static points (or the static fit's data)."""
        import matplotlib.pyplot as plt

        new = ax is None
        if new:
            _, ax = plt.subplots(figsize=(6, 3.5))
        if self.model is not None:
            st = self.model.static
            vmax = 1e-3
            if self.static is not None and "v" in self.static.data:
                v = np.asarray(self.static.data["v"])
                ax.plot(v, self.static.data["F"], "k*", ms=5, label="steady-state points")
                vmax = float(np.max(np.abs(v)))
            vv = np.linspace(-vmax, vmax, 801)
            ax.plot(vv, st.steady_state(vv), "-", label="identified map")
        ax.set_xlabel("velocity [rad/s]")
        ax.set_ylabel("friction torque [N·m]")
        ax.legend(fontsize=8)
        if new:
            ax.figure.tight_layout()
        return ax


def _static_law(res: IdentificationResult, shape: str, delta: float):
    def side(s):
        return Stribeck(Fc=max(res[f"Fc_{s}"], 0.0), Fs=max(res[f"Fs_{s}"], 0.0), vs=res[f"vs_{s}"],
                        delta=delta, sigma2=max(res[f"sigma2_{s}"], 0.0), shape=shape)
    return Directional(positive=side("pos"), negative=side("neg"))


def _rough_static(run, shape: str, delta: float) -> Directional:
    """A rough map from a sub-breakaway run: the peak net torque is below the breakaway level,
    so ``Fs = 1.2 peak``, ``Fc = 0.9 peak`` per direction, ``vs`` from the peak velocity."""
    _, u, v, load = run
    net = u - load
    net = net - net[0]
    peaks = {"pos": max(net.max(), 1e-12), "neg": max(-net.min(), 1e-12)}
    vs = max(10.0 * np.max(np.abs(v)), 1e-12)
    laws = {s: Stribeck(Fc=0.9 * p, Fs=1.2 * p, vs=vs, delta=delta, shape=shape) for s, p in peaks.items()}
    return Directional(positive=laws["pos"], negative=laws["neg"])


def _inverse_dynamics_static(run, inertia: float, shape: str, delta: float):
    """Start values of the static map from a run above breakaway: the net torque
    ``F − load − J dω/dt`` against ω over the sliding samples (|ω| above 1 % of its peak),
    fitted per direction (equation error; start values only: the breakaway transients bias it)."""
    t, u, v, load = run
    a = np.gradient(v, float(np.median(np.diff(t))))
    Fn = u - load - inertia * a
    sel = np.abs(v) > 0.01 * np.max(np.abs(v))
    if (v[sel] > 0).sum() < 6 or (v[sel] < 0).sum() < 6:
        return None
    try:
        res = fit_static_map(v[sel], Fn[sel], model=shape, delta=delta if shape == "exponential" else None,
                             direction="both")
    except IdentificationError:
        return None
    return _static_law(res, shape, delta), res


def _static_bounds(law: Directional, run) -> dict:
    """Generous bounds of the output-error static fit: levels within [0, 3 x peak net torque],
    vs within a factor 100 of its start, sigma2 within [0, 3 x peak torque / peak speed]."""
    _, u, v, load = run
    Tmax = float(np.max(np.abs(u - load)))
    vmax = float(np.max(np.abs(v)))
    out = {}
    for s, law in (("pos", law.positive), ("neg", law.negative)):
        out[f"Fc_{s}"] = (0.0, 3.0 * Tmax)
        out[f"Fs_{s}"] = (0.0, 3.0 * Tmax)
        out[f"vs_{s}"] = (law.vs / 100.0, law.vs * 100.0)
        out[f"sigma2_{s}"] = (0.0, 3.0 * Tmax / vmax)
    return out


def fit_two_step(
    *,
    inertia: float,
    triangle: Mapping,
    steady: Mapping | None = None,
    above: Mapping | None = None,
    also_below: Sequence[Mapping] = (),
    validate: Mapping[str, Mapping] | None = None,
    order: str = "static_first",
    map: str = "9b",
    delta: float = 2.0,
    zeta_guess: float = 1.0,
    starts: int = 1,
    max_nfev: int = 400,
    max_ripple_percent: float | None = MAX_RIPPLE_PERCENT,
    covariance: str = "run_robust",
    progress: Callable[[str], None] | None = None,
) -> TwoStepResult:
    """Identify a LuGre law of a slow heavy rotary axis in two steps (seed 002 §3).

    Parameters
    ----------
    inertia : float — axis inertia [kg·m²] (known, e.g. from the design or a rigid-body fit).
    triangle : mapping — the open-loop run driven by a triangle torque **below breakaway**:
        ``t`` [s], ``F`` axis torque [N·m], ``v`` measured velocity [rad/s], ``x`` measured angle
        [rad] (for the start values), optional ``load`` known load torque per sample [N·m].
    steady : mapping, optional — ``{"v": mean velocities, "F": mean torques}`` of the
        constant-velocity runs, both directions (``order="static_first"``); with
        ``"ripple_percent"`` per run (:func:`constant_velocity_ripple`) the runs whose speed was
        not constant are rejected first (:func:`screen_constant_velocity`, ``result.screen``).
    above : mapping, optional — a torque run **above breakaway** (``order="dynamic_first"``),
        same keys as ``triangle``.
    also_below : sequence of mappings — further open-loop runs below breakaway (same keys as
        ``triangle``; e.g. the sine of seed 002 §3.1: "sine and triangle torques of different
        amplitudes") fitted **jointly** with the triangle in eq. 12, each simulated from rest;
        the start values still come from the triangle alone.
    validate : mapping of name -> run, optional — further runs on which the identified model's
        velocity NRMSE is reported (not fitted).
    order : {"static_first", "dynamic_first"} — the paper's azimuth / altitude order.
    map : {"9b", "9a"} — eq. 9b (exponential, exponent ``delta``; 2 as eq. 10) or 9a (Lorentzian).
    delta : float — exponent of eq. 9b, held fixed (2: eq. 10).
    zeta_guess : float — damping-ratio guess of the pre-sliding oscillator for the σ1 start.
    starts : int — start points of the output-error fits (1: the triangle's guess only).
    max_nfev : int — evaluation limit of the output-error static fit (``dynamic_first``).
    max_ripple_percent : float or None — the screen's threshold (:data:`MAX_RIPPLE_PERCENT`);
        ``None`` keeps every run.
    covariance : {"run_robust", "residual"} — the intervals of eq. 10's static map
        (:data:`~frictionkit.identify.static_map.COVARIANCES`): each point is a run mean with its
        own error, so by default the larger of the residual and the run-level (HC3) variance.
    progress : callable(label), optional — called before each step.

    Returns
    -------
    TwoStepResult — ``status`` 1 with the failing step named when a fit does not converge.

    Examples
    --------
    The SDSS azimuth (noise-free data here; ``frictionkit.reproduce.sdss`` runs the real experiments):

    >>> import numpy as np, frictionkit as fk
    >>> from frictionkit.identify import fit_two_step
    >>> from frictionkit.presets import sdss
    >>> ax = sdss.AzimuthAxis()
    >>> v = np.r_[np.geomspace(2e-5, 2e-2, 10), -np.geomspace(2e-5, 2e-2, 10)]
    >>> steady = {"v": v, "F": ax.friction.static.steady_state(v)}     # run means
    >>> t = np.arange(301) * 0.02
    >>> T = 144.0 * (2 / np.pi) * np.arcsin(np.sin(np.pi * t))         # triangle below breakaway
    >>> sim = fk.simulate(ax.friction, plant=fk.Mass(ax.J), force=T, dt=0.02)
    >>> res = fit_two_step(inertia=ax.J, steady=steady, triangle={"t": t, "F": T, "v": sim.v, "x": sim.x})
    >>> res.status, round(res.model.sigma0 / ax.friction.sigma0, 2)
    (0, 1.0)
    """
    if order not in ("static_first", "dynamic_first"):
        raise ParameterError(f"fit_two_step: order = {order!r}: must be 'static_first' or 'dynamic_first'")
    if map not in _SHAPES:
        raise ParameterError(f"fit_two_step: map = {map!r}: must be '9a' or '9b'")
    if not (np.isfinite(inertia) and inertia > 0):
        raise ParameterError(f"fit_two_step: inertia = {inertia!r}: must be finite and > 0")
    if order == "static_first" and steady is None:
        raise ParameterError("fit_two_step: order='static_first' needs steady= (the constant-velocity points)")
    if covariance not in COVARIANCES:
        raise ParameterError(f"fit_two_step: covariance = {covariance!r}: must be one of {list(COVARIANCES)}")
    if max_ripple_percent is not None:  # checked even where the screen does not run (a typo is not ignored)
        max_ripple_percent = val.positive("fit_two_step", "max_ripple_percent", max_ripple_percent)
    if order == "dynamic_first" and above is None:
        raise ParameterError("fit_two_step: order='dynamic_first' needs above= (a torque run above breakaway)")
    shape = _SHAPES[map]
    step = progress or (lambda label: None)
    tri = _run_arrays(triangle, "triangle")
    tri_rec = {"t": tri[0], "F": tri[1], "v": tri[2]}
    steps: list = []
    static_res = dyn_res = screen = None
    if order == "static_first" and max_ripple_percent is not None and "ripple_percent" in steady:
        screen = screen_constant_velocity(steady, max_ripple_percent=max_ripple_percent)
        if not screen.success:
            return TwoStepResult(status=1, message=f"constant-velocity screen: {screen.message}", model=None,
                                 static=None, dynamic=None, order=order, inertia=float(inertia), screen=screen)
        steady = screen.steady()

    def dyn_fit(static_law, label):
        if "x" not in triangle:
            raise DataError("fit_two_step: triangle has no 'x' (measured angle) for the start values")
        g = initial_guess_lugre({"t": tri[0], "x": np.asarray(triangle["x"], float), "F": tri[1] - tri[3]},
                                mass=inertia, zeta=zeta_guess, sigma2=0.0)
        start = LuGre(static_law, sigma0=g["sigma0"], sigma1=max(g["sigma1"], 1e-6 * g["sigma0"]))
        recs, loads = [tri_rec], [tri[3]]
        for k, run in enumerate(also_below):
            r = _run_arrays(run, f"also_below[{k}]")
            recs.append({"t": r[0], "F": r[1], "v": r[2]})
            loads.append(r[3])
        res = fit_output_error(recs if len(recs) > 1 else tri_rec, start, free=("sigma0", "sigma1"),
                               inertia=inertia, external_load=loads if len(recs) > 1 else tri[3],
                               starts=starts, raise_on_failure=True)
        steps.append((label, res))
        return res, g

    try:
        if order == "static_first":
            step("static map (eq. 10)")
            pts_v = np.asarray(steady["v"], float)
            pts_F = np.asarray(steady["F"], float)
            static_res = fit_static_map(pts_v, pts_F, model="exponential" if map == "9b" else "lorentzian",
                                        delta=delta if map == "9b" else None, direction="both",
                                        units={"v": "rad/s", "F": "N·m"}, covariance=covariance)
            steps.append(("static map (eq. 10)", static_res))
            static_law = _static_law(static_res, shape, delta)
            step("sigma0, sigma1 (eq. 12)")
            dyn_res, guess = dyn_fit(static_law, "sigma0, sigma1 (eq. 12)")
            model = dyn_res.model
        else:
            step("sigma0, sigma1 over a rough map (eq. 12)")
            ab = _run_arrays(above, "above")
            got = _inverse_dynamics_static(ab, inertia, shape, delta)
            rough = _rough_static(tri, shape, delta) if got is None else got[0]
            if got is not None:
                steps.append(("start values of the static map (inverse dynamics, above breakaway)", got[1]))
            first, guess = dyn_fit(rough, "sigma0, sigma1 over a rough map (eq. 12)")
            step("static map by output error")
            # sigma0, sigma1 stay free here (ours): held at the first pass's values, which carry the
            # rough map's error, they bias the static fit (measured on the SDSS altitude: Fs_neg
            # +560 %, vs -69 %; freed, every parameter within 0.2 %)
            free = ("sigma0", "sigma1") + tuple(f"{p}_{s}" for s in ("pos", "neg") for p in _STATIC)
            start = LuGre(first.model.static, sigma0=first["sigma0"], sigma1=first["sigma1"])
            static_res = fit_output_error({"t": ab[0], "F": ab[1], "v": ab[2]}, start, free=free,
                                          inertia=inertia, external_load=ab[3], starts=starts,
                                          bounds=_static_bounds(start.static, ab), max_nfev=max_nfev,
                                          raise_on_failure=True)
            steps.append(("static map by output error (above breakaway)", static_res))
            step("sigma0, sigma1 again (ours)")
            dyn_res, _ = dyn_fit(static_res.model.static, "sigma0, sigma1 over the identified map (ours)")
            model = dyn_res.model
    except IdentificationError as exc:
        return TwoStepResult(status=1, message=f"step {len(steps) + 1} failed: {exc}", model=None,
                             static=static_res, dynamic=dyn_res, steps=tuple(steps), order=order,
                             inertia=float(inertia), screen=screen)
    nrmse = {"triangle": velocity_nrmse(model, triangle, inertia)}
    if above is not None:
        nrmse["above"] = velocity_nrmse(model, above, inertia)
    for k, run in (validate or {}).items():
        nrmse[k] = velocity_nrmse(model, run, inertia)
    flagged = [f"{label}: {w}" for label, r in steps for w in r.warnings]
    msg = "ok" if not flagged else f"ok, {len(flagged)} warning(s): " + "; ".join(flagged)
    return TwoStepResult(status=0, message=msg, model=model, static=static_res, dynamic=dyn_res,
                         steps=tuple(steps), order=order,
                         initial_guess={k: float(v) for k, v in guess.items()}, nrmse_percent=nrmse,
                         inertia=float(inertia), screen=screen)
