"""DWB (dwb_core / dwb_plugins / dwb_critics): sample velocities, simulate, score with critics.

Everything is vectorised over the sampled trajectories: a trajectory set is one
(S, T, 3) array of poses, and every critic scores all S at once (inf = illegal).
"""

from .critic import Trajectories, TrajectoryCritic
from .local_planner import DWBLocalPlanner

__all__ = ["DWBLocalPlanner", "Trajectories", "TrajectoryCritic"]
