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


class FrictionKitDeprecationWarning(DeprecationWarning):
    """A name that still works for one release but has a new spelling (the message names it)."""


def warn_renamed(owner: str, old: str, new: str, *, stacklevel: int = 3) -> None:
    """Warn that ``owner.old`` is now ``owner.new`` (kept for one release)."""
    import warnings

    warnings.warn(f"{owner}.{old} is deprecated: use {owner}.{new} (the old name goes in the next release)",
                  FrictionKitDeprecationWarning, stacklevel=stacklevel)
