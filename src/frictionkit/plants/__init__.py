"""Physical axes driven against friction."""

from .ballscrew import ElasticBallScrew, RigidBallScrew
from .mass import Mass
from .rigid_body import RigidBody

__all__ = ["ElasticBallScrew", "Mass", "RigidBallScrew", "RigidBody"]
