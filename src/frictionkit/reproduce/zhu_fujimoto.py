"""Reproduction of seed 001 (Zhu & Fujimoto) on the simulated elastic stage.

* :func:`table3` — the §5 reference ``25 (1 - cos 2 pi t)`` mm with the sinc, Coulomb and
  sigmoid compensators (and the control experiment ``sigmoid_post_only``): maximum tracking
  error during the reverse motion (Table 3, Fig. 15) and when the motor input and the drive
  force turn to braking before zero speed (Fig. 5(b)).
* :func:`fig10` — ``l_d / R`` through slow/fast, reverse/non-reverse zero-speed motions.
* :func:`fig5` — conventional (sinc) compensation after a slow vs a fast deceleration (Fig. 5).
* :func:`selector` — Table 2 selector vs each fixed compensator on a mixed trajectory.
* :func:`fast_non_reverse_redesign` — Table 2's redesigned reference for a fast non-reverse
  motion (:func:`redesigned_non_reverse_reference`) against the original fast stop.
* :func:`fig2` — frequency response current -> motor angle against the eq. 1 fit (Fig. 2).
* :func:`run` — all of them, the JSON-ready summary used by ``frictionkit reproduce zhu-fujimoto``.

Everything runs on the machine core (:func:`frictionkit.presets.ballscrew.simulate_stage`).
The plant is :class:`~frictionkit.plants.ballscrew.ElasticBallScrew` built from
:mod:`frictionkit.presets.zhu_fujimoto` (paper values + recorded assumptions, all chosen
before any run; none tuned towards a finding), in one of two stages: ``"fig2"`` (default,
inertia calibrated to the measured response of eq. 1 / Fig. 2) or ``"table1"`` (Table 1's
inertias as printed); the preset's docstring says why ``"fig2"`` is the default. The README
"Reproductions" table lists every finding for both stages with its numbers.

What the simulation shows on the ``"fig2"`` stage (quick, 13 variants, every nut model)
-------------------------------------------------------------------------------------
* Fig. 2 within 1 dB (-0.19 to +0.09 dB); Fig. 5(b) reproduced: the motor input turns to
  braking 53-55.5 ms before zero speed in the §5 reversal (F_bn 16.5-17 ms before).
* Table 3 in the paper's order, sigmoid 1.98-2.65 < sinc 2.13-2.83 < Coulomb 2.65-2.92 µm,
  but by 0.01-0.25 µm only, and *not* because of the reduction before zero speed: the
  post-only sigmoid is 0.50-0.98 µm better than the sigmoid in every run.
* Fig. 5: the conventional compensation is not worse after the fast deceleration (fast - slow
  -1.07 to -0.59 µm); l_d rises before zero speed in fast decelerations (the overrun), no drop;
  the selector does not beat sinc on the mixed run (wins 1 of 13); the redesigned fast
  non-reverse stop ends in Pattern I and lowers the error by 1.5-1.9 µm for 75 ms more.

What the simulation shows on the ``"table1"`` stage (quick and full, 13 variants)
-------------------------------------------------------------------------------
* Fig. 2 level +6.2 to +7.2 dB; Fig. 5(b) not reproduced: the motor input keeps the direction
  of motion until zero speed (F_bn turns 16-17.5 ms before). Fig. 5 reproduced: the sinc
  compensation is worse after the fast deceleration (fast - slow +1.09 to +1.70 µm). The
  post-only sigmoid beats the sigmoid by
  0.47-0.80 µm; the redesigned fast non-reverse stop lowers the error by 2.3-2.6 µm.
* Table 3: every law within a factor 3 of the paper and sinc < Coulomb, but the sigmoid
  is *not* best: sinc ≈ 2.4 < sigmoid ≈ 3.0 < Coulomb ≈ 3.2 µm (paper 4.24 / 1.65 / 5.44).
  In this model both friction sites are rate-form (Dahl) laws of their own sliding
  displacement: the friction keeps its sign until the stage stops, so reducing ``u_f``
  before zero speed under-compensates; the paper's mechanism (friction transition tied to
  the flank change of the balls when ``F_bn`` reverses, Pattern II) is not in the model.
* Fig. 10: ``l_d`` stays at ``R`` (within the scale resolution) through slow decelerations;
  in fast ones it departs before zero speed by ~1 %, but *upwards* (the table overruns the
  motor once the drive force turns into braking, the "overrun" of §4) — the paper reports a
  decrease.
* Table 2 selector: picks sinc for slow and sigmoid for fast reversals, and flags fast
  non-reverse motions; because of the Table 3 result it does not beat sinc everywhere.

Nut friction model ``"flank"`` (``nut_model=``; preset default stays ``"sliding"``)
---------------------------------------------------------------------------------
Adds the paper's Pattern I/II mechanism (§3.2, Figs. 8-9) as physics: the nut friction is
split into the load-independent drag (bearings, seals) and two groove-flank pre-rolling
sites whose levels follow the flank ball loads, i.e. the sign and size of ``F_bn``; a flank
that unloads loses its traction (see :class:`~frictionkit.plants.ballscrew.ElasticBallScrew`).
Parameters from catalogue values fixed before the first run (preset: 10 % Ca preload,
preload-drag law ``K = 0.05/sqrt(tan beta)``). Result (quick: 3 seeds, ±30 % on each
assumed stiffness, ±30 % on the preload and on the flank coefficient; full: 3 seeds): the
same three findings fail, with numbers within 0.1 µm (errors) and 0.003 (``l_d/R``) of the sliding
model. Why: in these
decelerations ``F_bn`` reverses ~17 ms (~150 µm) before zero speed (``C_t v`` and
``f_g`` vs ``M_t a``), both flanks stay loaded (``|F_bn| < 2P``) so the flank levels keep
their sum, and traction lost by the unloading flank is rebuilt by the forward rolling within
the 10 µm pre-rolling length — long before the sigmoid's few-µm window. And any deformation
released when ``F_bn`` turns into braking moves the table *ahead* of the motor, so ``l_d``
rises in this chain whatever the nut model.

Nut model ``"hertz"`` (flank friction on a preloaded Hertzian ball contact)
-------------------------------------------------------------------------
The contact becomes ``F_bn(d) = c (d0 + d)_+^1.5 - c (d0 - d)_+^1.5`` (two flank sets,
preload 10 % Ca = 3.5 kN, ``dF_bn/dd(0) = k_nut``: ``d0`` = 13.1 µm; one set unloads, with
lost motion, beyond ``2^1.5 P`` = 9.9 kN); no constant added, all fixed before the first
run. Result (quick, 3 seeds and ±30 % on each assumed stiffness): the same three findings
fail, Table 3 within one scale count (0.1 µm) of the flank model, ``l_d/R`` within 0.0003.
Why: the largest drive force in these runs is 1.7 kN (§5 reference) and 0.9-1.2 kN
(Fig. 10 cases), where the Hertz contact's tangent stiffness is within 0.5 % of ``k_nut``;
the flank change with lost motion lies at 9.9 kN, far outside the motions of the paper.

Fig. 2 (:func:`fig2`)
---------------------
The seed prints no resonance; the figure is not in the text, only that eq. 1 (J = 0.01,
B = 0.1) is the fitted line. The model's first anti-resonance/resonance of current ->
``theta_m`` are 139.9 / 165.9 Hz on the table1 stage, 139.9 / 149.7 Hz on the fig2 stage
(±30 % stiffness variants 128-148 / 137-176 Hz), above the 80 Hz DOB built on the rigid
model. The level in 5-50 Hz is +6.2 to +7.2 dB above the fitted line on the table1 stage
because Table 1's inertias add to 4.3e-3 kg·m², not 0.01 (mass, not stiffness); the fig2
stage is calibrated to it (-0.19 to +0.09 dB).
"""

