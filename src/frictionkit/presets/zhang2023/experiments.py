"""The virtual experiments of §5.2-5.4 and the tracking errors of Tables 7-8."""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ... import _validate as val
from ...errors import ParameterError
from .paper import PAPER_TABLES, R
from .plant import Reference, TDMSRecording, _integrate, _smooth, _staircase, run_reference

# =========================================================================== virtual experiments (§5.2-5.4)
DT = PAPER_TABLES["table2"]["dt"]


def _direction(direction) -> int:
    if direction not in (1, -1):
        raise ParameterError(f"direction = {direction!r}: must be +1 (clockwise) or -1 (counterclockwise)")
    return int(direction)


def co_speed_sweep(speeds=None, *, direction: int = 1, hold: float = 1.0, ramp: float = 0.1,
                   dt: float = DT, **run) -> TDMSRecording:
    """Two-axis co-speed sweep (§5.2.1, Fig. 9, eq. 17): both shafts at the same linear-equivalent
    speed ``|v|`` in the same rotation direction (``theta1' = -theta2'``), table still; a staircase of
    plateaus ``speeds`` [m/s, magnitudes, ascending by default], each ramped in ``ramp`` and
    held ``hold`` [s]. ``direction`` +1 = clockwise (screw +, nut -), -1 = counterclockwise.
    The plateaus are ``recording.segments`` (value = signed screw speed). ``run``: keywords
    of :func:`run_reference` (``loop`` defaults to ``"semi"``).

    Default speeds: 12 log-spaced from 0.05 to 20 mm/s (spanning Table 3's Stribeck
    velocities of 0.2-0.8 mm/s; assumption, Fig. 9's range is not printed).
    """
    s = _direction(direction)
    speeds = np.geomspace(0.05e-3, 20e-3, 12) if speeds is None else val.vector("co_speed_sweep", "speeds", speeds,
                                                                                  rule="positive")
    v, segs = _staircase(s * np.asarray(speeds), hold, ramp, dt, lead=0.05)
    th1 = _integrate(v, dt)
    ref = Reference(np.arange(v.size) * dt, th1, -th1, "same", segs, 0,
                    f"co-speed sweep {'CW' if s > 0 else 'CCW'}, {len(segs)} plateaus")
    run.setdefault("loop", "semi")
    return run_reference(ref, **run)


def _base_ramp(base, dt, ramp=0.2, hold=0.3):
    n1, n2 = int(round(ramp / dt)), int(round(hold / dt))
    return np.concatenate([base * _smooth(np.arange(n1) / n1), np.full(n2, base)])


def differential_sweep(base_speed: float = 4e-3, table_speeds=None, *, direction: int = 1,
                       driving: str = "screw", hold: float = 1.0, ramp: float = 0.1, settle: float = 0.3,
                       dt: float = DT, **run) -> TDMSRecording:
    """Two-axis differential-speed sweep (§5.2.2, Figs. 11-12, eq. 20).

    Both shafts are brought to the common ``base_speed`` [m/s, linear-equivalent, >= 0; 0 =
    the nut stopped: single drive] in 0.2 s and held there ``settle`` [s]; then the held shaft
    stays there and the driving shaft's speed steps so that the table moves at the plateaus
    ``table_speeds`` [m/s, magnitudes]. Note: the true supports relax after break-away with
    ``tau = T_S / C`` (Table 4's C in N/s): screw+ 0.45 s, screw- 0.27 s, nut+ 0.97 s, nut-
    1.8 s, so the held nut's friction still falls by up to ``T_S - T_C`` over the first
    seconds; plateaus read before ~3 tau include that transient.
    ``driving="screw"`` (eq. 11: ``|theta1'| > |theta2'|``; nut at ``-s base``, screw at
    ``s (base + v3)``, table speed ``s v3``) or ``"nut"`` (eq. 12, extension: screw at
    ``s base``, nut at ``-s (base + v3)``, table speed ``-s v3``), ``s = direction``.
    Segment values are the signed table speed. Default table speeds: 10 log-spaced from 0.02
    to 10 mm/s (assumption).
    """
    s = _direction(direction)
    base = val.nonnegative("differential_sweep", "base_speed", base_speed)
    if driving not in ("screw", "nut"):
        raise ParameterError(f"differential_sweep driving = {driving!r}: must be 'screw' or 'nut'")
    v3 = np.geomspace(0.02e-3, 10e-3, 10) if table_speeds is None else val.vector(
        "differential_sweep", "table_speeds", table_speeds, rule="positive")
    vb = _base_ramp(base, dt, hold=val.nonnegative("differential_sweep", "settle", settle))
    stair, segs = _staircase(np.asarray(v3), hold, ramp, dt)
    n0 = vb.size
    segs = tuple((a + n0, b + n0, (s if driving == "screw" else -s) * v) for a, b, v in segs)
    vb_all = np.concatenate([vb, np.full(stair.size, base)])
    dv = np.concatenate([np.zeros(n0), stair])
    if driving == "screw":
        v1, v2 = s * (vb_all + dv), -s * vb_all
    else:
        v1, v2 = s * vb_all, -s * (vb_all + dv)
    ref = Reference(np.arange(v1.size) * dt, _integrate(v1, dt), _integrate(v2, dt), "different", segs, n0,
                    f"differential sweep, {driving} driving, base {base * 1e3:g} mm/s, "
                    f"{'CW' if s > 0 else 'CCW'}")
    run.setdefault("loop", "semi")
    return run_reference(ref, **run)


