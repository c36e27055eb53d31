"""The TDMS and the single drive on the machine core; references, feed-forward, runs and recordings."""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from ... import _validate as val
from ...errors import DataError, ParameterError
from ...machines import PID, Machine, NormalLoad, Sum, simulate_machine
from .paper import PAPER_TABLES, R
from .truth import Assumptions, TrueFriction, true_friction

# =========================================================================== machines
ENCODER_RESOLUTION = 2.0 * math.pi / 2**23   # [rad], 23-bit encoders (§5.1)


def _pid_gains(J: float, f_hz: float, dt: float):
    from ...control.pid import PID as PIDDesign

    g = PIDDesign.pole_placement(K_tau=1.0, J=J, B=0.0, bandwidth_hz=f_hz, T=dt,
                                 derivative_cutoff_hz=10.0 * f_hz)
    return dict(Kp=g.Kp, Ki=g.Ki, Kd=g.Kd, tau_d=g.tau_d)


def tdms_machine(assumptions: Assumptions | None = None, truth: TrueFriction | None = None, *,
                 loop: str = "full", dt: float = 250e-6) -> Machine:
    """The TDMS on the machine core: screw ``theta1``, nut ``theta2`` [rad], worktable ``x_t`` [m].

    Degrees of freedom ``"screw"`` (inertia ``J_s``), ``"nut"`` (``J_n``) and ``"table"``
    (``M_t``); the axial spring ``"ball_axial"`` joins ``R (theta1 + theta2)`` to the table
    (its deflection is the clearance ``e_g`` of eq. 13, its force the axial load). Friction
    sites (linear-equivalent N): ``screw_support`` on ``R theta1``, ``nut_support`` on
    ``R theta2``, ``ball_preload`` and ``ball_load`` (``|F_ax|``-scaled) on
    ``R (theta1 + theta2)``, ``guide`` on ``x_t``. Motors ``"m1"``/``"m2"``: torque commands
    ``"u1"``/``"u2"`` [N·m] (``K_t i_q``), clipped at ``torque_limit``. Sensors ``"enc1"``,
    ``"enc2"`` (23 bit) and ``"scale"`` (10 nm, noise ``scale_noise``).

    Controller, once per 250 µs: per axis ``p_j = PID(e_j)`` [N·m] and
    ``u_j = p_j + ff_j + w_j`` (eq. 16: the PID output times ``K_t`` is a torque; ``ff_j`` the
    friction feed-forward inputs, ``w_j`` the current-loop noise inputs). ``loop="full"``:
    eq. 15, ``e1 = theta1* + theta2 - x_t / R`` (derivative on ``theta1* - theta1``),
    ``e2 = theta2* - theta2``; ``loop="semi"``: each motor on its encoder (identification
    runs, a servo drive in position mode). Inputs: ``th1_ref``, ``th2_ref`` [rad], ``ff1``,
    ``ff2``, ``w1``, ``w2`` [N·m] (:func:`run_reference` supplies them).
    """
    a = assumptions or Assumptions()
    tr = truth or true_friction(a)
    if loop not in ("full", "semi"):
        raise ParameterError(f"tdms_machine loop = {loop!r}: must be 'full' or 'semi'")
    T2 = PAPER_TABLES["table2"]
    m = Machine("TDMS (seed 000)")
    th1 = m.dof("screw", inertia=T2["J_s"], kind="rotational")
    th2 = m.dof("nut", inertia=T2["J_n"], kind="rotational")
    xt = m.dof("table", inertia=a.table_mass)
    rel = R * (th1 + th2)
    m.spring(rel, xt, k=a.k_axial, c=a.c_axial, name="ball_axial")
    m.friction("screw_support", R * th1, law=tr.screw_support)
    m.friction("nut_support", R * th2, law=tr.nut_support)
    m.friction("ball_preload", rel, law=tr.ball_preload)
    m.friction("ball_load", rel, law=tr.ball_load,
               load=NormalLoad(on="ball_axial", reference=a.ball_load_reference, preload=0.0, gain=1.0,
                               floor_gain=-1.0))
    m.friction("guide", xt, law=tr.guide)
    m.sensor("enc1", th1, resolution=ENCODER_RESOLUTION)
    m.sensor("enc2", th2, resolution=ENCODER_RESOLUTION)
    m.sensor("scale", xt, resolution=T2["scale_resolution"], noise=a.scale_noise)
    m.actuator("m1", th1, gain=1.0, limit=a.torque_limit, delay=a.actuator_delay, command="u1")
    m.actuator("m2", th2, gain=1.0, limit=a.torque_limit, delay=a.actuator_delay, command="u2")
    g1 = _pid_gains(T2["J_s"] + a.table_mass * R * R, a.bandwidth_screw_hz, dt)
    g2 = _pid_gains(T2["J_n"] + a.table_mass * R * R, a.bandwidth_nut_hz, dt)
    if loop == "full":
        m.add(Sum("e1", {"th1_ref": 1.0, "enc2": 1.0, "scale": -1.0 / R}),
              Sum("e1d", {"th1_ref": 1.0, "enc1": -1.0}))
    else:
        m.add(Sum("e1", {"th1_ref": 1.0, "enc1": -1.0}))
    m.add(Sum("e2", {"th2_ref": 1.0, "enc2": -1.0}),
          PID("p1", "e1", **g1, derivative_error="e1d" if loop == "full" else None, antiwindup="m1"),
          PID("p2", "e2", **g2, antiwindup="m2"),
          Sum("u1", {"p1": 1.0, "ff1": 1.0, "w1": 1.0}),
          Sum("u2", {"p2": 1.0, "ff2": 1.0, "w2": 1.0}))
    return m


