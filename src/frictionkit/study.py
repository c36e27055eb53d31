"""Monte-Carlo robustness studies on Dask: parameter spreads × compensators × noise seeds.

A study is one positioning axis on the machine core (``fk.Machine``: a mass, a friction site
holding the plant's law, an actuator with a force limit, a linear scale with resolution and
noise, a PID on the position error), driven along a reference, with a friction compensator
that knows only the *nominal* friction: ``none``, ``coulomb`` (Coulomb + viscous
feed-forward on the reference velocity) or ``static`` (the nominal Stribeck map as
feed-forward). Each run draws the plant's friction parameters from uniform spreads around
the nominal ones (±20–30 % in the robustness studies of the reproductions), simulates with
``fk.simulate_machine`` (one noise seed per run) and keeps the tracking-error statistics.

Runs are Dask tasks (the same cluster choices as :func:`frictionkit.fleet.identify_fleet`:
a LocalCluster of one-thread workers, a scheduler address, or ``scheduler="none"``); each
finished run is written atomically as a one-row Parquet part beside the results file, so a
rerun computes only what is missing; the results are one row per run.

The engine underneath is generic: :func:`run_tasks` runs a list of labelled :class:`Task` s
(a picklable function and its keyword arguments, returning one row as a dict) with one Dask
task each, one Parquet part per task, resumable, and the same rows in this process with
``workers=0``. :func:`run_study` and the reproductions' robustness sweeps
(:func:`frictionkit.reproduce.zhang2023.robustness`,
:func:`frictionkit.reproduce.zhu_fujimoto.robustness`) use it.

The study is described by a TOML file::

    [machine]                      # SI units
    mass = 20.0                    # kg
    law = "lugre"                  # "lugre" or "stribeck" (static)
    Fc = 20.0                      # N
    Fs = 30.0                      # N
    vs = 2e-3                      # m/s
    sigma2 = 200.0                 # N·s/m
    sigma0 = 1e6                   # N/m (LuGre)
    sigma1 = 2e3                   # N·s/m (LuGre)
    Kp = 2e5                       # N/m
    Ki = 2e6                       # N/(m·s)
    Kd = 2e3                       # N·s/m
    tau_d = 1e-3                   # s
    limit = 2000.0                 # N
    resolution = 1e-7              # m
    noise = 5e-8                   # m (std)

    [reference]                    # a sine: amplitude [m], frequency [Hz], duration [s], dt [s]
    amplitude = 1e-3
    frequency = 0.5
    duration = 4.0
    dt = 5e-4

    [spread]                       # relative half-widths of the uniform parameter spreads
    Fc = 0.3
    Fs = 0.3
    sigma2 = 0.2
    sigma0 = 0.3

    [study]
    draws = 20
    seeds = 2
    compensators = ["none", "coulomb", "static"]
    seed = 0

**A preset machine** instead of the generic axis: ``[machine] preset = "emps"`` is the EMPS
benchmark axis in its own position loop (:func:`frictionkit.presets.emps.emps_machine`: the
published P/P cascade, ±10 V, one-sample delay, the published offset −3.1648 N), with the
published mass and friction as the nominal values (M 95.1089 kg, Fc 20.3935 N, σ2
203.5034 N·s/m). Named assumptions (the benchmark gives no Stribeck or dynamic friction):
``Fs = Fc`` (no Stribeck rise) and ``law = "stribeck"`` (static); set ``Fs``, ``vs``,
``law = "lugre"``, ``sigma0``, ``sigma1`` to study them. The default reference is a
0.1 m, 0.2 Hz sine (peak 0.126 m/s, the benchmark's fastest plateau) at the controller's
1 kHz; ``Kp``, ``Ki``, ``Kd``, ``tau_d``, ``limit`` and ``noise`` do not apply (its own
controller), ``resolution`` is the encoder count. The compensators add the nominal friction
feed-forward on the reference velocity as a second force on the axis.

``[machine] preset = "ballscrew"`` is the seed 001 elastic ball-screw stage in its paper
controller (:func:`frictionkit.reproduce.zhu_fujimoto.paper_plant`, ``paper_controller``,
``paper_sensors``: PTC + 20 Hz PID + 80 Hz DOB at 0.5 ms, encoder and 100 nm scale with
noise), the machine of ``frictionkit compensate ballscrew``. Its own ``[machine]`` keys (the
plant's field names; defaults from :mod:`frictionkit.presets.zhu_fujimoto`)::

    [machine]
    preset = "ballscrew"
    mass = 273.0                   # kg, table mass M_t (Table 1)
    guide_friction = 100.0         # N, Dahl level of the guide (assumption)
    nut_friction = 1172.87         # N, nut level as a linear equivalent T / R (assumption)
    presliding_length = 1e-5       # m, Dahl transition length of both sites (Fig. 13 xs)
    nut_model = "sliding"          # "sliding", "flank" or "hertz"
    stage = "fig2"                 # "fig2" or "table1"

``[spread]`` draws from ``mass``, ``guide_friction``, ``nut_friction`` and
``presliding_length`` (default ±30 % on both friction levels). The reference is the §5
cosine ``x = amplitude (1 - cos 2 pi frequency t)`` (25 mm, 1 Hz; 2.15 s: four reversals;
0.65 s: the first), sampled at the controller's period: ``dt`` must stay 0.5 ms.
Compensators (``[study] compensators``, as ``frictionkit compensate ballscrew``): ``none``,
``coulomb`` (eq. 7), ``sinc`` (eq. 6), ``sigmoid`` (eq. 5) with the paper's F0, xs, sigma —
fixed, i.e. designed for the *nominal* friction, while the plant's friction is drawn; the
crossings they switch on are classified on the nominal plant. Each row adds
``reversal_error`` [m] (the largest error in −50…+100 ms around each reversal, as
:mod:`frictionkit.compensate`); ``max_force`` is the motor torque's linear equivalent
``K_tau i / R`` [N].

Results are reused on a rerun only when the study, the run and the frictionkit version agree
(the parts' tag includes the version; a part from another version is recomputed and the
result says so).
"""

from __future__ import annotations

import hashlib
import json
import math
import time
import tomllib
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any, Callable, Mapping

import numpy as np

from .errors import DataError, ParameterError

