"""The route's CollisionMonitor: looks `max_collision_dist` metres ahead along the route
(from the robot's closest point on its edge) on a costmap, at `rate` Hz; a cell at
`max_cost` or above (unknown excepted) blocks the edge it is on, and the route is
computed again around that edge (or tracking fails, without `reroute_on_collision`).

Not Nav2's collision_monitor node (which gates cmd_vel): this one judges the route.
Route points are taken into the costmap's frame (the local costmap is in `odom`).
"""

from __future__ import annotations

import math
from typing import Any

import numpy as np
from pydantic import Field

from ...core import fmath
from ...core.geometry import Pose2D
from ...costmap.cost_values import NO_INFORMATION
from ...params.schema import ParamsModel
from ...plugins import register
from ..context import CostmapView
from ..exceptions import OperationFailed
from ..graph import DirectionalEdge, Node, Route, closest_point
from ..line_cells import line_cells
from ..route_operation import OperationResult, RouteOperation, RouteOperationType


@register("route_operation", "nav2_route::CollisionMonitor")
class CollisionMonitor(RouteOperation):
    class Params(ParamsModel):
        costmap_topic: str = "local_costmap/costmap_raw"
        rate: float = Field(1.0, gt=0.0)
        reroute_on_collision: bool = True
        max_cost: float = Field(253.0, gt=0.0, le=255.0)
        check_resolution: int = Field(1, ge=1)
        max_collision_dist: float = Field(
            5.0, description="m ahead to check; <= 0: the whole route"
        )

    process_type = RouteOperationType.ON_QUERY

    def __init__(self, name: str, params: Any = None) -> None:
        super().__init__(name, params)
        self.last_check_time = 0.0

    def configure(self, context: Any) -> None:
        super().configure(context)
        self.last_check_time = context.now()

    def perform(
        self,
        node: Node | None,
        edge_entered: DirectionalEdge | None,
        edge_exited: DirectionalEdge | None,
        route: Route,
        pose: Pose2D,
        metadata: dict[str, Any] | None = None,
    ) -> OperationResult:
        assert self.context is not None
        now = self.context.now()
        if now - self.last_check_time < 1.0 / self.params.rate - 1e-9 or edge_entered is None:
            return OperationResult()
        self.last_check_time = now
        view = self.context.costmap(self.params.costmap_topic)
        if view is None:
            raise OperationFailed(
                f"Collision Monitor could not obtain a costmap from topic: {self.params.costmap_topic}"
            )
        blocked = self._first_blocked_edge(view, edge_entered, route, pose)
        if blocked is None:
            return OperationResult()
        if self.params.reroute_on_collision:
            return OperationResult(reroute=True, blocked_ids=[blocked])
        raise OperationFailed(
            "Collision detected, but rerouting is not enabled, canceling tracking task."
        )

    def _first_blocked_edge(
        self, view: CostmapView, edge: DirectionalEdge, route: Route, pose: Pose2D
    ) -> int | None:
        """The id of the first edge ahead with a blocking cell within reach, or None."""
        reach = self.params.max_collision_dist
        if reach <= 0.0:
            reach = math.inf
        ahead = [edge]
        ids = [e.edgeid for e in route.edges]
        if edge.edgeid in ids:
            ahead += route.edges[ids.index(edge.edgeid) + 1 :]
        start = closest_point(pose.x, pose.y, edge.start, edge.end)
        checked = 0.0
        for e in ahead:
            end = (e.end.x, e.end.y)
            length = fmath.hypot(end[0] - start[0], end[1] - start[1])
            last = checked + length >= reach
            if last and length > 1e-6:
                t = (reach - checked) / length
                end = (start[0] + (end[0] - start[0]) * t, start[1] + (end[1] - start[1]) * t)
            if self._in_collision(view, start, end):
                return e.edgeid
            if last:
                return None
            checked += length
            start = end
        return None

    def _in_collision(
        self, view: CostmapView, a: tuple[float, float], b: tuple[float, float]
    ) -> bool:
        """Along a -> b, the part on the costmap (the line stops where it leaves the map)."""
        cells, inside = view.cells([a, b])
        if not inside[0]:
            return False
        mx, my = line_cells(int(cells[0, 0]), int(cells[0, 1]), int(cells[1, 0]), int(cells[1, 1]))
        cm = view.costmap
        on = (mx >= 0) & (mx < cm.size_x) & (my >= 0) & (my < cm.size_y)
        stop = len(on) if on.all() else int(np.argmin(on))
        costs = cm.costs[
            my[: stop : self.params.check_resolution], mx[: stop : self.params.check_resolution]
        ]
        return bool(((costs >= self.params.max_cost) & (costs != NO_INFORMATION)).any())