def cdfs_machine(assumptions: Assumptions | None = None, truth: TrueFriction | None = None, *,
                 dt: float = 250e-6) -> Machine:
    """Extension (ours): the conventional single-drive feed system (CDFS) with the same parts.

    The nut is fixed to the table carriage and does not turn (no ``"nut"`` DOF, no nut
    support friction); the screw motor turns the same screw, the ball pair slides on
    ``R theta1``; same axial spring, guide, sensors and the screw's full closed loop on the
    scale (``e1 = theta1* - x_t / R``, derivative on the encoder). Inputs as
    :func:`tdms_machine` (``th2_ref``, ``ff2``, ``w2`` are accepted and unused).
    """
    a = assumptions or Assumptions()
    tr = truth or true_friction(a)
    T2 = PAPER_TABLES["table2"]
    m = Machine("CDFS (single drive, ours)")
    th1 = m.dof("screw", inertia=T2["J_s"], kind="rotational")
    xt = m.dof("table", inertia=a.table_mass)
    rel = R * th1
    m.spring(rel, xt, k=a.k_axial, c=a.c_axial, name="ball_axial")
    m.friction("screw_support", R * th1, law=tr.screw_support)
    m.friction("ball_preload", rel, law=tr.ball_preload)
    m.friction("ball_load", rel, law=tr.ball_load,
               load=NormalLoad(on="ball_axial", reference=a.ball_load_reference, preload=0.0, gain=1.0,
                               floor_gain=-1.0))
    m.friction("guide", xt, law=tr.guide)
    m.sensor("enc1", th1, resolution=ENCODER_RESOLUTION)
    m.sensor("scale", xt, resolution=T2["scale_resolution"], noise=a.scale_noise)
    m.actuator("m1", th1, gain=1.0, limit=a.torque_limit, delay=a.actuator_delay, command="u1")
    g1 = _pid_gains(T2["J_s"] + a.table_mass * R * R, a.bandwidth_screw_hz, dt)
    m.add(Sum("e1", {"th1_ref": 1.0, "scale": -1.0 / R}),
          Sum("e1d", {"th1_ref": 1.0, "enc1": -1.0}),
          PID("p1", "e1", **g1, derivative_error="e1d", antiwindup="m1"),
          Sum("u1", {"p1": 1.0, "ff1": 1.0, "w1": 1.0}))
    return m


# =========================================================================== references and runs
@dataclass(frozen=True, eq=False)
class Reference:
    """A motion command on the 250 µs grid.

    Attributes
    ----------
    t : ndarray — sample times [s].
    th1, th2 : ndarray — screw and nut angle commands ``theta1*``, ``theta2*`` [rad] (§2.3 signs).
    mode : str — ``"same"`` (co-speed), ``"different"`` (differential), ``"presliding"``,
        ``"memory"`` or ``"crawl"``.
    segments : tuple of (start, stop, value) — sample ranges of the constant-speed plateaus (or
        other phases) and their nominal value (a table or shaft speed [m/s]); empty if none.
    eval_from : int — first sample of the part to score (after run-up).
    description : str
    """

    t: np.ndarray
    th1: np.ndarray
    th2: np.ndarray
    mode: str
    segments: tuple = ()
    eval_from: int = 0
    description: str = ""

    def __post_init__(self) -> None:
        for f in ("t", "th1", "th2"):
            object.__setattr__(self, f, val.signal(f"Reference.{f}", getattr(self, f)))
        if not (self.t.size == self.th1.size == self.th2.size):
            raise DataError(f"Reference: t, th1, th2 have {self.t.size}, {self.th1.size}, {self.th2.size} "
                            "samples; they must match")

    @property
    def dt(self) -> float:
        return float(self.t[1] - self.t[0])

    @property
    def x_t(self) -> np.ndarray:
        """Worktable command ``x_t* = R (theta1* + theta2*)`` [m]."""
        return R * (self.th1 + self.th2)

    def speeds(self) -> tuple[np.ndarray, np.ndarray]:
        """Linear-equivalent shaft speed commands ``R theta1*'``, ``R theta2*'`` [m/s] (central differences)."""
        return R * np.gradient(self.th1, self.dt), R * np.gradient(self.th2, self.dt)

    def accelerations(self) -> tuple[np.ndarray, np.ndarray]:
        v1, v2 = self.speeds()
        return np.gradient(v1, self.dt) / R, np.gradient(v2, self.dt) / R


