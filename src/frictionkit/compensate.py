"""Friction compensators compared on a preset machine: the tracking-error table of ``frictionkit compensate``.

:func:`compensate` runs one machine preset along its test motion once per compensator and
measures the tracking error of the *true* position (``r - x``; the sensors' quantisation and
noise are in the loop but not in the measure):

* ``max_error`` and ``rms_error`` [m] after the first 10 % of the run (the loop settles from
  rest; the same cut as :mod:`frictionkit.study`);
* ``reversal_error`` [m]: the largest ``|r - x|`` within ``REVERSAL_WINDOW`` around each
  velocity reversal of the reference (the seed 001 window, -50 ms ... +100 ms), max over the
  reversals.

Presets (:data:`PRESETS`)
-------------------------
``ballscrew``
    The seed 001 elastic stage (:func:`frictionkit.reproduce.zhu_fujimoto.paper_plant`,
    Fig. 3 controller, paper sensors) on its §5 reversal test motion (25 mm, 1 s cosine;
    2.15 s, reversals at 0.5, 1.0, 1.5, 2.0 s; ``quick``: 0.65 s, the first reversal). The
    compensation torque enters as the controller's ``u_f``. Compensators ``none``,
    ``coulomb`` (eq. 7), ``sinc`` (eq. 6), ``sigmoid`` (eq. 5) with the paper's F0, xs, sigma
    (:func:`~frictionkit.reproduce.zhu_fujimoto.paper_compensator`), and ``model``.
``emps``
    The EMPS axis in its published P/P loop (:func:`frictionkit.presets.emps.emps_machine`)
    with the published friction as the *true* plant (``CoulombViscous(Fc=20.3935,
    sigma2=203.5034)`` and offset -3.1648 N) on the study's reference (0.1 m, 0.2 Hz sine,
    1 kHz; 5 s, reversals at 1.25 and 3.75 s; ``quick``: 2.5 s). The compensator is a second
    force on the axis (:class:`~frictionkit.machines.FrictionFeedforward` on the reference
    velocity), as in :mod:`frictionkit.study`. ``coulomb`` is the published Coulomb +
    viscous law, i.e. the plant's true friction (the offset is not compensated).

``sdss``
    The SDSS 2.5 m telescope's azimuth axis (:class:`frictionkit.presets.sdss.AzimuthAxis`,
    its LuGre friction as the true plant, 1 ms servo, encoder 2^25 counts/rev) tracking at the
    sidereal rate from rest (30 s; ``quick``: 15 s) with the PID of
    :func:`frictionkit.reproduce.sdss.sidereal_tracking` (pole placement on the inertia alone,
    2 Hz, tuned without friction). Compensators ``none``, ``lugre`` (the axis's own LuGre
    static map — what a perfect identification gives) and ``model`` (an identified model, e.g.
    the LuGre of ``frictionkit reproduce sdss``), each as a current feed-forward
    ``F(w_ref) / (2 n_c K_T)`` on the reference velocity. Errors are angles [rad] (shown in
    arcsec) over the whole run (the start from rest is the test: nothing skipped); there is no
    reversal (``reversal_error`` is None).

A machine model file (``fk.save_model(machine)``) runs with a **compensation test**
(:class:`CompensationTest`, a small TOML or JSON file, ``compensate MACHINE.json --test
SPEC.toml``): the machine's input arrays (``NAME = "FILE:COLUMN"`` or a number), which degree of
freedom is scored against which input (``error = input - position``), the input holding the
reference velocity (reversals; the feed-forward reads it) and the site along whose coordinate a
compensator's force acts (a :class:`~frictionkit.machines.FrictionFeedforward` block driving an
extra actuator there, as on ``emps``); its compensators are ``none``, ``model`` and the named
law files of the spec. ``quick`` runs the first half of the inputs.

``model`` (every preset) is the static feed-forward of an identified model,
``F_model(v_ref)`` (a dynamic law's steady-state map), from a model file
(:func:`frictionkit.load_model`). Named assumption: the file's law acts on the *table*
(linear force [N] at velocity [m/s]); on the ball-screw stage its torque is ``R F``. A model
file labelled with rotary units is refused rather than guessed. On ``sdss`` it acts on the
axis (torque [N·m] at [rad/s]) and a file must be labelled so (``units={"F": "N·m", "v":
"rad/s"}``); a linear label is refused.

Measured (``frictionkit compensate ballscrew`` / ``emps`` / ``sdss``, full runs; README "Command line")
---------------------------------------------------------------------------------------------------
* ballscrew, max error [µm]: none 6.627, coulomb 2.832, sinc 2.415, sigmoid 2.259 (every
  maximum at a reversal).
* emps: the true-law feed-forward lowers the max error 820.5 -> 786.9 µm and the error at the
  reversals 121.4 -> 104.3 µm. What remains is the P/P loop's lag ``v / kp`` (784.5 µm at the
  peak velocity 0.126 m/s), far above the friction's share (~35 µm); a feed-forward of 3x the
  true friction scores *better* (its viscous part acts as a velocity feed-forward). On this
  axis the table measures the loop as much as the compensator.
* sdss, RMS error over the whole run [arcsec]: none 0.078, lugre 0.051 (quick: 0.109 / 0.069);
  max 0.624 / 0.591 (the start from rest). The same numbers as the tracking extension of
  ``frictionkit reproduce sdss`` (its identified map gives 0.051 too): after the start both
  runs sit at the encoder's resolution (2^25 counts/rev = 0.039 arcsec) — the feed-forward's
  gain is the breakaway at the start, not the steady tracking.
* ballscrew ``model`` with ``CoulombViscous(Fc=F0 / R)``: the same torque as eq. 7 on every
  sample but the reversal sample (v_ref = +1.9e-17 m/s there: the static map gives +F0, eq. 7
  the new direction's -F0); that one 0.5 ms sample moves the max reversal error from 2.81 to
  2.34 µm (``--quick``). The reversal error is that sensitive to the zero-speed instant.
"""

