"""A costmap as a runtime component: Nav2's global_costmap / local_costmap nodes.

`CostmapServer(runtime, costmap_ros)` feeds the `CostmapROS` every scan the runtime
publishes (placed with the frame tree at the time the scan arrives, as a tf2
message filter would) and updates it at its `update_frequency` in the COSTMAP
stage, so the servers of the same step see a fresh costmap. The global costmap
lives in `map`, the local one rolls with the robot in `odom`; both come from their
params sections as they are. It also offers Nav2's clear-costmap services under
their Nav2 names (`clear_entirely_local_costmap`, ...).
"""

from __future__ import annotations

from collections.abc import Callable
from typing import Any

from ..core.messages import LaserScan
from ..costmap.costmap_ros import CostmapROS
from ..params.paramsfile import ServerParams
from .runtime import Runtime, Stage


class CostmapServer:
    """Schedules a `CostmapROS` on the runtime at its `update_frequency`."""

    stage = Stage.COSTMAP

    def __init__(self, runtime: Runtime, costmap_ros: CostmapROS) -> None:
        self.runtime = runtime
        self.costmap_ros = costmap_ros
        self.name = costmap_ros.name
        self._scans: list[LaserScan] = []
        runtime.subscribe("scan", self._on_scan)
        # The first update now, so a plan requested at t = 0 has a costmap to plan on.
        costmap_ros.update(frame_tree=runtime.frames, now=runtime.now, force=True)

    # -- the component --------------------------------------------------------------------

    @property
    def rate(self) -> float:
        return float(self.costmap_ros.params.update_frequency)

    @property
    def costmap(self) -> Any:
        """The master `Costmap2D` planners and controllers read."""
        return self.costmap_ros.costmap

    @property
    def global_frame(self) -> str:
        return self.costmap_ros.global_frame

    @property
    def robot_base_frame(self) -> str:
        return self.costmap_ros.robot_base_frame

    def _on_scan(self, scan: LaserScan) -> None:
        self.costmap_ros.receive_scan(scan, self.runtime.frames)

    def update(self, now: float) -> None:
        self.costmap_ros.update(frame_tree=self.runtime.frames, now=now, force=True)

    # -- services (nav2_costmap_2d ClearCostmapService) -----------------------------------

    def services(self) -> dict[str, Callable[..., None]]:
        """Nav2's service names (as a BT node's `service_name` spells them) -> the
        costmap's own clear methods."""
        n, ros = self.name, self.costmap_ros
        return {
            f"{n}/clear_entirely_{n}": ros.clear_entirely,
            f"{n}/clear_around_{n}": ros.clear_around_robot,
            f"{n}/clear_except_{n}": ros.clear_except_region,
        }

    # -- dynamic parameters ---------------------------------------------------------------

    def set_parameters(self, params: ServerParams) -> None:
        """Apply params `validate_update` accepted; a new update_frequency reschedules."""
        old_rate = self.rate
        self.costmap_ros.set_parameters(params)
        if self.rate != old_rate:
            self.runtime.remove(self)
            self.runtime.add(self)

    def __repr__(self) -> str:
        return f"CostmapServer({self.name!r}, {self.rate:g} Hz, frame={self.global_frame!r})"
