"""Physical axes driven against friction."""

from .mass import Mass

__all__ = ["Mass"]