from __future__ import annotations

import math
import time
from dataclasses import dataclass, field
from pathlib import Path
from collections.abc import Sequence
from typing import Any, Callable

import numpy as np

from .errors import DataError, ParameterError

__all__ = ["PRESETS", "COMPENSATORS", "REVERSAL_WINDOW", "TEST_FORMAT", "CompensationResult", "CompensationTest",
           "compensate"]

#: ``format`` of a compensation-test spec for a machine file (:class:`CompensationTest`).
TEST_FORMAT = "frictionkit.compensation-test/1"
#: ``format`` of :meth:`CompensationResult.to_dict` (``compensate --json``).
RESULT_FORMAT = "frictionkit.compensation/1"

#: Compensators each preset supports (the first is the default order of the table).
COMPENSATORS = {"ballscrew": ("none", "coulomb", "sinc", "sigmoid", "model"),
                "emps": ("none", "coulomb", "model"),
                "sdss": ("none", "lugre", "model")}
PRESETS = tuple(COMPENSATORS)
#: Unit of each preset's tracking error, and the unit and factor it is shown in.
ERROR_UNITS = {"ballscrew": ("m", "µm", 1e6), "emps": ("m", "µm", 1e6), "sdss": ("rad", "arcsec", 648000.0 / math.pi)}
#: Axis units a ``model`` file must carry per preset (force, velocity).
MODEL_UNITS = {"ballscrew": ("N", "m/s"), "emps": ("N", "m/s"), "sdss": ("N·m", "rad/s")}
#: Window around each reference reversal [s] for ``reversal_error`` (seed 001 Table 3 window).
REVERSAL_WINDOW = (-0.05, 0.10)
#: Fraction of the run skipped for ``max_error``/``rms_error`` (settling from rest).
SETTLE_FRACTION = 0.1
#: Per preset, where it differs: the sidereal start from rest is the test itself (a slewed and
#: settled axis starting to track), so nothing is skipped on ``sdss``.
SETTLE_FRACTIONS = {"sdss": 0.0}