def _integrate(v, dt):
    """Linear-equivalent speed [m/s] -> angle [rad] (trapezoidal)."""
    x = np.concatenate([[0.0], np.cumsum(0.5 * (v[1:] + v[:-1]) * dt)])
    return x / R


def _smooth(u):
    u = np.clip(u, 0.0, 1.0)
    return u * u * (3.0 - 2.0 * u)


def _staircase(levels, hold, ramp, dt, start=0.0, lead=0.0):
    """Speed profile: from ``start`` through the plateaus ``levels`` (each ramped in ``ramp``
    and held ``hold``); returns (v, segments) with plateau sample ranges (second half... whole hold)."""
    n_ramp, n_hold, n_lead = int(round(ramp / dt)), int(round(hold / dt)), int(round(lead / dt))
    parts = [np.full(n_lead, start)]
    segs = []
    prev = start
    pos = n_lead
    for lv in levels:
        s = _smooth(np.arange(1, n_ramp + 1) / n_ramp)
        parts.append(prev + (lv - prev) * s)
        pos += n_ramp
        parts.append(np.full(n_hold, lv))
        segs.append((pos, pos + n_hold, float(lv)))
        pos += n_hold
        prev = lv
    v = np.concatenate(parts + [[prev]])
    return v, tuple(segs)


@dataclass(frozen=True, kw_only=True, eq=False)
class FeedForward:
    """Friction feed-forward torques of eq. 16, one value per sample [N·m].

    ``ff1`` is added to the screw motor's command (``T*_fbs + T*_fs + T*_ft``), ``ff2`` to the
    nut motor's (``T*_fbn - T*_fn``): compute them from a model and the :class:`Reference`
    (``ref.speeds()``, ``ref.accelerations()``). ``name`` labels results.
    """

    ff1: np.ndarray
    ff2: np.ndarray
    name: str = "feed-forward"

    def __post_init__(self) -> None:
        object.__setattr__(self, "ff1", val.signal("FeedForward.ff1", self.ff1))
        object.__setattr__(self, "ff2", val.signal("FeedForward.ff2", self.ff2))
        if self.ff1.size != self.ff2.size:
            raise DataError(f"FeedForward: ff1 has {self.ff1.size} samples, ff2 {self.ff2.size}")


