"""`ground_truth`, the perfect localiser, for tests (the contract: `localizer.py`)."""

from __future__ import annotations

from typing import Any

from pydantic import Field

from ..core.messages import Odometry, PoseWithCovariance
from ..core.validation import StrictModel
from ..plugins import register
from .localizer import Localizer, LocalizerContext


class GroundTruthParams(StrictModel):
    rate: float = Field(50.0, gt=0, description="map -> odom updates per second of sim time")
    global_frame_id: str = "map"
    odom_frame_id: str = "odom"
    base_frame_id: str = "base_footprint"


@register("localizer", "ground_truth")
class GroundTruthLocalizer(Localizer):
    """Publishes `map -> odom` so that `map -> base_footprint` is the world's true pose.

    `map -> odom` is corrected on every odometry message, before the sensors of the same
    step measure, so a scan is placed where the robot truly was whatever the odometry's
    drift (corrected only at `rate`, a scan would be placed with up to one period of
    odometry noise, enough to wipe a wall seen at a grazing angle out of the global
    costmap). `rate` is how often `pose` (amcl_pose) is published.
    """

    Params = GroundTruthParams

    def __init__(self, name: str = "ground_truth", params: Any = None) -> None:
        super().__init__(name, params)

    def configure(self, context: LocalizerContext) -> None:  # type: ignore[override]
        super().configure(context)
        self.rate = self.params.rate
        frames = context.frames
        for frame in (
            self.params.global_frame_id,
            self.params.odom_frame_id,
            self.params.base_frame_id,
        ):
            frames.require(frame, key=f"ground_truth.{frame}")
        self.pose = PoseWithCovariance(
            context.clock.now,
            frames.lookup(self.params.global_frame_id, self.params.base_frame_id),
            frame_id=self.params.global_frame_id,
        )
        context.subscribe("odom", self._on_odom)

    def _on_odom(self, odom: Odometry) -> None:
        p = self.params
        true_pose = self.context.world.robot_pose  # base_footprint in the world (= map)
        odom_t_base = self.context.frames.lookup(p.odom_frame_id, p.base_frame_id)
        map_t_odom = true_pose @ odom_t_base.inverse()
        self.context.frames.set_transform(
            p.global_frame_id, p.odom_frame_id, map_t_odom, odom.stamp
        )

    def update(self, now: float) -> PoseWithCovariance:
        self.pose = PoseWithCovariance(
            now, self.context.world.robot_pose, frame_id=self.params.global_frame_id
        )
        return self.pose