from __future__ import annotations

import dataclasses
from dataclasses import dataclass, field

import numpy as np

from ..control.compensators import RollingCompensator
from ..control.dob import DisturbanceObserver
from ..control.loop import ClosedLoopResult, Sensors, TwoDofController
from ..control.pid import PID
from ..control.ptc import PerfectTrackingControl
from ..control.trajectories import (
    Reference,
    cosine_reference,
    mixed_reference,
    piecewise_reference,
    zero_speed_reference,
)
from ..control.zero_speed import (
    classify_crossings,
    deformation_ratio,
    max_ratio_before_zero,
    min_ratio_before_zero,
    pattern_i_stop_segments,
    reversal_lead,
    select_compensators,
)
from . import REPRODUCTION_FORMAT, worst_status
from ..errors import ParameterError, SimulationError
from ..plants.ballscrew import ElasticBallScrew
from ..presets import zhu_fujimoto as zf
from ..presets.ballscrew import simulate_stage

LAWS3 = ("sinc", "coulomb", "sigmoid")
#: Table 3's laws plus the control experiment ``sigmoid_post_only`` (the sigmoid without its
#: reduction before zero speed, :mod:`frictionkit.control.compensators`).
TABLE3_LAWS = LAWS3 + ("sigmoid_post_only",)
LD_CASES = ("slow_reverse", "fast_reverse", "slow_non_reverse", "fast_non_reverse")
STAGES = zf.STAGES


def paper_plant(nut_model: str = zf.NUT_MODEL, stage: str = zf.STAGE, **changes) -> ElasticBallScrew:
    """The elastic stage of the preset with nut model ``nut_model``
    (``"sliding"``/``"flank"``/``"hertz"``) and ``stage`` (``"fig2"``, the default: inertia
    calibrated to the measured response; ``"table1"``: Table 1 as printed; see
    :mod:`frictionkit.presets.zhu_fujimoto`); keyword ``changes`` replace fields."""
    return dataclasses.replace(ElasticBallScrew(**zf.plant_kwargs(nut_model, stage)), **changes)


def stage_of(plant: ElasticBallScrew) -> str:
    """``"table1"`` or ``"fig2"`` when the plant's motor inertia is that stage's, else ``"custom"``."""
    for name, J in (("table1", zf.J_m), ("fig2", zf.J_m_FIG2)):
        if abs(plant.J_m - J) <= 1e-12 * J:
            return name
    return "custom"