COMPENSATORS = ("none", "coulomb", "static")
#: Runs one study may hold (draws x seeds x compensators). Assumption: a run is >= 0.1 s of CPU, so
#: 1,000,000 runs are over a day on a 2-core machine — more is a typo, and the run list itself
#: (one dict per run, ~1 kB) must fit in memory.
MAX_RUNS = 1_000_000
#: Machines a study can be built on: the generic axis, or a preset.
PRESETS = ("custom", "emps", "ballscrew")
#: Compensators of each machine (the ball-screw stage's are those of ``frictionkit compensate ballscrew``).
PRESET_COMPENSATORS = {"custom": COMPENSATORS, "emps": COMPENSATORS,
                       "ballscrew": ("none", "coulomb", "sinc", "sigmoid")}
_MACHINE = {"preset": "custom", "mass": 20.0, "law": "lugre", "Fc": 20.0, "Fs": 30.0, "vs": 2e-3, "sigma2": 200.0, "sigma0": 1e6,
            "sigma1": 2e3, "Kp": 2e5, "Ki": 2e6, "Kd": 2e3, "tau_d": 1e-3, "limit": 2000.0, "resolution": 1e-7,
            "noise": 5e-8}
_REFERENCE = {"amplitude": 1e-3, "frequency": 0.5, "duration": 4.0, "dt": 5e-4}
_SPREADABLE = ("Fc", "Fs", "vs", "sigma2", "sigma0", "sigma1", "mass")
_STUDY = {"draws": 20, "seeds": 1, "compensators": list(COMPENSATORS), "seed": 0}
#: The EMPS preset's nominal machine and reference (published values: README of
#: ../shared/data/emps, EMPS_Description.pdf §3.4; Fs = Fc and the static law are assumptions).
_EMPS_MACHINE = {"mass": 95.1089, "law": "stribeck", "Fc": 20.3935, "Fs": 20.3935, "sigma2": 203.5034,
                 "resolution": 0.0}
_EMPS_REFERENCE = {"amplitude": 0.1, "frequency": 0.2, "duration": 5.0, "dt": 1e-3}
_SPREAD = {"Fc": 0.3, "Fs": 0.3, "sigma2": 0.2, "sigma0": 0.3}
#: The ball-screw stage's spreadable parameters (its plant's field names; ``mass`` = M_t).
_BALLSCREW_SPREADABLE = ("mass", "guide_friction", "nut_friction", "presliding_length")
_BALLSCREW_TEXT = ("preset", "nut_model", "stage")


def _ballscrew_defaults() -> tuple[dict, dict]:
    """[machine] and [reference] defaults of the ball-screw preset (seed 001 preset values)."""
    from .presets import zhu_fujimoto as zf

    machine = {"preset": "ballscrew", "mass": zf.M_t, "guide_friction": zf.GUIDE_FRICTION,
               "nut_friction": zf.NUT_FRICTION_TORQUE / zf.R, "presliding_length": zf.PRESLIDING_LENGTH,
               "nut_model": zf.NUT_MODEL, "stage": zf.STAGE}
    reference = {"amplitude": zf.REF_AMPLITUDE, "frequency": 1.0 / zf.REF_PERIOD, "duration": 2.15,
                 "dt": zf.T_CONTROL}
    return machine, reference


def _version() -> str:
    from . import __version__

    return str(__version__)


