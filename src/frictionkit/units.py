"""Unit conversions for the edges of the library (loaders, presets, reports). SI inside."""

from __future__ import annotations

import math

MM = 1e-3  # m per mm
UM = 1e-6  # m per µm
NM = 1e-9  # m per nm
RPM = 2.0 * math.pi / 60.0  # rad/s per rpm
DEG = math.pi / 180.0  # rad per degree
ARCSEC = math.pi / (180.0 * 3600.0)  # rad per arcsecond
N_PER_MM = 1e3  # (N/m) per (N/mm)
MM_PER_S = 1e-3  # (m/s) per (mm/s)
