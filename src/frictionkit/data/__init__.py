"""Recordings of motion axes: validated containers, file loaders, filters, segmentation."""

from .loaders import load_csv, load_groups, load_recording, read_table
from .recording import IrregularSamplingWarning, Recording
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
    "SteadyStatePoints",
    "decimate",
    "derivative",
    "find_cycles",
    "find_plateaus",
    "find_reversals",
    "load_csv",
    "load_groups",
    "load_recording",
    "lowpass",
    "read_table",
    "steady_state_points",
]
