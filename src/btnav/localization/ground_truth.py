"""The localiser contract and `ground_truth`, the perfect localiser, for tests.

Localisers publish `map -> odom`.

A localiser plugin (`@register("localizer", name)`) is built as `cls(context, params)`
and scheduled at its `rate` in the runtime's LOCALIZATION stage, before costmaps and
servers. `context` is anything shaped like `LocalizerContext` (the `Runtime` is), so
a localiser in `localization/` need not import the runtime. `params` is None for the
defaults, a mapping validated by the plugin's `Params`, or a `Params` instance.
"""

from __future__ import annotations

from collections.abc import Mapping
from typing import Any, Protocol

from pydantic import Field

from ..core.clock import SimClock
from ..core.frames import FrameTree
from ..core.messages import LaserScan, Odometry, PoseWithCovariance
from ..core.validation import StrictModel
from ..plugins import register
from ..sim.world import World


class LocalizerContext(Protocol):
    """What a localiser may use: the frame tree, the clock and the latest sensor data.

    Only `ground_truth` may read `world.robot_pose`; a real localiser knows the world
    only through scans, odometry and the map.
    """

    world: World
    frames: FrameTree
    clock: SimClock
    seed: int
    latest_odom: Odometry
    latest_scan: LaserScan | None

    def subscribe(self, topic: str, callback: Any) -> None: ...


class GroundTruthParams(StrictModel):
    rate: float = Field(50.0, gt=0, description="map -> odom updates per second of sim time")
    global_frame_id: str = "map"
    odom_frame_id: str = "odom"
    base_frame_id: str = "base_footprint"


def _params(cls: type[StrictModel], params: Any) -> Any:
    if params is None:
        return cls()
    if isinstance(params, cls):
        return params
    if isinstance(params, Mapping):
        return cls(**params)
    raise TypeError(f"params for a localiser are a mapping or {cls.__name__}, got {params!r}")


@register("localizer", "ground_truth")
class GroundTruthLocalizer:
    """Publishes `map -> odom` so that `map -> base_footprint` is the world's true pose.

    `map -> odom` is corrected on every odometry message, before the sensors of the same
    step measure, so a scan is placed where the robot truly was whatever the odometry's
    drift (corrected only at `rate`, a scan would be placed with up to one period of
    odometry noise, enough to wipe a wall seen at a grazing angle out of the global
    costmap). `rate` is how often `pose` (amcl_pose) is published.
    """

    Params = GroundTruthParams

    def __init__(self, context: LocalizerContext, params: Any = None) -> None:
        self.params = _params(self.Params, params)
        self.context = context
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