@dataclass(frozen=True, kw_only=True)
class StudySpec:
    """A Monte-Carlo study (see the module docstring for the TOML form)."""

    machine: dict = field(default_factory=dict)  # defaults (of the preset) filled in on construction
    reference: dict = field(default_factory=dict)
    spread: dict | None = None  # None: the preset's default spreads
    study: dict = field(default_factory=dict)
    source: str | None = None

    def __post_init__(self) -> None:
        where = f"study '{self.source}'" if self.source else "study"
        preset = self.machine.get("preset", "custom")
        if preset not in PRESETS:
            raise DataError(f"{where}: [machine] preset = {preset!r}: must be one of {list(PRESETS)}")
        comps_allowed = PRESET_COMPENSATORS[preset]
        base = {"machine": _MACHINE, "reference": _REFERENCE, "study": _STUDY}
        if preset == "emps":
            base = {**base, "machine": {**_MACHINE, **_EMPS_MACHINE}, "reference": _EMPS_REFERENCE}
        elif preset == "ballscrew":
            bm, br = _ballscrew_defaults()
            base = {"machine": bm, "reference": br, "study": {**_STUDY, "compensators": list(comps_allowed)}}
        if self.spread is None:
            object.__setattr__(self, "spread", {"guide_friction": 0.3, "nut_friction": 0.3}
                               if preset == "ballscrew" else dict(_SPREAD))
        for sec, defaults in base.items():
            d = getattr(self, sec)
            bad = set(d) - set(defaults)
            if bad:
                raise DataError(f"{where}: [{sec}] unknown key(s) {sorted(bad)}; allowed: {sorted(defaults)}")
            object.__setattr__(self, sec, {**defaults, **d})
        m = self.machine
        text = _BALLSCREW_TEXT if preset == "ballscrew" else ("law", "preset")
        if preset == "ballscrew":
            from .presets import zhu_fujimoto as zf

            for k, allowed in (("nut_model", zf.NUT_MODELS), ("stage", zf.STAGES)):
                if m[k] not in allowed:
                    raise DataError(f"{where}: [machine] {k} = {m[k]!r}: must be one of {list(allowed)}")
            dt = self.reference["dt"]
            if isinstance(dt, bool) or not isinstance(dt, (int, float)) or not math.isclose(dt, zf.T_CONTROL,
                                                                                               rel_tol=1e-9):
                raise DataError(f"{where}: [reference] dt = {self.reference['dt']!r}: the ball-screw stage's "
                                f"controller runs at its control period {zf.T_CONTROL} s (seed 001 §2.2); "
                                "leave dt out or set it to that")
        elif m["law"] not in ("lugre", "stribeck"):
            raise DataError(f"{where}: [machine] law = {m['law']!r}: must be 'lugre' or 'stribeck'")
        for k, v in {**m, **self.reference}.items():
            if k in text:
                continue
            if isinstance(v, bool) or not isinstance(v, (int, float)) or not math.isfinite(v) or v < 0:
                raise DataError(f"{where}: [{'reference' if k in self.reference else 'machine'}] {k} = {v!r}: must "
                                "be a finite number >= 0")
        for k in ("mass", "Fc", "Fs", "vs", "sigma0", "presliding_length", "dt", "duration", "frequency"):
            for sec, d in (("machine", m), ("reference", self.reference)):  # the section and value named
                if k in d and d[k] <= 0:
                    raise DataError(f"{where}: [{sec}] {k} = {d[k]!r}: must be > 0")
        spreadable = self.spreadable
        for k, v in self.spread.items():
            if k not in spreadable:
                raise DataError(f"{where}: [spread] {k!r}: spreadable parameters are {list(spreadable)}")
            if isinstance(v, bool) or not isinstance(v, (int, float)) or not 0 <= v < 1:
                raise DataError(f"{where}: [spread] {k} = {v!r}: a relative half-width in [0, 1)")
        s = self.study
        for k in ("draws", "seeds"):
            if isinstance(s[k], bool) or not isinstance(s[k], int) or not 1 <= s[k] <= 100_000:
                raise DataError(f"{where}: [study] {k} = {s[k]!r}: an integer from 1 to 100000")
        seed = s["seed"]
        if isinstance(seed, bool) or not isinstance(seed, int) or not 0 <= seed < 2**32 // 1000:
            # the runs' noise seeds are seed * 1000 + k (-1, 1.5, True and 2**70 were accepted and failed
            # in every run, or silently as seed 1)
            raise DataError(f"{where}: [study] seed = {seed!r}: an integer from 0 to {2**32 // 1000 - 1}")
        comps = s["compensators"]
        if isinstance(comps, list) and len(set(map(str, comps))) < len(comps):
            raise DataError(f"{where}: [study] compensators = {comps!r}: each compensator once (the runs are "
                            "labelled by it)")
        if not isinstance(comps, list) or not comps or any(c not in comps_allowed for c in comps):
            raise DataError(f"{where}: [study] compensators = {comps!r}: a list of {list(comps_allowed)}"
                            + (f" (machine preset {preset!r})" if preset != "custom" else ""))
        total = s["draws"] * s["seeds"] * len(comps)
        if total > MAX_RUNS:  # draws = seeds = 100000 listed 1e10 runs in memory: the process was killed
            raise DataError(f"{where}: [study] draws x seeds x compensators = {total:,} runs; at most "
                            f"{MAX_RUNS:,} per study (split it)")
        ref = self.reference
        if ref["frequency"] * ref["dt"] >= 0.5:  # 1e300 Hz failed every run as "Reference.a[0] = inf"
            raise DataError(f"{where}: [reference] frequency = {ref['frequency']!r} Hz: at or above half the "
                            f"sample rate (1 / (2 dt) = {0.5 / ref['dt']:.6g} Hz); the sampled reference would alias")
        if ref["duration"] < 2 * ref["dt"]:  # every run failed on a 1- or 2-sample reference
            raise DataError(f"{where}: [reference] duration = {ref['duration']!r} s: shorter than two samples "
                            f"(2 dt = {2 * ref['dt']:.6g} s)")
        if preset == "ballscrew" and ref["amplitude"] <= 0:  # the cosine reference needs a stroke
            raise DataError(f"{where}: [reference] amplitude = {ref['amplitude']!r}: must be > 0")
        amp = ref.get("amplitude", 0.0)
        for k in ("resolution", "noise"):  # round 6: resolution 1e300 ran 'ok' with the scale reading 0 throughout
            v = self.machine.get(k)
            if preset in ("custom", "emps") and k in self.machine and amp > 0 and v is not None and v >= amp:
                raise DataError(f"{where}: [machine] {k} = {v!r} m: not finer than the reference amplitude {amp!r} m; "
                                "the scale cannot see the motion it is to track")
        if self.reference["duration"] / self.reference["dt"] > 2_000_000:
            raise DataError(f"{where}: [reference] duration / dt above 2,000,000 samples per run")
        if preset == "ballscrew":
            self._check_ballscrew_plants(where)
        else:
            self._check_loop(where)

    def _check_loop(self, where: str) -> None:
        """The nominal axis's closed loop linearised at dt (:func:`frictionkit.machines.stability.screen`):
        an unstable loop is refused before any run. Was (issue 13 round 6): Kp = 1e300 ran 'ok' with a
        4.2 mm error on a 1 mm reference: the actuator sat at its limit in a limit cycle and the study
        reported that as the tracking error of the axis."""
        from .machines.stability import screen

        m = self.machine
        run = {k: m[k] for k in _SPREADABLE}
        run["compensator"] = "none"
        stab, _ = screen(_machine(self, run), float(self.reference["dt"]))
        if stab is not None and stab.unstable:
            keys = ("mass",) if m.get("preset") == "emps" else ("Kp", "Ki", "Kd", "tau_d", "mass")  # EMPS: its own PID
            raise DataError(f"{where}: [machine] " + ", ".join(f"{k} = {m[k]!r}" for k in keys if k in m)
                            + f": {stab.describe(float(self.reference['dt']))}; the runs would measure a limit "
                            "cycle, not the axis tracking its reference")

    def _check_ballscrew_plants(self, where: str) -> None:
        """Build the stage at both ends of every drawn range up front: an implausible plant
        (mass 1e300 / 1e-300 kg) is one error naming the key and value, not a failure in every
        run with the core's symptom ('mass matrix is singular', 'coupling.c = nan')."""
        from .errors import ParameterError
        from .presets.ballscrew import check_plant
        from .reproduce.zhu_fujimoto import paper_plant

        m = self.machine
        keys = {"mass": "M_t", "guide_friction": "guide_friction", "nut_friction": "nut_friction",
                "presliding_length": "presliding_length"}
        for k, field_ in keys.items():
            sp = self.spread.get(k, 0.0)
            ends = sorted({m[k] * (1.0 - sp), m[k] * (1.0 + sp)})
            drawn = f" (drawn in [{ends[0]:.6g}, {ends[-1]:.6g}] with [spread] {k} = {sp:g})" if sp else ""
            for end in ends:
                kw = {f: m[j] for j, f in keys.items()}
                kw[field_] = end
                try:
                    plant = paper_plant(m["nut_model"], m["stage"], **kw)
                except ParameterError:  # the plant's own checks (e.g. flank friction > nut level) stay per run
                    continue
                try:
                    check_plant(plant, f"{where}: [machine] {k} = {m[k]!r}{drawn}")
                except ParameterError as exc:
                    raise DataError(str(exc)) from None

    @property
    def spreadable(self) -> tuple[str, ...]:
        """Parameters ``[spread]`` may draw for this machine."""
        return _BALLSCREW_SPREADABLE if self.machine.get("preset") == "ballscrew" else _SPREADABLE

    @property
    def sha256(self) -> str:
        machine = {k: v for k, v in self.machine.items() if not (k == "preset" and v == "custom")}  # old hashes stay
        doc = {"machine": machine, "reference": self.reference, "spread": self.spread, "study": self.study}
        return hashlib.sha256(json.dumps(doc, sort_keys=True).encode()).hexdigest()

    def runs(self) -> list[dict[str, Any]]:
        """Every run: draw × compensator × seed, with the drawn parameters (same draws for every compensator)."""
        s = self.study
        rng = np.random.default_rng([int(s["seed"]), 7])
        out = []
        for d in range(s["draws"]):
            spreadable = self.spreadable
            u = {k: float(rng.uniform(-1.0, 1.0)) for k in spreadable}  # one draw of every parameter, in order
            params = {k: self.machine[k] * (1.0 + self.spread.get(k, 0.0) * u[k]) for k in spreadable}
            for comp in s["compensators"]:
                for seed in range(s["seeds"]):
                    out.append({"run": f"d{d:05d}-{comp}-s{seed:03d}", "draw": d, "compensator": comp,
                                "noise_seed": int(s["seed"]) * 1000 + seed, **params})
        return out