def scaled_plant(name: str, factor: float, nut_model: str = zf.NUT_MODEL, stage: str = zf.STAGE) -> ElasticBallScrew:
    """The paper plant with one assumed stiffness (``zf.ASSUMED_STIFFNESSES``) scaled by ``factor``."""
    if name not in zf.ASSUMED_STIFFNESSES:
        raise ParameterError(f"name = {name!r}: must be one of {zf.ASSUMED_STIFFNESSES}")
    p = paper_plant(nut_model, stage)
    if name == "k_axial":
        return dataclasses.replace(p, k_axial=p.k_axial * factor, k_axial_right=p.k_axial_right * factor)
    return dataclasses.replace(p, **{name: getattr(p, name) * factor})


def paper_controller() -> TwoDofController:
    """§2.2: PTC (1 ms, n = 2) + 20 Hz pole-placement PID + 80 Hz DOB, all on eq. 1 nominal."""
    nom = dict(K_tau=zf.K_tau, J=zf.J_n, B=zf.B_n)
    return TwoDofController(
        ptc=PerfectTrackingControl(**nom, T_frame=zf.T_PTC, n=2),
        pid=PID.pole_placement(**nom, bandwidth_hz=zf.BANDWIDTH_HZ, T=zf.T_CONTROL,
                               derivative_cutoff_hz=zf.DERIVATIVE_CUTOFF_HZ),
        dob=DisturbanceObserver(**nom, cutoff_hz=zf.DOB_CUTOFF_HZ, T=zf.T_CONTROL),
        R=zf.R, i_max=zf.I_MAX, feedback=zf.FEEDBACK,
    )


def paper_sensors() -> Sensors:
    return Sensors(encoder_counts=zf.ENCODER_COUNTS, scale_resolution=zf.SCALE_RESOLUTION,
                   encoder_noise_counts=zf.ENCODER_NOISE_COUNTS, scale_noise=zf.SCALE_NOISE)


def paper_compensator() -> RollingCompensator:
    return RollingCompensator(F0=zf.F0_COMPENSATION, xs=zf.XS, sigma=zf.SIGMA)


def _classify(ref: Reference, plant: ElasticBallScrew):
    return classify_crossings(ref, table_mass=plant.M_t, guide_friction=plant.guide_friction,
                              guide_viscosity=plant.C_t)


def _run(plant, ref, u_f, seed) -> ClosedLoopResult:
    res = simulate_stage(plant, paper_controller(), ref, compensation=u_f, sensors=paper_sensors(),
                         seed=seed, substeps=zf.N_SUBSTEPS)
    if not res.success:
        raise SimulationError(res.message)
    return res


def reversal_errors(res: ClosedLoopResult, crossings, window=zf.REVERSAL_WINDOW, *,
                    reverse_only: bool = True) -> np.ndarray:
    """Max ``|r - x_t,meas|`` [m] in ``[t0 + window[0], t0 + window[1]]`` for each reversal
    (each zero-speed point with ``reverse_only=False``)."""
    out = []
    for c in crossings:
        if reverse_only and not c.reverse:
            continue
        sel = (res.t >= c.t0 + window[0]) & (res.t <= c.t0 + window[1])
        out.append(np.max(np.abs(res.error[sel])))
    return np.array(out)


def _decel_start(ref: Reference, c) -> float:
    """Start of the deceleration that ends at the zero-speed point ``c`` [s]."""
    idx = np.flatnonzero((ref.t < c.t0) & (c.before * ref.a >= 0.0))
    return float(ref.t[idx[-1] + 1]) if idx.size and idx[-1] + 1 < ref.t.size else float(ref.t[0])


def leads_ms(res: ClosedLoopResult, ref: Reference, c) -> dict:
    """How long before the zero-speed point ``c`` [ms] the motor input (applied current, with
    the compensation) and the drive force ``F_bn`` turned against the motion and stayed so
    (searched from the start of the deceleration); ``None`` where they did not."""
    since = _decel_start(ref, c)
    out = {}
    for key, sig in (("motor_input", res.i), ("drive_force", res.drive_force)):
        lead = reversal_lead(res.t, sig, c, since=since)
        out[key] = None if lead is None else lead * 1e3
    return out


@dataclass(frozen=True, eq=False)
class Table3Result:
    """Max tracking error [µm] during the reverse motion per law (:data:`TABLE3_LAWS`), the
    lead [ms] of the motor-input and drive-force reversals before the first zero-speed point
    per law (:func:`leads_ms`), and the runs behind them."""

    max_error_um: dict
    runs: dict = field(repr=False)
    crossings: list = field(repr=False)
    leads_ms: dict = field(default_factory=dict)

    def plot(self, *, crossing: int = 0, ax=None):
        """Fig. 15-like error traces around one reversal; returns the axes."""
        from ..plotting.ballscrew import plot_reversal_errors

        return plot_reversal_errors(self, crossing=crossing, ax=ax)


