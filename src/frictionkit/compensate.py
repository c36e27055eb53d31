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
from typing import Any, Callable

import numpy as np

from .errors import DataError, ParameterError

__all__ = ["PRESETS", "COMPENSATORS", "REVERSAL_WINDOW", "CompensationResult", "compensate"]

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
        return "ok" if not bad else "failed: " + "; ".join(bad)

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
        return {"preset": self.preset, "quick": self.quick, "model": self.model,
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
        ax.set_xlabel("time [s]")
        ax.set_ylabel(f"tracking error r - x [{label}]")
        ax.set_title(f"{self.preset}: friction compensators")
        ax.legend(fontsize=8)
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
        res = fk.simulate_machine(m, dt=dt, inputs={"qg": r, "vref": vr}, seed=seed)
        each(name, t, vr, r - res.q[:, 0], res.status, res.message)


def _refuse_file(path: Path) -> None:
    """A model file in place of a preset: say in one line what compensate would need from it.

    A machine file holds the machine and its controller, not a compensation test: the test
    motion (reference arrays are inputs, not part of the file), which coordinate's error is
    scored, and the input the compensation enters by. Until machine files carry those, only
    the presets run here.
    """
    from .models.files import ModelFile

    mf = ModelFile.load(path, kind=None)
    if mf.kind == "law":
        raise ParameterError(f"'{path}' is a friction law, not a machine: give it as --model to a preset "
                             f"({', '.join(PRESETS)})")
    raise ParameterError(f"machine file '{path}' ({mf.model.name}) carries no compensation test: compensate needs "
                         "its test motion, the coordinate whose error is scored and the input a compensator "
                         f"enters by, which machine files do not hold; run a preset ({', '.join(PRESETS)}) or "
                         f"'frictionkit simulate {path} --input ...' with a FrictionFeedforward block")


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
        res = simulate_machine(m, dt=dt, inputs={"r": r, "w_ref": w}, seed=seed)
        each(name, t, w, r - res.position("theta"), res.status, res.message)


def compensate(preset: str, compensators=None, *, model: Any = None, quick: bool = False, seed: int = 0,
               progress: Callable[[str], None] | None = None) -> CompensationResult:
    """Run a machine preset with each compensator; the tracking-error table.

    Parameters
    ----------
    preset : str — one of :data:`PRESETS` (see the module docstring for each machine and motion).
        A machine file in its place is refused in one line naming what it lacks (a test
        motion, the scored coordinate, the compensation input).
    compensators : sequence of str, optional — default every compensator of the preset
        (:data:`COMPENSATORS`) except ``model`` unless a model is given.
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
    if isinstance(preset, (str, Path)) and str(preset) not in PRESETS and Path(preset).is_file():
        _refuse_file(Path(preset))
    if preset not in PRESETS:
        raise ParameterError(f"preset {preset!r}: must be one of {', '.join(PRESETS)}")
    allowed = COMPENSATORS[preset]
    model_name = None
    if model is not None:
        if isinstance(model, (str, Path)):
            from .models.files import ModelFile

            mf = ModelFile.load(model)
            want = MODEL_UNITS[preset]
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
            raise ParameterError(f"compensator {c!r}: preset {preset!r} supports {', '.join(allowed)}")
    if "model" in compensators and model is None:
        raise ParameterError("compensator 'model' needs a model (--model MODEL.json)")
    if isinstance(seed, bool) or int(seed) != seed or seed < 0:
        raise ParameterError(f"compensate seed = {seed!r}: must be an integer >= 0")

    rows, errors, store = {}, {}, {}

    def each(name, t, v, e, status, message):
        store["t"], store["v"] = t, v
        ok = status == 0 and bool(np.all(np.isfinite(e)))
        errors[name] = e
        rows[name] = {"ok": ok, "message": message if status != 0 or ok else "non-finite error",
                      **(_errors(t, e, _reversals(t, v), SETTLE_FRACTIONS.get(preset, SETTLE_FRACTION)) if ok else
                         {"max_error": None, "rms_error": None, "reversal_error": None})}

    def tracked(names):
        for n in names:
            if progress is not None:
                progress(n)
            yield n

    run = {"ballscrew": _ballscrew, "emps": _emps, "sdss": _sdss}[preset]
    run(tracked(compensators), model, bool(quick), int(seed), each)
    t = store.get("t", np.zeros(0))
    revs = _reversals(t, store["v"]) if "v" in store else []
    return CompensationResult(preset=preset, rows=rows, t=t, errors=errors, reversals=revs, model=model_name,
                              quick=bool(quick), elapsed=time.perf_counter() - t0, unit=ERROR_UNITS[preset][0])
