"""The controller plugin base (nav2_core::Controller, in Python spelling)."""

from __future__ import annotations

from typing import Any

import numpy as np

from ..core.geometry import Pose2D
from ..core.messages import Path, Twist
from ..costmap.costmap_2d import Costmap2D
from ..params.schema import ParamsModel
from ..plugins import Plugin


class Controller(Plugin):
    """Base of every `controller` plugin: follows a path on the local costmap.

    `compute_velocity_commands` gets the robot pose in the costmap's frame (odom for
    Nav2's rolling local costmap) and raises one of `control.exceptions` (Nav2's
    controller exceptions, each carrying FollowPath's error code) when it cannot.
    """

    class Params(ParamsModel):
        pass

    def set_plan(self, path: Path) -> None:
        """A new path to follow (Nav2's setPlan: a controller may reset its state)."""
        raise NotImplementedError

    def refresh_plan(self, path: Path) -> None:
        """The same path re-expressed in the costmap frame after `map -> odom` moved:
        a controller keeps its state (the default treats it as a new path)."""
        self.set_plan(path)

    def compute_velocity_commands(
        self, pose: Pose2D, velocity: Twist, costmap: Costmap2D, goal_checker: Any = None
    ) -> Twist:
        raise NotImplementedError

    def set_speed_limit(self, speed_limit: float, percentage: bool) -> None:
        """Nav2's speed limit (from a speed filter); 0 means no limit."""

    def reset(self) -> None:
        """Forget the state of the last path (a new goal is coming)."""

    def local_plan(self, pose: Pose2D) -> np.ndarray | None:
        """(N, 3) x, y, yaw in the costmap frame: what the controller means to drive next
        (Nav2's `local_plan` topic), for the live view, `run.gif` and the bag. None: no
        plan of its own, so the viewers draw the plan the controller server cut."""
        return None
