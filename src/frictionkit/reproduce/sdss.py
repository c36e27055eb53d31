"""Seed 002 (2.5 m SDSS telescope): the paper's experiments on the three simulated axes.

Virtual experiments (§3) on the axes of :mod:`frictionkit.presets.sdss`, run on the machine
core, then the two-step estimation (:func:`frictionkit.identify.two_step.fit_two_step`) in the
paper's order per axis:

* azimuth: closed-loop constant-velocity runs at many speeds in both directions, averaged per
  run, the runs whose speed was not constant rejected by name (ours: velocity ripple from the
  encoder angle above :data:`~frictionkit.identify.two_step.MAX_RIPPLE_PERCENT`; eq. 10 needs a
  constant speed) → static map (eq. 10, Fig. 3); open-loop triangle and sine torques below breakaway →
  σ0, σ1 (eq. 12, Figs. 4a/4b), slightly above breakaway (Fig. 4c, shown, not fitted);
* altitude: open-loop torque runs only, with the gravity term (eq. 13a): σ0, σ1 from the
  sub-breakaway triangle first (Fig. 6a), then the static map per direction from a run above
  breakaway; Fig. 6b slightly above breakaway; Fig. 7 the computed static curve;
* rotator: constant-velocity runs (screened the same way: its 2 Hz loop hunts in the
  Stribeck region) → the combined static map of bearing and harmonic drive
  (eq. 13b, Fig. 8); **beyond the paper**: the separation the paper calls necessary — a bench
  run of the motor and harmonic drive alone (capstan disengaged), then the bearing map from
  the combined points minus ``n_c T_fHD`` (the paper's own suggestion, §3.3: "identify the
  friction parameters of the harmonic drive and then proceed indirectly with ... the central
  bearing");
* **extension (ours; the paper designs no controller)**: sidereal-rate tracking of the azimuth
  axis with a PID tuned without friction, and the same with the identified LuGre map as
  feed-forward (:class:`~frictionkit.machines.FrictionFeedforward` on the reference velocity);
  RMS tracking error in arcsec.

Measurement model: the encoder of :class:`~frictionkit.presets.sdss.Encoder` (2^25 counts/rev,
half a count RMS noise) on the machine's sensor; torque runs are logged every
:data:`DT_LOG` = 20 ms and the velocity is the central difference of the logged angle (no lag);
the torque is the commanded current times eq. 2's gain (the amplifiers run in current mode).
NRMSE = RMS(model − measured velocity) / range(measured velocity).
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

from ..identify.static_map import fit_static_map
from . import REPRODUCTION_FORMAT, worst_status
from ..errors import IdentificationError, ParameterError
from ..identify.two_step import (MAX_RIPPLE_PERCENT, TwoStepResult, constant_velocity_ripple, fit_two_step,
                                  is_flagged, screen_constant_velocity, velocity_nrmse)
from ..machines import PID, FrictionFeedforward, Sum, simulate_machine
from ..models.lugre import LuGre
from ..presets import sdss

_STATIC = ("Fc", "Fs", "vs", "sigma2")

#: Logging period of the open-loop torque runs [s] (assumption; the paper gives none).
DT_LOG = 0.02
#: Sub-steps per logged sample of the open-loop runs (h = 2 ms; max velocity change against
#: 160 sub-steps: 1e-8 rad/s on the azimuth triangle, 0.01 % of its peak).
SUBSTEPS_OPEN = 10


# --------------------------------------------------------------------------- experiments
def central_velocity(x: np.ndarray, dt: float) -> np.ndarray:
    """Velocity from a sampled angle by central differences (one-sided at the ends)."""
    return np.gradient(np.asarray(x, float), dt)


def torque_signal(kind: str, amplitude: float, period: float, duration: float, dt: float = DT_LOG):
    """``(t, T)``: a zero-mean ``"sine"`` or ``"triangle"`` torque [N·m] starting at 0."""
    t = np.arange(int(round(duration / dt)) + 1) * dt
    ph = 2.0 * np.pi * t / period
    if kind == "sine":
        return t, amplitude * np.sin(ph)
    if kind == "triangle":
        return t, amplitude * (2.0 / np.pi) * np.arcsin(np.clip(np.sin(ph), -1.0, 1.0))
    raise ParameterError(f"torque_signal kind = {kind!r}: must be 'sine' or 'triangle'")


def torque_run(axis, kind: str | None = None, amplitude: float = 0.0, period: float = 1.0, cycles: float = 1.0, *,
               segments=None, seed: int = 0) -> dict:
    """An open-loop torque-driven run (§3.1, §3.2): the current follows a sine or triangle, or
    ``segments = [(kind, amplitude, period, cycles), ...]`` played one after the other in one run.

    The altitude axis starts at ``axis.theta_test`` with the known gravity torque balanced by a
    constant current. Returns ``t``, ``F`` (axis torque), ``x`` (encoder angle), ``v`` (central
    difference), ``load`` (the known load on the encoder angle), ``v_true``, ``x_true``.
    """
    segs = list(segments) if segments is not None else [(kind, amplitude, period, cycles)]
    parts = [torque_signal(k, A, P, c * P)[1][:-1] for k, A, P, c in segs]
    T = np.concatenate(parts + [[0.0]])
    t = np.arange(T.size) * DT_LOG
    theta0 = getattr(axis, "theta_test", 0.0)
    bias = float(axis.gravity(theta0))
    u = (T + bias) / axis.torque_constant
    m = axis.machine(loop="open", theta0=theta0)
    res = simulate_machine(m, dt=DT_LOG, inputs={"i": u}, substeps=SUBSTEPS_OPEN, seed=seed,
                           raise_on_failure=True)
    enc = res.signal("encoder")
    return {"t": t, "F": u * axis.torque_constant, "x": enc - enc[0], "v": central_velocity(enc, DT_LOG),
            "load": axis.gravity(enc), "v_true": res.velocity("theta"), "x_true": res.position("theta") - theta0,
            "segments": [(k, float(A), float(P), float(c)) for k, A, P, c in segs]}


#: Travel at speed before a constant-velocity run is averaged [rad]: 60 arcsec, 15x the pre-sliding
#: range ("a few arc seconds", seed 002 §2.2), so the bristle state has settled at every speed.
SETTLE_TRAVEL = 60.0 * sdss.ARCSEC


def constant_velocity_runs(axis, speeds, *, seed: int = 0, accel: float = 0.01, settle: float = 1.5,
                           average: float = 3.0, machine=None) -> dict:
    """Closed-loop constant-velocity runs (§3.1), one per signed speed [rad/s].

    The position loop follows a ramp reached with ``accel`` [rad/s²]; after ``settle`` s at speed
    (at least :data:`SETTLE_TRAVEL` of travel) the encoder angle and the current are averaged over ``average`` s: mean velocity =
    angle change / time, mean torque = eq. 2's gain × mean current. Returns ``v``, ``F`` and, per run, the
    velocity ripple over the same window from the encoder angle (``ripple_percent``, ``floor_percent``, ``windows``:
    :func:`~frictionkit.identify.two_step.constant_velocity_ripple` with windows of a tenth of the position
    loop's period, ``1 / (10 bandwidth_hz)``, and the encoder's data-sheet resolution and noise).
    """
    m = machine or axis.machine(loop="position")
    dt = axis.dt
    v_out, F_out, rip, floor, nwin = [], [], [], [], []
    window = 0.1 / axis.bandwidth_hz
    for k, w in enumerate(np.asarray(speeds, float)):
        ta = abs(w) / accel
        ts = max(settle, SETTLE_TRAVEL / abs(w))
        n = int(round((ta + ts + average) / dt)) + 1
        t = np.arange(n) * dt
        r = np.where(t < ta, 0.5 * np.sign(w) * accel * t**2, w * (t - 0.5 * ta))
        res = simulate_machine(m, dt=dt, inputs={"r": r}, seed=seed * 1000 + k, raise_on_failure=True)
        sel = t >= ta + ts
        enc = res.signal("encoder")[sel]
        i = res.signal("motor.applied" if "motor.applied" in res.signal_names else "motors.applied")[sel]
        v_out.append((enc[-1] - enc[0]) / (t[sel][-1] - t[sel][0]))
        F_out.append(axis.torque_constant * float(np.mean(i)))
        r = constant_velocity_ripple(t[sel], enc, window=window, resolution=axis.encoder.resolution,
                                     noise=axis.encoder.noise)
        rip.append(r["ripple_percent"])
        floor.append(r["floor_percent"])
        nwin.append(r["windows"])
    return {"v": np.array(v_out), "F": np.array(F_out), "ripple_percent": np.array(rip),
            "floor_percent": np.array(floor), "windows": np.array(nwin)}


def speed_grid(quick: bool) -> np.ndarray:
    """Signed speeds of the constant-velocity runs: 2e-5 … 2e-2 rad/s (0.3 x sidereal … 1.1 deg/s)."""
    s = np.geomspace(2e-5, 2e-2, 8 if quick else 14)
    return np.concatenate([s, -s])


# --------------------------------------------------------------------------- per axis
@dataclass(frozen=True, eq=False)
class AxisOutcome:
    name: str
    truth: dict
    fit: TwoStepResult | None
    identified: dict
    nrmse: dict          # the identified model, per figure
    nrmse_floor: dict    # the true model on the same noisy data
    runs: dict = field(default_factory=dict)
    steady: dict | None = None
    extra: dict = field(default_factory=dict)


def _true_model_nrmse(axis, runs: dict) -> dict:
    return {k: velocity_nrmse(axis.friction, r, axis.inertia) for k, r in runs.items()}


def run_azimuth(axis=None, *, quick: bool = False, seed: int = 0, joint: bool = True,
                max_ripple_percent: float | None = MAX_RIPPLE_PERCENT) -> AxisOutcome:
    """The azimuth in the paper's order; ``joint=False`` fits σ0, σ1 on the triangle alone.
    ``max_ripple_percent``: the constant-velocity screen (``None``: every run kept, the state
    before the screen)."""
    axis = axis or sdss.AzimuthAxis()
    Ts = min(axis.friction.static.positive.Fs, axis.friction.static.negative.Fs)
    steady = constant_velocity_runs(axis, speed_grid(quick), seed=seed)
    cyc = 3 if quick else 5
    runs = {"fig4a_triangle": torque_run(axis, "triangle", 0.9 * Ts, 2.0, cyc, seed=seed + 11),
            "fig4b_sine": torque_run(axis, "sine", 0.8 * Ts, 2.0, cyc, seed=seed + 12),
            "fig4c_above": torque_run(axis, "sine", 1.1 * Ts, 4.0, 2, seed=seed + 13)}
    # eq. 12 on the triangle and the sine together (§3.1: "sine and triangle torques of different
    # amplitudes ... below breakaway"), each from rest; Fig. 4b's NRMSE is then on fitted data
    fit = fit_two_step(inertia=axis.inertia, steady=steady, triangle=runs["fig4a_triangle"],
                       also_below=[runs["fig4b_sine"]] if joint else (),
                       validate={"fig4b_sine": runs["fig4b_sine"], "fig4c_above": runs["fig4c_above"]},
                       order="static_first", max_ripple_percent=max_ripple_percent)
    nr = {k: v for k, v in fit.nrmse_percent.items() if k != "triangle"}
    if "triangle" in fit.nrmse_percent:
        nr["fig4a_triangle"] = fit.nrmse_percent["triangle"]
    return AxisOutcome("azimuth", axis.truth(), fit, fit.parameters(), nr, _true_model_nrmse(axis, runs),
                       runs, steady, extra={"screen": fit.screen})


def run_altitude(axis=None, *, quick: bool = False, seed: int = 0) -> AxisOutcome:
    axis = axis or sdss.AltitudeAxis()
    Ts = min(axis.friction.static.positive.Fs, axis.friction.static.negative.Fs)
    cyc = 3 if quick else 5
    runs = {"fig6a_triangle": torque_run(axis, "triangle", 0.9 * Ts, 2.0, cyc, seed=seed + 21),
            # "a sine wave and a triangle wave with different amplitudes" (§3.2), in one record
            "above": torque_run(axis, segments=[("sine", 2.5 * Ts, 8.0, 2), ("triangle", 1.3 * Ts, 8.0, 2)],
                                seed=seed + 22),
            "fig6b_above": torque_run(axis, "sine", 1.1 * Ts, 4.0, 2, seed=seed + 23)}
    fit = fit_two_step(inertia=axis.inertia, triangle=runs["fig6a_triangle"], above=runs["above"],
                       validate={"fig6b_above": runs["fig6b_above"]}, order="dynamic_first")
    nr = dict(fit.nrmse_percent)
    if "triangle" in nr:
        nr["fig6a_triangle"] = nr.pop("triangle")
    return AxisOutcome("altitude", axis.truth(), fit, fit.parameters(), nr, _true_model_nrmse(axis, runs), runs)


def _screened(steady: dict, max_ripple_percent):
    """The constant-velocity screen of a campaign (``None``: keep every run)."""
    if max_ripple_percent is None:
        return None, steady
    scr = screen_constant_velocity(steady, max_ripple_percent=max_ripple_percent)
    if not scr.success:
        raise IdentificationError(f"constant-velocity screen: {scr.message}")
    return scr, scr.steady()


def run_rotator(axis=None, *, quick: bool = False, seed: int = 0,
                max_ripple_percent: float | None = MAX_RIPPLE_PERCENT) -> AxisOutcome:
    """Eq. 13b's combined static map from constant-velocity runs, the runs whose speed was not
    constant rejected first (``max_ripple_percent``, ``None`` keeps every run); then the
    separation attempt (ours) from a bench campaign screened the same way."""
    axis = axis or sdss.RotatorAxis()
    speeds = speed_grid(quick)
    steady = constant_velocity_runs(axis, speeds, seed=seed)
    screen, used = _screened(steady, max_ripple_percent)
    res = fit_static_map(used["v"], used["F"], model="exponential", delta=2.0, direction="both",
                         units={"v": "rad/s", "F": "N·m"}, covariance="run_robust")
    identified = {n: {"value": res.parameter(n)["value"], "ci95": res.parameter(n)["ci95"],
                      "unit": res.parameter(n)["unit"], "flagged": is_flagged(n, res.warnings)}
                  for n in res.names}
    # separation attempt (ours, the paper's suggestion): the HD on the bench, then the bearing
    bench = constant_velocity_runs(axis, speeds, seed=seed + 500, machine=axis.machine(hd_only=True))
    bench_screen, bench_used = _screened(bench, max_ripple_percent)
    hd = fit_static_map(bench_used["v"], bench_used["F"], model="exponential", delta=2.0, direction="both",
                        units={"v": "rad/s", "F": "N·m"}, covariance="run_robust")
    bearing = fit_static_map(used["v"], used["F"] - hd.model.steady_state(used["v"]), model="exponential",
                             delta=2.0, direction="both", units={"v": "rad/s", "F": "N·m"}, covariance="run_robust")
    b, h, nc = axis.bearing.static, axis.hd_friction.static, axis.n_c
    sep = {"hd_at_rotator": {"truth": {"Fc": nc * h.Fc, "Fs": nc * h.Fs, "vs": h.vs / nc, "sigma2": nc**2 * h.sigma2},
                             "identified": {k: hd[f"{k}_pos"] for k in _STATIC}},
           "bearing": {"truth": {"Fc": b.Fc, "Fs": b.Fs, "vs": b.vs, "sigma2": b.sigma2},
                       "identified": {k: bearing[f"{k}_pos"] for k in _STATIC}}}
    return AxisOutcome("rotator", axis.truth(), None, identified, {}, {}, {}, steady,
                       extra={"static_result": res, "separation": sep, "hd_result": hd, "bearing_result": bearing,
                              "screen": screen, "bench_screen": bench_screen})



# --------------------------------------------------------------------------- extension
def sidereal_tracking(axis=None, model: LuGre | None = None, *, duration: float = 20.0, seed: int = 0) -> dict:
    """Extension (ours): azimuth tracking at sidereal rate, PID tuned without friction
    (pole placement on the inertia alone, 2 Hz), without and with the identified map as
    feed-forward on the reference velocity. The axis is at rest when tracking starts (after a slew
    and settle); returns the RMS tracking error over the whole run [arcsec]."""
    axis = axis or sdss.AzimuthAxis()
    dt = axis.dt
    n = int(round(duration / dt)) + 1
    t = np.arange(n) * dt
    w = sdss.SIDEREAL_RATE
    r = w * t
    out = {}
    for label, ff in (("no_compensation", None), ("lugre_feedforward", model)):
        m = axis.machine(loop="open")
        g = sdss._pid_gains(axis.inertia, axis.torque_constant, axis.bandwidth_hz)
        blocks = [Sum("e", {"r": 1.0, "encoder": -1.0}), PID("i_fb", "e", **g)]
        terms = {"i_fb": 1.0}
        if ff is not None:
            blocks.append(FrictionFeedforward("T_ff", "w_ref", law=ff.static, scale=1.0 / axis.torque_constant))
            terms["T_ff"] = 1.0
        blocks.append(Sum("i", terms))
        m.add(*blocks)
        res = simulate_machine(m, dt=dt, inputs=m.read_inputs({"r": r, "w_ref": np.full(n, w)}), seed=seed,
                               raise_on_failure=True)
        e = r - res.position("theta")
        out[label] = float(np.sqrt(np.mean(e**2)) / sdss.ARCSEC)
    return out


# --------------------------------------------------------------------------- the whole reproduction
@dataclass(frozen=True, eq=False)
class SdssReproduction:
    """All three axes and the tracking extension; :meth:`to_dict` is the JSON document of issue 10,
    :meth:`summary` its text (each identified parameter against the truth, with its interval).
    ``status``: the worst status of its fits, each as its docstring says (the two-step fits: 1
    failed; the rotator's static maps: 1 converged with warnings, such as ``vs`` not identifiable,
    2 not converged); ``message`` names each fit that is not ok (in the JSON document too)."""

    axes: dict
    tracking: dict
    quick: bool
    seed: int
    status: int = 0
    message: str = "ok"

    def summary(self) -> str:
        lines = [f"SDSS telescope axes (seed 002){', quick' if self.quick else ''}, seed {self.seed}: "
                 f"status {self.status} ({self.message})"]
        for name, o in self.axes.items():
            lines.append(f"  {name}:")
            for k, p in o.identified.items():
                true = o.truth.get(k)
                lo, hi = p["ci95"]
                rel = "" if not true else f" ({100 * (p['value'] / true - 1):+.2f} % of the truth {true:.4g}" + (
                    ", inside the 95 % interval)" if lo <= true <= hi else ", OUTSIDE the 95 % interval)")
                lines.append(f"    {k:<10} {p['value']:.5g} [{lo:.5g}, {hi:.5g}]{rel}")
        if self.tracking:
            lines.append("  sidereal tracking RMS [arcsec]: "
                         + ", ".join(f"{k} {v:.3g}" for k, v in self.tracking.items()))
        return "\n".join(lines)

    def to_dict(self) -> dict:
        axes = {}
        for name, o in self.axes.items():
            ident = {k: {"value": p["value"], "ci95": list(p["ci95"])} for k, p in o.identified.items()}
            nr = None
            if name == "azimuth":
                nr = o.nrmse.get("fig4a_triangle")
            elif name == "altitude":
                nr = o.nrmse.get("fig6b_above")
            axes[name] = {"truth": dict(o.truth), "identified": ident, "velocity_nrmse_percent": nr,
                          "nrmse_by_figure_percent": o.nrmse, "nrmse_true_model_percent": o.nrmse_floor}
            if name == "rotator":
                axes[name]["separation_ours"] = o.extra["separation"]
            for key, label in (("screen", "constant_velocity_screen"), ("bench_screen", "hd_bench_screen")):
                scr = o.extra.get(key)
                if scr is not None:  # ours: runs whose speed was not constant, rejected before eq. 10
                    axes[name][label] = {"max_ripple_percent": scr.max_ripple_percent, "runs": int(scr.v.size),
                                         "kept": int(scr.accepted.sum()), "rejected": scr.rejected(),
                                         "not_resolvable_rad_s": [] if scr.resolvable is None else
                                         [float(v) for v, ok in zip(scr.v, scr.resolvable) if not ok]}
            if o.fit is not None:
                axes[name]["initial_guess"] = {k: v for k, v in o.fit.initial_guess.items() if k.startswith("sigma")}
                axes[name]["status"] = o.fit.status
                axes[name]["message"] = o.fit.message
        return {"format": REPRODUCTION_FORMAT, "reproduction": "sdss",
                "paper": "seed 002, Friction Model of the 2.5 m SDSS Telescope", "quick": self.quick, "seed": self.seed,
                "status": self.status, "message": self.message,
                "axes": axes, "sidereal_tracking_rms_arcsec": self.tracking,
                "encoder": sdss.Encoder().name, "dt_log_s": DT_LOG}

    def plot(self, ax=None):
        from ..plotting.sdss import reproduction_figure

        return reproduction_figure(self)


def run(*, quick: bool = False, seed: int = 0, progress=None,
        max_ripple_percent: float | None = MAX_RIPPLE_PERCENT) -> SdssReproduction:
    """Run every experiment and estimation. ``progress(label)`` is called before each part.
    ``max_ripple_percent``: the constant-velocity screen of the azimuth and rotator campaigns
    (``None`` keeps every run)."""
    step = progress or (lambda label: None)
    step("azimuth")
    az = run_azimuth(quick=quick, seed=seed, max_ripple_percent=max_ripple_percent)
    step("altitude")
    alt = run_altitude(quick=quick, seed=seed)
    step("rotator")
    rot = run_rotator(quick=quick, seed=seed, max_ripple_percent=max_ripple_percent)
    step("sidereal tracking (ours)")
    trk = sidereal_tracking(model=az.fit.model if az.fit.model is not None else None,
                            duration=15.0 if quick else 30.0, seed=seed)
    axes = {"azimuth": az, "altitude": alt, "rotator": rot}
    status, message = worst_status(_parts(axes))
    return SdssReproduction(axes=axes, tracking=trk, quick=quick, seed=seed, status=status, message=message)


def _parts(axes: dict) -> dict:
    """``{part: (status, message)}`` of the fits of every axis (:func:`worst_status`): the azimuth
    and altitude two-step fits, the rotator's static map and its separation fits."""
    parts = {}
    for name, o in axes.items():
        if name in ("azimuth", "altitude"):
            parts[name] = (1, "no fit") if o.fit is None else (o.fit.status, o.fit.message)
        for key in ("static_result", "hd_result", "bearing_result"):
            r = o.extra.get(key)
            if r is not None:  # a static map's status 1 is "converged with warnings": name them
                why = "; ".join(getattr(r, "warnings", ())) or r.message
                parts[f"{name} {key.removesuffix('_result')}"] = (r.status, why)
    return parts


