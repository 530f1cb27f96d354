"""explore's decisions (explore_lite's): which goal, kept or changed, blacklisted, and when done."""

from __future__ import annotations

from types import SimpleNamespace

import numpy as np
import pytest

from btnav.core.geometry import Pose2D
from btnav.costmap.cost_values import LETHAL_OBSTACLE, NO_INFORMATION
from btnav.costmap.costmap_2d import Costmap2D
from btnav.nav.explore_server import ExploreServer
from btnav.params.explore import ExploreParams


class Scene:
    """A runtime, a global costmap and a map_server, as much as explore reads of them."""

    def __init__(self, costs: np.ndarray, robot=(3.0, 5.0), **params) -> None:
        self.now = 0.0
        self.robot = Pose2D(*robot, 0.0)
        self.costmap = Costmap2D(costs, 0.05)
        costmap = SimpleNamespace(costmap=self.costmap, global_frame="map")
        model = ExploreParams(**params)
        self.server = ExploreServer(
            _Clock(self), SimpleNamespace(model=model), costmap, SimpleNamespace(map=None)
        )


class _Clock:
    def __init__(self, scene: Scene) -> None:
        self.scene = scene

    @property
    def now(self) -> float:
        return self.scene.now

    def robot_pose(self, frame: str, base: str) -> Pose2D:
        return self.scene.robot


def two_rooms() -> np.ndarray:
    c = np.full((200, 200), NO_INFORMATION, np.uint8)
    c[50:150, 50:150] = 0
    c[50:150, 100] = LETHAL_OBSTACLE
    c[60:70, 100] = 0
    c[50:150, 149] = LETHAL_OBSTACLE
    return c


def test_the_goal_is_kept_while_its_frontier_lasts_and_changes_when_blacklisted():
    scene = Scene(two_rooms())
    first = scene.server.compute_frontiers()
    assert first.goal is not None and len(first.frontiers) == 3
    scene.now, scene.robot = 1.0, Pose2D(2.9, 5.0, 0.0)  # on its way
    assert scene.server.compute_frontiers().goal == first.goal
    scene.server.blacklist_frontier()  # the tree could not reach it
    after = scene.server.compute_frontiers()
    assert after.goal is not None and after.goal != first.goal and len(after.frontiers) == 2


def test_no_progress_for_progress_timeout_blacklists_the_goal():
    scene = Scene(two_rooms(), progress_timeout=10.0)
    first = scene.server.compute_frontiers().goal
    for t in np.arange(1.0, 13.0, 1.0):  # the robot does not move (from t = 1 s on)
        scene.now = float(t)
        step = scene.server.compute_frontiers()
    assert step.goal != first and len(scene.server.blacklist) == 1


def closed_room() -> np.ndarray:
    costs = np.full((100, 100), LETHAL_OBSTACLE, np.uint8)
    costs[20:80, 20:80] = 0  # all known: no frontier
    return costs


def test_with_nothing_left_exploring_is_done():
    assert Scene(closed_room(), robot=(2.0, 2.0)).server.compute_frontiers().goal is None


def test_with_return_to_init_the_start_is_the_last_goal():
    scene = Scene(closed_room(), robot=(1.5, 1.5), return_to_init=True)
    scene.server.compute_frontiers()  # the start is where the first call finds the robot
    scene.now, scene.robot = 10.0, Pose2D(3.5, 3.5, 0.0)  # explored, now far from it
    home = scene.server.compute_frontiers()
    assert home.returning and (home.goal.x, home.goal.y) == (1.5, 1.5)
    scene.now, scene.robot = 20.0, Pose2D(1.5, 1.6, 0.0)  # back home
    assert scene.server.compute_frontiers().goal is None


def test_it_waits_while_the_robot_stands_on_unknown_cells():
    step = Scene(np.full((100, 100), NO_INFORMATION, np.uint8), robot=(2.0, 2.0))
    out = step.server.compute_frontiers()
    assert out.waiting and out.goal is None


@pytest.mark.parametrize("value", [0.0, -1.0])
def test_planner_frequency_must_be_positive(value):
    with pytest.raises(ValueError):
        ExploreParams(planner_frequency=value)
