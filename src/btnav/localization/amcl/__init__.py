"""nav2_amcl in numpy: the particle filter, motion and laser models, and the `amcl` localiser."""

from .amcl import Amcl
from .laser_models import BeamModel, LaserData, LikelihoodFieldModel, LikelihoodFieldModelProb
from .likelihood_field import MapField
from .motion_models import DifferentialMotionModel, OmniMotionModel
from .particle_filter import ParticleFilter

__all__ = [
    "Amcl",
    "BeamModel",
    "DifferentialMotionModel",
    "LaserData",
    "LikelihoodFieldModel",
    "LikelihoodFieldModelProb",
    "MapField",
    "OmniMotionModel",
    "ParticleFilter",
]
