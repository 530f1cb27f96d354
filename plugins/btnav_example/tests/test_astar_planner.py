"""AStarPlanner: shortest on free space, round walls and costly cells, Nav2's planner errors."""

from __future__ import annotations

import math

import numpy as np
import pytest
from btnav import plugins
from btnav.core.errors import ParamsError
from btnav.core.geometry import Pose2D
from btnav.costmap import Costmap2D
from btnav.costmap.cost_values import INSCRIBED_INFLATED_OBSTACLE, LETHAL_OBSTACLE
from btnav.params import load_params
from btnav.planning.exceptions import (
    GoalOccupied,
    GoalOutsideMapBounds,
    NoValidPathCouldBeFound,
    PlannerCancelled,
)

from btnav_example.astar_planner import AStarPlanner

from .conftest import EXAMPLE_PARAMS

RES = 0.1


def grid(nx: int = 40, ny: int = 30) -> Costmap2D:
    return Costmap2D(np.zeros((ny, nx), np.uint8), RES)


def cell(x: int, y: int) -> Pose2D:
    """The centre of cell (x, y) of a `grid()`."""
    return Pose2D((x + 0.5) * RES, (y + 0.5) * RES, 0.0)


def plan(costmap: Costmap2D, start: Pose2D, goal: Pose2D, **params) -> np.ndarray:
    planner = AStarPlanner("GridBased", AStarPlanner.Params(**params))
    return planner.create_plan(start, goal, costmap).poses


def length(poses: np.ndarray) -> float:
    return float(np.hypot(*np.diff(poses[:, :2], axis=0).T).sum())


def test_it_is_registered_under_both_nav2_spellings():
    for name in ("btnav_example::AStarPlanner", "btnav_example/AStarPlanner"):
        assert plugins.lookup("planner", name) is AStarPlanner


def test_on_free_space_the_path_is_as_short_as_8_connected_steps_allow():
    poses = plan(grid(), cell(2, 2), Pose2D(1.25, 0.75, 1.0))
    # 10 cells right, 5 up: 5 diagonal and 5 straight steps between cell centres
    assert length(poses) == pytest.approx((5 * math.sqrt(2) + 5) * RES)
    assert poses[0, :2].tolist() == pytest.approx([0.25, 0.25])
    assert poses[-1].tolist() == pytest.approx([1.25, 0.75, 1.0])  # the goal's yaw
    assert poses[0, 2] == pytest.approx(math.pi / 4)  # the others face along the path


def test_it_goes_through_the_gap_in_a_wall_without_cutting_its_corners():
    costmap = grid()
    costmap.costs[:, 20] = LETHAL_OBSTACLE
    costmap.costs[12:14, 20] = 0  # a two-cell gap
    costmap.costs[14, 19] = INSCRIBED_INFLATED_OBSTACLE
    poses = plan(costmap, cell(5, 25), cell(35, 25))
    assert costmap.cost_at(poses[:, :2]).max() < INSCRIBED_INFLATED_OBSTACLE
    crossing = poses[np.argmin(np.abs(poses[:, 0] - 2.05))]
    assert 1.2 <= crossing[1] <= 1.4


def test_cost_weight_trades_length_for_lower_costs():
    costmap = grid()
    costmap.costs[5:25, 15:25] = 200  # a costly block between start and goal
    straight = plan(costmap, cell(5, 15), cell(35, 15), cost_weight=0.0)
    around = plan(costmap, cell(5, 15), cell(35, 15), cost_weight=5.0)
    assert length(straight) == pytest.approx(3.0)
    assert costmap.cost_at(around[:, :2]).max() == 0  # round the block
    assert length(around) > length(straight)


def test_unknown_space_is_free_only_with_allow_unknown():
    costmap = grid()
    costmap.costs[:, 20] = 255  # a column of unknown cells
    assert len(plan(costmap, cell(5, 5), cell(35, 5), allow_unknown=True)) > 0
    with pytest.raises(NoValidPathCouldBeFound):
        plan(costmap, cell(5, 5), cell(35, 5), allow_unknown=False)


def test_nav2s_planner_errors():
    costmap = grid()
    costmap.costs[10, 10] = LETHAL_OBSTACLE
    with pytest.raises(GoalOccupied):
        plan(costmap, cell(2, 2), cell(10, 10))
    with pytest.raises(GoalOutsideMapBounds):
        plan(costmap, cell(2, 2), Pose2D(10.0, 1.0, 0.0))
    costmap.costs[20:25, 20] = costmap.costs[20:25, 25] = LETHAL_OBSTACLE  # a closed box
    costmap.costs[20, 20:26] = costmap.costs[25, 20:26] = LETHAL_OBSTACLE
    with pytest.raises(NoValidPathCouldBeFound):
        plan(costmap, cell(2, 2), cell(22, 22))
    planner = AStarPlanner("GridBased")
    with pytest.raises(PlannerCancelled):
        big = Costmap2D(np.zeros((300, 300), np.uint8), RES)
        planner.create_plan(Pose2D(0.1, 0.1, 0), Pose2D(29, 29, 0), big, lambda: True)


def test_a_robot_inside_an_inscribed_cell_can_still_leave_it():
    costmap = grid()
    costmap.costs[4:7, 4:7] = INSCRIBED_INFLATED_OBSTACLE
    costmap.costs[5, 5] = INSCRIBED_INFLATED_OBSTACLE
    costmap.costs[5, 6] = 0  # one way out
    assert len(plan(costmap, cell(5, 5), cell(30, 20))) > 2


def test_on_the_office_it_plans_round_the_keepout_zone(office_costmap):
    costmap = office_costmap.costmap
    planner = AStarPlanner("GridBased", AStarPlanner.Params(cost_weight=3.0))
    path = planner.create_plan(Pose2D(1.0, 1.0, 0.0), Pose2D(9.0, 1.5, 0.0), costmap)
    costs = costmap.cost_at(path.poses[:, :2])
    assert costs.max() < INSCRIBED_INFLATED_OBSTACLE
    in_zone = (np.abs(path.poses[:, 0] - 7.05) < 0.25) & (np.abs(path.poses[:, 1] - 2.25) < 0.65)
    assert not in_zone.any()


def test_the_params_file_validates_its_section():
    section = load_params(EXAMPLE_PARAMS).server("planner_server").plugin("GridBased")
    assert section.cls is AStarPlanner
    assert section.params.cost_weight == 3.0


def test_a_misspelt_key_names_the_line_and_the_right_spelling(tmp_path):
    text = EXAMPLE_PARAMS.read_text().replace("cost_weight: 3.0", "cost_wieght: 3.0")
    (tmp_path / "params.yaml").write_text(text)
    with pytest.raises(ParamsError) as info:
        load_params(tmp_path / "params.yaml")
    assert info.value.suggestion == "cost_weight"
    assert info.value.line == text.splitlines().index("      cost_wieght: 3.0") + 1
