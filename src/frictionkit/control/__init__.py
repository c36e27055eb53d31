"""Controllers, trajectories and zero-speed compensation (seed 001 §2.2-§5)."""

from .compensators import RollingCompensator
from .dob import DisturbanceObserver
from .loop import ClosedLoopResult, Sensors, TwoDofController, simulate_closed_loop
from .pid import PID
from .ptc import PerfectTrackingControl
from .trajectories import Reference, cosine_reference, mixed_reference, piecewise_reference, zero_speed_reference
from .zero_speed import (
    TABLE2,
    Crossing,
    DeformationRatio,
    Selection,
    classify_crossings,
    deformation_ratio,
    find_crossings,
    max_ratio_before_zero,
    min_ratio_before_zero,
    select_compensators,
)

__all__ = [
    "TABLE2",
    "ClosedLoopResult",
    "Crossing",
    "DeformationRatio",
    "DisturbanceObserver",
    "PID",
    "PerfectTrackingControl",
    "Reference",
    "RollingCompensator",
    "Selection",
    "Sensors",
    "TwoDofController",
    "classify_crossings",
    "cosine_reference",
    "deformation_ratio",
    "find_crossings",
    "max_ratio_before_zero",
    "min_ratio_before_zero",
    "mixed_reference",
    "piecewise_reference",
    "select_compensators",
    "simulate_closed_loop",
    "zero_speed_reference",
]