def load_study(path: str | Path) -> StudySpec:
    """Read a study TOML file (every mistake is one :class:`~frictionkit.DataError`)."""
    from ._io import read_input_bytes

    p = Path(path)
    raw = read_input_bytes(p, f"study '{p}'", missing="not found")  # a FIFO or /dev/zero was "not found" (round 11)
    try:
        doc = tomllib.loads(raw.decode("utf-8-sig"))  # a BOM is read as the JSON loaders read it
    except (UnicodeDecodeError, tomllib.TOMLDecodeError) as exc:
        raise DataError(f"study '{p}': not valid TOML ({exc})") from None
    if not doc:  # an empty (or truncated to nothing) file ran a 20-run default study (campaign round 5)
        raise DataError(f"study '{p}': the file holds no table; give at least [machine] (and [reference], [spread], "
                        "[study] to change their defaults)")
    bad = set(doc) - {"machine", "reference", "spread", "study"}
    if bad:
        raise DataError(f"study '{p}': unknown section(s) {sorted(bad)}; allowed: machine, reference, spread, study")
    for sec in doc:
        if not isinstance(doc[sec], dict):
            raise DataError(f"study '{p}': [{sec}] must be a table")
    return StudySpec(**{k: dict(v) for k, v in doc.items()}, source=str(p))


def _nominal(m0: dict, comp: str):
    import frictionkit as fk

    return (fk.CoulombViscous(Fc=m0["Fc"], sigma2=m0["sigma2"]) if comp == "coulomb" else
            fk.Stribeck(Fc=m0["Fc"], Fs=m0["Fs"], vs=m0["vs"], sigma2=m0["sigma2"]))


def _machine(spec: StudySpec, run: dict):
    import frictionkit as fk
    from frictionkit.machines import PID, FrictionFeedforward, Sum

    m0 = spec.machine
    plant = fk.Stribeck(Fc=run["Fc"], Fs=run["Fs"], vs=run["vs"], sigma2=run["sigma2"])
    law = fk.LuGre(plant, sigma0=run["sigma0"], sigma1=run["sigma1"]) if m0["law"] == "lugre" else plant
    comp = run["compensator"]
    if m0["preset"] == "emps":
        from .presets.emps import PUBLISHED, emps_machine

        m = emps_machine(M=run["mass"], friction=law, offset=PUBLISHED["offset"],
                         constants={"dt": float(spec.reference["dt"])}, encoder_resolution=m0["resolution"])
        if comp != "none":  # the feed-forward as a second force on the axis (the preset's loop untouched)
            m.add(FrictionFeedforward("ff", "vref", law=_nominal(m0, comp)))
            m.actuator("ff_drive", m.sites[0].at, gain=1.0, command="ff")
        return m
    m = fk.Machine("study axis")
    x = m.dof("table", inertia=run["mass"])
    m.friction("guide", x, law=law)
    m.actuator("drive", x, gain=1.0, limit=m0["limit"] if m0["limit"] > 0 else math.inf, command="u")
    m.sensor("scale", x, resolution=m0["resolution"], noise=m0["noise"])
    blocks = [Sum("e", {"r": 1.0, "scale": -1.0}),
              PID("pid", "e", Kp=m0["Kp"], Ki=m0["Ki"], Kd=m0["Kd"], tau_d=m0["tau_d"], antiwindup="drive")]
    if comp == "none":
        blocks.append(Sum("u", {"pid": 1.0}))
    else:
        blocks += [FrictionFeedforward("ff", "vref", law=_nominal(m0, comp)), Sum("u", {"pid": 1.0, "ff": 1.0})]
    m.add(*blocks)
    return m


def _ballscrew_run(spec: StudySpec, run: dict) -> dict[str, float]:
    """One run on the seed 001 ball-screw stage: the paper's controller and compensators, the
    drawn plant (error measures as :mod:`frictionkit.compensate`)."""
    from .compensate import SETTLE_FRACTION, _errors, _reversals
    from .control.trajectories import cosine_reference
    from .presets import zhu_fujimoto as zf
    from .presets.ballscrew import simulate_stage
    from .reproduce.zhu_fujimoto import _classify, paper_compensator, paper_controller, paper_plant, paper_sensors
    from .errors import SimulationError

    m0, ref_spec = spec.machine, spec.reference
    nominal = paper_plant(m0["nut_model"], m0["stage"])
    plant = paper_plant(m0["nut_model"], m0["stage"], M_t=run["mass"], guide_friction=run["guide_friction"],
                        nut_friction=run["nut_friction"], presliding_length=run["presliding_length"])
    ref = cosine_reference(amplitude=ref_spec["amplitude"], period=1.0 / ref_spec["frequency"],
                           duration=ref_spec["duration"], T=zf.T_CONTROL)
    comp = run["compensator"]
    # the compensator knows the nominal stage only (its crossings classified on the nominal plant)
    u_f = None if comp == "none" else paper_compensator().signal(ref, comp, _classify(ref, nominal))
    res = simulate_stage(plant, paper_controller(), ref, compensation=u_f, sensors=paper_sensors(),
                         seed=int(run["noise_seed"]), substeps=zf.N_SUBSTEPS)
    if res.status != 0:
        raise SimulationError(res.message)
    e = ref.x - res.x_t
    skip = int(SETTLE_FRACTION * ref.t.size)
    out = _errors(ref.t, e, _reversals(ref.t, ref.v))
    out["max_error_measured"] = float(np.max(np.abs(res.error[skip:])))
    out["max_force"] = float(np.max(np.abs(res.i)) * plant.K_tau / plant.R)  # motor torque, linear equivalent
    return out