@dataclass(frozen=True, eq=False)
class CompensationResult:
    """Tracking errors of one preset per compensator.

    Attributes
    ----------
    preset : str
    rows : dict — per compensator: ``max_error``, ``rms_error``, ``reversal_error`` [``unit``], ``ok``,
        ``message``.
    t : ndarray — time [s]; ``errors`` : dict of true tracking-error traces ``r - x`` [m].
    reversals : list of float — reference reversal instants [s].
    status : int — 0 all runs succeeded, 1 some failed, 2 all failed. ``message`` : str.
    """

    preset: str
    rows: dict
    t: np.ndarray = field(repr=False)
    errors: dict = field(repr=False)
    reversals: list
    model: str | None = None
    quick: bool = False
    elapsed: float = 0.0
    unit: str = "m"
    #: What the numbers do not show (e.g. a reference velocity without a reversal), "" when nothing.
    note: str = ""
    #: Fraction of the run left out of ``max_error`` / ``rms_error`` (shaded in ``plot``).
    settle_fraction: float = SETTLE_FRACTION

    @property
    def shown(self) -> tuple[str, float]:
        """``(label, factor)`` the errors are shown in (µm for m, arcsec for rad)."""
        return {"m": ("µm", 1e6), "rad": ("arcsec", 648000.0 / math.pi)}.get(self.unit, (self.unit, 1.0))

    @property
    def status(self) -> int:
        bad = [k for k, r in self.rows.items() if not r["ok"]]
        return 0 if not bad else (2 if len(bad) == len(self.rows) else 1)

    @property
    def message(self) -> str:
        bad = [f"{k}: {r['message']}" for k, r in self.rows.items() if not r["ok"]]
        text = "ok" if not bad else "failed: " + "; ".join(bad)
        return f"{text}; note: {self.note}" if self.note else text

    @property
    def success(self) -> bool:
        return self.status == 0

    def summary(self) -> str:
        """The error table as text: one line per compensator, errors in µm (arcsec on a rotary axis)."""
        label, k = self.shown

        def um(x):
            return "-" if x is None else f"{x * k:.3f}"

        head = (f"{self.preset}: tracking error r - x [{label}] over {float(self.t[-1]) if self.t.size else 0.0:.2f} s, "
                f"{len(self.reversals)} reversal(s); status {self.status} ({self.message})")
        rows = [f"  {name:<10} max {um(r['max_error'])}  RMS {um(r['rms_error'])}  "
                f"at reversals {um(r['reversal_error'])}" + ("" if r["ok"] else f"  FAILED: {r['message']}")
                for name, r in self.rows.items()]
        return "\n".join([head, *rows])

    def to_dict(self) -> dict[str, Any]:
        """JSON-ready: preset, motion, the per-compensator errors [m], status and message."""
        return {"format": RESULT_FORMAT, "preset": self.preset, "quick": self.quick, "model": self.model,
                "duration_s": float(self.t[-1]) if self.t.size else 0.0,
                "reversals_s": [round(x, 6) for x in self.reversals], "reversal_window_s": list(REVERSAL_WINDOW),
                "units": {"error": self.unit}, "compensators": {k: dict(r) for k, r in self.rows.items()},
                "status": self.status, "message": self.message, "elapsed_s": round(self.elapsed, 3)}

    def plot(self, ax=None):
        """True tracking error [µm or arcsec] over time per compensator, reversals marked; returns the Axes."""
        import matplotlib.pyplot as plt

        label, k = self.shown
        if ax is None:
            _, ax = plt.subplots(figsize=(8, 4))
        for name, e in self.errors.items():
            ax.plot(self.t, e * k, lw=0.8, label=name)
        for t0 in self.reversals:
            ax.axvline(t0, color="0.6", ls=":", lw=0.8)
        if self.settle_fraction > 0 and self.t.size:  # the start transient the max and RMS leave out
            t_end = float(self.t[int(self.settle_fraction * self.t.size)])
            ax.axvspan(float(self.t[0]), t_end, color="0.9", zorder=0, label="not scored (settling)")
        ax.set_xlabel("time [s]")
        ax.set_ylabel(f"tracking error r - x [{label}]")
        ax.set_title(f"{self.preset}: friction compensators")
        # outside, right: inside, 'best' sat beside the error peaks of the later reversals
        ax.legend(fontsize=8, loc="upper left", bbox_to_anchor=(1.01, 1.0), frameon=False)
        if ax.figure.get_layout_engine() is None:
            ax.figure.tight_layout()
        return ax


def _reversals(t: np.ndarray, v: np.ndarray) -> list[float]:
    """Instants where the reference velocity changes sign (linear interpolation)."""
    s = np.sign(v)
    idx = np.flatnonzero((s[:-1] * s[1:]) < 0)
    return [float(t[i] - v[i] * (t[i + 1] - t[i]) / (v[i + 1] - v[i])) for i in idx]


def _errors(t: np.ndarray, e: np.ndarray, reversals: list[float], settle: float = SETTLE_FRACTION) -> dict[str, float]:
    skip = int(settle * t.size)
    es = e[skip:]
    rev = [np.max(np.abs(e[(t >= t0 + REVERSAL_WINDOW[0]) & (t <= t0 + REVERSAL_WINDOW[1])]))
           for t0 in reversals]
    return {"max_error": float(np.max(np.abs(es))), "rms_error": float(np.sqrt(np.mean(es ** 2))),
            "reversal_error": float(max(rev)) if rev else None}


