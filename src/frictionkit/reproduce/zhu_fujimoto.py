"""Reproduction of seed 001 (Zhu & Fujimoto) on the simulated elastic stage.

* :func:`table3` — the §5 reference ``25 (1 - cos 2 pi t)`` mm with the sinc, Coulomb and
  sigmoid compensators: maximum tracking error during the reverse motion (Table 3, Fig. 15).
* :func:`fig10` — ``l_d / R`` through slow/fast, reverse/non-reverse zero-speed motions.
* :func:`selector` — Table 2 selector vs each fixed compensator on a mixed trajectory.
* :func:`fig2` — frequency response current -> motor angle against the eq. 1 fit (Fig. 2).
* :func:`run` — all of them, the JSON-ready summary used by ``frictionkit reproduce zhu-fujimoto``.

The plant is :class:`~frictionkit.plants.ballscrew.ElasticBallScrew` built from
:mod:`frictionkit.presets.zhu_fujimoto` (paper values + recorded assumptions, all chosen
before any run; none tuned towards a finding).

What the simulation shows (quick and full, 3 noise seeds, each assumed stiffness ±30 %)
-------------------------------------------------------------------------------------
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
``theta_m`` are 139.9 / 165.9 Hz (±30 % stiffness variants 128-148 / 151-176 Hz), above the
80 Hz DOB built on the rigid model; the level in 5-50 Hz is +6.2 to +7.2 dB above the
fitted line because Table 1's inertias add to 4.3e-3 kg·m², not 0.01 (mass, not stiffness).
"""

from __future__ import annotations

import dataclasses
from dataclasses import dataclass, field

import numpy as np

from ..control.compensators import RollingCompensator
from ..control.dob import DisturbanceObserver
from ..control.loop import ClosedLoopResult, Sensors, TwoDofController, simulate_closed_loop
from ..control.pid import PID
from ..control.ptc import PerfectTrackingControl
from ..control.trajectories import Reference, cosine_reference, mixed_reference, zero_speed_reference
from ..control.zero_speed import (
    classify_crossings,
    deformation_ratio,
    max_ratio_before_zero,
    min_ratio_before_zero,
    select_compensators,
)
from ..errors import ParameterError, SimulationError
from ..plants.ballscrew import ElasticBallScrew
from ..presets import zhu_fujimoto as zf

LAWS3 = ("sinc", "coulomb", "sigmoid")
LD_CASES = ("slow_reverse", "fast_reverse", "slow_non_reverse", "fast_non_reverse")


def paper_plant(nut_model: str = zf.NUT_MODEL, **changes) -> ElasticBallScrew:
    """The elastic stage of the preset with nut model ``nut_model``
    (``"sliding"``/``"flank"``/``"hertz"``); keyword ``changes`` replace fields."""
    return dataclasses.replace(ElasticBallScrew(**zf.plant_kwargs(nut_model)), **changes)


def scaled_plant(name: str, factor: float, nut_model: str = zf.NUT_MODEL) -> ElasticBallScrew:
    """The paper plant with one assumed stiffness (``zf.ASSUMED_STIFFNESSES``) scaled by ``factor``."""
    if name not in zf.ASSUMED_STIFFNESSES:
        raise ParameterError(f"name = {name!r}: must be one of {zf.ASSUMED_STIFFNESSES}")
    p = paper_plant(nut_model)
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
    res = simulate_closed_loop(plant, paper_controller(), ref, compensation=u_f, sensors=paper_sensors(),
                               seed=seed, n_substeps=zf.N_SUBSTEPS)
    if not res.success:
        raise SimulationError(res.message)
    return res


def reversal_errors(res: ClosedLoopResult, crossings, window=zf.REVERSAL_WINDOW) -> np.ndarray:
    """Max ``|r - x_t,meas|`` [m] in ``[t0 + window[0], t0 + window[1]]`` for each reversal."""
    out = []
    for c in crossings:
        if not c.reverse:
            continue
        sel = (res.t >= c.t0 + window[0]) & (res.t <= c.t0 + window[1])
        out.append(np.max(np.abs(res.error[sel])))
    return np.array(out)


@dataclass(frozen=True, eq=False)
class Table3Result:
    """Max tracking error [µm] during the reverse motion per law, and the runs behind it."""

    max_error_um: dict
    runs: dict = field(repr=False)
    crossings: list = field(repr=False)

    def plot(self, *, crossing: int = 0, ax=None):
        """Fig. 15-like error traces around one reversal; returns the axes."""
        from ..plotting.ballscrew import plot_reversal_errors

        return plot_reversal_errors(self, crossing=crossing, ax=ax)


def table3(*, plant: ElasticBallScrew | None = None, seed: int = 0, quick: bool = False) -> Table3Result:
    """Seed 001 Table 3 / Fig. 15 on the simulated stage.

    The §5 reference runs through its reversals at 0.5, 1.0, 1.5 and 2.0 s (2.15 s); quick
    mode stops after the first (0.65 s). Each law's value is the max over the reversals.
    """
    plant = paper_plant() if plant is None else plant
    ref = cosine_reference(amplitude=zf.REF_AMPLITUDE, period=zf.REF_PERIOD,
                           duration=0.65 if quick else 2.15, T=zf.T_CONTROL)
    cs = _classify(ref, plant)
    comp = paper_compensator()
    runs, err = {}, {}
    for law in LAWS3:
        res = _run(plant, ref, comp.signal(ref, law, cs), seed)
        runs[law] = res
        err[law] = float(reversal_errors(res, cs).max() * 1e6)
    return Table3Result(max_error_um=err, runs=runs, crossings=cs)


