"""ObstacleFootprint: BaseObstacle for a robot of any shape.

Nav2 (obstacle_footprint.cpp): each pose lays the costmap server's footprint, turned to
the pose's yaw, on the grid, and scores the highest cost on its outline (each edge
rasterised between its vertices' cells). A lethal or unknown cell on the outline, or a
vertex or the centre off the grid, makes the trajectory illegal; an inscribed cell does
not. The trajectory scores its last pose (or the sum, with sum_scores). With no
footprint, prepare fails and so does the planner.
"""

from __future__ import annotations

import math
from types import SimpleNamespace

import numpy as np
import pytest

from btnav.control.dwb import DWBLocalPlanner
from btnav.control.dwb.critics.base_obstacle import BaseObstacleCritic
from btnav.control.dwb.critics.obstacle_footprint import ObstacleFootprintCritic
from btnav.control.dwb.local_planner import DWBParams
from btnav.control.exceptions import NoValidControl
from btnav.control.goal_checkers import SimpleGoalChecker
from btnav.core.geometry import Pose2D
from btnav.core.messages import Twist
from btnav.costmap.cost_values import INSCRIBED_INFLATED_OBSTACLE, LETHAL_OBSTACLE, NO_INFORMATION
from btnav.costmap.footprint import footprint_from_radius
from btnav.costmap.footprint_cost import footprint_costs
from btnav.plugins import lookup

from ..unicycle import drive, free_costmap, straight_path
from .trajs import costmap, line_plan, prepare, set_cost, straight, trajectories

#: 0.4 m long, 0.2 m wide, centred on the robot.
BOX = np.array([[0.2, 0.1], [0.2, -0.1], [-0.2, -0.1], [-0.2, 0.1]])
#: 0.6 m long, 0.1 m wide.
PLANK = np.array([[0.3, 0.05], [0.3, -0.05], [-0.3, -0.05], [-0.3, 0.05]])


def critic(footprint=BOX, **params) -> ObstacleFootprintCritic:
    c = ObstacleFootprintCritic("ObstacleFootprint", ObstacleFootprintCritic.Params(**params))
    if footprint is not None:
        c.configure(SimpleNamespace(footprint=np.asarray(footprint, float)))
    return c


def scores(c: ObstacleFootprintCritic, trajs, cm) -> np.ndarray:
    plan = line_plan(1.0, 1.0, 3.0, 1.0)
    assert prepare(c, Pose2D(1.05, 1.05, 0.0), plan, cm)
    return c.score(trajs, cm)


def test_registered_under_nav2s_names():
    assert lookup("critic", "dwb_critics::ObstacleFootprint") is ObstacleFootprintCritic
    assert lookup("critic", "dwb_critics::ObstacleFootprintCritic") is ObstacleFootprintCritic


def test_a_corner_that_clips_an_obstacle_is_illegal_where_the_centre_misses_it():
    cm = costmap()
    # Driving along y = 1.05 from x = 1.05: the box's left edge runs along row 11 (y 1.1-1.2),
    # and at the last pose (x = 1.45) its front edge reaches column 16 (x 1.6-1.7).
    set_cost(cm, 16, 11, LETHAL_OBSTACLE)
    trajs = trajectories([straight(1.05, 1.05, 0.0, 0.1, 5)])
    assert np.isfinite(BaseObstacleCritic("BaseObstacle").score(trajs, cm)).all()
    assert np.isinf(scores(critic(), trajs, cm)).all()


def test_the_footprint_turns_with_the_pose():
    cm = set_cost(costmap(), 13, 10, LETHAL_OBSTACLE)  # 0.25-0.35 m ahead of (1.05, 1.05)
    along = trajectories([np.tile([1.05, 1.05, 0.0], (3, 1))])
    across = trajectories([np.tile([1.05, 1.05, math.pi / 2], (3, 1))])
    assert np.isinf(scores(critic(PLANK), along, cm)).all()
    assert scores(critic(PLANK), across, cm)[0] == 0.0


@pytest.mark.parametrize(
    ("cost", "legal"),
    [
        (40, True),
        (INSCRIBED_INFLATED_OBSTACLE, True),  # the footprint itself decides: it only touches
        (LETHAL_OBSTACLE, False),
        (NO_INFORMATION, False),
    ],
)
def test_the_outline_scores_its_dearest_cell_and_lethal_or_unknown_is_illegal(cost, legal):
    cm = costmap()
    set_cost(cm, 12, 11, 20)  # on the box's left edge at the last pose, (1.25, 1.15)
    set_cost(cm, 8, 9, cost)  # on its right edge, (0.85, 0.95)
    pose = np.tile([1.05, 1.05, 0.0], (3, 1))
    got = scores(critic(), trajectories([pose]), cm)[0]
    assert got == (max(cost, 20) if legal else math.inf)


def test_only_the_outline_counts_as_in_nav2():
    """An obstacle wholly inside a large footprint is not seen (Nav2 rasterises edges only)."""
    cm = set_cost(costmap(), 10, 10, LETHAL_OBSTACLE)  # under the centre
    got = scores(
        critic(footprint_from_radius(0.3)), trajectories([np.tile([1.05, 1.05, 0.0], (2, 1))]), cm
    )
    assert got[0] == 0.0
    assert np.isinf(
        BaseObstacleCritic("BaseObstacle").score(
            trajectories([np.tile([1.05, 1.05, 0.0], (2, 1))]), cm
        )
    ).all()