def _ballscrew(names, law, quick, seed, each):
    from .control.trajectories import cosine_reference
    from .presets import zhu_fujimoto as zf
    from .presets.ballscrew import simulate_stage
    from .reproduce.zhu_fujimoto import _classify, paper_compensator, paper_controller, paper_plant, paper_sensors

    plant = paper_plant()
    ref = cosine_reference(amplitude=zf.REF_AMPLITUDE, period=zf.REF_PERIOD, duration=0.65 if quick else 2.15,
                           T=zf.T_CONTROL)
    cs = _classify(ref, plant)
    comp = paper_compensator()
    for name in names:
        if name == "model":
            u_f = plant.R * np.asarray(law.steady_state(ref.v), dtype=float)  # table force -> screw torque
        else:
            u_f = comp.signal(ref, name, cs)
        res = simulate_stage(plant, paper_controller(), ref, compensation=u_f, sensors=paper_sensors(), seed=seed,
                             substeps=zf.N_SUBSTEPS)
        each(name, ref.t, ref.v, ref.x - res.x_t, res.status, res.message)


def _emps(names, law, quick, seed, each):
    import frictionkit as fk
    from .machines import FrictionFeedforward
    from .presets.emps import PUBLISHED, emps_machine

    dt, A, f = 1e-3, 0.1, 0.2
    t = np.arange(int(round((2.5 if quick else 5.0) / dt)) + 1) * dt
    w = 2.0 * math.pi * f
    r, vr = A * np.sin(w * t), A * w * np.cos(w * t)
    true = fk.CoulombViscous(Fc=PUBLISHED["Fc"], sigma2=PUBLISHED["Fv"])
    for name in names:
        m = emps_machine(M=PUBLISHED["M"], friction=true, offset=PUBLISHED["offset"])
        if name != "none":
            m.add(FrictionFeedforward("ff", "vref", law=true if name == "coulomb" else law))
            m.actuator("ff_drive", m.sites[0].at, gain=1.0, command="ff")
        res = fk.simulate_machine(m, dt=dt, inputs=m.read_inputs({"qg": r, "vref": vr}), seed=seed)
        each(name, t, vr, r - res.q[:, 0], res.status, res.message)


def _refuse_file(path: Path) -> None:
    """A law file in place of a preset, or a machine file without ``test``: say in one line what to do."""
    from .models.files import ModelFile

    mf = ModelFile.load(path, kind=None)
    if mf.kind == "law":
        raise ParameterError(f"'{path}' is a friction law, not a machine: give it as --model to a preset "
                             f"({', '.join(PRESETS)})")
    raise ParameterError(f"machine file '{path}' ({mf.model.name}) carries no compensation test: give one with "
                         "--test SPEC.toml (its test motion as input files, the coordinate whose error is scored, "
                         "the input holding the reference velocity and the site a compensator acts at; README "
                         f"'Command line', 'Compensate'), or run a preset ({', '.join(PRESETS)})")


