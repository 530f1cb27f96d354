"""nav2_costmap_2d::BinaryFilter: a boolean that flips while the robot is in a zone.

On each costmap update the filter reads the mask under the robot: where
`base + multiplier * value` is above `flip_threshold` the state is the opposite of
`default_state`, elsewhere (and off the mask) it is `default_state`; an unknown cell
changes nothing. Each change is published on `binary_state_topic` (std_msgs/Bool):
in btnav `binary_state` holds it and `subscribe(callback)` delivers it to any
component (a camera switched off, a beeper, a parameter changed in a zone).
"""

from __future__ import annotations

from collections.abc import Callable

from pydantic import Field

from ...core.geometry import Pose2D
from ...plugins import register
from ..costmap_2d import Costmap2D
from ..layer import Window
from .costmap_filter import CostmapFilter
from .filter_info import BINARY_FILTER, OCC_GRID_UNKNOWN


@register("costmap_filter", "nav2_costmap_2d::BinaryFilter", aliases=("btnav/BinaryFilter",))
class BinaryFilter(CostmapFilter):
    """A binary state from a mask, published on every flip."""

    class Params(CostmapFilter.Params):
        default_state: bool = False
        binary_state_topic: str = Field("binary_state", min_length=1)
        flip_threshold: float = 50.0

    info_types = (BINARY_FILTER,)

    def __init__(self, name: str, params: Params | None = None) -> None:
        super().__init__(name, params)
        self.params: BinaryFilter.Params
        self.binary_state = bool(self.params.default_state)
        self._subscribers: list[Callable[[bool], None]] = []

    def subscribe(self, callback: Callable[[bool], None]) -> None:
        """Call `callback(state)` on every change of state (the `binary_state_topic`)."""
        self._subscribers.append(callback)

    def change_state(self, state: bool) -> None:
        self.binary_state = bool(state)
        for callback in self._subscribers:
            callback(self.binary_state)

    def process(self, master: Costmap2D, window: Window, pose: Pose2D) -> None:
        if self.filter_mask is None or self.filter_info is None:
            return
        if self.mask_transform() is None:
            return
        default = bool(self.params.default_state)
        data = self.mask_data_at(pose)
        if data is None:  # off the mask: the default state (published again, as Nav2 does)
            self.change_state(default)
            return
        if data == OCC_GRID_UNKNOWN:
            return
        flipped = float(self.filter_info.filter_value(data)) > self.params.flip_threshold
        if flipped and self.binary_state == default:
            self.change_state(not default)
        elif not flipped and self.binary_state != default:
            self.change_state(default)