@dataclass(frozen=True, eq=False)
class Fig10Result:
    """``min(l_d)/R`` and ``max(l_d)/R`` over the deceleration per case, and the runs behind them."""

    min_ratio: dict
    max_ratio: dict
    runs: dict = field(repr=False)
    ratios: dict = field(repr=False)
    crossings: dict = field(repr=False)
    decel_start: dict = field(repr=False)

    def plot(self, case: str = "fast_reverse", *, ax=None):
        """Fig. 10-like ``l_d / R - 1`` through one case; returns the axes."""
        from ..plotting.ballscrew import plot_deformation_ratio

        return plot_deformation_ratio(self, case, ax=ax)


def fig10(*, plant: ElasticBallScrew | None = None, seed: int = 0, quick: bool = False) -> Fig10Result:
    """Seed 001 Fig. 10: ``l_d`` through the four zero-speed cases (sinc/hold compensation
    after zero speed, as in the paper's experiments)."""
    plant = paper_plant() if plant is None else plant
    comp = paper_compensator()
    ratios, runs, mins, maxs, css, starts = {}, {}, {}, {}, {}, {}
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
        runs[case], ratios[case], css[case], starts[case] = res, d, cs, t_start
        mins[case] = min_ratio_before_zero(d, t_start=t_start, t_zero=c.t0)
        maxs[case] = max_ratio_before_zero(d, t_start=t_start, t_zero=c.t0)
    return Fig10Result(min_ratio=mins, max_ratio=maxs, runs=runs, ratios=ratios, crossings=css, decel_start=starts)


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

    def summary(self) -> dict:
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
    """Everything :func:`run` computed; :meth:`summary` is the JSON document."""

    table3: Table3Result
    fig10: Fig10Result
    selector: SelectorResult
    quick: bool
    seed: int
    nut_model: str = zf.NUT_MODEL
    fig2: Fig2Result | None = None

    def summary(self) -> dict:
        return {
            "paper": "Zhu & Fujimoto, High-precision control for ball-screw-driven stage in zero-speed region (seed 001)",
            "quick": self.quick,
            "seed": self.seed,
            "nut_model": self.nut_model,
            "table3": {k: {"max_error_um": v, "paper_um": TABLE3_PAPER_UM[k]} for k, v in self.table3.max_error_um.items()},
            "ld": {k: {"min_ratio_before_zero": self.fig10.min_ratio[k],
                       "max_ratio_before_zero": self.fig10.max_ratio[k]} for k in LD_CASES},
            "selector": {
                "laws": [s.law for s in self.selector.selected],
                "kinds": [s.crossing.kind for s in self.selector.selected],
                "mixed_max_error_um": self.selector.mixed_max_error_um,
                "best_fixed_max_error_um": self.selector.best_fixed_max_error_um,
                "fixed_max_error_um": self.selector.fixed_max_error_um,
            },
            **({"fig2": self.fig2.summary()} if self.fig2 is not None else {}),
        }


def run(*, quick: bool = False, seed: int = 0, plant: ElasticBallScrew | None = None,
        nut_model: str | None = None, progress=None) -> ReproductionResult:
    """Table 3, Fig. 10 and the Table 2 selector. ``progress(label)`` is called before each part.

    Also returns the Fig. 2 frequency-response check (:func:`fig2`, no simulation).

    ``nut_model`` (``"sliding"``/``"flank"``/``"hertz"``) selects the preset plant's nut friction model
    when ``plant`` is not given (default ``zf.NUT_MODEL``); with ``plant`` it must match it.
    """
    step = progress or (lambda label: None)
    if plant is None:
        plant = paper_plant(zf.NUT_MODEL if nut_model is None else nut_model)
    elif nut_model is not None and nut_model != plant.nut_model:
        raise ParameterError(f"nut_model = {nut_model!r} but plant.nut_model = {plant.nut_model!r}")
    step("Table 3 / Fig. 15: sinc, Coulomb, sigmoid")
    t3 = table3(plant=plant, seed=seed, quick=quick)
    step("Fig. 10: l_d in four zero-speed cases")
    f10 = fig10(plant=plant, seed=seed, quick=quick)
    step("Table 2 selector on a mixed trajectory")
    sel = selector(plant=plant, seed=seed, quick=quick)
    return ReproductionResult(table3=t3, fig10=f10, selector=sel, quick=quick, seed=seed,
                              nut_model=plant.nut_model, fig2=fig2(plant=plant))


def robustness_variants(seeds=(0, 1, 2), factors=(0.7, 1.3), nut_model: str = zf.NUT_MODEL):
    """``(label, seed, plant)`` for each noise seed (paper plant) and each assumed stiffness
    scaled by each factor (seed 0)."""
    out = [(f"seed={s}", s, paper_plant(nut_model)) for s in seeds]
    for name in zf.ASSUMED_STIFFNESSES:
        for f in factors:
            out.append((f"{name}x{f:g}", 0, scaled_plant(name, f, nut_model)))
    return out


def robustness(*, quick: bool = True, seeds=(0, 1, 2), factors=(0.7, 1.3), nut_model: str = zf.NUT_MODEL,
               progress=None) -> dict:
    """:func:`run` summary per variant of :func:`robustness_variants` (label -> summary)."""
    out = {}
    for label, seed, plant in robustness_variants(seeds, factors, nut_model):
        if progress is not None:
            progress(label)
        out[label] = run(quick=quick, seed=seed, plant=plant).summary()
    return out