@dataclass(frozen=True, eq=False)
class CompensationTest:
    """A compensation test for a machine file: what :func:`compensate` needs beyond the machine.

    Attributes
    ----------
    inputs : dict of str -> ndarray — every input array of the run (SI), one sample per ``dt``.
    dt : float — sample period [s].
    position : str — the degree of freedom whose position is scored.
    reference : str — the input holding that position's reference; error = reference - position.
    velocity : str — the input holding the reference velocity: the feed-forward's input and
        where the reversals are (sign changes).
    site : str — the site along whose coordinate a compensator's force acts (an extra actuator
        with gain 1 commanded by a :class:`~frictionkit.machines.FrictionFeedforward` on ``velocity``).
    compensators : dict of str -> friction law — named compensators besides ``none`` and ``model``.
    settle_fraction : float — fraction of the run left out of ``max_error`` / ``rms_error``.
    source : str or None — the spec file.
    """

    inputs: dict
    dt: float
    position: str
    reference: str
    velocity: str
    site: str
    compensators: dict = field(default_factory=dict)
    settle_fraction: float = SETTLE_FRACTION
    source: str | None = None

    def __post_init__(self) -> None:
        w = f"compensation test '{self.source}'" if self.source else "compensation test"
        if not (isinstance(self.dt, (int, float)) and not isinstance(self.dt, bool) and math.isfinite(self.dt)
                and self.dt > 0):
            raise ParameterError(f"{w}: dt = {self.dt!r}: must be a finite number > 0 [s]")
        for k in ("position", "reference", "velocity", "site"):
            v = getattr(self, k)
            if not isinstance(v, str) or not v:
                raise ParameterError(f"{w}: {k} = {v!r}: must be a name")
        if not isinstance(self.inputs, dict) or not self.inputs:
            raise ParameterError(f"{w}: inputs: give the machine's input arrays")
        n = {np.asarray(a).shape for a in self.inputs.values()}
        if len(n) != 1 or len(next(iter(n))) != 1 or next(iter(n))[0] < 2:
            raise DataError(f"{w}: inputs must be 1-D arrays of one length (>= 2 samples); got shapes {sorted(n)}")
        for k in ("reference", "velocity"):
            if getattr(self, k) not in self.inputs:
                raise ParameterError(f"{w}: {k} = {getattr(self, k)!r} is not one of the inputs "
                                     f"({', '.join(self.inputs)})")
        for name, law in self.compensators.items():
            if name in ("none", "model"):
                raise ParameterError(f"{w}: compensator name {name!r} is reserved (none and model always exist)")
            if not hasattr(law, "steady_state"):
                raise ParameterError(f"{w}: compensator {name!r} = {type(law).__name__}: must be a friction law")
        f = self.settle_fraction
        if not (isinstance(f, (int, float)) and not isinstance(f, bool) and 0.0 <= f < 1.0):
            raise ParameterError(f"{w}: settle_fraction = {f!r}: must be in [0, 1)")

    @property
    def n(self) -> int:
        """Samples of the run."""
        return int(np.asarray(next(iter(self.inputs.values()))).size)

    @classmethod
    def load(cls, path: str | Path) -> CompensationTest:
        """Read a spec (``.toml`` or ``.json``; file names in it are relative to the spec).

        Keys: ``format`` (optional, :data:`TEST_FORMAT`), ``dt`` and ``duration`` [s] (only
        when no input comes from a file: files give both), ``settle_fraction``;
        ``[inputs]`` ``NAME = "FILE:COLUMN"`` or a number; ``[score]`` ``position`` (a degree
        of freedom), ``reference`` (an input); ``[compensation]`` ``velocity`` (an input),
        ``site``; ``[compensators]`` ``NAME = "LAW_OR_MODEL_FILE"``. Unknown keys are refused.
        """
        p = Path(path)
        w = f"compensation test '{p}'"
        from ._io import check_regular_input

        check_regular_input(p, w)  # a FIFO blocked for ever, /dev/zero filled the memory (round 11)
        try:
            text = p.read_text(encoding="utf-8-sig")  # a BOM is read as the JSON loaders read it
        except OSError as exc:
            raise DataError(f"{w}: cannot be read ({exc.strerror or exc})") from None
        except UnicodeDecodeError:
            raise DataError(f"{w}: not UTF-8 text") from None
        try:
            if p.suffix.lower() == ".json":
                from ._io import json_loads

                doc = json_loads(text)  # a key named twice is refused (ValueError below)
            else:
                import tomllib

                doc = tomllib.loads(text)
        except ValueError as exc:
            raise DataError(f"{w}: not valid {'JSON' if p.suffix.lower() == '.json' else 'TOML'} "
                            f"({' '.join(str(exc).split())[:160]})") from None
        if not isinstance(doc, dict):
            raise DataError(f"{w}: must be a table of keys")
        fmt = doc.get("format", TEST_FORMAT)
        if fmt != TEST_FORMAT:
            raise DataError(f"{w}: format {fmt!r}; this frictionkit reads {TEST_FORMAT!r}")
        allowed = {"format", "dt", "duration", "settle_fraction", "inputs", "score", "compensation", "compensators"}
        extra = sorted(set(doc) - allowed)
        if extra:
            raise DataError(f"{w}: unknown key(s) {', '.join(extra)}; expected {', '.join(sorted(allowed))}")

        def table(key: str, keys: tuple[str, ...] | None) -> dict:
            t = doc.get(key, {} if keys is None else None)
            if not isinstance(t, dict):
                raise DataError(f"{w}: [{key}] missing or not a table" + (f" (keys {', '.join(keys)})" if keys else ""))
            if keys is not None:
                miss = [k for k in keys if k not in t]
                bad = sorted(set(t) - set(keys))
                if miss or bad:
                    raise DataError(f"{w}: [{key}] needs exactly {', '.join(keys)}"
                                    + (f"; missing {', '.join(miss)}" if miss else "")
                                    + (f"; unknown {', '.join(bad)}" if bad else ""))
            return t

        inputs_spec = table("inputs", None)
        if not inputs_spec:
            raise DataError(f"{w}: [inputs] missing: give the machine's inputs (NAME = \"FILE:COLUMN\" or a number)")
        score, comp = table("score", ("position", "reference")), table("compensation", ("velocity", "site"))
        inputs, dt = _read_inputs(inputs_spec, p.parent, doc.get("dt"), doc.get("duration"), w)
        laws = {}
        for name, f in table("compensators", None).items():
            if not isinstance(f, str):
                raise DataError(f"{w}: [compensators] {name} = {f!r}: must be a law or model file name")
            from .models.files import ModelFile

            q = Path(f) if Path(f).is_absolute() else p.parent / f
            laws[name] = ModelFile.load(q, kind="law").model
        return cls(inputs=inputs, dt=dt, position=score["position"], reference=score["reference"],
                   velocity=comp["velocity"], site=comp["site"], compensators=laws,
                   settle_fraction=doc.get("settle_fraction", SETTLE_FRACTION), source=str(p))


