"""Identification of friction and rigid-body parameters from recordings."""

from .motion_data import evaluate_motion, motion_data
from .motion_error import fit_motion_error, motion_start
from .fit_options import MOTION_ERROR_FIT, OUTPUT_ERROR_FIT, FitOptions
from .emps_dynamic import emps_closed_loop, emps_closed_loop_errors, emps_compare, emps_stribeck_fit
from .output_error import OUTPUT_ERROR_OPTIONS, fit_output_error, initial_guess_lugre
from .presliding import fit_presliding, piecewise_linear_fit
from .reversal import fit_reversal
from .result import IdentificationResult, parameter_statistics
from ..plants.rigid_body import RigidBody  # re-exported: the plant fit_rigid_body identifies
from .rigid_body import fit_rigid_body, rigid_body_regressors
from .static_map import MODELS as STATIC_MODELS
from .static_map import fit_static_map, fit_static_records, stribeck_model
from .two_step import ConstantVelocityScreen, TwoStepResult, fit_two_step, screen_constant_velocity

__all__ = [
    "FitOptions",
    "MOTION_ERROR_FIT",
    "OUTPUT_ERROR_FIT",
    "OUTPUT_ERROR_OPTIONS",
    "STATIC_MODELS",
    "emps_closed_loop",
    "emps_closed_loop_errors",
    "emps_compare",
    "emps_stribeck_fit",
    "evaluate_motion",
    "fit_motion_error",
    "fit_output_error",
    "fit_presliding",
    "fit_reversal",
    "initial_guess_lugre",
    "motion_data",
    "motion_start",
    "piecewise_linear_fit",
    "IdentificationResult",
    "RigidBody",
    "TwoStepResult",
    "fit_two_step",
    "ConstantVelocityScreen",
    "screen_constant_velocity",
    "fit_rigid_body",
    "fit_static_map",
    "fit_static_records",
    "parameter_statistics",
    "rigid_body_regressors",
    "stribeck_model",
]