def _triangle(turns, speed, dt, lead=0.05):
    """Position path through the turning points ``turns`` [m] at constant ``speed`` [m/s]."""
    pts = [np.full(int(round(lead / dt)), turns[0])]
    segs = []
    pos = pts[0].size
    for a, b in zip(turns[:-1], turns[1:]):
        n = max(int(round(abs(b - a) / speed / dt)), 1)
        pts.append(a + (b - a) * np.arange(1, n + 1) / n)
        segs.append((pos, pos + n, float(b)))
        pos += n
    pts.append(np.full(int(round(lead / dt)), turns[-1]))
    return np.concatenate(pts), tuple(segs)


def presliding_reciprocation(shaft: str = "screw", *, mode: str = "same", stroke: float | None = None,
                             speed: float | None = None, cycles: int = 1, dt: float = DT,
                             **run) -> TDMSRecording:
    """µm reciprocation for the pre-sliding curves (WSIM steps 2 and 4; Figs. 10 and 13).

    ``mode="same"`` (step 2, co-speed): both shafts turn together (table still) along the
    linear-equivalent path 0 -> +stroke -> -stroke -> +stroke ... (virgin curve first);
    ``shaft`` only sets the default stroke (screw ~10 µm, nut ~30 µm, §5.2.1) — read the
    shaft's own torque. ``mode="different"`` (step 4): the nut is held still and the screw
    reciprocates by ``stroke`` (table moves). ``speed`` [m/s] defaults to stroke / 1 s (the
    paper's "micro-speed" is not given). Segment values are the turning points [m].
    """
    if shaft not in ("screw", "nut"):
        raise ParameterError(f"presliding_reciprocation shaft = {shaft!r}: must be 'screw' or 'nut'")
    if mode not in ("same", "different"):
        raise ParameterError(f"presliding_reciprocation mode = {mode!r}: must be 'same' or 'different'")
    A = val.positive("presliding_reciprocation", "stroke",
                     stroke if stroke is not None else (10e-6 if shaft == "screw" else 30e-6))
    sp = val.positive("presliding_reciprocation", "speed", speed if speed is not None else A / 1.0)
    turns = [0.0, A] + [-A, A] * int(cycles)
    x, segs = _triangle(turns, sp, dt)
    th = x / R
    th1, th2 = (th, -th) if mode == "same" else (th, np.zeros_like(th))
    ref = Reference(np.arange(x.size) * dt, th1, th2, "presliding", segs, 0,
                    f"pre-sliding, {mode} speed, {shaft} stroke {A * 1e6:g} µm at {sp * 1e6:g} µm/s")
    run.setdefault("loop", "semi")
    return run_reference(ref, **run)


#: Turning points of the Fig. 14 non-local-memory command, as fractions of the amplitude: an
#: outer loop with two nested inner loops that close on it (assumption: Fig. 14 is an image;
#: this is the standard nested-loop test of Al-Bender et al. that the figure shows in shape).
MEMORY_TURNS = (0.0, 1.0, -1.0, 0.6, -0.2, 0.6, -0.6, 0.2, -0.6, 1.0, -1.0)


def memory_test(mode: str = "same", *, amplitude: float = 5e-6, speed: float | None = None,
                turns=MEMORY_TURNS, dt: float = DT, **run) -> TDMSRecording:
    """Non-local memory command of Fig. 14 (§5.3): nested reciprocation at 3 µm/s in co-speed
    mode (``"same"``: both shafts, table still) or 1 µm/s in differential mode
    (``"different"``: nut still, screw moves the table). ``amplitude`` [m] scales
    :data:`MEMORY_TURNS`. The segments mark each leg (value = its end point); legs that
    extend the outer loop are the "unidirectional" part, the inner ones the reciprocating part.
    """
    if mode not in ("same", "different"):
        raise ParameterError(f"memory_test mode = {mode!r}: must be 'same' or 'different'")
    sp = speed if speed is not None else (3e-6 if mode == "same" else 1e-6)
    sp = val.positive("memory_test", "speed", sp)
    A = val.positive("memory_test", "amplitude", amplitude)
    x, segs = _triangle([A * f for f in turns], sp, dt)
    th = x / R
    th1, th2 = (th, -th) if mode == "same" else (th, np.zeros_like(th))
    ref = Reference(np.arange(x.size) * dt, th1, th2, "memory", segs, 0,
                    f"non-local memory, {mode} speed, {A * 1e6:g} µm at {sp * 1e6:g} µm/s")
    run.setdefault("loop", "semi")
    return run_reference(ref, **run)


