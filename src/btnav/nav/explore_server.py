"""explore: which frontier to visit next, as explore_lite decides it, offered as two services.

explore_lite is a node of its own that searches frontiers on a timer and sends
NavigateToPose goals. btnav keeps its decisions and gives the driving to a behaviour
tree (`trees/explore.yaml`), which calls `explore/compute_frontiers` each tick and
`explore/blacklist_frontier` when a goal fails. The search runs again when the goal
is reached, blacklisted or gone (no frontier cell left within `GOAL_KEPT_WITHIN` of
it), and at least every `1 / planner_frequency` seconds; in between the same goal is
answered, so the planner is not sent a new goal each tick. A goal the robot has not
come closer to for `progress_timeout` seconds is blacklisted, as explore_lite does.
With `return_to_init`, the start pose is the last goal. Until the costmap knows the
robot's own cell (SLAM's first map, the first scans), the answer is "wait".
"""

from __future__ import annotations

import math
from collections.abc import Callable
from dataclasses import dataclass, field
from typing import Any

import numpy as np

from ..core import fmath
from ..core.geometry import Pose2D
from ..costmap.cost_values import NO_INFORMATION
from ..exploration.frontier_search import Frontier, find_frontiers
from ..maps.occupancy_grid import OccupancyGrid
from ..params.paramsfile import ServerParams
from .costmap_server import CostmapServer
from .map_server import MapServer
from .runtime import Runtime

#: m: a goal stays while a frontier cell lies this close to it (and the robot is not there).
GOAL_KEPT_WITHIN = 0.5
#: m: closer than this, a goal counts as reached and a new one is searched.
GOAL_REACHED_WITHIN = 0.35
#: m: a frontier whose goal lies this close to a blacklisted goal is left out.
BLACKLIST_RADIUS = 0.5
#: m: getting this much closer to the goal counts as progress.
PROGRESS_STEP = 0.05


@dataclass
class ExploreStep:
    """What `compute_frontiers` answers: the goal to go to (None: nothing left)."""

    goal: Pose2D | None
    frontiers: list[Frontier] = field(default_factory=list)
    returning: bool = False  # the goal is the start pose (return_to_init)
    waiting: bool = False  # no map around the robot yet: ask again


class ExploreServer:
    """The explore node's decisions on the global costmap; `explored_area` of the map."""

    def __init__(
        self,
        runtime: Runtime,
        params: ServerParams,
        global_costmap: CostmapServer,
        map_server: MapServer,
    ) -> None:
        self.runtime = runtime
        self.server_params = params
        self.params = params.model
        self.global_costmap = global_costmap
        self.map_server = map_server
        self.blacklist: list[tuple[float, float]] = []
        self.goal: Pose2D | None = None
        self.frontiers: list[Frontier] = []
        self.returning = False
        self._returned = False
        self._searched_at = -math.inf
        self._best_distance = math.inf
        self._progress_at = 0.0
        self.start: Pose2D | None = None
        self._area_of: OccupancyGrid | None = None
        self._area = 0.0

    def set_parameters(self, params: ServerParams) -> None:
        self.server_params = params
        self.params = params.model

    def services(self) -> dict[str, Callable[..., Any]]:
        return {
            "explore/compute_frontiers": self.compute_frontiers,
            "explore/blacklist_frontier": self.blacklist_frontier,
        }

    # -- the services ---------------------------------------------------------------------

    def compute_frontiers(self) -> ExploreStep:
        now = self.runtime.now
        robot = self.runtime.robot_pose(
            self.global_costmap.global_frame, self.params.robot_base_frame
        )
        if self.global_costmap.costmap.cost_at_point(robot.x, robot.y) == NO_INFORMATION:
            return ExploreStep(None, waiting=True)  # SLAM's first map is not in yet
        if self.start is None:
            self.start = robot
        keep = self.goal is not None and self._goal_stands(robot, now)
        if keep and now - self._searched_at < 1.0 / self.params.planner_frequency:
            return ExploreStep(self.goal, self.frontiers, self.returning)
        return self._search(robot, now, keep)

    def blacklist_frontier(self, goal: Pose2D | None = None) -> None:
        """Never choose a frontier whose goal lies near `goal` (default: the current goal) again."""
        goal = goal if goal is not None else self.goal
        if goal is None:
            return
        self.blacklist.append((float(goal.x), float(goal.y)))
        if self.returning:
            self._returned = True  # the way home failed: exploring is over all the same
        self.goal = None

    # -- the search -----------------------------------------------------------------------

    def _goal_stands(self, robot: Pose2D, now: float) -> bool:
        """The goal is not reached, and the robot got closer to it within progress_timeout."""
        assert self.goal is not None
        away = fmath.hypot(self.goal.x - robot.x, self.goal.y - robot.y)
        if away < self._best_distance - PROGRESS_STEP:
            self._best_distance, self._progress_at = away, now
        elif now - self._progress_at > self.params.progress_timeout:
            self.blacklist_frontier(self.goal)  # explore_lite: no progress, give it up
            return False
        if away <= GOAL_REACHED_WITHIN:
            self._returned = self._returned or self.returning
            return False
        return True

    def _search(self, robot: Pose2D, now: float, keep: bool) -> ExploreStep:
        """Search now; with `keep`, the goal stays while its frontier is still there."""
        p = self.params
        self._searched_at = now
        self.frontiers = find_frontiers(
            self.global_costmap.costmap,
            (robot.x, robot.y),
            min_frontier_size=p.min_frontier_size,
            potential_scale=p.potential_scale,
            gain_scale=p.gain_scale,
            blacklist=self.blacklist,
            blacklist_radius=BLACKLIST_RADIUS,
        )
        if keep and ((self.returning and not self.frontiers) or self._near_a_frontier()):
            return ExploreStep(self.goal, self.frontiers, self.returning)
        goal, self.returning = None, False
        if self.frontiers:
            goal, self._returned = self.frontiers[0].goal, False
        elif p.return_to_init and self.start is not None and not self._returned:
            goal, self.returning = self.start, True
        if goal is None or self.goal is None or (goal.x, goal.y) != (self.goal.x, self.goal.y):
            self._best_distance, self._progress_at = math.inf, now
        self.goal = goal
        return ExploreStep(goal, self.frontiers, self.returning)

    def _near_a_frontier(self) -> bool:
        """Whether a frontier cell still lies near the goal (a frontier recedes as it is seen)."""
        assert self.goal is not None
        near = GOAL_KEPT_WITHIN**2
        xy = (self.goal.x, self.goal.y)
        return any(bool(np.any(((f.cells - xy) ** 2).sum(axis=1) <= near)) for f in self.frontiers)

    # -- what was explored ----------------------------------------------------------------

    def explored_area(self) -> float:
        """m^2 of free space on map_server's map (SLAM's map as it stands)."""
        grid: OccupancyGrid | None = self.map_server.map
        if grid is None:
            return 0.0
        if grid is not self._area_of:  # a new map: count once (feedback asks every tick)
            self._area_of = grid
            self._area = float(np.count_nonzero(grid.data == 0)) * grid.resolution**2
        return self._area