def table3(*, plant: ElasticBallScrew | None = None, seed: int = 0, quick: bool = False) -> Table3Result:
    """Seed 001 Table 3 / Fig. 15 on the simulated stage.

    The §5 reference runs through its reversals at 0.5, 1.0, 1.5 and 2.0 s (2.15 s); quick
    mode stops after the first (0.65 s). Each law's value is the max over the reversals.
    Besides the paper's three laws, ``sigmoid_post_only`` (the sigmoid without its reduction
    before zero speed) tests whether that reduction is what lowers the error.
    """
    plant = paper_plant() if plant is None else plant
    ref = cosine_reference(amplitude=zf.REF_AMPLITUDE, period=zf.REF_PERIOD,
                           duration=0.65 if quick else 2.15, T=zf.T_CONTROL)
    cs = _classify(ref, plant)
    comp = paper_compensator()
    runs, err, leads = {}, {}, {}
    for law in TABLE3_LAWS:
        res = _run(plant, ref, comp.signal(ref, law, cs), seed)
        runs[law] = res
        err[law] = float(reversal_errors(res, cs).max() * 1e6)
        leads[law] = leads_ms(res, ref, cs[0])
    return Table3Result(max_error_um=err, runs=runs, crossings=cs, leads_ms=leads)


@dataclass(frozen=True, eq=False)
class Fig10Result:
    """``min(l_d)/R`` and ``max(l_d)/R`` over the deceleration per case, and the runs behind them."""

    min_ratio: dict
    max_ratio: dict
    runs: dict = field(repr=False)
    ratios: dict = field(repr=False)
    crossings: dict = field(repr=False)
    decel_start: dict = field(repr=False)
    #: the same from the true (unquantised, noiseless) x_t and theta_m of the runs
    true_min_ratio: dict = field(default_factory=dict)
    true_max_ratio: dict = field(default_factory=dict)
    references: dict = field(default_factory=dict, repr=False)

    def plot(self, case: str = "fast_reverse", *, ax=None):
        """Fig. 10-like ``l_d / R - 1`` through one case; returns the axes."""
        from ..plotting.ballscrew import plot_deformation_ratio

        return plot_deformation_ratio(self, case, ax=ax)


def fig10(*, plant: ElasticBallScrew | None = None, seed: int = 0, quick: bool = False) -> Fig10Result:
    """Seed 001 Fig. 10: ``l_d`` through the four zero-speed cases (sinc/hold compensation
    after zero speed, as in the paper's experiments)."""
    plant = paper_plant() if plant is None else plant
    comp = paper_compensator()
    ratios, runs, mins, maxs, css, starts, tmins, tmaxs, refs = {}, {}, {}, {}, {}, {}, {}, {}, {}
    for case in LD_CASES:
        fast = case.startswith("fast")
        decel = zf.LD_FAST_DECEL if fast else zf.LD_SLOW_DECEL
        ref = zero_speed_reference(reverse=not case.endswith("non_reverse"), speed=zf.LD_SPEED, decel=decel,
                                   accel=zf.LD_FAST_DECEL, t_cruise=0.1 if quick else 0.3,
                                   t_after=0.05, T=zf.T_CONTROL)
        cs = _classify(ref, plant)
        res = _run(plant, ref, comp.signal(ref, "sinc", cs), seed)
        d = deformation_ratio(res.t, res.x_t_meas, res.theta_m_meas, R=plant.R, Tp=zf.LD_WINDOW)
        c = cs[0]
        t_start = c.t0 - zf.LD_SPEED / decel
        runs[case], ratios[case], css[case], starts[case], refs[case] = res, d, cs, t_start, ref
        mins[case] = min_ratio_before_zero(d, t_start=t_start, t_zero=c.t0)
        maxs[case] = max_ratio_before_zero(d, t_start=t_start, t_zero=c.t0)
        dt = deformation_ratio(res.t, res.x_t, res.theta_m, R=plant.R, Tp=zf.LD_WINDOW)
        tmins[case] = min_ratio_before_zero(dt, t_start=t_start, t_zero=c.t0)
        tmaxs[case] = max_ratio_before_zero(dt, t_start=t_start, t_zero=c.t0)
    return Fig10Result(min_ratio=mins, max_ratio=maxs, runs=runs, ratios=ratios, crossings=css, decel_start=starts,
                       true_min_ratio=tmins, true_max_ratio=tmaxs, references=refs)


@dataclass(frozen=True, eq=False)
class Fig5Result:
    """Seed 001 Fig. 5: conventional (sinc, from the reverse point) compensation after a slow
    and after a fast deceleration: max error [µm] in ``zf.ZERO_SPEED_WINDOW`` around the
    reversal and the leads [ms] of the motor-input and drive-force reversals before zero speed
    (``None``: no reversal)."""

    max_error_um: dict
    leads_ms: dict
    runs: dict = field(repr=False)
    crossings: dict = field(repr=False)

    def plot(self, *, signal: str = "error", ax=None):
        """Fig. 5-like traces of the slow and the fast reversal against the time from zero speed:
        tracking error (``signal="error"``) or motor current (``"input"``); returns the axes."""
        from ..plotting.ballscrew import plot_fig5

        return plot_fig5(self, signal=signal, ax=ax)