def tracking_reference(mode: str = "different", base_speed: float = 6e-3, *, amplitude: float = 2e-3,
                       period: float = 1.0, duration: float = 2.0, dt: float = DT) -> Reference:
    """The sinusoidal-speed command of §5.4 (Figs. 17-20); amplitude, period and duration are
    assumptions (not given).

    ``mode="same"``: both shafts at ``base + amplitude sin(2 pi t / period)`` (co-speed, table
    still; base 0 = synchronous reciprocation from standstill). ``"different"``: the nut at
    ``-base``, the screw at ``base + amplitude sin(...)``: the table speed is the sine.
    Both shafts reach the base speed in 0.5 s first; scored from then on (``eval_from``).
    """
    if mode not in ("same", "different"):
        raise ParameterError(f"tracking_reference mode = {mode!r}: must be 'same' or 'different'")
    base = val.nonnegative("tracking_reference", "base_speed", base_speed)
    A = val.positive("tracking_reference", "amplitude", amplitude)
    P = val.positive("tracking_reference", "period", period)
    D = val.positive("tracking_reference", "duration", duration)
    vb = _base_ramp(base, dt)
    n = int(round(D / dt))
    ts = np.arange(n) * dt
    sine = A * np.sin(2 * np.pi * ts / P)
    vb_all = np.concatenate([vb, np.full(n, base), [base]])
    sine = np.concatenate([np.zeros(vb.size), sine, [0.0]])
    v1 = vb_all + sine
    v2 = -(vb_all + sine) if mode == "same" else -vb_all
    return Reference(np.arange(v1.size) * dt, _integrate(v1, dt), _integrate(v2, dt), mode,
                     ((vb.size, v1.size, base),), vb.size,
                     f"sinusoidal speed, {mode} speed, base {base * 1e3:g} mm/s, ±{A * 1e3:g} mm/s, "
                     f"{P:g} s period")


def sinusoidal_tracking(mode: str = "different", base_speed: float = 6e-3, *, feedforward=None,
                        amplitude: float = 2e-3, period: float = 1.0, duration: float = 2.0, dt: float = DT,
                        **run) -> TDMSRecording:
    """Full closed-loop tracking run (§5.4, eqs. 15-16) of :func:`tracking_reference`;
    ``feedforward`` as :func:`run_reference`. Score it with :func:`tracking_errors`."""
    ref = tracking_reference(mode, base_speed, amplitude=amplitude, period=period, duration=duration, dt=dt)
    run.setdefault("loop", "full")
    return run_reference(ref, feedforward=feedforward, **run)


@dataclass(frozen=True)
class TrackingErrors:
    """Mean and std of the tracking errors [µm] per structure (Tables 7-8 layout).

    ``screw``/``nut``: ``R (theta* - theta)`` from the encoders; ``worktable``:
    ``x_t* - x_scale`` with ``x_t* = R (theta1* + theta2*)``. Over samples ``eval_from`` on.
    """

    screw: tuple
    nut: tuple
    worktable: tuple
    status: int = 0
    message: str = "ok"

    def rows(self) -> list:
        return [{"structure": s, "mean_um": getattr(self, s)[0], "std_um": getattr(self, s)[1]}
                for s in ("screw", "nut", "worktable")]

    def summary(self) -> str:
        return "; ".join(f"{r['structure']} {r['mean_um']:+.3f} ({r['std_um']:.3f}) µm" for r in self.rows())

    def plot(self, ax=None):
        import matplotlib.pyplot as plt

        if ax is None:
            _, ax = plt.subplots(figsize=(5, 3))
        rows = self.rows()
        ax.bar(range(3), [r["mean_um"] for r in rows], yerr=[r["std_um"] for r in rows], capsize=4)
        ax.set_xticks(range(3), [r["structure"] for r in rows])
        ax.set_ylabel("tracking error [µm]")
        return ax


def tracking_errors(rec: TDMSRecording) -> TrackingErrors:
    """Mean and std of screw, nut and worktable tracking errors of a run [µm]."""
    k = rec.reference.eval_from
    e1 = R * (rec.th1_ref - rec.theta1)[k:] * 1e6
    e2 = R * (rec.th2_ref - rec.theta2)[k:] * 1e6
    et = (rec.reference.x_t - rec.x_scale)[k:] * 1e6
    st = (lambda e: (float(np.mean(e)), float(np.std(e))))
    return TrackingErrors(st(e1), st(e2), st(et), rec.status, rec.message)