def _axis_run(spec: StudySpec, run: dict) -> dict[str, float]:
    """One run on the generic axis or the EMPS preset (machine core, sine reference)."""
    import frictionkit as fk

    ref = spec.reference
    dt = float(ref["dt"])
    t = np.arange(int(round(ref["duration"] / dt)) + 1) * dt
    w = 2.0 * math.pi * ref["frequency"]
    r = ref["amplitude"] * np.sin(w * t)
    vr = ref["amplitude"] * w * np.cos(w * t)
    emps = spec.machine["preset"] == "emps"
    inputs = {"qg": r, "vref": vr} if emps else {"r": r, "vref": vr}
    machine = _machine(spec, run)
    # vref is read only by the compensators that use it
    res = fk.simulate_machine(machine, dt=dt, inputs=machine.read_inputs(inputs), seed=int(run["noise_seed"]))
    if res.status != 0:
        raise fk.SimulationError(res.message)
    # a drawn plant (mass) can turn the loop unstable: a failed row even when the run converged (to a limit
    # cycle). The screen's own verdict (LoopStability.unstable, remembered: simulate_machine screened this
    # machine already), not the text of the result's note (round 7 leftover: the check matched the message)
    from .machines.stability import screen

    stab, _ = screen(machine, dt)
    if stab is not None and stab.unstable:
        raise fk.SimulationError(f"{stab.describe(dt)}; the run measured a limit cycle, not the axis tracking "
                                 "its reference")
    skip = int(0.1 * t.size)  # the first 10 %: the loop settles from rest
    e_true = r - res.q[:, 0]
    if emps:  # measured error on the encoder; force = gtau · nu applied (+ feed-forward)
        from .presets.emps import EMPS_CONSTANTS

        e_meas = r - res.signal("qm")
        force = res.signal("motor.applied") * EMPS_CONSTANTS["gtau"]
        if run["compensator"] != "none":
            force = force + res.signal("ff_drive.applied")
    else:
        e_meas, force = res.signal("e"), res.signal("u")
    return {"max_error": float(np.max(np.abs(e_true[skip:]))), "rms_error": float(np.sqrt(np.mean(e_true[skip:] ** 2))),
            "max_error_measured": float(np.max(np.abs(e_meas[skip:]))), "max_force": float(np.max(np.abs(force)))}


def run_one(spec: StudySpec, run: dict, parts: str | None = None) -> dict[str, Any]:
    """Simulate one run; one row (``ok``/``error`` instead of an exception), written to ``parts`` if given."""
    t0 = time.perf_counter()
    ballscrew = spec.machine["preset"] == "ballscrew"
    row = dict(run)
    row.update({"ok": False, "error": None, "max_error": float("nan"), "rms_error": float("nan"),
                "max_error_measured": float("nan"), "max_force": float("nan"),
                **({"reversal_error": float("nan")} if ballscrew else {}), "study_sha256": spec.sha256,
                "frictionkit_version": _version()})
    try:
        row.update(_ballscrew_run(spec, run) if ballscrew else _axis_run(spec, run), ok=True)
    except (KeyboardInterrupt, SystemExit, MemoryError):
        raise
    except Exception as exc:  # noqa: BLE001 - a failing run is a row
        row["error"] = f"{type(exc).__name__}: {' '.join(str(exc).split())}"
    row["run_seconds"] = time.perf_counter() - t0
    if parts is not None:
        import pandas as pd
        import pyarrow as pa
        import pyarrow.parquet as pq

        from ._io import atomic_open

        with atomic_open(Path(parts) / f"{run['run']}__{spec.sha256[:16]}.parquet", "wb") as f:
            pq.write_table(pa.Table.from_pandas(pd.DataFrame([row]), preserve_index=False), f)
    return row


#: The figure of merit that orders a study's compensators, best (lowest) first: the median over the runs
#: of each run's max tracking error (the number the summary leads with; the 95th percentile and RMS follow
#: it). Compensators without a successful run come last, in the table's order.
RANK_BY = "max_error_median_m"


def _merit(value: Any) -> tuple[bool, float]:
    """Sort key of one compensator's :data:`RANK_BY` value: lowest first, a missing or non-finite one last."""
    ok = isinstance(value, (int, float, np.floating, np.integer)) and not isinstance(value, bool) \
        and bool(np.isfinite(value))
    return (not ok, float(value) if ok else 0.0)


def rank_compensators(table: Any) -> list[str]:
    """The compensators of a study table (one row per run), best first by the median of ``max_error`` over
    the successful runs; ties and compensators whose every run failed keep the table's order, last."""
    comps = list(dict.fromkeys(table["compensator"].dropna().astype(str))) if len(table) else []
    ok = table[table["ok"].astype(bool)] if len(table) else table
    med = {c: float(ok.loc[ok["compensator"].astype(str) == c, "max_error"].median()) for c in comps}
    return sorted(comps, key=lambda c: _merit(med[c]))


def rank_summaries(compensators: Mapping[str, Mapping[str, Any]]) -> list[str]:
    """The compensators of a study summary (``{name: {RANK_BY: value, ...}}``, the ``"compensators"`` of
    :meth:`StudyResult.to_dict`), best first by :data:`RANK_BY` with the rule of :func:`rank_compensators`
    (files written before the ranking listed them in the table's order)."""
    return sorted(compensators, key=lambda c: _merit(compensators[c].get(RANK_BY)))


#: ``format`` of :meth:`StudyResult.to_dict` (``frictionkit study --json``).
STUDY_FORMAT = "frictionkit.study/1"