# --------------------------------------------------------------------------- interval coverage
def _coverage_seed(*, seed: int, quick: bool, joint: bool = True,
                   max_ripple_percent: float | None = MAX_RIPPLE_PERCENT) -> dict:
    """One noise seed of :func:`coverage` (a task of :func:`frictionkit.study.run_tasks`):
    ``{axis: {name: [value, lo, hi, truth]}}`` of every identified parameter, in ``"params"``."""
    out = {}
    for name, fn in (("azimuth", run_azimuth), ("altitude", run_altitude), ("rotator", run_rotator)):
        kw = {} if name == "altitude" else {"max_ripple_percent": max_ripple_percent}
        o = fn(quick=quick, seed=seed, **kw, **({"joint": joint} if name == "azimuth" else {}))
        if o.fit is not None and o.fit.status != 0:
            raise RuntimeError(f"{name} seed {seed}: {o.fit.message}")
        out[name] = {k: [float(p["value"]), float(p["ci95"][0]), float(p["ci95"][1]), float(o.truth[k])]
                     for k, p in o.identified.items()}
    return {"params": out}


def coverage(*, seeds=range(20), quick: bool = False, joint: bool = True, workers: int | None = 0, scheduler=None,
             out=None, progress=True, max_ripple_percent: float | None = MAX_RIPPLE_PERCENT) -> dict:
    """How often the reported 95 % intervals contain the truth (issue 10: 85–99 % over 20 noise
    seeds and all identified parameters together): every identified parameter of the azimuth
    (8 static + σ0, σ1), the altitude (the same ten, dynamic first) and the rotator (the combined
    map of eq. 13b, 8) per noise seed, each seed one task of the study engine
    (:func:`frictionkit.study.run_tasks`; ``workers=0`` this process, ``N`` a LocalCluster).
    ``joint=False``: the azimuth's σ0, σ1 from the triangle alone (the state before the joint fit).
    ``max_ripple_percent``: the constant-velocity screen (``None``: every run kept, the state before it).

    Returns a JSON-ready dict: ``hits``/``n``/``percent`` overall and per axis, per parameter,
    the misses (axis, parameter, seed), and per parameter the mean error over the seeds in
    units of the interval half-width (``mean_z``; |mean_z| well above 1/sqrt(seeds) is a bias
    the intervals do not carry) and the RMS of that z (about 1 for calibrated Wald intervals,
    i.e. the interval width is the spread of the estimates over seeds).
    """
    import json
    import time
    from pathlib import Path

    from ..study import Task, run_tasks

    t0 = time.perf_counter()
    seeds = [int(s) for s in seeds]
    tasks = [Task(label=f"seed={s}", func=_coverage_seed,
                  kwargs={"seed": s, "quick": bool(quick), "joint": bool(joint), "max_ripple_percent": max_ripple_percent})
             for s in seeds]
    res = run_tasks(tasks, out=None if out is None else Path(out) / "sdss_coverage.parquet", key="seed",
                    scheduler=scheduler, workers=workers, progress=progress, label="sdss coverage")
    per_param: dict = {}
    misses = []
    failed = {}
    for row in res.table.to_dict("records"):
        if not row["ok"]:
            failed[row["seed"]] = row["error"]
            continue
        for axis, params in json.loads(row["params"]).items():
            for k, (v, lo, hi, tr) in params.items():
                hit = lo <= tr <= hi
                half = max(0.5 * (hi - lo), 1e-300)
                per_param.setdefault((axis, k), []).append((hit, (v - tr) / half * 1.959964))
                if not hit:
                    misses.append([axis, k, row["seed"]])
    axes: dict = {}
    for (axis, k), rows in per_param.items():
        z = np.array([r[1] for r in rows])
        a = axes.setdefault(axis, {"hits": 0, "n": 0, "parameters": {}})
        h = int(sum(r[0] for r in rows))
        a["hits"] += h
        a["n"] += len(rows)
        a["parameters"][k] = {"hits": h, "n": len(rows), "mean_z": float(np.mean(z)),
                              "rms_z": float(np.sqrt(np.mean(z**2)))}
    for a in axes.values():
        a["percent"] = 100.0 * a["hits"] / max(a["n"], 1)
    hits = sum(a["hits"] for a in axes.values())
    n = sum(a["n"] for a in axes.values())
    return {"seeds": len(seeds), "quick": bool(quick), "joint": bool(joint), "max_ripple_percent": max_ripple_percent,
            "hits": hits, "n": n, "percent": 100.0 * hits / max(n, 1),
            "axes": axes, "misses": misses, "failed": failed, "engine": res.to_dict(),
            "elapsed_s": time.perf_counter() - t0}