def fig5(fig10_result: Fig10Result) -> Fig5Result:
    """Seed 001 Fig. 5 from the slow- and fast-reverse runs of :func:`fig10` (the same
    references and the same conventional sinc compensation from the reverse point)."""
    err, leads, runs, css = {}, {}, {}, {}
    for case in ("slow_reverse", "fast_reverse"):
        res, cs = fig10_result.runs[case], fig10_result.crossings[case]
        err[case] = float(reversal_errors(res, cs, zf.ZERO_SPEED_WINDOW).max() * 1e6)
        leads[case] = leads_ms(res, fig10_result.references[case], cs[0])
        runs[case], css[case] = res, cs
    return Fig5Result(max_error_um=err, leads_ms=leads, runs=runs, crossings=css)


def redesigned_non_reverse_reference(plant: ElasticBallScrew, *, quick: bool = False,
                                     margin: float = zf.REDESIGN_MARGIN) -> Reference:
    """The Fig. 10 fast non-reverse motion with its stop redesigned (Table 2: "redesign of
    trajectory reference is necessary"): the same cruise and re-acceleration, the stop from
    :func:`~frictionkit.control.zero_speed.pattern_i_stop_segments` (fast deceleration while
    eq. 2 keeps the drive force in the direction of motion, then ``(1 - margin) f_g / M_t``
    to rest), so the zero-speed point is reached in Pattern I."""
    a = zf.LD_FAST_DECEL
    stop = pattern_i_stop_segments(speed=zf.LD_SPEED, decel=a, table_mass=plant.M_t,
                                   guide_friction=plant.guide_friction, guide_viscosity=plant.C_t, margin=margin)
    segs = [(zf.LD_SPEED / a, a), (0.1 if quick else 0.3, 0.0), *stop, (zf.LD_SPEED / a, a), (0.05, 0.0)]
    return piecewise_reference(segs, T=zf.T_CONTROL)


@dataclass(frozen=True, eq=False)
class RedesignResult:
    """Table 2, fast non-reverse: the original fast stop (``"original"``, the Fig. 10 run with
    the ``hold`` compensation) against the redesigned Pattern I stop (``"redesigned"``, same
    compensation). Per variant: Table 2 kind of the zero-speed point, max error [µm] in
    ``zf.ZERO_SPEED_WINDOW`` around it, leads [ms] of the motor-input / drive-force reversals
    before it (``None``: none) and the stop's duration [ms]."""

    kind: dict
    max_error_um: dict
    leads_ms: dict
    stop_ms: dict
    runs: dict = field(repr=False)
    crossings: dict = field(repr=False)

    def summary(self) -> str:
        return "Table 2 fast non-reverse stop: " + "; ".join(
            f"{k} ({self.kind[k]}) max error {self.max_error_um[k]:.3f} µm, stop {self.stop_ms[k]:.1f} ms"
            for k in ("original", "redesigned"))

    def to_dict(self) -> dict:
        return {k: {"kind": self.kind[k], "max_error_um": self.max_error_um[k], "stop_ms": self.stop_ms[k],
                    "motor_input_reverses_before_zero_ms": self.leads_ms[k]["motor_input"],
                    "drive_force_reverses_before_zero_ms": self.leads_ms[k]["drive_force"]}
                for k in ("original", "redesigned")}


def fast_non_reverse_redesign(fig10_result: Fig10Result, *, plant: ElasticBallScrew | None = None, seed: int = 0,
                              quick: bool = False) -> RedesignResult:
    """Table 2's answer for a fast non-reverse motion, run: the redesigned reference
    (:func:`redesigned_non_reverse_reference`) against the original Fig. 10 fast non-reverse
    run, both with the ``hold`` compensation the selector falls back to."""
    plant = paper_plant() if plant is None else plant
    new_ref = redesigned_non_reverse_reference(plant, quick=quick)
    cs_new = _classify(new_ref, plant)
    res_new = _run(plant, new_ref, paper_compensator().signal(new_ref, "hold", cs_new), seed)
    res_old, cs_old = fig10_result.runs["fast_non_reverse"], fig10_result.crossings["fast_non_reverse"]
    refs = {"original": fig10_result.references["fast_non_reverse"], "redesigned": new_ref}
    out = {k: {} for k in ("kind", "err", "leads", "stop")}
    runs = {"original": res_old, "redesigned": res_new}
    css = {"original": cs_old, "redesigned": cs_new}
    for k in ("original", "redesigned"):
        c = css[k][0]
        out["kind"][k] = c.kind
        err = reversal_errors(runs[k], css[k], zf.ZERO_SPEED_WINDOW, reverse_only=False)
        out["err"][k] = float(err[0] * 1e6)
        out["leads"][k] = leads_ms(runs[k], refs[k], c)
        out["stop"][k] = (c.t0 - _decel_start(refs[k], c)) * 1e3
    return RedesignResult(kind=out["kind"], max_error_um=out["err"], leads_ms=out["leads"], stop_ms=out["stop"],
                          runs=runs, crossings=css)