@dataclass(frozen=True, kw_only=True)
class StudyResult:
    """Rows (one per run), what ran, and the summary per compensator."""

    out: Path
    table: Any = field(repr=False)
    runs: int
    computed: int
    skipped: int
    elapsed: float
    other_version: int = 0  # runs recomputed because their part came from another frictionkit version

    def _failed(self) -> tuple[int, int]:
        """(runs in the table, runs that failed)."""
        n = int(len(self.table))
        return n, (n - int(self.table["ok"].astype(bool).sum()) if n else 0)

    @property
    def status(self) -> int:
        """0: every run ok; 1: some failed; 2: all failed (or none ran)."""
        n, bad = self._failed()
        return 0 if n and not bad else (2 if bad == n else 1)

    @property
    def message(self) -> str:
        n, bad = self._failed()
        return "ok" if n and not bad else (f"{bad} of {n} run(s) failed" if n else "no runs")

    def summary(self) -> str:
        """Per compensator, best first (:data:`RANK_BY`): the median and 95th percentile of the max tracking
        error [µm]."""
        d = self.to_dict()
        lines = [f"study: {self.runs} run(s), {self.computed} simulated, {self.skipped} done before; "
                 f"status {self.status} ({self.message}); {self.out}",
                 "compensators, best first by the median of the runs' max tracking error:"]
        for comp, c in d["compensators"].items():
            med, p95 = c["max_error_median_m"], c["max_error_p95_m"]
            lines.append(f"  {comp:<10} max error median {1e6 * med:.3f} µm, 95th percentile {1e6 * p95:.3f} µm "
                         f"({c['runs']} runs, {c['failed']} failed)" if med is not None else
                         f"  {comp:<10} every run failed")
        return "\n".join(lines)

    def plot(self, ax=None):
        """Max tracking error [µm] of every run, one box per compensator (best first); returns the Axes."""
        import matplotlib.pyplot as plt

        if ax is None:
            _, ax = plt.subplots(figsize=(6, 3.5))
        df = self.table[self.table["ok"].astype(bool)] if len(self.table) else self.table
        comps = [c for c in rank_compensators(self.table) if (df["compensator"].astype(str) == c).any()]
        data = [1e6 * df.loc[df["compensator"].astype(str) == c, "max_error"].to_numpy(float) for c in comps]
        if data:
            ax.boxplot(data)  # labels= is gone from matplotlib 3.10's boxplot (TypeError): ticks instead
            ax.set_xticks(np.arange(1, len(comps) + 1), comps)
            for i, y in enumerate(data, start=1):
                ax.plot(np.full(y.size, i), y, ".", color="0.3", ms=3)
        ax.set_ylabel("max tracking error [µm]")
        ax.set_title(f"study: {self.runs} run(s)")
        return ax

    def to_dict(self) -> dict[str, Any]:
        """Per compensator, best first (``"ranked_by"``: :data:`RANK_BY`): runs, failures, median and 95th
        percentile of the max and RMS tracking error [m]."""
        df = self.table
        per = {}
        groups = dict(tuple(df.groupby(df["compensator"].astype(str), sort=False))) if len(df) else {}
        for comp in rank_compensators(df):
            g = groups[comp]
            ok = g[g["ok"]]
            per[comp] = {"runs": int(len(g)), "failed": int((~g["ok"]).sum()),
                         "max_error_median_m": float(ok["max_error"].median()) if len(ok) else None,
                         "max_error_p95_m": float(ok["max_error"].quantile(0.95)) if len(ok) else None,
                         "rms_error_median_m": float(ok["rms_error"].median()) if len(ok) else None}
            if "reversal_error" in g:  # the ball-screw stage: the error around the reversals
                per[comp]["reversal_error_median_m"] = float(ok["reversal_error"].median()) if len(ok) else None
        return {"format": STUDY_FORMAT, "out": str(self.out), "runs": self.runs, "computed": self.computed,
                "skipped": self.skipped, "other_version": self.other_version,
                "elapsed_s": round(self.elapsed, 3), "ranked_by": f"{RANK_BY}, best first", "compensators": per}


# ============================================================================ the engine
_LABEL_BAD = set('/\\:*?"<>|\0')


def _jsonable(v):
    """numpy scalars and arrays as plain Python (for the JSON text of nested values)."""
    if hasattr(v, "tolist"):
        return v.tolist()
    raise TypeError(f"{type(v).__name__} is not JSON serialisable")


@dataclass(frozen=True, kw_only=True)
class Task:
    """One labelled task of :func:`run_tasks`: ``func(**kwargs)`` returns one row (a dict).

    Parameters
    ----------
    label : str
        Unique within a run; names the task's Parquet part (no path separators).
    func : callable
        Picklable (a module-level function), run on a Dask worker or in this process.
    kwargs : dict
        Its keyword arguments (picklable).
    tag : str or None
        What the result depends on besides the label (16 hex digits); None: a hash of the
        function's name and ``repr`` of the sorted keyword arguments. A part is reused only
        when label, tag and the frictionkit version agree (the part's name carries all three),
        so changed arguments and results of another version are recomputed.
    """

    label: str
    func: Callable[..., dict]
    kwargs: dict = field(default_factory=dict)
    tag: str | None = None

    def __post_init__(self) -> None:
        if not isinstance(self.label, str) or not self.label or set(self.label) & _LABEL_BAD:
            raise ParameterError(f"Task.label = {self.label!r}: a non-empty name without any of / \\ : * ? \" < > |")
        if not callable(self.func):
            raise ParameterError(f"Task.func = {self.func!r}: must be callable")
        if not isinstance(self.kwargs, dict):
            raise ParameterError(f"Task.kwargs = {self.kwargs!r}: must be a dict")
        if self.tag is None:
            name = f"{getattr(self.func, '__module__', '')}.{getattr(self.func, '__qualname__', repr(self.func))}"
            doc = name + "|" + repr(sorted(self.kwargs.items()))
            object.__setattr__(self, "tag", hashlib.sha256(doc.encode()).hexdigest()[:16])
        elif not isinstance(self.tag, str) or not self.tag or set(self.tag) & _LABEL_BAD:
            raise ParameterError(f"Task.tag = {self.tag!r}: a non-empty name without path separators")

    @property
    def part(self) -> str:
        """File name of the task's Parquet part: label, tag and the frictionkit version."""
        return f"{self.label}__{self.tag}__fk{_version_tag()}.parquet"


def _version_tag() -> str:
    """The frictionkit version as a file-name piece (characters other than ``[A-Za-z0-9._-]`` -> ``_``)."""
    import re

    return re.sub(r"[^A-Za-z0-9._-]", "_", _version())


def _other_versions(todo: list, done: set[str]) -> dict[str, str]:
    """Tasks to run that have a part of the same label and tag from another frictionkit version
    (or from before the parts carried one): label -> that part's version (``"unknown"``)."""
    out = {}
    for t in todo:
        stem = f"{t.label}__{t.tag}"
        for name in done:
            if name == f"{stem}.parquet":
                out[t.label] = "unversioned part"
            elif name.startswith(f"{stem}__fk") and name.endswith(".parquet"):
                out[t.label] = name[len(stem) + 4:-len(".parquet")]
    return out


