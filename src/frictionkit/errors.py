"""Exceptions raised by frictionkit.

Each is also a built-in exception, so ``except ValueError`` keeps working for
callers that do not know frictionkit.
"""

from __future__ import annotations


class FrictionKitError(Exception):
    """Base class of every error frictionkit raises on purpose."""


class ParameterError(FrictionKitError, ValueError):
    """A parameter value breaks its rule (NaN, negative stiffness, ``vs <= 0`` ...)."""


class DataError(FrictionKitError, ValueError):
    """Input data (arrays, files, columns) cannot be used as given."""


class SimulationError(FrictionKitError, RuntimeError):
    """A simulation could not be carried out."""


class IdentificationError(FrictionKitError, RuntimeError):
    """An identification could not produce a trustworthy result."""