@dataclass(frozen=True, eq=False)
class SelectorResult:
    """Max reversal error [µm] of the Table 2 selector and of each fixed law on a mixed run."""

    selected: list
    mixed_max_error_um: float
    fixed_max_error_um: dict
    per_crossing_um: dict = field(repr=False)

    @property
    def best_fixed_max_error_um(self) -> float:
        return float(min(self.fixed_max_error_um.values()))


def selector(*, plant: ElasticBallScrew | None = None, seed: int = 0, quick: bool = False) -> SelectorResult:
    """Table 2 selector vs sinc/Coulomb/sigmoid everywhere on slow+fast reversals."""
    plant = paper_plant() if plant is None else plant
    ref = mixed_reference(speed=zf.LD_SPEED, slow_decel=zf.LD_SLOW_DECEL, fast_decel=zf.LD_FAST_DECEL,
                          t_cruise=0.1, pattern="sf" if quick else "sfsf", T=zf.T_CONTROL)
    cs = _classify(ref, plant)
    sel = select_compensators(cs)
    comp = paper_compensator()
    per = {}
    res = _run(plant, ref, comp.signal(ref, [s.law for s in sel], cs), seed)
    per["selector"] = reversal_errors(res, cs) * 1e6
    for law in LAWS3:
        per[law] = reversal_errors(_run(plant, ref, comp.signal(ref, law, cs), seed), cs) * 1e6
    return SelectorResult(selected=sel, mixed_max_error_um=float(per["selector"].max()),
                          fixed_max_error_um={k: float(per[k].max()) for k in LAWS3}, per_crossing_um=per)


@dataclass(frozen=True, eq=False)
class Fig2Result:
    """Frequency response current -> motor angle of the elastic stage vs the eq. 1 fit.

    Attributes: ``f`` [Hz], ``response`` (elastic plant, friction left out) and ``eq1``
    (``K_tau / (J s^2 + B s)`` with the identified J = 0.01, B = 0.1) [rad/A];
    ``antiresonance_hz`` / ``resonance_hz`` (first undamped pair of the chain);
    ``gain_offset_db`` (min, max) of ``|response| / |eq1|`` over ``band_hz``.
    """

    f: np.ndarray
    response: np.ndarray
    eq1: np.ndarray
    antiresonance_hz: float
    resonance_hz: float
    band_hz: tuple
    gain_offset_db: tuple

    def summary(self) -> str:
        lo, hi = self.gain_offset_db
        return (f"Fig. 2: first antiresonance {self.antiresonance_hz:.1f} Hz, resonance {self.resonance_hz:.1f} Hz; "
                f"|response|/|eq. 1| {lo:+.2f}…{hi:+.2f} dB over {self.band_hz[0]:g}–{self.band_hz[1]:g} Hz")

    def to_dict(self) -> dict:
        return {"first_antiresonance_hz": self.antiresonance_hz, "first_resonance_hz": self.resonance_hz,
                "band_hz": list(self.band_hz), "gain_offset_vs_eq1_db": list(self.gain_offset_db)}


def fig2(*, plant: ElasticBallScrew | None = None, f=None, band_hz=(5.0, 50.0)) -> Fig2Result:
    """Seed 001 Fig. 2 check: current -> motor angle of the elastic plant (friction left out,
    see :meth:`ElasticBallScrew.frequency_response`) against the rigid eq. 1 model the paper
    fitted to the measured response.

    The seed text holds only the figure's caption and the statement that eq. 1 (J = 0.01,
    B = 0.1) is the fitted line; it prints no resonance frequency. What can be compared is
    therefore (i) the level of the response in the band where the rigid fit applies (set by
    Table 1's inertias in the model) and (ii) where the elastic chain first departs from a
    rigid body (its first anti-resonance/resonance pair), to be read against the 80 Hz DOB
    built on the rigid model.
    """
    plant = paper_plant() if plant is None else plant
    f = np.logspace(0.0, 3.5, 400) if f is None else np.asarray(f, dtype=float)
    G = plant.frequency_response(f)
    s = 2j * np.pi * f
    G1 = zf.K_tau / (zf.J_n * s * s + zf.B_n * s)
    sel = (f >= band_hz[0]) & (f <= band_hz[1])
    if not sel.any():
        raise ParameterError(f"band_hz = {band_hz!r}: no frequency of f lies in it")
    off = 20.0 * np.log10(np.abs(G[sel] / G1[sel]))
    return Fig2Result(f=f, response=G, eq1=G1,
                      antiresonance_hz=float(plant.antiresonances()[0] / (2 * np.pi)),
                      resonance_hz=float(plant.modes()[0] / (2 * np.pi)), band_hz=tuple(band_hz),
                      gain_offset_db=(float(off.min()), float(off.max())))


#: Paper values the findings are compared with (Table 3 [µm]).
TABLE3_PAPER_UM = dict(zf.TABLE3_UM)


