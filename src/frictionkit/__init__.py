"""frictionkit: model, identify, simulate and compensate friction in precision motion axes.

>>> import frictionkit as fk
>>> law = fk.Stribeck(Fc=1.0, Fs=1.5, vs=1e-3, delta=2.0, sigma2=0.4)
>>> gms = fk.GMS(law, k=[1e4, 1e5, 1e6], xi=[0.5, 0.3, 0.2], C=20.0)

Sub-packages: ``frictionkit.control`` (controllers, compensators, zero-speed
analysis), ``frictionkit.simulation.reference`` (solve_ivp twins),
``frictionkit.reproduce`` (paper reproductions). ``fk.simulate`` is the function; the
sub-package that holds it is ``frictionkit.simulation`` (one name each).
"""

from .errors import DataError, FrictionKitError, IdentificationError, ParameterError, SimulationError
from .models import (
    GMS,
    CoulombViscous,
    Dahl,
    Directional,
    LuGre,
    Stribeck,
    TDMSSC,
    coulomb_compensation,
    sigmoid_compensation,
    sinc_compensation,
)
from .data import (
    Recording,
    decimate,
    derivative,
    find_cycles,
    find_plateaus,
    find_reversals,
    load_csv,
    load_groups,
    load_recording,
    lowpass,
)
from .identify import (
    IdentificationResult,
    fit_output_error,
    fit_presliding,
    fit_rigid_body,
    fit_static_map,
    fit_static_records,
    stribeck_model,
)
from .plants import ElasticBallScrew, Mass, RigidBallScrew, RigidBody
from .machines import Machine, MachineResult, simulate_machine
from .simulation import BatchResult, SimOptions, SimulationResult, simulate, simulate_batch
from .models.files import ModelFile, load_model, save_model

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
    "Machine",
    "MachineResult",
    "simulate_machine",
    "ElasticBallScrew",
    "RigidBallScrew",
    "Recording",
    "IdentificationResult",
    "RigidBody",
    "decimate",
    "derivative",
    "find_cycles",
    "find_plateaus",
    "find_reversals",
    "fit_output_error",
    "fit_presliding",
    "fit_rigid_body",
    "fit_static_map",
    "fit_static_records",
    "load_csv",
    "load_groups",
    "load_recording",
    "lowpass",
    "stribeck_model",
    "BatchResult",
    "SimOptions",
    "SimulationResult",
    "simulate",
    "simulate_batch",
    "ModelFile",
    "load_model",
    "save_model",
    "ParameterError",
    "SimulationError",
    "Stribeck",
    "TDMSSC",
    "coulomb_compensation",
    "sigmoid_compensation",
    "sinc_compensation",
]