@dataclass(frozen=True, eq=False)
class TDMSRecording:
    """One virtual experiment: what a real TDMS would log, plus the plant's truth (SI).

    Logged (what identification may use): ``t``, ``theta1``, ``theta2`` (23-bit encoder
    readings [rad]), ``x_scale`` (10 nm scale [m]), ``torque1``, ``torque2`` (``K_t i_q`` of
    each motor, i.e. the applied torque [N·m]), ``th1_ref``, ``th2_ref``.
    Truth (for checks only): ``theta1_true``, ``theta2_true``, ``x_t_true``, ``v_t_true``
    (table velocity [m/s]), ``omega1``, ``omega2`` (shaft speeds [rad/s]), ``F_axial`` (ball
    pair axial force [N]), ``site_forces`` (dict site -> force [N]).
    """

    reference: Reference
    drive: str
    t: np.ndarray
    theta1: np.ndarray
    theta2: np.ndarray
    x_scale: np.ndarray
    torque1: np.ndarray
    torque2: np.ndarray
    theta1_true: np.ndarray
    theta2_true: np.ndarray
    x_t_true: np.ndarray
    v_t_true: np.ndarray
    omega1: np.ndarray
    omega2: np.ndarray
    F_axial: np.ndarray
    site_forces: dict
    status: int
    message: str
    wall_time: float = float("nan")

    def __repr__(self) -> str:
        """Sizes, duration and mode, not the arrays (``print(rec)`` dumped every one of them)."""
        n = self.t.size
        dt = self.t[1] - self.t[0] if n > 1 else float("nan")
        dur = self.t[-1] - self.t[0] if n else 0.0
        return (f"TDMSRecording(drive={self.drive!r}, mode={self.reference.mode!r}, n={n}, dt={dt:.6g} s, "
                f"duration={dur:.6g} s, plateaus={len(self.segments)}, sites={sorted(self.site_forces)}, "
                f"status={self.status})")

    @property
    def success(self) -> bool:
        return self.status == 0

    @property
    def th1_ref(self) -> np.ndarray:
        return self.reference.th1

    @property
    def th2_ref(self) -> np.ndarray:
        return self.reference.th2

    @property
    def segments(self) -> tuple:
        return self.reference.segments

    @property
    def i_q1(self) -> np.ndarray:
        """Screw motor q-axis current ``torque1 / K_t`` [A] (Table 2: K_t = 0.605 N·m/A)."""
        return self.torque1 / PAPER_TABLES["table2"]["K_t"]

    @property
    def i_q2(self) -> np.ndarray:
        return self.torque2 / PAPER_TABLES["table2"]["K_t"]

    @property
    def force1(self) -> np.ndarray:
        """Screw motor torque as a linear-equivalent force ``K_t i_q / R`` [N] (Table 3's unit)."""
        return self.torque1 / R

    @property
    def force2(self) -> np.ndarray:
        return self.torque2 / R

    @property
    def v_shaft(self) -> tuple[np.ndarray, np.ndarray]:
        """True linear-equivalent shaft speeds ``R theta'`` [m/s]."""
        return R * self.omega1, R * self.omega2

    def plateau_means(self, fraction: float = 0.5) -> dict:
        """Per plateau of the reference: nominal value and the mean logged speeds and torques over
        its last ``fraction`` (linear-equivalent m/s and N). Keys: ``value``, ``v1``, ``v2``,
        ``v_t``, ``F1``, ``F2`` (arrays, one entry per plateau)."""
        out = {k: [] for k in ("value", "v1", "v2", "v_t", "F1", "F2")}
        dt = self.t[1] - self.t[0]
        for a, b, v in self.segments:
            a2 = b - max(int((b - a) * fraction), 2)
            out["value"].append(v)
            out["v1"].append(R * (self.theta1[b - 1] - self.theta1[a2]) / ((b - 1 - a2) * dt))
            out["v2"].append(R * (self.theta2[b - 1] - self.theta2[a2]) / ((b - 1 - a2) * dt))
            out["v_t"].append((self.x_scale[b - 1] - self.x_scale[a2]) / ((b - 1 - a2) * dt))
            out["F1"].append(float(np.mean(self.force1[a2:b])))
            out["F2"].append(float(np.mean(self.force2[a2:b])))
        return {k: np.array(v) for k, v in out.items()}

    def summary(self) -> str:
        return (f"{self.drive} {self.reference.mode} run: {self.t.size} samples over {self.t[-1]:.4g} s, "
                f"status {self.status} ({self.message}); {self.reference.description}; "
                f"max |torque| {np.nanmax(np.abs(self.torque1)):.3g} / {np.nanmax(np.abs(self.torque2)):.3g} N·m; "
                f"table travel {1e6 * (np.nanmax(self.x_t_true) - np.nanmin(self.x_t_true)):.4g} µm; "
                f"wall {self.wall_time:.3g} s")

    def hysteresis(self, shaft: str = "screw") -> tuple[np.ndarray, np.ndarray]:
        """``(x, F)``: a shaft's logged linear-equivalent displacement from the start ``R (theta -
        theta_0)`` [m] and its motor force ``K_t i_q / R`` [N] — the pre-sliding / memory loops of
        Figs. 10, 13, 15-16."""
        if shaft not in ("screw", "nut"):
            raise ParameterError(f"TDMSRecording.hysteresis shaft = {shaft!r}: must be 'screw' or 'nut'")
        th, F = (self.theta1, self.force1) if shaft == "screw" else (self.theta2, self.force2)
        return R * (th - th[0]), F

    def plot_hysteresis(self, shaft: str = "screw", ax=None):
        """Force against displacement of one shaft (µm, N); returns the Axes."""
        import matplotlib.pyplot as plt

        if ax is None:
            _, ax = plt.subplots(figsize=(4.5, 3.5))
        x, F = self.hysteresis(shaft)
        ax.plot(x * 1e6, F, lw=0.8)
        ax.set_xlabel(f"{shaft} displacement R·θ [µm]")
        ax.set_ylabel("K_t i_q / R [N]")
        ax.set_title(self.reference.description, fontsize=8)
        return ax

    def plot(self, ax=None):
        """Motor torques as linear-equivalent forces over time (left) and table position [µm] (right)."""
        import matplotlib.pyplot as plt

        new = ax is None
        if new:
            _, ax = plt.subplots(figsize=(7, 3.5))
        ax.plot(self.t, self.force1, label="screw K_t i_q / R [N]")
        if self.drive == "tdms":
            ax.plot(self.t, self.force2, label="nut K_t i_q / R [N]")
        ax.set_xlabel("t [s]")
        ax.set_ylabel("force [N]")
        r = ax.twinx()
        r.plot(self.t, self.x_t_true * 1e6, "k--", lw=0.8, label="table [µm]")
        r.set_ylabel("x_t [µm]")
        ax.legend(loc="upper left", fontsize=8)
        ax.set_title(f"{self.drive}: {self.reference.description}")
        if new:
            ax.figure.tight_layout()
        return ax