@pytest.mark.parametrize(
    "pose",
    [
        (0.15, 1.05, 0.0),  # the centre on the map, the box's back 0.05 m off it
        (1.05, 4.95, math.pi / 2),  # the front off the top edge
        (-0.05, 1.05, 0.0),  # the centre off the map
    ],
)
def test_a_footprint_off_the_grid_is_illegal(pose):
    got = scores(critic(), trajectories([np.tile(pose, (2, 1))]), costmap())
    assert np.isinf(got).all()


def test_sum_scores_adds_every_poses_outline_cost():
    cm = costmap()
    cm.costs[:, 12] = 30  # column 12 (x 1.2-1.3)
    cm.costs[:, 14] = 50  # column 14 (x 1.4-1.5)
    # x = 1.05 ... 1.45: the box spans columns 8-12, 9-13, 10-14, 11-15, 12-16; its top and
    # bottom edges cross every column it spans, so the poses cost 30, 30, 50, 50, 50.
    trajs = trajectories([straight(1.05, 1.05, 0.0, 0.1, 5)])
    assert scores(critic(sum_scores=True), trajs, cm)[0] == 210.0
    assert scores(critic(), trajs, cm)[0] == 50.0


def test_without_a_footprint_the_critic_cannot_prepare_and_dwb_fails():
    c = critic(footprint=None)
    assert not prepare(c, Pose2D(1.05, 1.05, 0.0), line_plan(1.0, 1.0, 3.0, 1.0), costmap())
    dwb = DWBLocalPlanner(params=DWBParams(critics=["ObstacleFootprint", "PathDist"]))
    dwb.set_plan(straight_path())
    with pytest.raises(NoValidControl, match="ObstacleFootprint"):
        dwb.compute_velocity_commands(Pose2D(), Twist(), free_costmap())


def test_a_wide_robot_stops_short_of_a_post_its_centre_would_miss():
    """A 0.64 m wide robot drives along a path with a post 0.25-0.35 m to its left, on a
    costmap with no inflation. With BaseObstacle (the cell under the centre only) DWB drives
    its side through the post; with ObstacleFootprint no trajectory whose outline touches
    the post is legal, so the robot stops short of it (and Nav2's progress checker would
    call for a recovery: the global planner is what routes round it)."""
    wide = np.array([[0.2, 0.32], [0.2, -0.32], [-0.2, -0.32], [-0.2, 0.32]])
    cm = free_costmap()
    cm.costs[25:27, 60:62] = LETHAL_OBSTACLE  # x 2.0-2.1, y 0.25-0.35

    def run(critic_name: str) -> tuple[float, bool]:
        dwb = DWBLocalPlanner(
            params=DWBParams(
                max_vel_x=0.5,
                max_speed_xy=0.5,
                max_vel_theta=1.5,
                critics=[critic_name, "GoalAlign", "PathAlign", "PathDist", "GoalDist"],
            )
        )
        dwb.configure(SimpleNamespace(footprint=wide))
        _pose, _cmds, poses, _reached = drive(
            dwb, straight_path(), cm, SimpleGoalChecker(), max_steps=120
        )
        hits = footprint_costs(cm, wide, poses[:, 0], poses[:, 1], poses[:, 2]) == LETHAL_OBSTACLE
        return float(poses[:, 0].max()), bool(hits.any())

    furthest, hit = run("ObstacleFootprint")
    assert not hit
    assert 1.5 < furthest < 2.0
    furthest, hit = run("BaseObstacle")
    assert hit and furthest > 2.5


@pytest.mark.parametrize("sum_scores", [False, True])
def test_laying_the_footprint_only_near_hazards_changes_no_score(sum_scores):
    """The critic lays the footprint only where a hazard may lie under the outline (and at
    the poses the score reads): its scores equal laying it at every pose, on grids strewn
    with lethal and unknown cells and trajectories that run off the grid."""
    rng = np.random.default_rng(7)
    legal = illegal_seen = 0
    for _ in range(40):
        cm = costmap()
        cm.costs[:] = rng.integers(0, 253, cm.costs.shape)
        for hazard in (LETHAL_OBSTACLE, NO_INFORMATION):
            cm.costs[rng.random(cm.costs.shape) < rng.uniform(0, 0.01)] = hazard
        fp = rng.normal(0.0, rng.uniform(0.05, 0.4), (int(rng.integers(1, 7)), 2))
        start = rng.uniform(-0.5, 5.5, (60, 1, 3))
        step = rng.normal(0.0, 0.05, (60, 1, 3))
        trajs = trajectories(start + step * np.arange(12)[None, :, None])
        c = critic(fp, sum_scores=sum_scores)
        got = scores(c, trajs, cm)
        x, y, yaw = (trajs.poses[..., i] for i in range(3))
        every = footprint_costs(cm, fp, x, y, yaw).astype(float)
        _, inside = cm.world_to_map(trajs.poses[..., :2])
        illegal = (~inside | (every >= LETHAL_OBSTACLE)).any(axis=1)
        expected = np.where(illegal, np.inf, every.sum(axis=1) if sum_scores else every[:, -1])
        assert np.array_equal(got, expected)
        legal += int(np.isfinite(got).sum())
        illegal_seen += int(np.isinf(got).sum())
    assert legal > 200 and illegal_seen > 200  # (of 2400)
