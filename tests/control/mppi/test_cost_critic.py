"""CostCritic scores the costmap under every trajectory_point_step-th rollout point as Nav2's does.

Nav2 (cost_critic.cpp): for each evaluated point, a free cell adds nothing; a point in
collision (lethal; inscribed unless consider_footprint; unknown or off the map unless
tracking unknown space) makes the rollout's whole term `collision_cost`; a cost at or
above `near_collision_cost` adds `critical_cost`; any other cost adds itself, except
within `near_goal_distance` of the goal. The sum is multiplied by cost_weight / 254 /
(number of evaluated points), then raised to cost_power. fail_flag: every rollout
collides.
"""

from __future__ import annotations

import numpy as np
import pytest

from btnav.control.mppi.critics import CostCritic
from btnav.core.errors import ParamsError
from btnav.costmap.cost_values import INSCRIBED_INFLATED_OBSTACLE, LETHAL_OBSTACLE, NO_INFORMATION

from .batch import (
    LONG_ROBOT,
    costmap,
    costmap_server,
    line,
    make_data,
    paint,
    polyline,
    straight_path,
)

T = 5  # rollout points 0..4; with trajectory_point_step 2, points 0, 2 and 4 are scored
SCALE = 3.81 / 254.0 / 3  # cost_weight / 254 / evaluated points


def critic(**params) -> CostCritic:
    return CostCritic("CostCritic", CostCritic.Params(**params))


def row(y: float):
    """A rollout along +x at height y, 5 cm a step, over five cells."""
    return line(0.0, y, 0.0, 0.05, T)


def paint_row(cm, y: float, costs):
    for k, c in enumerate(costs):
        paint(cm, [(0.05 * k, y)], c)


def scene(track_unknown: bool = False):
    """Six rollouts over hand-painted cells (x = 0 .. 0.2 m at each height)."""
    cm = costmap(track_unknown)
    paint_row(cm, 0.5, [100, 250, 50, 250, 20])  # scored 100 + 50 + 20 = 170
    paint_row(cm, 1.0, [0, 0, LETHAL_OBSTACLE, 0, 0])  # hits a lethal cell
    paint_row(cm, -0.5, [0, 0, 0, 0, NO_INFORMATION])  # ends in unknown space
    paint_row(cm, -1.0, [0, LETHAL_OBSTACLE, 0, LETHAL_OBSTACLE, 0])  # only unscored points
    paint_row(cm, 1.5, [INSCRIBED_INFLATED_OBSTACLE, 0, 0, 0, 0])  # starts inscribed
    trajs = [row(y) for y in (0.0, 0.5, 1.0, -0.5, -1.0, 1.5)]
    return trajs, cm


def data_for(trajs, cm, path=None, **kw):
    return make_data(trajs, cm=cm, path=straight_path(3.0) if path is None else path, **kw)


def test_defaults_are_nav2s():
    p = CostCritic.Params()
    assert p.cost_weight == 3.81 and p.cost_power == 1
    assert (p.critical_cost, p.near_collision_cost, p.collision_cost) == (300.0, 253, 1e6)
    assert (p.near_goal_distance, p.trajectory_point_step, p.consider_footprint) == (0.5, 2, False)


def test_costs_are_the_scored_cells_normalised_and_collisions_cost_collision_cost():
    trajs, cm = scene()
    data = data_for(trajs, cm)
    critic().score(data)
    collision = 1e6 * SCALE  # 5000
    expected = [0.0, 170 * SCALE, collision, collision, 0.0, collision]  # 170 -> 0.85
    assert data.costs == pytest.approx(expected, rel=1e-5)
    assert data.costs[1] == pytest.approx(0.85, rel=1e-5)
    assert not data.fail_flag
    # The free rollout is best; the ones into lethal, unknown and inscribed cells are worst.
    assert np.argmin(data.costs) in (0, 4)
    assert set(np.flatnonzero(data.costs == data.costs.max())) == {2, 3, 5}


def test_trajectory_point_step_1_scores_every_point():
    trajs, cm = scene()
    data = data_for(trajs, cm)
    critic(trajectory_point_step=1).score(data)
    scale = 3.81 / 254.0 / 5
    # Row 0.5: 100 + 250 + 50 + 250 + 20 = 670; row -1.0 now hits its lethal cells.
    assert data.costs[1] == pytest.approx(670 * scale, rel=1e-5)
    assert data.costs[4] == pytest.approx(1e6 * scale, rel=1e-5)


def test_near_collision_cost_adds_the_critical_cost_instead_of_the_cell_cost():
    cm = costmap()
    paint_row(cm, 0.5, [210, 0, 30, 0, 0])
    data = data_for([row(0.0), row(0.5)], cm)
    critic(near_collision_cost=200).score(data)
    assert data.costs == pytest.approx([0.0, (300 + 30) * SCALE], rel=1e-5)  # 1.65


