"""nav2_msgs' route interfaces: ComputeRoute and ComputeAndTrackRoute, Route, RouteNode,
RouteEdge (the two actions' error codes, the 400s, are in `core.error_codes` with the
others).

Kept beside `core.nav2_msgs` (not in it) as nav2_msgs keeps them in their own files: a
tree node builds its goal from here and never imports the route server.
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

from .messages import Path
from .nav2_msgs import PoseLike


@dataclass(frozen=True)
class RouteNode:
    """nav2_msgs/RouteNode: a node's id and position in the route's frame."""

    nodeid: int
    x: float
    y: float


@dataclass(frozen=True)
class RouteEdge:
    """nav2_msgs/RouteEdge: an edge's id and its two ends."""

    edgeid: int
    start: tuple[float, float]
    end: tuple[float, float]


@dataclass(frozen=True)
class Route:
    """nav2_msgs/Route: the ordered nodes and the edges that join them (one fewer)."""

    stamp: float = 0.0
    frame_id: str = "map"
    route_cost: float = 0.0
    nodes: tuple[RouteNode, ...] = ()
    edges: tuple[RouteEdge, ...] = ()

    def polyline(self) -> np.ndarray:
        """The nodes' positions, (N, 2): the route as a line to follow."""
        return np.array([(n.x, n.y) for n in self.nodes], dtype=float).reshape(-1, 2)


@dataclass
class ComputeRouteGoal:
    """Start and goal by node id, or by pose (`use_poses`); the start is the robot's pose
    unless `use_start`."""

    start_id: int = 0
    goal_id: int = 0
    start: PoseLike | None = None
    goal: PoseLike | None = None
    use_start: bool = False
    use_poses: bool = False


@dataclass
class ComputeAndTrackRouteGoal(ComputeRouteGoal):
    """The same request; the server then tracks the robot along the route until it ends."""


@dataclass(frozen=True)
class ComputeRouteResult:
    """The sparse route, its dense path and the planning time (sim seconds: 0)."""

    route: Route
    path: Path
    planning_time: float = 0.0


@dataclass(frozen=True)
class ComputeAndTrackRouteResult:
    execution_duration: float = 0.0


@dataclass(frozen=True)
class ComputeAndTrackRouteFeedback:
    """Published on each change of the tracking state (a node passed, an operation run,
    a reroute), as Nav2's route tracker publishes it."""

    last_node_id: int = 0
    next_node_id: int = 0
    current_edge_id: int = 0
    route: Route = field(default_factory=Route)
    path: Path | None = None
    operations_triggered: tuple[str, ...] = ()
    rerouted: bool = False
