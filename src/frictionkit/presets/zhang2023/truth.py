"""The TDMS plant's true friction (fixed before any comparison) and the named assumptions."""

from __future__ import annotations

from dataclasses import dataclass, fields, replace

import numpy as np

from ... import _validate as val
from ...errors import ParameterError
from ...models.gms import GMS
from ...models.static import Directional, Stribeck
from .paper import PAPER_TABLES, UM, paper_stribeck

# =========================================================================== the plant's true friction
# Pre-sliding of the shaft supports (our truth, fixed before any comparison).
# * Target virgin curve per column: F(x) = T_S (1 - (1 + x/a)^-b), least squares through the
#   paper's P1-P3 of that column (points capped at 0.92 / 0.97 / 0.99 T_S: screw- P2 and P3 exceed
#   its own Table 3 T_S = 79.87 N and cannot be reached when the elements sum to the static map).
# * 7 GMS elements per shaft with ONE stiffness set k_i for both directions: the elastic contacts
#   have the same stiffness whichever way they are loaded. (A direction-dependent k, as Table 4
#   prints, loads an element with k+ and unloads it with k-: under µm reciprocation the force
#   ratchets — the nut support drifted from -22 N to -51 N over four +-2 µm cycles in a first
#   version of this plant — which no passive contact does.) Per direction the weights xi (sum 1,
#   so the truth slides on its Stribeck map) set the break-away strokes xi s / k.
# * k and both weight sets by least squares to both directions' target curves at 40 log-spaced
#   strokes from P1/4 to 3 P3 (start: k geometric 60 ... 0.05 N/µm, equal weights).
# Virgin curve vs the paper's P-points [N]: screw+ 73.76 / 86.71 / 89.74 (paper 71.82 / 86.18 /
# 89.37), screw- 73.20 / 77.53 / 78.77 (73.41 / 80.2 / 86.18), nut+ 57.01 / 64.47 / 67.19
# (57.45 / 64.24 / 67.03), nut- 34.08 / 37.90 / 45.56 (31.92 / 39.9 / 44.69); RMS misfit of the
# target curves 0.8 % (screw) and 0.7 % (nut) of T_S. :func:`_design_presliding` re-derives it.
# Keys "+" / "-": the paper's columns (clockwise / counterclockwise), not the sign of theta'.
_PRESLIDING = {
    "screw": dict(k_N_per_um=(68.4454, 34.927, 9.6874, 2.3532, 0.4483, 0.0844, 0.0299),
                  xi={"+": (0.1535, 0.2374, 0.1975, 0.1512, 0.0907, 0.0848, 0.0848),
                      "-": (0.4826, 0.198, 0.1698, 0.0909, 0.031, 0.0143, 0.0134)}),
    "nut": dict(k_N_per_um=(60.0, 18.3029, 5.8375, 4.7618, 1.5027, 0.4458, 0.1771),
                xi={"+": (0.0419, 0.1853, 0.0591, 0.3141, 0.2042, 0.1036, 0.0918),
                    "-": (0.0171, 0.0171, 0.0129, 0.0576, 0.1649, 0.1564, 0.574)}),
}


def _target_curve(column: str):
    from scipy.optimize import least_squares

    Fs = PAPER_TABLES["table3"][column]["Fs"]
    P = PAPER_TABLES["table4"][column]["points"]
    x = np.array([abs(p[0]) for p in P]) / UM
    F = np.minimum(np.array([abs(p[1]) for p in P]), Fs * np.array([0.92, 0.97, 0.99]))
    r = least_squares(lambda p: Fs * (1 - (1 + x / np.exp(p[0])) ** (-np.exp(p[1]))) - F, [0.0, 0.0])
    a, b = np.exp(r.x)
    return Fs, x, (lambda xx: Fs * (1 - (1 + xx / a) ** (-b)))


