"""The critic plugin base (dwb_core::TrajectoryCritic), scoring all trajectories at once."""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any, ClassVar

import numpy as np
from numpy.typing import NDArray

from ...core.geometry import Pose2D
from ...core.messages import Twist
from ...costmap.costmap_2d import Costmap2D
from ...params.schema import ParamsModel


@dataclass
class Trajectories:
    """S simulated trajectories: `velocity` (S, 3) commanded (vx, vy, wz), `poses` (S, T, 3), `dt` per step."""

    velocity: NDArray[np.float64]
    poses: NDArray[np.float64]
    dt: float

    def __len__(self) -> int:
        return int(self.velocity.shape[0])


class TrajectoryCritic:
    """Base of every `critic` plugin. `score` returns (S,) raw scores; inf marks an illegal trajectory.

    The planner multiplies each score by `get_scale()` (the `<Critic>.scale` param) and sums.
    `planner` is the owning DWBLocalPlanner's params (critics read shared keys such as
    xy_goal_tolerance from it, as Nav2's read `<plugin>.xy_goal_tolerance`).
    """

    class Params(ParamsModel):
        scale: float = 1.0

    plugin_kind: ClassVar[str]
    plugin_name: ClassVar[str]

    def __init__(
        self, name: str, params: ParamsModel | None = None, planner: object = None
    ) -> None:
        self.name = name
        self.params = params if params is not None else self.Params()
        self.planner = planner

    #: The local costmap server (Nav2's costmap_ros_), once the planner is configured.
    costmap_ros: Any = None

    def configure(self, costmap_ros: Any) -> None:
        """Nav2's initialize(): the costmap server whose footprint a critic may read."""
        self.costmap_ros = costmap_ros

    def prepare(
        self,
        pose: Pose2D,
        velocity: Twist,
        goal: Pose2D,
        plan: NDArray[np.float64],
        costmap: Costmap2D,
    ) -> bool:
        """Per-cycle setup; False means the critic cannot score this cycle (the planner fails)."""
        return True

    def score(self, trajs: Trajectories, costmap: Costmap2D) -> NDArray[np.float64]:
        raise NotImplementedError

    def get_scale(self, costmap: Costmap2D) -> float:
        return float(self.params.scale)

    def debrief(self, cmd: Twist, pose: Pose2D) -> None:
        """Told the command that was chosen (Oscillation tracks it)."""

    def reset(self) -> None:
        """A new plan: forget state."""
