"""Progress checkers (nav2_controller's): is the robot still getting somewhere?

`SimpleProgressChecker` keeps a baseline pose and the sim time it was taken; a
move farther than `required_movement_radius` from it takes a new baseline. If
`movement_time_allowance` seconds pass without such a move, `check` returns
False and the controller server fails FollowPath with FAILED_TO_MAKE_PROGRESS.
`PoseProgressChecker` also counts a rotation of `required_movement_angle` as progress.
Time is the caller's sim time: nothing here reads a clock.
"""

from __future__ import annotations

from pydantic import Field

from ..core.geometry import Pose2D, angle_diff
from ..params.schema import ParamsModel
from ..plugins import Plugin, register


class ProgressChecker(Plugin):
    """Base of every `progress_checker` plugin (nav2_core::ProgressChecker)."""

    class Params(ParamsModel):
        pass

    def __init__(self, name: str = "progress_checker", params: ParamsModel | None = None) -> None:
        super().__init__(name, params)

    def check(self, pose: Pose2D, now: float) -> bool:
        """True while the robot makes progress; `now` is sim time in seconds."""
        raise NotImplementedError

    def reset(self) -> None:
        """Forget the baseline (a new goal)."""


@register("progress_checker", "nav2_controller::SimpleProgressChecker")
class SimpleProgressChecker(ProgressChecker):
    class Params(ParamsModel):
        required_movement_radius: float = Field(0.5, ge=0.0)
        movement_time_allowance: float = Field(10.0, ge=0.0)

    params: Params

    def __init__(self, name: str = "progress_checker", params: ParamsModel | None = None) -> None:
        super().__init__(name, params)
        self.baseline_pose: Pose2D | None = None
        self.baseline_time = 0.0

    def check(self, pose: Pose2D, now: float) -> bool:
        if self.baseline_pose is None or self._moved_enough(pose):
            self.baseline_pose = pose
            self.baseline_time = float(now)
            return True
        return not (now - self.baseline_time > self.params.movement_time_allowance)

    def _moved_enough(self, pose: Pose2D) -> bool:
        assert self.baseline_pose is not None
        return pose.distance_to(self.baseline_pose) > self.params.required_movement_radius

    def reset(self) -> None:
        self.baseline_pose = None


@register("progress_checker", "nav2_controller::PoseProgressChecker")
class PoseProgressChecker(SimpleProgressChecker):
    class Params(SimpleProgressChecker.Params):
        required_movement_angle: float = Field(0.5, ge=0.0)

    params: Params

    def _moved_enough(self, pose: Pose2D) -> bool:
        assert self.baseline_pose is not None
        return super()._moved_enough(pose) or (
            abs(angle_diff(pose.yaw, self.baseline_pose.yaw)) > self.params.required_movement_angle
        )


__all__ = ["PoseProgressChecker", "ProgressChecker", "SimpleProgressChecker"]