def run_task(task: Task, key: str = "task", parts: str | None = None) -> dict[str, Any]:
    """Run one :class:`Task`: its row under ``{key: label, ok, error, task_seconds}``.

    An exception becomes ``ok=False`` and its message in ``error`` (the row the function would
    have returned is empty); the function may set ``ok``/``error`` itself. Nested values
    (dict, list, tuple) are stored as JSON text, so the row is the same in memory and read back
    from its Parquet part (written atomically to ``parts`` if given)."""
    t0 = time.perf_counter()
    row: dict[str, Any] = {key: task.label, "ok": True, "error": None}
    try:
        res = task.func(**task.kwargs)
        if not isinstance(res, dict):
            raise TypeError(f"{getattr(task.func, '__qualname__', task.func)!r} returned "
                            f"{type(res).__name__}, not a dict (one row)")
        row.update({k: v for k, v in res.items() if k != key})
    except (KeyboardInterrupt, SystemExit, MemoryError):
        raise
    except Exception as exc:  # noqa: BLE001 - a failing task is a row
        row.update(ok=False, error=f"{type(exc).__name__}: {' '.join(str(exc).split())}")
    row = {k: json.dumps(v, sort_keys=True, default=_jsonable) if isinstance(v, (dict, list, tuple)) else v
           for k, v in row.items()}
    row["task_seconds"] = time.perf_counter() - t0
    if parts is not None:
        import pandas as pd
        import pyarrow as pa
        import pyarrow.parquet as pq

        from ._io import atomic_open

        with atomic_open(Path(parts) / task.part, "wb") as f:
            pq.write_table(pa.Table.from_pandas(pd.DataFrame([row]), preserve_index=False), f)
    return row


@dataclass(frozen=True, kw_only=True)
class TaskRun:
    """Rows of :func:`run_tasks` (one per task, in the tasks' order) and what ran."""

    out: Path | None
    table: Any = field(repr=False)
    key: str
    tasks: int
    computed: int
    skipped: int
    elapsed: float
    other_version: int = 0  # tasks recomputed because their part came from another frictionkit version

    @property
    def failed(self) -> list[str]:
        """Labels of the tasks whose row has ``ok`` False."""
        t = self.table
        return [] if not len(t) else [str(x) for x in t.loc[~t["ok"].astype(bool), self.key]]

    @property
    def status(self) -> int:
        """0: every task ok; 1: some failed; 2: all failed."""
        n = len(self.failed)
        return 0 if n == 0 else (2 if n == self.tasks else 1)

    @property
    def message(self) -> str:
        f = self.failed
        return "ok" if not f else f"{len(f)} of {self.tasks} task(s) failed: {', '.join(f[:5])}" + (
            " ..." if len(f) > 5 else "")

    def summary(self) -> str:
        d = self.to_dict()
        return (f"{self.tasks} task(s): {self.computed} computed, {self.skipped} done before, "
                f"{len(self.failed)} failed; {d['task_seconds_total']:.3g} s of tasks (largest "
                f"{d['task_seconds_max']:.3g} s), {d['elapsed_s']:.3g} s wall; status {self.status} ({self.message})")

    def to_dict(self) -> dict[str, Any]:
        """Counts, the failed labels and the task seconds (total and largest)."""
        sec = self.table["task_seconds"] if len(self.table) else []
        return {"out": None if self.out is None else str(self.out), "tasks": self.tasks, "computed": self.computed,
                "skipped": self.skipped, "other_version": self.other_version, "failed": self.failed,
                "elapsed_s": round(self.elapsed, 3),
                "task_seconds_total": float(np.sum(sec)) if len(sec) else 0.0,
                "task_seconds_max": float(np.max(sec)) if len(sec) else 0.0,
                "status": self.status, "message": self.message}

    def plot(self, ax=None):
        """Seconds per task (failed ones in red)."""
        import matplotlib.pyplot as plt

        if ax is None:
            _, ax = plt.subplots(figsize=(7, 3))
        t = self.table
        if len(t):
            ok = t["ok"].astype(bool).to_numpy()
            ax.bar(np.arange(len(t)), t["task_seconds"], color=np.where(ok, "C0", "C3"))
            ax.set_xticks(np.arange(len(t)), [str(x) for x in t[self.key]], rotation=90, fontsize=7)
        ax.set_ylabel("task time [s]")
        ax.set_title(f"{self.tasks} task(s): {self.computed} computed, {self.skipped} reused, "
                     f"{len(self.failed)} failed")
        return ax


def _cluster_failed_row(task: Task, key: str, exc) -> dict[str, Any]:
    msg = " ".join(str(exc).split())
    return {key: task.label, "ok": False, "error": f"task failed on the cluster ({type(exc).__name__}: {msg}); "
            "rerun to retry", "task_seconds": float("nan")}


