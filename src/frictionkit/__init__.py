"""frictionkit: model, identify, simulate and compensate friction in precision motion axes.

>>> import frictionkit as fk
>>> law = fk.Stribeck(Fc=1.0, Fs=1.5, vs=1e-3, delta=2.0, sigma2=0.4)
>>> gms = fk.GMS(law, k=[1e4, 1e5, 1e6], xi=[0.5, 0.3, 0.2], C=20.0)
"""

from .errors import DataError, FrictionKitError, IdentificationError, ParameterError, SimulationError
from .models import (
    GMS,
    CoulombViscous,
    Dahl,
    Directional,
    LuGre,
    Stribeck,
    coulomb_compensation,
    sigmoid_compensation,
    sinc_compensation,
)
from .plants import Mass
from .simulate import BatchResult, SimOptions, SimulationResult, simulate, simulate_batch

__version__ = "0.1.0"

__all__ = [
    "GMS",
    "CoulombViscous",
    "Dahl",
    "DataError",
    "Directional",
    "FrictionKitError",
    "IdentificationError",
    "LuGre",
    "Mass",
    "BatchResult",
    "SimOptions",
    "SimulationResult",
    "simulate",
    "simulate_batch",
    "ParameterError",
    "SimulationError",
    "Stribeck",
    "coulomb_compensation",
    "sigmoid_compensation",
    "sinc_compensation",
]
