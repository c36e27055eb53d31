"""Identification of friction and rigid-body parameters from recordings."""

from .result import IdentificationResult, parameter_statistics
from .rigid_body import RigidBody, fit_rigid_body, rigid_body_regressors
from .static_map import MODELS as STATIC_MODELS
from .static_map import fit_static_map, fit_static_records, stribeck_model

__all__ = [
    "STATIC_MODELS",
    "IdentificationResult",
    "RigidBody",
    "fit_rigid_body",
    "fit_static_map",
    "fit_static_records",
    "parameter_statistics",
    "rigid_body_regressors",
    "stribeck_model",
]