@dataclass(frozen=True, eq=False)
class ReproductionResult:
    """Everything :func:`run` computed; :meth:`to_dict` is the JSON document, :meth:`summary` a text digest."""

    table3: Table3Result
    fig10: Fig10Result
    selector: SelectorResult
    quick: bool
    seed: int
    nut_model: str = zf.NUT_MODEL
    fig2: Fig2Result | None = None
    stage: str = zf.STAGE
    fig5: Fig5Result | None = None
    redesign: RedesignResult | None = None

    def _parts(self) -> dict:
        """``{part: (status, message)}`` of its simulation runs (:func:`~frictionkit.reproduce.worst_status`)."""
        parts = {}
        for part, runs in (("table3", self.table3.runs), ("fig10", self.fig10.runs),
                           ("fig5", {} if self.fig5 is None else self.fig5.runs),
                           ("table2 redesign", {} if self.redesign is None else self.redesign.runs)):
            for k, r in runs.items():
                parts[f"{part} {k}"] = (r.status, r.message)
        return parts

    @property
    def status(self) -> int:
        """The worst status of its simulation runs (0: all ok; see ``ClosedLoopResult``). :func:`run`
        raises on a run that fails, so its results have status 0."""
        return worst_status(self._parts())[0]

    @property
    def message(self) -> str:
        """``"ok"``, or each run that is not ok with its status and message."""
        return worst_status(self._parts())[1]

    def plot(self, ax=None):
        """Without ``ax``: the whole reproduction figure (Fig. 15, Fig. 10, Fig. 5, Table 2's
        redesign), returning its Axes array; with ``ax``: Table 3's error traces in that Axes."""
        from ..plotting.ballscrew import plot_reversal_errors, reproduction_figure

        if ax is None:
            return reproduction_figure(self)[1]
        return plot_reversal_errors(self.table3, ax=ax)

    def summary(self) -> str:
        """Table 3 (simulated vs paper, µm), Fig. 5(b), the selector, Table 2's redesign and Fig. 2."""
        t3 = self.table3
        lines = [f"Zhu & Fujimoto (seed 001), stage {self.stage}, nut model {self.nut_model}, seed {self.seed}"
                 f"{', quick' if self.quick else ''}",
                 "  Table 3 max error during the reverse motion [µm] (simulated / paper):"]
        for k, v in t3.max_error_um.items():
            paper = TABLE3_PAPER_UM.get(k)
            lines.append(f"    {k:<18} {v:7.3f} / {'-' if paper is None else f'{paper:.3f}'}")
        lead = t3.leads_ms["sinc"]["motor_input"]
        lines.append("  Fig. 5(b) motor input reverses before zero speed: "
                     + ("no" if lead is None else f"yes, {lead:.1f} ms"))
        sel = self.selector
        lines.append(f"  selector: mixed {sel.mixed_max_error_um:.3f} µm vs best fixed law "
                     f"{sel.best_fixed_max_error_um:.3f} µm")
        if self.redesign is not None:
            lines.append("  " + self.redesign.summary())
        if self.fig2 is not None:
            lines.append("  " + self.fig2.summary())
        return "\n".join(lines)

    def to_dict(self) -> dict:
        t3 = self.table3
        out = {
            "format": REPRODUCTION_FORMAT, "reproduction": "zhu-fujimoto",
            "paper": "Zhu & Fujimoto, High-precision control for ball-screw-driven stage in zero-speed region (seed 001)",
            "quick": self.quick,
            "seed": self.seed,
            "status": self.status,
            "message": self.message,
            "stage": self.stage,
            "nut_model": self.nut_model,
            "table3": {k: {"max_error_um": v, "paper_um": TABLE3_PAPER_UM.get(k)} for k, v in t3.max_error_um.items()},
            # Fig. 5(b): the §5 fast reversal with the conventional compensation (sinc, from the
            # reverse point): does the motor input turn to braking before zero speed?
            "fig5b": {"motor_input_reverses_before_zero_ms": t3.leads_ms["sinc"]["motor_input"],
                      "drive_force_reverses_before_zero_ms": t3.leads_ms["sinc"]["drive_force"],
                      "reference": "§5 cosine, first reversal (t0 = 0.5 s), sinc compensation"},
            "ld": {k: {"min_ratio_before_zero": self.fig10.min_ratio[k],
                       "max_ratio_before_zero": self.fig10.max_ratio[k],
                       "true_min_ratio_before_zero": self.fig10.true_min_ratio.get(k),
                       "true_max_ratio_before_zero": self.fig10.true_max_ratio.get(k)} for k in LD_CASES},
            "selector": {
                "laws": [s.law for s in self.selector.selected],
                "kinds": [s.crossing.kind for s in self.selector.selected],
                "mixed_max_error_um": self.selector.mixed_max_error_um,
                "best_fixed_max_error_um": self.selector.best_fixed_max_error_um,
                "fixed_max_error_um": self.selector.fixed_max_error_um,
            },
        }
        if self.fig5 is not None:
            out["fig5"] = {k: {"max_error_um": self.fig5.max_error_um[k],
                               "motor_input_reverses_before_zero_ms": self.fig5.leads_ms[k]["motor_input"],
                               "drive_force_reverses_before_zero_ms": self.fig5.leads_ms[k]["drive_force"]}
                           for k in self.fig5.max_error_um}
        if self.redesign is not None:
            out["table2_fast_non_reverse"] = self.redesign.to_dict()
        if self.fig2 is not None:
            out["fig2"] = self.fig2.to_dict()
        return out