def _virgin(k, xi, Fs, x):
    """GMS virgin curve ``sum k_i min(x, xi_i Fs / k_i)`` at strokes ``x`` (any consistent units)."""
    d = np.asarray(xi) * Fs / np.asarray(k)
    return np.sum(np.asarray(k)[:, None] * np.minimum(np.atleast_1d(x)[None, :], d[:, None]), axis=0)


def _design_presliding(shaft: str, M: int = 7) -> dict:
    """Re-derive the 7-element pre-sliding truth of a shaft (procedure in the comment above)."""
    from scipy.optimize import least_squares

    T = [_target_curve(f"{shaft}{s}") for s in "+-"]
    xs = [np.geomspace(x[0] / 4, 3 * x[-1], 40) for _, x, _ in T]

    def unpack(p):
        k = np.exp(p[:M])
        return k, [np.exp(p[M * (1 + j):M * (2 + j)]) / np.exp(p[M * (1 + j):M * (2 + j)]).sum() for j in (0, 1)]

    def res(p):
        k, xis = unpack(p)
        return np.concatenate([(_virgin(k, xi, Fs, xx) - tg(xx)) / Fs for (Fs, _, tg), xi, xx in zip(T, xis, xs)])

    r = least_squares(res, np.r_[np.log(np.geomspace(60, 0.05, M)), np.zeros(2 * M)])
    k, xis = unpack(r.x)
    return {"k_N_per_um": k, "xi": {"+": xis[0], "-": xis[1]}, "rms_rel": float(np.sqrt(np.mean(r.fun ** 2)))}


def _shaft_truth(shaft: str) -> Directional:
    p = _PRESLIDING[shaft]
    k = np.asarray(p["k_N_per_um"]) * 1e6
    laws = {}
    for s in "+-":
        col = f"{shaft}{s}"
        xi = np.asarray(p["xi"][s])
        laws[PAPER_TABLES["table3"][col]["v_sign"]] = GMS(paper_stribeck(col), k=list(k), xi=list(xi / xi.sum()),
                                                          C=PAPER_TABLES["table4"][col]["C"])
    return Directional(positive=laws[1], negative=laws[-1])


def _scaled_screw_shape(pos: Stribeck, neg: Stribeck, stroke_scale: float, C_per_Fs: float) -> Directional:
    """GMS-7 with the screw support's weights and one stiffness set, levels ``pos``/``neg``, strokes
    scaled by ``stroke_scale`` (the screw+ break-away strokes times it)."""
    p = _PRESLIDING["screw"]
    k = np.asarray(p["k_N_per_um"]) * 1e6 * (pos.Fs / PAPER_TABLES["table3"]["screw+"]["Fs"]) / stroke_scale
    return Directional(positive=GMS(pos, k=list(k), xi=list(p["xi"]["+"]), C=C_per_Fs * pos.Fs),
                       negative=GMS(neg, k=list(k), xi=list(p["xi"]["-"]), C=C_per_Fs * neg.Fs))


@dataclass(frozen=True, kw_only=True)
class TrueFriction:
    """The plant's true friction, one law per site (linear-equivalent N on ``R theta``).

    Attributes
    ----------
    screw_support, nut_support : law — bearings/seals of each shaft against ground, on
        ``R theta1`` and ``R theta2``.
    ball_preload : law — the ball pair at its preload, on the relative rotation
        ``R (theta1 + theta2)``.
    ball_load : law — the ball pair's load-dependent part, given at the axial load
        ``Assumptions.ball_load_reference``; scaled by ``|F_ax|`` (:class:`NormalLoad` on the
        axial spring, ``N = max(y, -y)``).
    guide : law — worktable on its rails, on ``x_t``.
    """

    screw_support: object
    nut_support: object
    ball_preload: object
    ball_load: object
    guide: object

    def __post_init__(self) -> None:
        from ...machines.simulate import law_family

        for f in fields(self):
            law_family(getattr(self, f.name), f"TrueFriction.{f.name}")

    def sites(self) -> dict:
        return {f.name: getattr(self, f.name) for f in fields(self)}


