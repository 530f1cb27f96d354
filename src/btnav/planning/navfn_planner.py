"""nav2_navfn_planner::NavfnPlanner: Dijkstra or A* over NavFn's potential, Nav2's plan rules."""

from __future__ import annotations

import math
from collections.abc import Callable

import numpy as np
from pydantic import Field

from ..core import fmath
from ..core.geometry import Pose2D
from ..core.messages import Path
from ..costmap.cost_values import INSCRIBED_INFLATED_OBSTACLE, LETHAL_OBSTACLE
from ..costmap.costmap_2d import Costmap2D
from ..plugins import register
from .exceptions import (
    GoalOccupied,
    GoalOutsideMapBounds,
    NoValidPathCouldBeFound,
    StartOccupied,
    StartOutsideMapBounds,
)
from .global_planner import GlobalPlanner
from .navfn import (
    DEFAULT_METHOD,
    POT_HIGH,
    GridGraph,
    Method,
    compute_potential,
    extract_path,
    navfn_costs,
)


@register("planner", "nav2_navfn_planner::NavfnPlanner", aliases=("btnav/NavfnPlanner",))
class NavfnPlanner(GlobalPlanner):
    """NavFn, as Nav2 runs it.

    - The potential spreads from the robot's cell; the path is read from the goal back
      down the potential and reversed, so it starts at the robot's cell centre and ends
      exactly at the goal (Nav2's smoothApproachToGoal). Points are in the costmap's
      frame with cell centres where Costmap2D puts them (NavFn's own world/map
      conversion rounds, which shifts its paths by half a cell; btnav does not).
    - A goal NavFn cannot reach is replaced by the reachable point closest to it within
      `tolerance` (searched on a resolution-spaced square around the goal, as Nav2 does);
      the path then ends there.
    - Poses carry yaw 0 except the last, which has the goal's yaw, or with
      `use_final_approach_orientation` the direction of the last segment (Nav2's
      orientations; a smoother or the controller sets the rest).
    - Points are spaced half a cell apart (NavFn's gradient step), one cell where the
      path follows the grid next to obstacles, or all the way where NavFn's gradient
      descent fails on btnav's potential (among a SLAM map's scattered unknown cells,
      with `allow_unknown`): a goal the potential reaches gets a path (within `max_cycles`).
    """

    class Params(GlobalPlanner.Params):
        tolerance: float = Field(0.5, ge=0.0, description="metres around an unreachable goal")
        use_astar: bool = False
        allow_unknown: bool = True
        use_final_approach_orientation: bool = False
        max_cycles_factor: float = Field(
            4.0, gt=0.0, description="path extraction gives up after factor * max(size) steps"
        )

    params: Params

    def __init__(self, name: str, params: Params | None = None) -> None:
        super().__init__(name, params)
        self._graph: GridGraph | None = None
        #: The potential of the last plan (ny, nx), for inspection and plots.
        self.potential: np.ndarray | None = None
        #: The compiled search and descent or the reference (the same plans; BTNAV_NAVFN=numpy).
        self.method: Method = DEFAULT_METHOD

    def _graph_for(self, shape: tuple[int, int]) -> GridGraph:
        if self._graph is None or self._graph.shape != shape:
            self._graph = GridGraph(*shape)
        return self._graph

    def create_plan(
        self,
        start: Pose2D,
        goal: Pose2D,
        costmap: Costmap2D,
        cancel_checker: Callable[[], bool] | None = None,
    ) -> Path:
        p = self.params
        (sx, sy), start_in = costmap.world_to_map([start.x, start.y])
        if not start_in:
            raise StartOutsideMapBounds(
                f"Start coordinates of ({start.x:.3f}, {start.y:.3f}) was outside bounds"
            )
        (gx, gy), goal_in = costmap.world_to_map([goal.x, goal.y])
        if not goal_in:
            raise GoalOutsideMapBounds(
                f"Goal coordinates of ({goal.x:.3f}, {goal.y:.3f}) was outside bounds"
            )
        costs = costmap.costs
        if p.tolerance == 0 and costs[gy, gx] in (LETHAL_OBSTACLE, INSCRIBED_INFLATED_OBSTACLE):
            raise GoalOccupied(
                f"Goal coordinates of ({goal.x:.3f}, {goal.y:.3f}) was in lethal cost"
            )
        if costs[sy, sx] == LETHAL_OBSTACLE:
            raise StartOccupied(
                f"Start coordinates of ({start.x:.3f}, {start.y:.3f}) was in lethal cost"
            )
        frame = costmap.frame_id
        if start.x == goal.x and start.y == goal.y:
            yaw = start.yaw if p.use_final_approach_orientation else goal.yaw
            return Path(0.0, np.array([[start.x, start.y, yaw]]), frame)

        costarr = navfn_costs(costs, p.allow_unknown)
        # NavFn clears the robot's cell (clearRobotCell); here the source's own cost never
        # enters its distances, so the cost array stays as it is (and cacheable).
        graph = self._graph_for(costs.shape)
        pot = compute_potential(
            graph,
            costarr,
            (int(sx), int(sy)),
            (int(gx), int(gy)),
            p.use_astar,
            cancel_checker,
            self.method,
        )
        self.potential = pot

        best = self._reachable_goal(goal, costmap, pot)
        if best is None:
            raise NoValidPathCouldBeFound(
                f"Failed to create plan with tolerance of: {p.tolerance:.6f}"
            )
        origin = np.array([costmap.origin_x, costmap.origin_y])
        bx, by = (best[:2] - origin) / costmap.resolution - 0.5  # cell centres at integers
        max_cycles = int(p.max_cycles_factor * max(costmap.size_x, costmap.size_y))
        cells = extract_path(
            pot, (bx, by), (int(sx), int(sy)), max_cycles, cancel_checker, self.method
        )
        if cells is None or len(cells) == 0:
            raise NoValidPathCouldBeFound(
                f"Failed to create plan with tolerance of: {p.tolerance:.6f}"
            )
        xy = costmap.map_to_world(cells[::-1])
        # smoothApproachToGoal: end exactly at the (tolerance-adjusted) goal; the descent
        # began on the goal itself, so its first point is replaced rather than doubled
        if len(xy) >= 2 and np.sum((xy[-1] - xy[-2]) ** 2) >= np.sum((best[:2] - xy[-2]) ** 2):
            xy[-1] = best[:2]
        else:
            xy = np.vstack([xy, best[:2]])
        poses = np.zeros((len(xy), 3))
        poses[:, :2] = xy
        poses[-1, 2] = goal.yaw
        if p.use_final_approach_orientation:
            if len(poses) == 1:
                poses[-1, 2] = start.yaw
            else:
                approach = poses[-2, :2]
                if len(poses) > 2 and np.all(np.abs(poses[-1, :2] - approach) < 1e-4):
                    approach = poses[-3, :2]
                d = poses[-1, :2] - approach
                poses[-1, 2] = fmath.arctan2(float(d[1]), float(d[0]))
        return Path(0.0, poses, frame)

    def _reachable_goal(
        self, goal: Pose2D, costmap: Costmap2D, pot: np.ndarray
    ) -> np.ndarray | None:
        """The goal if NavFn reached it, else the reachable point closest to it within tolerance."""
        (gx, gy), _ = costmap.world_to_map([goal.x, goal.y])
        if pot[gy, gx] < POT_HIGH:
            return np.array([goal.x, goal.y])
        tol, res = self.params.tolerance, costmap.resolution
        if tol <= 0:
            return None
        steps = np.arange(math.floor(2 * tol / res + 1e-9) + 1) * res - tol
        py, px = np.meshgrid(goal.y + steps, goal.x + steps, indexing="ij")  # y-major, as Nav2
        pts = np.stack([px.ravel(), py.ravel()], axis=-1)
        m, inside = costmap.world_to_map(pts)
        ok = np.zeros(len(pts), dtype=bool)
        ok[inside] = pot[m[inside, 1], m[inside, 0]] < POT_HIGH
        if not ok.any():
            return None
        sdist = np.where(ok, np.sum((pts - (goal.x, goal.y)) ** 2, axis=1), np.inf)
        return pts[int(np.argmin(sdist))]