#: Largest run of a compensation test [samples] (the traces of every compensator stay in memory).
MAX_TEST_SAMPLES = 10_000_000


def _read_inputs(spec: dict, base: Path, dt: Any, duration: Any, w: str) -> tuple[dict, float]:
    """``[inputs]`` of a spec -> (arrays on one grid, dt); files give the grid, else ``dt``/``duration``."""
    from .data import read_table
    from .data.loaders import _grid_input

    arrays, consts, grid, tables = {}, {}, None, {}
    for name, value in spec.items():
        if isinstance(value, (int, float)) and not isinstance(value, bool):
            if not math.isfinite(value):
                raise DataError(f"{w}: [inputs] {name} = {value!r}: not finite")
            consts[name] = float(value)
            continue
        if not isinstance(value, str) or ":" not in value:
            raise DataError(f"{w}: [inputs] {name} = {value!r}: expected \"FILE:COLUMN\" or a number")
        f, _, col = value.rpartition(":")
        path = Path(f) if Path(f).is_absolute() else base / f
        if path not in tables:
            tables[path] = read_table(path)
        tab = tables[path]
        arrays[name], grid = _grid_input(tab, path, next(iter(tab)), col, f"input {name}", grid)
    if grid is not None:
        if duration is not None or dt is not None:
            raise DataError(f"{w}: dt/duration come from the input files here; drop them")
        n, h = grid[0], grid[1]
    else:
        ok = all(isinstance(x, (int, float)) and not isinstance(x, bool) and math.isfinite(x) and x > 0
                 for x in (dt, duration))
        if not ok:
            raise DataError(f"{w}: without input files give dt and duration [s] (numbers > 0); got dt = {dt!r}, "
                            f"duration = {duration!r}")
        h, n = float(dt), int(round(duration / dt)) + 1
    if n > MAX_TEST_SAMPLES:
        raise DataError(f"{w}: {n} samples; at most {MAX_TEST_SAMPLES:,}")
    for name, value in consts.items():
        arrays[name] = np.full(n, value)
    return arrays, h


