"""Seed 000 (Zhang et al., Actuators 2023): the two-axis differential micro-feed system (TDMS).

A ball screw whose screw (``theta1``) and nut (``theta2``) each have a motor; the worktable
moves at the *difference* of two fast rotations. This module holds

* the paper's Tables 2-6 in SI, with every correction recorded next to the value
  (:data:`PAPER_TABLES`, :func:`paper_stribeck`, :func:`paper_gms`);
* the simulated plant on the machine core (:func:`tdms_machine`, :func:`cdfs_machine`), its
  true friction (:class:`TrueFriction`, :func:`true_friction`) and every value the paper does
  not give as a named, validated assumption (:class:`Assumptions`);
* the virtual experiments of §5.2-5.4 (:func:`co_speed_sweep`, :func:`differential_sweep`,
  :func:`presliding_reciprocation`, :func:`memory_test`, :func:`sinusoidal_tracking`) returning
  :class:`TDMSRecording` objects, and the full closed loop of eqs. 15-16 with a feed-forward
  hook (:class:`FeedForward`, :func:`tracking_errors`);
* the extension (ours): a conventional single-drive feed system (CDFS) against the TDMS at
  table speeds of 1-10 µm/s (:func:`crawling_comparison`).

Conventions (SI inside)
-----------------------
* **Linear-equivalent coordinates.** The paper prints shaft torques in N and shaft speeds in
  mm/s: they are linear-equivalent values at the lead ratio ``R = P_h / 2 pi``
  (``T [N·m] = R F [N]``, ``v [m/s] = R theta' [rad/s]``). The plant's shaft friction sites act
  on ``R theta1`` and ``R theta2`` (force in N, stiffness in N/m) so the tables enter as
  printed after unit conversion; motor torques are N·m (``K_t i_q``) and are converted with
  ``R`` at the edges (:func:`torque_to_force`).
* **Sign convention (§2.3).** Clockwise rotation of both motors: screw speed positive, nut
  speed negative. Co-rotation at equal speed is ``theta1' = -theta2'`` and holds the table
  still; the screw-nut relative rotation is ``theta1 + theta2`` and the table sits at
  ``x_t = R (theta1 + theta2) - e_g`` (eq. 13).
* **Table columns.** "Positive" = clockwise for both shafts (figure captions of Fig. 9), so
  the screw's positive column is ``theta1' > 0`` and the nut's positive column is
  ``theta2' < 0`` — Table 3 prints the nut's Stribeck velocity as ``-0.4858`` mm/s and the nut
  P-points of the clockwise run at negative angles, which confirms it.

Physics the plant derives (differs from eqs. 11-12)
----------------------------------------------------
The ball pair is one contact, so its axial force ``F_ax`` reacts on *both* shafts: the
generalised force of a force ``F`` acting at ``R (theta1 + theta2)`` is ``R F`` on each
shaft. The table load ``T_dt = R (M_t x_t'' + F_ft)`` therefore loads the driving shaft *and*
drives the other (in screw-driving mode it brakes the screw and pushes the nut along its
rotation), where eqs. 11-12 put it on the driving shaft only. The same holds for the ball
pair friction (the paper's "T_fbs decelerates the screw and accelerates the nut": equal
magnitudes ``R F_b`` here). The lumped per-motor friction of eq. 20 that WSIM identifies is
then ``T_s = T_fs + R (F_b + F_ft)`` and ``T_n = T_fn - R (F_b + F_ft)`` (nut speed negative).

Clearance ``e_g``
-----------------
THK's DIR series is an offset-preload nut: the preload removes the geometric clearance, so
``e_g`` of eq. 13 is modelled as the *elastic* lost motion of the preloaded ball pair, screw
shaft and support bearings under the axial force: the table is a degree of freedom joined to
``R (theta1 + theta2)`` by the axial spring ``k_axial`` (``e_g = F_ax / k_axial``). That
spring's force is the axial load that scales the ball pair's friction (:class:`NormalLoad`).
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field, fields, replace
from types import MappingProxyType

import numpy as np

from .. import _validate as val
from ..errors import DataError, ParameterError
from ..machines import PID, Machine, NormalLoad, Sum, simulate_machine
from ..models.gms import GMS
from ..models.static import Directional, Stribeck

__all__ = [
    "PAPER_TABLES", "R", "Assumptions", "TrueFriction", "true_friction", "paper_stribeck", "paper_gms",
    "torque_to_force", "force_to_torque", "tdms_machine", "cdfs_machine", "TDMSRecording", "FeedForward",
    "Reference", "run_reference", "co_speed_sweep", "differential_sweep", "presliding_reciprocation",
    "memory_test", "sinusoidal_tracking", "tracking_errors", "TrackingErrors", "crawling_comparison",
    "CrawlingResult", "velocity_ripple",
]

# =========================================================================== paper values
MM = 1e-3
UM = 1e-6

#: Lead ratio ``R = P_h / 2 pi`` [m/rad] (Table 2: P_h = 5 mm).
R = 5e-3 / (2.0 * math.pi)

_T2 = {
    "P_h": 5e-3,            # lead [m]; Table 2 "5" mm
    "R": R,                 # [m/rad]
    "J_s": 9.85e-5,         # screw-side inertia [kg·m²], Table 2
    "J_n": 53.62e-5,        # nut-side inertia [kg·m²], Table 2
    "K_t": 0.605,           # motor torque constant [N·m/A], Table 2 (both motors)
    "T_rated": 1.27,        # rated torque [N·m], Table 2 / §5.1
    "d_screw": 16e-3,       # screw diameter [m] (detached in Table 2; §5.1 "16 mm")
    "stroke": 0.280,        # [m], §5.1
    "encoder_bits": 23,     # §5.1 MBDLT25BF / MHMF042LV2M
    "scale_resolution": 10e-9,  # [m], §5.1 KEYENCE GVS 600T
    "dt": 250e-6,           # control period [s], §5.1
}


def _t3(Fc, Fs, vs_mm_s, delta, sigma_printed, shaft, column):
    # Table 3: T_C, T_S printed in "N" = linear-equivalent force at R (torque = R F);
    # theta_s printed signed in mm/s (linear-equivalent) -> magnitude in m/s, the sign gives
    # the shaft direction of the column; sigma printed "N·s/m" but fitted against speeds in
    # mm/s like theta_s: read as N·s/mm (at 6 mm/s the N·s/m reading gives 0.004 N, an
    # invisible term nobody would fit to four digits) -> x 1e3 to N·s/m.
    return MappingProxyType({
        "Fc": float(Fc), "Fs": float(Fs), "vs": abs(vs_mm_s) * MM, "delta": float(delta),
        "sigma2": sigma_printed * 1e3, "v_sign": 1 if vs_mm_s > 0 else -1, "shaft": shaft,
        "column": column, "printed": (Fc, Fs, vs_mm_s, delta, sigma_printed)})


_T3 = {
    "screw+": _t3(87.4, 113.5, 0.2439, 1.0, 0.6033, "screw", "positive"),
    "nut+": _t3(62.0, 67.85, -0.4858, 3.0, 2.297, "nut", "positive"),
    "screw-": _t3(74.04, 79.87, -0.1986, 5.58, 1.131, "screw", "negative"),
    "nut-": _t3(78.97, 99.64, 0.8266, 1.5, 1.907, "nut", "negative"),
}


def _t4(k, xi, C, points):
    # Table 4 prints k in "N/mm"; the P-points (µm, N) give the same numbers as slopes in N/µm
    # (screw+: slopes 30.04 / 3.234 / 0.9225 -> k = 26.804 / 2.311 / 0.922): k in N/µm -> x 1e6.
    # C printed without unit: N/s in the form C (xi - F/s) (time constant |s| / C).
    # points: the paper's critical points P1..P3 (position µm, force N), linear-equivalent.
    return MappingProxyType({"k": tuple(x * 1e6 for x in k), "xi": tuple(xi), "C": float(C),
                             "sum_xi": float(sum(xi)),
                             "points": tuple((p[0] * UM, p[1]) for p in points),
                             "printed_k_N_per_mm": tuple(k)})


_T4 = {
    # the text labels both screw point sets "counterclockwise"; the first set is the positive column
    "screw+": _t4((26.804, 2.312, 0.922), (0.565, 0.139, 0.0835), 250,
                  ((2.391, 71.82), (6.832, 86.18), (10.290, 89.37))),
    "nut+": _t4((6.521, 0.803, 0.182), (0.736, 0.191, 0.084), 70,
                ((-7.654, -57.45), (-16.11, -64.24), (-31.43, -67.03))),
    "screw-": _t4((36.563, 2.871, 1.102), (0.829, 0.150, 0.135), 300,
                  ((-1.811, -73.41), (-4.176, -80.2), (-9.766, -86.18))),
    "nut-": _t4((1.452, 0.912, 0.390), (0.169, 0.162, 0.117), 55,
                ((11.59, 31.92), (17.72, 39.9), (30.01, 44.69))),
}

# Table 5 (differential mode, screw driving; screw values at base speed 4 mm/s). The nut's
# levels are affine in the nut (base) speed theta2' printed in mm/s: slope 6.45 N per mm/s
# -> 6450 N·s/m; sigma read as N·s/mm (as Table 3) -> x 1e3; epsilon read as N·s²/mm² -> x 1e6.
# Which sign of theta2' the affine levels take is not stated (they are negative at the Fig. 12
# base speeds whichever sign is read); the printed numbers are kept and the SI slope applies
# to theta2' as printed (linear-equivalent, m/s).
_T5 = {
    "screw+": MappingProxyType({"Fc": 95.92, "Fs": 112.43, "vs": 2.796 * MM, "delta": 1.551,
                                "sigma2": 1.38e3, "v_sign": 1}),
    "screw-": MappingProxyType({"Fc": 88.11, "Fs": 108.90, "vs": 3.064 * MM, "delta": 2.146,
                                "sigma2": 2.06e3, "v_sign": -1}),
    "nut+": MappingProxyType({"Fc_slope": 6.45e3, "Fc_offset": -4.52, "Fs_slope": 6.45e3, "Fs_offset": -19.56,
                              "vs": 0.065 * MM, "delta": 1.7, "sigma2": -1.12e3, "epsilon": 5.852e6,
                              "v_sign": 1}),
    "nut-": MappingProxyType({"Fc": -48.34, "Fs": -62.26, "vs": 0.169 * MM, "delta": 0.9, "sigma2": 0.39e3,
                              "epsilon": 3.754e6, "v_sign": -1}),
}

# Table 6 (differential, screw reciprocating with the nut still); units as Table 4.
_T6 = {
    "screw+": MappingProxyType({"k": (4.39e6, 0.239e6, 0.161e6), "xi": (0.919, 0.193, 0.258), "C": 100.0,
                                "sum_xi": 1.37}),
    "screw-": MappingProxyType({"k": (17.74e6, 0.521e6, 0.365e6), "xi": (1.014, 0.124, 0.160), "C": 50.0,
                                "sum_xi": 1.298}),
}

# Tables 7 and 8 (tracking error, µm, mean and std): (structure, method) -> ((mean, std), ...)
_T7 = {  # ACIM -> WSIM per case; the differential-6 nut "16" is probably a dropped minus (kept as printed)
    ("same", 6): {"screw": ((6.4, 1.0), (-1.3, 1.1)), "nut": ((-9.8, 1.3), (-9.4, 1.4)),
                  "worktable": ((-0.328, 0.102), (-2.5, 0.532))},
    ("same", 0): {"screw": ((1.225, 6.3), (1.218, 5.9)), "nut": ((-0.459, 6.9), (-0.426, 6.6)),
                  "worktable": ((0.0526, 0.0533), (0.0601, 0.115))},
    ("different", 6): {"screw": ((10.9, 9.1), (5.9, 2.4)), "nut": ((-16.9, 8.6), (16.0, 7.7)),
                       "worktable": ((-13.1, 12.7), (5.5, 5.7))},
    ("different", 0): {"screw": ((1.8, 17.0), (-1.6, 9.9)), "nut": ((2.3, 1.5), (-0.535, 1.6)),
                       "worktable": ((-13.2, 12.7), (1.5, 8.5))},
}
_T8 = {  # LuGre -> GMS
    ("same", 6): {"screw": ((1.8, 1.2), (-1.3, 1.1)), "nut": ((-9.3, 1.3), (-9.2, 1.4)),
                  "worktable": ((-2.4, 0.950), (-2.0, 0.382))},
    ("same", 0): {"screw": ((-1.2, 6.2), (1.0, 6.3)), "nut": ((-0.515, 6.6), (-0.276, 6.8)),
                  "worktable": ((0.189, 0.104), (0.067, 0.076))},
    ("different", 6): {"screw": ((17.8, 3.0), (1.8, 2.2)), "nut": ((-15.9, 8.8), (-14.1, 8.1)),
                       "worktable": ((-5.0, 17.1), (-3.7, 16.3))},
    ("different", 0): {"screw": ((-4.3, 9.8), (-4.4, 9.5)), "nut": ((-0.664, 1.8), (-0.826, 1.7)),
                       "worktable": ((1.3, 19.5), (-0.444, 18.6))},
}

#: The paper's Tables 2-8 in SI (linear-equivalent forces in N, speeds in m/s, stiffness in
#: N/m), read-only. Keys: ``"table2"`` (dict), ``"table3"``/``"table4"``/``"table5"``/
#: ``"table6"`` (column -> dict; columns ``"screw+"``, ``"nut+"``, ``"screw-"``, ``"nut-"``
#: where ``+`` is the paper's *positive = clockwise* column; ``v_sign`` is the sign of the
#: shaft speed in the §2.3 convention), ``"table7"``/``"table8"`` ((speeds, base mm/s) ->
#: structure -> ((mean, std) before, (mean, std) after) in µm).
PAPER_TABLES = MappingProxyType({
    "table2": MappingProxyType(_T2), "table3": MappingProxyType(_T3), "table4": MappingProxyType(_T4),
    "table5": MappingProxyType(_T5), "table6": MappingProxyType(_T6),
    "table7": MappingProxyType(_T7), "table8": MappingProxyType(_T8),
})


def torque_to_force(T):
    """Shaft torque [N·m] -> linear-equivalent force at ``R`` [N] (``F = T / R``)."""
    return np.asarray(T, dtype=float) / R


def force_to_torque(F):
    """Linear-equivalent force [N] -> shaft torque [N·m] (``T = R F``; Table 3's "N" values)."""
    return np.asarray(F, dtype=float) * R


def paper_stribeck(column: str, table: str = "table3") -> Stribeck:
    """The Stribeck map of one column of Table 3 (or the screw columns of Table 5), linear-equivalent
    [N, m/s, N·s/m]; the Stribeck velocity as a magnitude (the printed sign is the direction)."""
    cols = PAPER_TABLES[table]
    if column not in cols or "Fc" not in cols[column] or cols[column]["Fc"] < 0:
        raise ParameterError(f"paper_stribeck column = {column!r}: not a Stribeck column of {table} "
                             f"(have {[c for c in cols if 'Fc' in cols[c] and cols[c]['Fc'] >= 0]})")
    c = cols[column]
    return Stribeck(Fc=c["Fc"], Fs=c["Fs"], vs=c["vs"], delta=c["delta"], sigma2=max(c["sigma2"], 0.0))


def paper_gms(shaft: str, *, table: str = "table4", sum_xi: str = "normalise") -> Directional:
    """The paper's GMS-3 of one shaft as a ``Directional`` law on the linear-equivalent coordinate.

    ``table="table4"`` (co-speed, screw or nut, static map of Table 3) or ``"table6"``
    (differential, screw only, static map of Table 5's screw columns).

    ``sum_xi`` — the Σξ decision. Tables 4/6 weights sum to 0.45-1.37 (eq. 19 with
    ``s = T_S`` over the P-points), so used as printed the elements settle at that fraction of the
    Table 3/5 curve. ``"normalise"`` (default, our decision): ``xi / sum(xi)`` with ``k`` kept, so
    the model slides on the Stribeck curve it was identified with (the break-away strokes
    ``xi s / k`` stretch by ``1 / sum(xi)``); ``"as_printed"``: the printed weights.
    """
    if sum_xi not in ("normalise", "as_printed"):
        raise ParameterError(f"paper_gms sum_xi = {sum_xi!r}: must be 'normalise' or 'as_printed'")
    if table not in ("table4", "table6"):
        raise ParameterError(f"paper_gms table = {table!r}: must be 'table4' or 'table6'")
    if shaft not in ("screw", "nut") or (table == "table6" and shaft != "screw"):
        raise ParameterError(f"paper_gms shaft = {shaft!r}: must be 'screw' or 'nut' ('screw' for table6)")
    stat_table = "table3" if table == "table4" else "table5"
    laws = {}
    for col in (f"{shaft}+", f"{shaft}-"):
        g = PAPER_TABLES[table][col]
        xi = np.array(g["xi"])
        if sum_xi == "normalise":
            xi = xi / xi.sum()
        sign = PAPER_TABLES[stat_table][col]["v_sign"] if stat_table == "table3" else (1 if col.endswith("+") else -1)
        laws[sign] = GMS(paper_stribeck(col, stat_table), k=list(g["k"]), xi=list(xi), C=g["C"])
    return Directional(positive=laws[1], negative=laws[-1])


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
        from ..machines.simulate import law_family

        for f in fields(self):
            law_family(getattr(self, f.name), f"TrueFriction.{f.name}")

    def sites(self) -> dict:
        return {f.name: getattr(self, f.name) for f in fields(self)}


def _stribeck_field(default: Stribeck, doc: str):
    return field(default=default, metadata={"doc": doc})


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
    substeps : int — plant sub-steps per 250 µs sample, 2. Convergence against 16 sub-steps:
        the screw's virgin pre-sliding curve (WSIM step 2 data, 5 µm at 10 µm/s) differs by
        0.09 N RMS at 2, 0.07 N at 4, 0.06 N at 8 (< 0.1 % of T_S = 113.5 N); the closed-loop
        sinusoidal run by one 10 nm scale count and ~0.09 N RMS of screw torque at 1-8
        sub-steps (the floor of quantised feedback: any change flips counts).
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
    substeps: int = 2

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

    def scaled(self, name: str, factor: float) -> "Assumptions":
        """A copy with one numeric assumption multiplied by ``factor`` (robustness sweeps)."""
        if name not in {f.name for f in fields(self)} or name == "substeps":
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


# =========================================================================== machines
ENCODER_RESOLUTION = 2.0 * math.pi / 2**23   # [rad], 23-bit encoders (§5.1)
SIGNALS_IN = ("th1_ref", "th2_ref", "ff1", "ff2", "w1", "w2")


def _pid_gains(J: float, f_hz: float, dt: float):
    from ..control.pid import PID as PIDDesign

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
    m.actuator("m1", th1, gain=1.0, limit=a.torque_limit, command="u1")
    m.actuator("m2", th2, gain=1.0, limit=a.torque_limit, command="u2")
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
    m.actuator("m1", th1, gain=1.0, limit=a.torque_limit, command="u1")
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


# =========================================================================== extension (ours): CDFS vs TDMS crawling
def velocity_ripple(v, v_nominal: float) -> dict:
    """Velocity ripple of a constant-speed window: ``std(v) / v_nominal`` and peak-to-peak over
    ``v_nominal`` [%], and the fraction of samples with ``v`` below 10 % of nominal (sticking)."""
    v = np.asarray(v, dtype=float)
    vn = abs(float(v_nominal))
    return {"ripple_percent": 100.0 * float(np.std(v)) / vn,
            "peak_to_peak_percent": 100.0 * float(np.ptp(v)) / vn,
            "mean_percent": 100.0 * float(np.mean(v)) / float(v_nominal),
            "stuck_fraction": float(np.mean(np.abs(v) < 0.1 * vn))}


def crawl_reference(drive: str, table_speed: float, *, base_speed: float = 6e-3, duration: float = 2.0,
                    approach_speed: float = 0.2e-3, approach: float = 0.3, dt: float = DT) -> Reference:
    """Steady feed at the table speed ``table_speed`` [m/s] for ``duration`` [s].

    Crawling is a property of steady feed, so the table first *approaches* at
    ``approach_speed`` for ``approach`` [s] (0.2 mm/s for 0.3 s = 60 µm, beyond every
    pre-sliding stroke of the truth, so all contacts slide) and then slows to the feed speed
    in 0.05 s (started from rest, 3 s at 1 µm/s would stay inside the 67 µm pre-sliding
    range of the screw support and test pre-sliding, not crawling). The CDFS does this with
    its screw; the TDMS first brings both shafts to ``base_speed`` (co-speed, 0.5 s) and then
    runs the screw faster than the nut by the table speed (differential, screw driving).
    ``eval_from``: 0.5 s into the feed (transients out)."""
    v = val.positive("crawl_reference", "table_speed", table_speed)
    va = val.positive("crawl_reference", "approach_speed", approach_speed)
    n_run = int(round(duration / dt))
    nr = int(round(0.05 / dt))
    na = int(round(val.positive("crawl_reference", "approach", approach) / dt))
    vt = np.concatenate([va * _smooth(np.arange(nr) / nr), np.full(na, va),
                         va + (v - va) * _smooth(np.arange(nr) / nr), np.full(n_run + 1, v)])
    if drive == "cdfs":
        v1, v2 = vt, np.zeros_like(vt)
        n0 = 2 * nr + na
    elif drive == "tdms":
        vb = _base_ramp(val.positive("crawl_reference", "base_speed", base_speed), dt)
        n0 = vb.size + 2 * nr + na
        vb_all = np.concatenate([vb, np.full(vt.size, vb[-1])])
        v1 = vb_all + np.concatenate([np.zeros(vb.size), vt])
        v2 = -vb_all
    else:
        raise ParameterError(f"crawl_reference drive = {drive!r}: must be 'cdfs' or 'tdms'")
    k0 = n0 + int(round(0.5 / dt))
    return Reference(np.arange(v1.size) * dt, _integrate(v1, dt), _integrate(v2, dt), "crawl",
                     ((k0, v1.size, v),), k0, f"crawling at {v * 1e6:g} µm/s ({drive})")


@dataclass(frozen=True)
class CrawlingResult:
    """Extension (ours): CDFS vs TDMS at low table speeds. ``rows``: one dict per table speed
    with ``table_speed_um_s``, ``cdfs_ripple_percent``, ``tdms_ripple_percent`` (std of the
    TRUE table velocity over the window / nominal), the true velocity averaged over 10 ms
    (``*_ripple_10ms_percent``: crawling is slow; this drops the table-mode jitter that the
    current-loop noise excites), the same from the 10 nm scale over ``scale_window``
    (``*_scale_ripple_percent``), peak-to-peak and stuck fractions.
    ``recordings``: (speed, drive) -> TDMSRecording."""

    rows: tuple
    recordings: dict
    scale_window: float
    status: int = 0
    message: str = "ok"

    def summary(self) -> str:
        lines = [f"CDFS vs TDMS crawling (ours), ripple = std(v_true)/v; scale estimate over "
                 f"{self.scale_window * 1e3:g} ms windows; status {self.status} ({self.message})"]
        for r in self.rows:
            lines.append(f"  {r['table_speed_um_s']:6.3g} µm/s: CDFS {r['cdfs_ripple_percent']:8.1f} % "
                         f"(10 ms {r['cdfs_ripple_10ms_percent']:6.1f} %, scale {r['cdfs_scale_ripple_percent']:6.1f} %, stuck {r['cdfs_stuck_fraction']:.2f})  "
                         f"TDMS {r['tdms_ripple_percent']:8.1f} % (10 ms {r['tdms_ripple_10ms_percent']:6.1f} %, scale {r['tdms_scale_ripple_percent']:6.1f} %, "
                         f"stuck {r['tdms_stuck_fraction']:.2f})")
        return "\n".join(lines)

    def plot(self, ax=None):
        import matplotlib.pyplot as plt

        if ax is None:
            _, ax = plt.subplots(figsize=(5, 3.5))
        v = [r["table_speed_um_s"] for r in self.rows]
        ax.semilogy(v, [r["cdfs_ripple_percent"] for r in self.rows], "o-", label="CDFS (true v)")
        ax.semilogy(v, [r["tdms_ripple_percent"] for r in self.rows], "s-", label="TDMS (true v)")
        ax.semilogy(v, [r["cdfs_scale_ripple_percent"] for r in self.rows], "o:", label="CDFS (scale)")
        ax.semilogy(v, [r["tdms_scale_ripple_percent"] for r in self.rows], "s:", label="TDMS (scale)")
        ax.set_xlabel("table speed [µm/s]")
        ax.set_ylabel("velocity ripple [%]")
        ax.legend(fontsize=8)
        ax.set_title("single drive vs TDMS (ours)")
        return ax


def crawling_comparison(table_speeds=(1e-6, 2e-6, 5e-6, 10e-6), *, base_speed: float = 6e-3,
                        duration: float = 2.0, scale_window: float = 0.1, assumptions: Assumptions | None = None,
                        truth: TrueFriction | None = None, seed: int = 0,
                        substeps: int | None = None) -> CrawlingResult:
    """Extension (ours): the single drive (CDFS, :func:`cdfs_machine`) against the TDMS
    (differential, screw driving at ``base_speed``) at the table speeds [m/s], both in full
    closed loop on the scale, same parts, same truth, same noise seed.

    The ripple is measured on the plant's TRUE table velocity (a 10 nm scale read every
    250 µs resolves only 40 µm/s per sample); beside it, the scale-based estimate
    ``(x[k + W] - x[k]) / (W dt)`` over ``scale_window`` [s] (0.1 s: 0.1 µm/s resolution).
    """
    speeds = val.vector("crawling_comparison", "table_speeds", table_speeds, rule="positive")
    W = val.positive("crawling_comparison", "scale_window", scale_window)
    rows, recs, status, msgs = [], {}, 0, []
    for v in speeds:
        row = {"table_speed_um_s": float(v) * 1e6}
        for drive in ("cdfs", "tdms"):
            ref = crawl_reference(drive, float(v), base_speed=base_speed, duration=duration)
            rec = run_reference(ref, assumptions=assumptions, truth=truth, drive=drive, loop="full", seed=seed,
                                substeps=substeps)
            recs[(float(v), drive)] = rec
            if rec.status:
                status, _ = rec.status, msgs.append(f"{drive} {v * 1e6:g} µm/s: {rec.message}")
            k = ref.eval_from
            rr = velocity_ripple(rec.v_t_true[k:], v)
            nW = max(int(round(W / ref.dt)), 1)
            xs = rec.x_scale[k:]
            v_est = (xs[nW:] - xs[:-nW]) / (nW * ref.dt)
            rs = velocity_ripple(v_est, v)
            n_lp = max(int(round(0.01 / ref.dt)), 1)
            v_lp = np.convolve(rec.v_t_true[k:], np.ones(n_lp) / n_lp, mode="valid")
            rl = velocity_ripple(v_lp, v)
            row.update({f"{drive}_ripple_percent": rr["ripple_percent"],
                        f"{drive}_peak_to_peak_percent": rr["peak_to_peak_percent"],
                        f"{drive}_mean_percent": rr["mean_percent"],
                        f"{drive}_stuck_fraction": rr["stuck_fraction"],
                        f"{drive}_ripple_10ms_percent": rl["ripple_percent"],
                        f"{drive}_scale_ripple_percent": rs["ripple_percent"]})
        rows.append(row)
    return CrawlingResult(tuple(rows), recs, W, status, "; ".join(msgs) or "ok")
