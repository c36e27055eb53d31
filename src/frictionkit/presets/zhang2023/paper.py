"""Seed 000 (Zhang et al. 2023) Tables 2-8 in SI, every correction recorded next to the value."""

from __future__ import annotations

import math
from types import MappingProxyType

import numpy as np

from ...errors import ParameterError
from ...models.gms import GMS
from ...models.static import Directional, Stribeck
from ...units import MM, UM

# =========================================================================== paper values

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


