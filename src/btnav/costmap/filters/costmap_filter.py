"""The costmap filter plugin base (nav2_costmap_2d::CostmapFilter).

A filter is a layer the LayeredCostmap runs after its layers, on the master grid the
layers made (so no layer ever sees what a filter wrote): `update_bounds` records the
robot pose (and may grow the window), `update_costs` calls `process` when the filter
is enabled. What a filter applies comes from two servers Nav2's launch brings up
beside the costmaps: a costmap_filter_info_server (`set_filter_info`: the mask topic,
the filter type, `base` and `multiplier`) and a map_server serving the mask
(`set_mask`). The navigation stack connects them by topic name
(`nav.costmap_filter_servers`); a user's filter is a subclass that implements `process`.
"""

from __future__ import annotations

from typing import ClassVar

from pydantic import Field

from ...core.geometry import Pose2D
from ...maps.occupancy_grid import OccupancyGrid
from ...params.schema import Why, ignored
from ..costmap_2d import Costmap2D
from ..layer import Bounds, Layer, Window
from .filter_info import CostmapFilterInfo


class CostmapFilter(Layer):
    """Base of every `costmap_filter` plugin: the enabled switch, the filter info and the mask."""

    class Params(Layer.Params):
        filter_info_topic: str = Field(
            min_length=1, description="the topic of the costmap_filter_info_server to read"
        )
        transform_tolerance: float = ignored(0.1, Why.TF, ge=0.0)

    #: The CostmapFilterInfo types this filter accepts (empty: any, as Nav2's keepout filter).
    info_types: ClassVar[tuple[int, ...]] = ()

    def __init__(self, name: str, params: Params | None = None) -> None:
        super().__init__(name, params)
        self.params: CostmapFilter.Params
        self._enabled = bool(self.params.enabled)
        self.filter_info: CostmapFilterInfo | None = None
        self.filter_mask: OccupancyGrid | None = None
        self.latest_pose: Pose2D | None = None

    # -- the enabled switch: the param, or Nav2's `<filter>/toggle_filter` service ----------

    @property
    def enabled(self) -> bool:
        return self._enabled

    def toggle(self, enabled: bool) -> None:
        """Nav2's `toggle_filter` service (std_srvs/SetBool): on or off until the next toggle."""
        self._enabled = bool(enabled)

    def on_params_changed(self) -> None:
        self._enabled = bool(self.params.enabled)

    # -- what the servers deliver ---------------------------------------------------------

    def accepts(self, info: CostmapFilterInfo) -> bool:
        """Whether this filter reads masks of `info.type` (Nav2 drops other infos)."""
        return not self.info_types or info.type in self.info_types

    def set_filter_info(self, info: CostmapFilterInfo) -> bool:
        """The info server's latched message (Nav2's filterInfoCallback); False if refused."""
        if not self.accepts(info):
            return False
        self.filter_info = info
        self.filter_mask = None  # a new info means a new mask subscription
        self.on_filter_info()
        return True

    def on_filter_info(self) -> None:
        """React to a new filter info (a speed filter takes its percentage flag)."""

    def set_mask(self, mask: OccupancyGrid) -> None:
        """A mask from the mask server's latched topic (Nav2's maskCallback)."""
        self.filter_mask = mask
        self.on_mask()

    def on_mask(self) -> None:
        """React to a new mask (the keepout filter repaints its whole extent)."""

    @property
    def is_active(self) -> bool:
        """Whether a mask has arrived (Nav2's isActive)."""
        return self.filter_mask is not None

    # -- the two passes ---------------------------------------------------------------------

    def update_bounds(self, robot: Pose2D, bounds: Bounds) -> None:
        if self.enabled:
            self.latest_pose = robot

    def update_costs(self, master: Costmap2D, window: Window) -> None:
        if not self.enabled or self.latest_pose is None:
            return
        self.process(master, window, self.latest_pose)
        self.current = True

    def process(self, master: Costmap2D, window: Window, pose: Pose2D) -> None:
        """Apply the mask: write costs into `master` in `window`, or act on the robot's `pose`."""
        raise NotImplementedError

    def reset(self) -> None:
        # Nav2 re-subscribes; the latched info and mask come again, so only the update is owed.
        self.current = False
        if self.filter_mask is not None:
            self.on_mask()

    def is_clearable(self) -> bool:
        return False

    # -- the mask at a point ----------------------------------------------------------------

    def mask_transform(self) -> Pose2D | None:
        """The costmap's global frame in the mask's frame (maps costmap points into the
        mask); None when the frame tree cannot say (Nav2 skips the update then)."""
        assert self.filter_mask is not None and self.layered is not None
        mask_frame, global_frame = self.filter_mask.frame_id, self.layered.global_frame
        if mask_frame == global_frame:
            return Pose2D()
        tree = self.layered.frame_tree
        if tree is None or not (tree.has(mask_frame) and tree.has(global_frame)):
            return None
        return tree.lookup(mask_frame, global_frame)

    def mask_data_at(self, pose: Pose2D) -> int | None:
        """The mask value under the robot's position; None off the mask or without a
        transform (Nav2's transformPose + worldToMap + getMaskData)."""
        tf = self.mask_transform()
        if tf is None or self.filter_mask is None:
            return None
        mask = self.filter_mask
        rc = mask.world_to_cell(tf.transform_points([[pose.x, pose.y]]))[0]
        if not bool(mask.in_bounds(rc)):
            return None
        return int(mask.data[rc[0], rc[1]])