def run(*, quick: bool = False, seed: int = 0, plant: ElasticBallScrew | None = None,
        nut_model: str | None = None, stage: str | None = None, progress=None) -> ReproductionResult:
    """Table 3, Fig. 10, Fig. 5, the Table 2 selector and the fast non-reverse redesign.
    ``progress(label)`` is called before each part.

    Also returns the Fig. 2 frequency-response check (:func:`fig2`, no simulation).

    ``nut_model`` (``"sliding"``/``"flank"``/``"hertz"``) and ``stage`` (``"fig2"``/``"table1"``)
    select the preset plant when ``plant`` is not given (defaults ``zf.NUT_MODEL``,
    ``zf.STAGE``); with ``plant`` they must match it.
    """
    step = progress or (lambda label: None)
    if stage is not None and stage not in zf.STAGES:
        raise ParameterError(f"stage = {stage!r}: must be one of {zf.STAGES}")
    if plant is None:
        plant = paper_plant(zf.NUT_MODEL if nut_model is None else nut_model,
                            zf.STAGE if stage is None else stage)
    else:
        if nut_model is not None and nut_model != plant.nut_model:
            raise ParameterError(f"nut_model = {nut_model!r} but plant.nut_model = {plant.nut_model!r}")
        if stage is not None and stage != stage_of(plant):
            raise ParameterError(f"stage = {stage!r} but the plant's motor inertia J_m = {plant.J_m!r} is "
                                 f"that of stage {stage_of(plant)!r}")
    step("Table 3 / Fig. 15: sinc, Coulomb, sigmoid, post-only sigmoid")
    t3 = table3(plant=plant, seed=seed, quick=quick)
    step("Fig. 10 / Fig. 5: l_d in four zero-speed cases")
    f10 = fig10(plant=plant, seed=seed, quick=quick)
    f5 = fig5(f10)
    step("Table 2: selector on a mixed trajectory, redesigned fast non-reverse stop")
    sel = selector(plant=plant, seed=seed, quick=quick)
    red = fast_non_reverse_redesign(f10, plant=plant, seed=seed, quick=quick)
    return ReproductionResult(table3=t3, fig10=f10, selector=sel, quick=quick, seed=seed,
                              nut_model=plant.nut_model, fig2=fig2(plant=plant), stage=stage_of(plant),
                              fig5=f5, redesign=red)


def robustness_variants(seeds=(0, 1, 2), factors=(0.7, 1.3), nut_model: str = zf.NUT_MODEL,
                        stage: str = zf.STAGE):
    """``(label, seed, plant)`` for each noise seed (paper plant) and each assumed stiffness
    scaled by each factor (seed 0)."""
    out = [(f"seed={s}", s, paper_plant(nut_model, stage)) for s in seeds]
    for name in zf.ASSUMED_STIFFNESSES:
        for f in factors:
            out.append((f"{name}x{f:g}", 0, scaled_plant(name, f, nut_model, stage)))
    return out


def _robustness_variant(**run_kwargs) -> dict:
    """One variant of :func:`robustness` (a task of :func:`frictionkit.study.run_tasks`)."""
    return {"summary": run(**run_kwargs).to_dict()}


def robustness(*, quick: bool = True, seeds=(0, 1, 2), factors=(0.7, 1.3), nut_model: str = zf.NUT_MODEL,
               stage: str = zf.STAGE, progress=None, out=None, scheduler=None, workers: int | None = 0) -> dict:
    """:func:`run` summary per variant of :func:`robustness_variants` (label -> summary, as JSON
    would give it back: tuples are lists).

    The variants run on the study engine (:func:`frictionkit.study.run_tasks`, one Dask task
    per variant): ``workers=0`` (default) in this process, ``workers=N`` a LocalCluster of N
    single-threaded processes (``None``: the cores), ``scheduler`` a Dask scheduler address.
    ``out`` (a directory): one Parquet row per variant in ``out/zhu_fujimoto_robustness.parquet``
    (the summary as JSON text), parts beside it; a rerun computes only the missing variants.
    ``progress``: True for a progress bar, or a callable given each finished variant's label.
    A variant that fails raises :class:`~frictionkit.SimulationError` naming it (after the
    others have finished and been written)."""
    import json
    from pathlib import Path

    from ..study import Task, run_tasks

    tasks = [Task(label=label, func=_robustness_variant, kwargs={"quick": quick, "seed": seed, "plant": plant})
             for label, seed, plant in robustness_variants(seeds, factors, nut_model, stage)]
    note = (lambda row: progress(row["variant"])) if callable(progress) else bool(progress)
    res = run_tasks(tasks, out=None if out is None else Path(out) / "zhu_fujimoto_robustness.parquet",
                    key="variant", scheduler=scheduler, workers=workers, progress=note,
                    label="zhu-fujimoto robustness")
    if res.status:
        raise SimulationError(f"robustness: {res.message}; first error: "
                              f"{res.table.loc[~res.table['ok'].astype(bool), 'error'].iloc[0]}")
    return {row["variant"]: json.loads(row["summary"]) for row in res.table.to_dict("records")}