def run_reference(ref: Reference, *, assumptions: Assumptions | None = None, truth: TrueFriction | None = None,
                  drive: str = "tdms", loop: str = "semi", feedforward=None, seed: int = 0,
                  substeps: int | None = None) -> TDMSRecording:
    """Run a :class:`Reference` on the plant and return the :class:`TDMSRecording`.

    ``drive``: ``"tdms"`` or ``"cdfs"`` (always full closed loop); ``loop``: ``"semi"`` (each
    motor on its encoder) or ``"full"`` (eq. 15). ``feedforward``: None, a :class:`FeedForward`
    or a callable ``f(ref) -> FeedForward`` (eq. 16's starred terms). ``seed`` seeds the
    current-loop torque noise and the scale noise. ``substeps``: plant sub-steps per sample
    (default ``assumptions.substeps``).
    """
    import time

    a = assumptions or Assumptions()
    if drive not in ("tdms", "cdfs"):
        raise ParameterError(f"run_reference drive = {drive!r}: must be 'tdms' or 'cdfs'")
    N = ref.t.size
    dt = ref.dt
    if callable(feedforward) and not isinstance(feedforward, FeedForward):
        feedforward = feedforward(ref)
    if feedforward is None:
        ff1 = ff2 = np.zeros(N)
    elif isinstance(feedforward, FeedForward):
        if feedforward.ff1.size != N:
            raise DataError(f"run_reference: feed-forward has {feedforward.ff1.size} samples, the reference {N}")
        ff1, ff2 = feedforward.ff1, feedforward.ff2
    else:
        raise ParameterError(f"run_reference feedforward = {type(feedforward).__name__}: must be None, a "
                             "FeedForward or a callable returning one")
    rng = np.random.default_rng(seed)
    w1 = a.torque_noise * rng.standard_normal(N)
    w2 = a.torque_noise * rng.standard_normal(N)
    m = (tdms_machine(a, truth, loop=loop, dt=dt) if drive == "tdms" else cdfs_machine(a, truth, dt=dt))
    inputs = {"th1_ref": ref.th1, "ff1": ff1, "w1": w1}
    if drive == "tdms":
        inputs.update(th2_ref=ref.th2, ff2=ff2, w2=w2)
    t0 = time.perf_counter()
    res = simulate_machine(m, dt=dt, inputs=inputs, substeps=int(substeps or a.substeps), seed=seed)
    wall = time.perf_counter() - t0
    th1 = res.position("screw")
    th2 = res.position("nut") if drive == "tdms" else np.zeros(N)
    om2 = res.velocity("nut") if drive == "tdms" else np.zeros(N)
    rel = R * (th1 + th2)
    F_ax = a.k_axial * (rel - res.position("table")) + a.c_axial * (
        R * (res.velocity("screw") + om2) - res.velocity("table"))
    zero = np.zeros(N)
    return TDMSRecording(
        reference=ref, drive=drive, t=res.t, theta1=res.signal("enc1"),
        theta2=res.signal("enc2") if drive == "tdms" else zero, x_scale=res.signal("scale"),
        torque1=res.signal("m1.applied"), torque2=res.signal("m2.applied") if drive == "tdms" else zero,
        theta1_true=th1, theta2_true=th2, x_t_true=res.position("table"), v_t_true=res.velocity("table"),
        omega1=res.velocity("screw"), omega2=om2, F_axial=F_ax,
        site_forces={s: res.force(s) for s in res.site_names}, status=res.status, message=res.message,
        wall_time=wall)


