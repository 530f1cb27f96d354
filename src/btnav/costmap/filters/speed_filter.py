"""nav2_costmap_2d::SpeedFilter: the speed limit of the zone the robot is in.

On each costmap update the filter reads the mask under the robot and turns the value
into a limit, `base + multiplier * value`: a percentage of the controller's maximum
speed (info type 1) or metres per second (type 2). Mask value 0 means no limit, so
driving out of a zone onto a 0 cell lifts the limit (NO_SPEED_LIMIT, 0.0); an unknown
cell, or a pose off the mask, keeps the last limit; a limit out of range (below 0, or
above 100 %) is no limit. Only a change is published, as a `SpeedLimit` to the
subscribers (the controller_server whose `speed_limit_topic` matches, through
`ControllerServer.set_speed_limit`).

The limit is as fresh as the costmap: a filter in Nav2's global_costmap (1 Hz) sees a
zone up to a second after the robot entered it, and the controller then needs its
deceleration to get under the limit.
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass

from pydantic import Field

from ...core.geometry import Pose2D
from ...params.schema import ignored
from ...plugins import register
from ..costmap_2d import Costmap2D
from ..layer import Window
from .costmap_filter import CostmapFilter
from .filter_info import (
    NO_SPEED_LIMIT,
    SPEED_FILTER_ABSOLUTE,
    SPEED_FILTER_PERCENT,
    SPEED_MASK_NO_LIMIT,
    SPEED_MASK_UNKNOWN,
)

_LOOKAHEAD = (
    "the speed filter's path lookahead is not implemented yet: the limit is the robot's cell's"
)


@dataclass(frozen=True)
class SpeedLimit:
    """nav2_msgs/SpeedLimit: `speed_limit` in % of the maximum speed (`percentage`) or m/s;
    NO_SPEED_LIMIT (0.0) lifts the limit."""

    speed_limit: float
    percentage: bool
    frame_id: str = "map"


@register("costmap_filter", "nav2_costmap_2d::SpeedFilter", aliases=("btnav/SpeedFilter",))
class SpeedFilter(CostmapFilter):
    """Speed zones: publishes the limit of the zone under the robot when it changes."""

    class Params(CostmapFilter.Params):
        speed_limit_topic: str = Field("speed_limit", min_length=1)
        enable_path_lookahead: bool = ignored(False, _LOOKAHEAD)
        max_decel: float = ignored(-0.5, _LOOKAHEAD)
        min_lookahead: float = ignored(0.3, _LOOKAHEAD)
        max_lookahead: float = ignored(5.0, _LOOKAHEAD)
        path_topic: str = ignored("plan", _LOOKAHEAD)
        odom_topic: str = ignored("odom", _LOOKAHEAD)

    info_types = (SPEED_FILTER_PERCENT, SPEED_FILTER_ABSOLUTE)

    def __init__(self, name: str, params: Params | None = None) -> None:
        super().__init__(name, params)
        self.params: SpeedFilter.Params
        self.percentage = False
        #: The limit of the last update (NO_SPEED_LIMIT: none), and the last one published.
        self.speed_limit = NO_SPEED_LIMIT
        self.speed_limit_prev = NO_SPEED_LIMIT
        self._subscribers: list[Callable[[SpeedLimit], None]] = []

    def subscribe(self, callback: Callable[[SpeedLimit], None]) -> None:
        """Call `callback(SpeedLimit)` on every change of the limit (the `speed_limit` topic)."""
        self._subscribers.append(callback)

    def on_filter_info(self) -> None:
        assert self.filter_info is not None
        self.percentage = self.filter_info.type == SPEED_FILTER_PERCENT

    def speed_limit_at(self, pose: Pose2D) -> float | None:
        """The limit at `pose` (Nav2's getSpeedLimitAtPose); None where the mask cannot say
        (off the mask, an unknown cell): the last limit holds."""
        if self.filter_mask is None or self.filter_info is None:
            return None
        data = self.mask_data_at(pose)
        if data is None or data == SPEED_MASK_UNKNOWN:
            return None
        if data == SPEED_MASK_NO_LIMIT:
            return NO_SPEED_LIMIT
        limit = float(self.filter_info.filter_value(data))
        if limit < 0.0 or (self.percentage and limit > 100.0):
            return NO_SPEED_LIMIT  # Nav2 warns and drops an impossible limit
        return limit

    def process(self, master: Costmap2D, window: Window, pose: Pose2D) -> None:
        limit = self.speed_limit_at(pose)
        if limit is None:
            return
        self.speed_limit = limit
        if limit == self.speed_limit_prev:
            return
        frame = self.layered.global_frame if self.layered is not None else "map"
        message = SpeedLimit(limit, self.percentage, frame)
        for callback in self._subscribers:
            callback(message)
        self.speed_limit_prev = limit