def test_near_the_goal_only_critical_costs_count():
    cm = costmap()
    paint_row(cm, 0.5, [210, 0, 30, 0, 0])
    paint_row(cm, -0.5, [100, 250, 50, 250, 20])
    # A straight path of 0.4 m: the goal is nearer than near_goal_distance (0.5).
    data = data_for([row(0.0), row(0.5), row(-0.5)], cm, path=straight_path(0.4))
    critic(near_collision_cost=200).score(data)
    assert data.costs == pytest.approx([0.0, 300 * SCALE, 0.0], rel=1e-5)  # 1.5


def test_unknown_space_is_a_collision_unless_tracked_then_critical():
    trajs, cm = scene(track_unknown=True)
    data = data_for(trajs, cm)
    critic().score(data)
    # Row -0.5 ends in an unknown cell: 255 >= near_collision_cost, so critical_cost.
    assert data.costs[3] == pytest.approx(300 * SCALE, rel=1e-5)  # 1.5
    assert data.costs[2] == pytest.approx(1e6 * SCALE, rel=1e-5)  # lethal still collides


def test_off_the_map_reads_as_unknown():
    off = line(5.45, 0.0, 0.0, 0.05, T)  # points 2.. leave the map at x = 5.525
    for tracked, expected in ((False, 1e6 * SCALE), (True, 2 * 300 * SCALE)):
        data = data_for([row(0.0), off], costmap(tracked))
        critic().score(data)
        assert data.costs[1] == pytest.approx(expected, rel=1e-5)


def test_fail_flag_when_every_rollout_collides():
    trajs, cm = scene()
    data = data_for([trajs[2], trajs[3], trajs[5]], cm)
    critic().score(data)
    assert data.fail_flag
    data = data_for(trajs, cm)
    critic().score(data)
    assert not data.fail_flag


def test_weight_and_power_act_on_the_normalised_term():
    trajs, cm = scene()
    data = data_for(trajs[:2], cm)
    critic(cost_weight=7.62).score(data)
    assert data.costs[1] == pytest.approx(1.7, rel=1e-5)
    data = data_for(trajs[:2], cm)
    critic(cost_power=2).score(data)
    assert data.costs[1] == pytest.approx(0.85**2, rel=1e-5)
    data = data_for(trajs, cm)
    critic(enabled=False).score(data)
    assert (data.costs == 0).all() and not data.fail_flag


def test_near_goal_is_judged_by_path_length():
    trajs, cm = scene()
    # An L-shaped detour: the goal is 0.4 m away in a straight line but 0.8 m along the path.
    path = polyline((0.0, 0.0), (0.0, 0.2), (0.4, 0.2), (0.4, 0.0))
    data = data_for(trajs[:2], cm, path=path)
    critic().score(data)
    assert data.costs[1] == pytest.approx(0.85, rel=1e-5)  # not near the goal: cells count


SQUARE_ROBOT = [[0.2, 0.2], [0.2, -0.2], [-0.2, -0.2], [-0.2, 0.2]]


def test_consider_footprint_inscribed_centre_is_not_a_collision():
    cm = costmap()
    # A lone inscribed cell with no lethal cell anywhere: any footprint larger than a cell
    # has an outline over free cells only, so Nav2's footprint check finds no collision.
    paint(cm, [(0.1, 0.5)], INSCRIBED_INFLATED_OBSTACLE)
    data = data_for([row(0.0), row(0.5)], cm)
    c = critic(consider_footprint=True)
    c.configure(costmap_server(SQUARE_ROBOT))
    c.score(data)
    assert data.costs[1] == pytest.approx(300 * SCALE, rel=1e-5)


def test_consider_footprint_sees_a_long_robots_nose_on_a_wall():
    # The centre's cost says 0.5 m to the obstacle, beyond the inscribed radius: the
    # circle check lets it pass; the 1 m long footprint's front edge is on the lethal cell.
    cm = costmap()
    paint(cm, [(0.0, 0.0)], 88)  # the inflation cost 0.5 m from an obstacle (k = 3)
    paint(cm, [(0.5, 0.0)], LETHAL_OBSTACLE)
    standing = [np.zeros((T, 3))]
    circle = data_for(standing, cm)
    critic().score(circle)
    assert circle.costs[0] == pytest.approx(3 * 88 * SCALE, rel=1e-5)  # scored, not a collision
    assert not circle.fail_flag
    footprint = data_for(standing, cm)
    c = critic(consider_footprint=True)
    c.configure(costmap_server(LONG_ROBOT, k=3.0, radius=0.7))
    c.score(footprint)
    assert footprint.costs[0] == pytest.approx(1e6 * SCALE, rel=1e-5)
    assert footprint.fail_flag


def test_consider_footprint_on_a_round_robot_is_refused_as_nav2_does():
    with pytest.raises(ParamsError, match="consider_footprint") as info:
        critic(consider_footprint=True).configure(costmap_server())
    assert "footprint" in str(info.value)


def test_fail_flag_is_this_critics_verdict():
    trajs, cm = scene()
    data = data_for(trajs, cm, fail_flag=True)
    critic().score(data)
    assert not data.fail_flag
