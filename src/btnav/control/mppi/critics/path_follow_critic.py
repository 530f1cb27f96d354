"""PathFollowCritic: drives progress along the path (what moves the robot forward)."""

from __future__ import annotations

from pydantic import Field

from ....core import fmath
from ....plugins import register
from ..critic_data import CriticData
from ..critic_function import NAMESPACE, CriticFunction


@register("critic", NAMESPACE + "PathFollowCritic")
class PathFollowCritic(CriticFunction):
    """Distance from each rollout's end to a path point ahead of the furthest one reached.

    The target is `offset_from_furthest` points past the path point that the best
    rollout reaches, skipped forward past points in collision (up to the second-to-last).
    Off once the pruned path is shorter than `threshold_to_consider`, where GoalCritic
    takes over.
    """

    class Params(CriticFunction.Params):
        cost_weight: float = Field(5.0, ge=0.0)
        threshold_to_consider: float = Field(1.4, ge=0.0)
        offset_from_furthest: int = Field(6, ge=0)

    def score(self, data: CriticData) -> None:
        n = len(data.path)
        if (
            not self.enabled
            or n < 2
            or data.local_path_length() < self.params.threshold_to_consider
        ):
            return
        idx = min(data.furthest_reached_path_point() + self.params.offset_from_furthest, n - 1)
        valid = data.path_points_valid()
        # Nav2's loop stops short of the last two points (path_size - 1, with path_size
        # = points - 1): a blocked second-to-last target is kept, the end never checked
        while idx < n - 2 and not valid[idx]:
            idx += 1
        px, py = data.path[idx, 0], data.path[idx, 1]
        self.add(data, fmath.hypot(data.x[:, -1] - px, data.y[:, -1] - py))