def run_tasks(tasks: list[Task], *, out: str | Path | None = None, key: str = "task", scheduler=None,
              workers: int | None = None, progress=True, label: str = "tasks") -> TaskRun:
    """Run labelled tasks on Dask, one Dask task per :class:`Task`, one Parquet part each.

    Parameters
    ----------
    tasks : list of Task
        Unique labels.
    out : str, Path or None
        Results Parquet file (one row per task); parts go to ``<out>.parts/`` and a rerun
        computes only the tasks without a part of the same label, tag and frictionkit version
        (a part from another version is recomputed, with a warning, and counted in
        ``TaskRun.other_version``). None: nothing written, nothing reused.
    key : str
        Column holding the labels.
    scheduler, workers
        As in :func:`frictionkit.fleet.identify_fleet`: None a LocalCluster (``workers``
        single-threaded processes, default the cores); ``"none"`` or ``workers=0`` this process
        without Dask (the same rows); a scheduler address or a ``Client``.
    progress : bool or callable
        True: a progress bar on stderr; a callable gets each finished row.
    label : str
        Name on the progress bar and in the Dask keys.

    Returns
    -------
    TaskRun
        A task lost on the cluster (worker died, unpicklable result) is a row with ``ok`` False
        and no part (a rerun retries it).

    Examples
    --------
    >>> from frictionkit.study import Task, run_tasks
    >>> run = run_tasks([Task(label="a", func=dict, kwargs={"x": 1.0})], workers=0, progress=False)
    >>> run.table[["task", "ok", "x"]].to_dict("records")
    [{'task': 'a', 'ok': True, 'x': 1.0}]
    """
    import pandas as pd

    from ._io import atomic_open
    from .fleet.identify import _Progress, dask_client

    t_start = time.perf_counter()
    tasks = list(tasks)
    for t in tasks:
        if not isinstance(t, Task):
            raise ParameterError(f"run_tasks.tasks: {t!r} is not a Task")
    labels = [t.label for t in tasks]
    if len(set(labels)) != len(labels):
        dup = sorted({x for x in labels if labels.count(x) > 1})
        raise ParameterError(f"run_tasks.tasks: duplicate label(s) {dup[:5]}")
    if not isinstance(key, str) or not key:
        raise ParameterError(f"run_tasks.key = {key!r}: a non-empty column name")
    if workers is not None and (isinstance(workers, bool) or not isinstance(workers, int) or workers < 0):
        raise ParameterError(f"run_tasks.workers = {workers!r}: must be an integer >= 0")
    single = scheduler == "none" or workers == 0
    if not single and scheduler is not None and workers is not None:
        raise ParameterError("run_tasks: workers= starts a local cluster; with a scheduler the cluster decides")
    parts = None
    if out is not None:
        out = Path(out)
        out.parent.mkdir(parents=True, exist_ok=True)
        parts = out.with_name(out.name + ".parts")
        parts.mkdir(exist_ok=True)
        done = {f.name for f in parts.glob("*.parquet")}
        todo = [t for t in tasks if t.part not in done]
        other = _other_versions(todo, done)
        if other:
            import warnings

            vers = sorted(set(other.values()))
            warnings.warn(f"{len(other)} result(s) in '{parts}' were written by another frictionkit version "
                          f"({', '.join(vers[:3])}; this is {_version()}): not reused, recomputed", stacklevel=2)
    else:
        todo, other = tasks, {}
    bar = _Progress(progress is True, len(todo), label)
    notify = progress if callable(progress) else None
    rows: dict[str, dict] = {}

    def finished(row: dict) -> None:
        rows[row[key]] = row
        bar.advance(sum(not r["ok"] for r in rows.values()))
        if notify is not None:
            notify(row)

    try:
        if todo and single:
            for t in todo:
                finished(run_task(t, key, None if parts is None else str(parts)))
        elif todo:
            from dask.distributed import as_completed

            with dask_client(scheduler, workers, timeout=15) as (client, _mode):
                futs = {client.submit(run_task, t, key, None if parts is None else str(parts),
                                      key=f"{label}-{t.label}-{t.tag}", pure=False): t for t in todo}
                for fut in as_completed(list(futs)):
                    try:
                        finished(fut.result())
                    except Exception as exc:  # noqa: BLE001 - lost on the cluster: a row, retried on a rerun
                        finished(_cluster_failed_row(futs[fut], key, exc))
                    fut.release()
    finally:
        bar.close()
    frames = []
    for t in tasks:
        if t.label in rows:
            frames.append(pd.DataFrame([rows[t.label]]))
        elif parts is not None and (parts / t.part).is_file():
            frames.append(pd.read_parquet(parts / t.part))
    df = pd.concat(frames, ignore_index=True) if frames else pd.DataFrame({key: [], "ok": [], "error": []})
    if out is not None:
        with atomic_open(out, "wb") as f:
            df.to_parquet(f, index=False)
    return TaskRun(out=out, table=df, key=key, tasks=len(tasks), computed=len(todo), skipped=len(tasks) - len(todo),
                   elapsed=time.perf_counter() - t_start, other_version=len(other))


def run_study(spec: StudySpec | str | Path, *, out: str | Path, scheduler=None, workers: int | None = None,
              progress: bool = True) -> StudyResult:
    """Run every draw × compensator × seed of a study on Dask; one row per run in ``out`` (Parquet).

    Parameters
    ----------
    spec : StudySpec, str or Path
        The study or its TOML file.
    out : str or Path
        Results Parquet file; parts go to ``<out>.parts/`` (a rerun computes only what is missing).
    scheduler, workers
        As in :func:`frictionkit.fleet.identify_fleet` (None: a LocalCluster; ``"none"`` or
        ``workers=0``: this process; an address or a Client).
    progress : bool
        Progress bar on stderr.

    Returns
    -------
    StudyResult

    Examples
    --------
    >>> from frictionkit.study import run_study
    >>> res = run_study("study.toml", out="study.parquet", workers=2)  # doctest: +SKIP
    >>> res.to_dict()["compensators"]["static"]["max_error_p95_m"]  # doctest: +SKIP
    """
    t_start = time.perf_counter()
    if not isinstance(spec, StudySpec):
        spec = load_study(spec)
    if workers is not None and (isinstance(workers, bool) or int(workers) != workers or workers < 0):
        raise ParameterError(f"run_study.workers = {workers!r}: must be an integer >= 0")
    if not (scheduler == "none" or workers == 0) and scheduler is not None and workers is not None:
        raise ParameterError("run_study: workers= starts a local cluster; with a scheduler the cluster decides")
    tag = spec.sha256[:16]  # parts named <run>__<tag>__fk<version>.parquet
    runs = spec.runs()
    tasks = [Task(label=r["run"], func=run_one, kwargs={"spec": spec, "run": r}, tag=tag) for r in runs]
    res = run_tasks(tasks, out=out, key="run", scheduler=scheduler, workers=None if workers is None else int(workers),
                    progress=progress, label="study")
    df = res.table
    if len(df) and df["ok"].eq(False).any() and "compensator" in df and df["compensator"].isna().any():
        by = {r["run"]: r for r in runs}  # a run lost on the cluster: its drawn parameters back on its row
        for i in df.index[df["compensator"].isna()]:
            for k, v in by[df.at[i, "run"]].items():
                if k in df and k != "run":
                    df.at[i, k] = v
    if len(df):
        df = df.drop(columns=["task_seconds"], errors="ignore")
        df = df.drop_duplicates("run", keep="last").sort_values("run").reset_index(drop=True)
    from ._io import atomic_open

    with atomic_open(Path(out), "wb") as f:  # the study's table: sorted by run, without the engine's timing
        df.to_parquet(f, index=False)
    return StudyResult(out=Path(out), table=df, runs=res.tasks, computed=res.computed, skipped=res.skipped,
                       elapsed=time.perf_counter() - t_start, other_version=res.other_version)


__all__ = ["COMPENSATORS", "PRESETS", "StudyResult", "StudySpec", "Task", "TaskRun", "load_study", "run_one", "run_study",
           "run_task", "run_tasks"]
