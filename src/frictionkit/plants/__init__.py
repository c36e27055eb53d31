"""Physical axes driven against friction."""

from .ballscrew import ElasticBallScrew, RigidBallScrew
from .mass import Mass

__all__ = ["ElasticBallScrew", "Mass", "RigidBallScrew"]
