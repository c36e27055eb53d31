"""Recordings of motion axes: validated containers, file loaders, filters, segmentation."""

from .loaders import ShortRowWarning, load_csv, load_groups, load_recording, read_table
from .recording import IrregularSamplingWarning, Recording
from .rests import find_rests, motion_segments
from .segmentation import (
    Segment,
    SteadyStatePoints,
    find_cycles,
    find_plateaus,
    find_reversals,
    steady_state_points,
)
from .signals import decimate, derivative, lowpass

__all__ = [
    "IrregularSamplingWarning",
    "Recording",
    "Segment",
    "ShortRowWarning",
    "SteadyStatePoints",
    "decimate",
    "derivative",
    "find_cycles",
    "find_plateaus",
    "find_reversals",
    "find_rests",
    "load_csv",
    "load_groups",
    "load_recording",
    "lowpass",
    "motion_segments",
    "read_table",
    "steady_state_points",
]
