"""GoalOrientationScorer and StartPoseOrientationScorer: how far an edge's heading is from
the goal pose's (for the edge reaching the goal node) or the start pose's (for the edge
leaving the start node); with `use_orientation_threshold`, an edge beyond
`orientation_tolerance` is refused instead, so the route leaves or arrives facing the
requested way. Both need a request by poses."""

from __future__ import annotations

import math

from pydantic import Field

from ...core import fmath
from ...core.geometry import Pose2D
from ...plugins import register
from ..edge_scorer import EdgeCostFunction
from ..exceptions import InvalidEdgeScorerUse
from ..graph import DirectionalEdge, EdgeType, RouteRequest


def _angle_between(a: float, b: float) -> float:
    d = (b - a) % (2.0 * math.pi)
    return abs(d - 2.0 * math.pi if d > math.pi else d)


class _OrientationScorer(EdgeCostFunction):
    EDGE_TYPE = EdgeType.NONE
    WHICH = ""

    class Params(EdgeCostFunction.Params):
        orientation_tolerance: float = Field(math.pi / 2.0, ge=0.0)
        orientation_weight: float = 1.0
        use_orientation_threshold: bool = False

    def _pose(self, request: RouteRequest) -> Pose2D:
        raise NotImplementedError

    def score(
        self, edge: DirectionalEdge, request: RouteRequest, edge_type: EdgeType
    ) -> float | None:
        if not request.use_poses:
            raise InvalidEdgeScorerUse(
                f"Cannot use {type(self).__name__} without the {self.WHICH} pose specified"
            )
        if edge_type != self.EDGE_TYPE:
            return 0.0
        heading = float(fmath.arctan2(edge.end.y - edge.start.y, edge.end.x - edge.start.x))
        d_yaw = _angle_between(heading, self._pose(request).yaw)
        if self.params.use_orientation_threshold and d_yaw > self.params.orientation_tolerance:
            return None
        return self.params.orientation_weight * d_yaw


@register("edge_cost_function", "nav2_route::GoalOrientationScorer")
class GoalOrientationScorer(_OrientationScorer):
    EDGE_TYPE = EdgeType.END
    WHICH = "goal"

    def _pose(self, request: RouteRequest) -> Pose2D:
        return request.goal_pose


@register("edge_cost_function", "nav2_route::StartPoseOrientationScorer")
class StartPoseOrientationScorer(_OrientationScorer):
    EDGE_TYPE = EdgeType.START
    WHICH = "start"

    def _pose(self, request: RouteRequest) -> Pose2D:
        return request.start_pose