def _machine_test(machine, test: CompensationTest, names, law, quick, seed, each):
    """Run a machine file's compensation test once per compensator (see :class:`CompensationTest`)."""
    import copy

    from .machines import FrictionFeedforward, simulate_machine

    n = test.n if not quick else max((test.n + 1) // 2, 2)
    inputs = {k: np.asarray(v, dtype=float)[:n] for k, v in test.inputs.items()}
    t = np.arange(n) * test.dt
    for name in names:
        m = copy.deepcopy(machine)
        if name != "none":
            ff = law if name == "model" else test.compensators[name]
            m.add(FrictionFeedforward("compensation_ff", test.velocity, law=ff))
            m.actuator("compensation_drive", _site(m, test.site).at, gain=1.0, command="compensation_ff")
        # the run without compensation does not read test.velocity; the others read every input
        res = simulate_machine(m, dt=test.dt, inputs=m.read_inputs(inputs) if name == "none" else inputs, seed=seed)
        each(name, t, inputs[test.velocity], inputs[test.reference] - res.position(test.position), res.status,
             res.message)


def _site(machine, name: str):
    for s in machine.sites:
        if s.name == name:
            return s
    raise ParameterError(f"compensation test: site {name!r} not in machine {machine.name!r} "
                         f"(sites: {', '.join(s.name for s in machine.sites) or 'none'})")


def _sdss(names, law, quick, seed, each):
    from .machines import PID, FrictionFeedforward, Sum, simulate_machine
    from .presets import sdss
    axis = sdss.AzimuthAxis()
    dt = axis.dt
    n = int(round((15.0 if quick else 30.0) / dt)) + 1
    t = np.arange(n) * dt
    w = np.full(n, sdss.SIDEREAL_RATE)
    r = sdss.SIDEREAL_RATE * t
    g = sdss._pid_gains(axis.inertia, axis.torque_constant, axis.bandwidth_hz)
    for name in names:
        m = axis.machine(loop="open")  # the current input "i" is written by the blocks below
        blocks = [Sum("e", {"r": 1.0, "encoder": -1.0}), PID("i_fb", "e", **g)]
        terms = {"i_fb": 1.0}
        if name != "none":
            ff = axis.friction if name == "lugre" else law
            blocks.append(FrictionFeedforward("T_ff", "w_ref", law=ff, scale=1.0 / axis.torque_constant))
            terms["T_ff"] = 1.0
        m.add(*blocks, Sum("i", terms))
        res = simulate_machine(m, dt=dt, inputs=m.read_inputs({"r": r, "w_ref": w}), seed=seed)
        each(name, t, w, r - res.position("theta"), res.status, res.message)


def compensate(preset: str | Path, compensators: str | Sequence[str] | None = None, *, model: Any = None,
               test: CompensationTest | str | Path | None = None, quick: bool = False, seed: int = 0,
               progress: Callable[[str], None] | None = None) -> CompensationResult:
    """Run a machine preset with each compensator; the tracking-error table.

    Parameters
    ----------
    preset : str or Path — one of :data:`PRESETS` (see the module docstring for each machine and
        motion), or a machine model file run with ``test``.
    compensators : sequence of str, optional — default every compensator of the preset
        (:data:`COMPENSATORS`; a machine file: ``none``, the spec's, ``model``) except ``model``
        unless a model is given.
    test : CompensationTest, str or Path, optional — the compensation test of a machine file
        (a spec file is read with :meth:`CompensationTest.load`); refused with a preset.
    model : friction law, str or Path, optional — the identified model (a law or a model file)
        for the ``model`` compensator (its static map on the reference velocity, table side, N).
    quick : bool — a short motion (ballscrew: the first reversal; emps: half the run).
    seed : int — sensor-noise seed (the same for every compensator).
    progress : callable, optional — called with the compensator's name before each run.

    Returns
    -------
    CompensationResult

    Examples
    --------
    >>> from frictionkit.compensate import compensate
    >>> res = compensate("emps", ["none", "coulomb"], quick=True)
    >>> res.status, res.rows["coulomb"]["rms_error"] < res.rows["none"]["rms_error"]
    (0, True)
    """
    t0 = time.perf_counter()
    machine = None
    if isinstance(preset, (str, Path)) and str(preset) not in PRESETS and Path(preset).is_file():
        if test is None:
            _refuse_file(Path(preset))
        from .models.files import ModelFile

        mf_machine = ModelFile.load(preset, kind=None)
        if mf_machine.kind == "law":
            _refuse_file(Path(preset))
        machine, preset = mf_machine.model, str(preset)
        if not isinstance(test, CompensationTest):
            test = CompensationTest.load(test)
        dof = next((d for d in machine.dofs if d.name == test.position), None)
        if dof is None:
            raise ParameterError(f"compensation test '{test.source}': position = {test.position!r} is not a degree "
                                 f"of freedom of machine {machine.name!r} ({', '.join(d.name for d in machine.dofs)})")
        _site(machine, test.site)
        need = set(machine.input_names())
        miss = sorted(need - set(test.inputs))
        if miss:
            raise ParameterError(f"compensation test '{test.source}': machine {machine.name!r} reads inputs "
                                 f"{', '.join(sorted(need))}; missing {', '.join(miss)}")
        unread = sorted(set(test.inputs) - need - {test.reference, test.velocity})
        if unread:  # a misspelt or stale input would otherwise be read and ignored (campaign round 5)
            raise ParameterError(f"compensation test '{test.source}': [inputs] {', '.join(unread)}: not read by machine "
                                 f"{machine.name!r} (it reads {', '.join(sorted(need)) or 'none'}) nor the score's "
                                 f"reference or the compensation's velocity; drop or rename it")
        allowed = ("none", *test.compensators, "model")
        unit = dof.unit
        want = ("N", "m/s") if unit == "m" else ("N·m", "rad/s")
    elif test is not None:
        raise ParameterError("test: only for a machine file (a preset has its own test motion)")
    elif preset not in PRESETS:
        raise ParameterError(f"preset {preset!r}: must be one of {', '.join(PRESETS)} or a machine model file")
    else:
        allowed, unit, want = COMPENSATORS[preset], ERROR_UNITS[preset][0], MODEL_UNITS[preset]
    model_name = None
    if model is not None:
        if isinstance(model, (str, Path)):
            from .models.files import ModelFile

            mf = ModelFile.load(model)
            if (mf.units.get("F"), mf.units.get("v")) != want:
                where = "the table" if want[0] == "N" else "the axis"
                raise DataError(f"model '{model}': units {dict(mf.units)}; the compensators act on {where} "
                                f"(force [{want[0]}], velocity [{want[1]}]); convert or relabel the model first")
            model_name, model = str(model), mf.model
        elif not hasattr(model, "steady_state"):
            raise ParameterError(f"compensate model = {type(model).__name__}: must be a friction law or a model file")
        else:
            model_name = type(model).__name__
    if isinstance(compensators, str):
        compensators = [compensators]
    if compensators is None:
        compensators = [c for c in allowed if c != "model" or model is not None]
    compensators = list(dict.fromkeys(compensators))
    if not compensators:
        raise ParameterError("compensators: give at least one")
    for c in compensators:
        if c not in allowed:
            raise ParameterError(f"compensator {c!r}: {'machine file' if machine is not None else 'preset'} "
                                 f"{preset!r} supports {', '.join(allowed)}")
    if "model" in compensators and model is None:
        raise ParameterError("compensator 'model' needs a model (--model MODEL.json)")
    if isinstance(seed, bool) or int(seed) != seed or seed < 0:
        raise ParameterError(f"compensate seed = {seed!r}: must be an integer >= 0")

    rows, errors, store = {}, {}, {}

    def each(name, t, v, e, status, message):
        store["t"], store["v"] = t, v
        ok = status == 0 and bool(np.all(np.isfinite(e)))
        with np.errstate(over="ignore", invalid="ignore"):  # an overflow is judged below, not warned about
            stats = _errors(t, e, _reversals(t, v), settle) if ok else {}
        if ok and not all(x is None or math.isfinite(x) for x in stats.values()):
            # e.g. a reference of 1e300 m: each error finite, its RMS overflows (was a row 'ok' with RMS inf)
            ok, message = False, (f"error statistics overflow (largest error {float(np.max(np.abs(e))):.3g}): "
                                  "the run's scale is not physical; check the test's inputs")
        errors[name] = e
        rows[name] = {"ok": ok, "message": message if status != 0 or ok or stats else "non-finite error",
                      **(stats if ok else {"max_error": None, "rms_error": None, "reversal_error": None})}

    def tracked(names):
        for n in names:
            if progress is not None:
                progress(n)
            yield n

    if machine is not None:
        settle = test.settle_fraction
        _machine_test(machine, test, tracked(compensators), model, bool(quick), int(seed), each)
    else:
        settle = SETTLE_FRACTIONS.get(preset, SETTLE_FRACTION)
        run = {"ballscrew": _ballscrew, "emps": _emps, "sdss": _sdss}[preset]
        run(tracked(compensators), model, bool(quick), int(seed), each)
    t = store.get("t", np.zeros(0))
    revs = _reversals(t, store["v"]) if "v" in store else []
    note = ""
    if machine is not None and "v" in store and not revs:  # was (issue 13 round 6): 'ok' without a word
        v = np.asarray(store["v"], dtype=float)
        name = test.velocity
        note = (f"the reference velocity {name!r} is zero throughout: the compensators never acted (their "
                "feed-forward reads it), so every row shows the loop alone" if not np.any(v) else
                f"the reference velocity {name!r} never changes sign: no reversal, so there is no reversal error "
                "and the compensators were tested away from reversals only")
    return CompensationResult(preset=preset, rows=rows, t=t, errors=errors, reversals=revs, model=model_name,
                              quick=bool(quick), elapsed=time.perf_counter() - t0, unit=unit, note=note,
                              settle_fraction=float(settle))