@dataclass(frozen=True, kw_only=True)
class Assumptions:
    """Every value of the plant the paper does not give, with its reasoning (SI).

    Parameters
    ----------
    table_mass : float — worktable + carriage mass ``M_t`` [kg]. 8 kg: a 280 mm-stroke
        precision stage with a 16 mm screw carries a table of a few kg plus 4 guide blocks.
    k_axial : float — axial stiffness of the screw-nut-bearing chain [N/m], 5e7: DIR1605 nut
        ~3e8 N/m in series with a 13 mm root shaft over ~0.15 m (~1.8e8 N/m) and the support
        bearings (~1e8 N/m).
    c_axial : float — its damping [N·s/m], 2e3 (about 5 % of critical on the table mode).
    ball_load_reference : float — axial load at which ``TrueFriction.ball_load`` is given [N], 100.
    ball_load_coefficient : float — ball-pair friction per axial load [-], 0.05 (a ball screw's
        efficiency of ~0.95 loses ~5 % of the axial force; the paper: friction "directly
        proportional to the pressure in addition to the pretension").
    ball_preload_level : float — Coulomb level of the ball pair at preload, linear-equivalent
        [N], 7 (differential Table 5 screw levels exceed co-speed Table 3 by 8.5-14 N, which
        must hold ball pair + guide: split about evenly).
    guide_level : float — Coulomb level of the guide [N], 6 (see above; 4 rolling blocks with
        light preload and seals).
    asymmetry : float — negative-direction levels of ball pair and guide = (1 + asymmetry) x
        positive [-], 0.1 (every measured column of Table 3 is direction dependent).
    torque_limit : float — motor torque limit [N·m], 3 x rated = 3.81 (MHMF042 peak).
    torque_noise : float — std of the current-loop torque noise added to each motor [N·m],
        2e-3 (0.16 % of rated; i_q ripple of a 23-bit servo drive at standstill).
    scale_noise : float — std of the scale reading noise [m], 2e-9 (below one 10 nm count).
    bandwidth_screw_hz, bandwidth_nut_hz : float — PID pole-placement bandwidths [Hz], 40 and
        40 (no gains are given; the same drive model and tuning on both axes: three poles at
        -2 pi f with each axis's inertia, derivative
        filter at 10 f).
    actuator_delay : int — whole 250 µs periods between computing a torque command and
        applying it, 0: the drive's current loop (kHz bandwidth, not modelled) applies it within
        the period it is computed; 1 models a one-cycle EtherCAT PDO delay.
    substeps : int — plant sub-steps per 250 µs sample, 3: the fewest at which the machine
        core's sub-step check (``simulate_machine``) does not flag the plant. At 2 the guide's
        GMS couples 0.0331 per sub-step (> 0.03), every run repeats itself at 32 sub-steps
        to check (6-11x the wall time of a run at 3) and the co-speed pre-sliding run is
        flagged: its near-still table (148 nm range) moves by 1.6 nm = 1.06 %. At 3 (coupling
        0.022) no check runs; forced, it passes every experiment but the differential memory
        test, whose held nut differs by 0.6 of an encoder count at any sub-step count (3, 8 and
        32 vs 64: the floor of quantised feedback, not a discretisation error). Against 64
        sub-steps (nine experiments, measured 2026-11-23, issue 9): the table within
        1.4 nm (co-speed pre-sliding) to 9.4 nm (20 µm differential stroke; 10 nm scale count,
        2 nm scale noise), the screw's logged force within 0.11 N RMS (< 0.1 % of T_S =
        113.5 N) at 3 against 0.14 N at 2; worktable tracking mean/std within 0.1 nm of 64.
    """

    table_mass: float = 8.0
    k_axial: float = 5e7
    c_axial: float = 2e3
    ball_load_reference: float = 100.0
    ball_load_coefficient: float = 0.05
    ball_preload_level: float = 7.0
    guide_level: float = 6.0
    asymmetry: float = 0.1
    torque_limit: float = 3.81
    torque_noise: float = 2e-3
    scale_noise: float = 2e-9
    bandwidth_screw_hz: float = 40.0
    bandwidth_nut_hz: float = 40.0
    actuator_delay: int = 0
    substeps: int = 3

    def __post_init__(self) -> None:
        o = "Assumptions"
        for f in ("table_mass", "k_axial", "ball_load_reference", "ball_preload_level", "guide_level",
                  "torque_limit", "bandwidth_screw_hz", "bandwidth_nut_hz"):
            object.__setattr__(self, f, val.positive(o, f, getattr(self, f)))
        for f in ("c_axial", "ball_load_coefficient", "torque_noise", "scale_noise"):
            object.__setattr__(self, f, val.nonnegative(o, f, getattr(self, f)))
        a = val.finite(o, "asymmetry", self.asymmetry)
        if not -0.9 < a < 9.0:
            raise ParameterError(f"{o}.asymmetry = {a!r}: must lie in (-0.9, 9)")
        object.__setattr__(self, "asymmetry", a)
        if isinstance(self.substeps, bool) or not isinstance(self.substeps, (int, np.integer)) or self.substeps < 1:
            raise ParameterError(f"{o}.substeps = {self.substeps!r}: must be an integer >= 1")
        d = self.actuator_delay
        if isinstance(d, bool) or not isinstance(d, (int, np.integer)) or d < 0:
            raise ParameterError(f"{o}.actuator_delay = {d!r}: must be an integer >= 0")

    def scaled(self, name: str, factor: float) -> "Assumptions":
        """A copy with one numeric assumption multiplied by ``factor`` (robustness sweeps)."""
        if name not in {f.name for f in fields(self)} or name in ("substeps", "actuator_delay"):
            raise ParameterError(f"Assumptions.scaled name = {name!r}: not a numeric assumption")
        return replace(self, **{name: getattr(self, name) * factor})


