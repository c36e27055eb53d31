"""The machine core: any friction law at any site of a multi-body drive, in one compiled loop.

A :class:`Machine` holds degrees of freedom (translational or rotational), the rigid
transmissions between them (coordinates are linear combinations, :class:`Coord`), linear
springs and dampers, nonlinear compliances (:class:`HertzContact`,
:class:`PiecewiseLinearSpring`), position-dependent loads (:class:`SineLoad`), friction
sites holding any friction law, actuators, sensors and controller blocks (:class:`Sum`,
:class:`PID`, :class:`StateSpace`, :class:`Saturation`, :class:`FrictionFeedforward`).
:func:`simulate_machine` runs it in :mod:`frictionkit.kernels.machine`.
"""

from .elements import (PID, Coord, CoordSignal, FrictionFeedforward, Gain, HertzContact, NormalLoad, PiecewiseLinearSpring,
                       Saturation, SineLoad, StateSpace, Sum)
from .machine import Machine
from .simulate import MachineResult, discretise, simulate_machine

__all__ = [
    "Coord",
    "CoordSignal",
    "FrictionFeedforward",
    "Gain",
    "HertzContact",
    "Machine",
    "MachineResult",
    "NormalLoad",
    "PID",
    "PiecewiseLinearSpring",
    "Saturation",
    "SineLoad",
    "StateSpace",
    "Sum",
    "discretise",
    "simulate_machine",
]
