"""MPPI's critics, one per file; importing this package registers them (kind `critic`)."""

from .constraint_critic import ConstraintCritic
from .cost_critic import CostCritic
from .goal_angle_critic import GoalAngleCritic
from .goal_critic import GoalCritic
from .obstacles_critic import ObstaclesCritic
from .path_align_critic import PathAlignCritic
from .path_angle_critic import PathAngleCritic
from .path_follow_critic import PathFollowCritic
from .prefer_forward_critic import PreferForwardCritic
from .twirling_critic import TwirlingCritic
from .velocity_deadband_critic import VelocityDeadbandCritic

__all__ = [
    "ConstraintCritic",
    "CostCritic",
    "GoalAngleCritic",
    "GoalCritic",
    "ObstaclesCritic",
    "PathAlignCritic",
    "PathAngleCritic",
    "PathFollowCritic",
    "PreferForwardCritic",
    "TwirlingCritic",
    "VelocityDeadbandCritic",
]