def true_friction(assumptions: Assumptions | None = None) -> TrueFriction:
    """The plant's true friction (fixed before any comparison; reasoning in the module text).

    * Shaft supports: direction-dependent GMS-7 over the Table 3 Stribeck map of the shaft's
      columns (the co-speed curves *are* the support friction: in co-speed the balls do not
      slide, eq. 17); one element stiffness set for both directions and per-direction weights
      (sum xi = 1) fitted to the P-points of Table 4 (comment at ``_PRESLIDING``); C of
      Table 4 [N/s] per direction.
    * Ball pair and guide (not given): GMS-7 with the screw support's weights and stiffness
      shape, strokes x0.5 (ball pair) and x0.25 (rolling guide), a Stribeck map with a modest
      Stribeck rise (Fs = 1.3 Fc), Stribeck velocity 2 mm/s / 1 mm/s, viscous 400 / 150 N·s/m,
      the negative direction (1 + asymmetry) stronger; relaxation ``C = 20 Fs`` (50 ms).
    So neither the compared LuGre nor GMS-3 equals the truth at any site.
    """
    a = assumptions or Assumptions()

    def extra(level, vs, delta, sigma2, stroke_scale):
        f = 1.0 + a.asymmetry
        pos = Stribeck(Fc=level, Fs=1.3 * level, vs=vs, delta=delta, sigma2=sigma2)
        neg = Stribeck(Fc=level * f, Fs=1.3 * level * f, vs=vs, delta=delta, sigma2=sigma2 * f)
        return _scaled_screw_shape(pos, neg, stroke_scale, C_per_Fs=20.0)

    load_level = a.ball_load_coefficient * a.ball_load_reference
    return TrueFriction(
        screw_support=_shaft_truth("screw"), nut_support=_shaft_truth("nut"),
        ball_preload=extra(a.ball_preload_level, 2e-3, 1.5, 400.0, 0.5),
        ball_load=extra(max(load_level, 1e-9), 2e-3, 1.5, 0.0, 0.5),
        guide=extra(a.guide_level, 1e-3, 2.0, 150.0, 0.25),
    )


