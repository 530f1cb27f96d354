"""ObstaclesCritic keeps rollouts clear of obstacles, from distances the inflated costs encode.

Nav2 (obstacles_critic.cpp), for each rollout point on a non-free cell: a collision
(lethal; inscribed unless consider_footprint; unknown unless tracked) ends the rollout.
Otherwise the cost is turned back into the clearance between the robot's inscribed
circle and the obstacle, `(ln 253 - ln cost) / cost_scaling_factor`; a clearance under
`collision_margin_distance` adds `margin - clearance` to the critical term, and (away
from the goal, local_path_length >= near_goal_distance) every point adds
`inflation_radius - clearance` to the repulsive term. The rollout's cost is
`critical_weight * (collision_cost if it collides else critical) + repulsion_weight *
(repulsive - min over the batch) / points`, raised to cost_power. fail_flag: every
rollout collides.

The inflation parameters are those of the inflation layer that painted the costs, read
from the local costmap the controller is configured with (Nav2 Humble's own keys win
when given); a critic on its own uses Humble's defaults (0.55 m, 10, inscribed 0.22 m).
"""

from __future__ import annotations

import math

import numpy as np
import pytest

from btnav.control.mppi.critics import ObstaclesCritic
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

T = 4
K, R_INFL = 10.0, 0.55  # the inflation layer's cost_scaling_factor and inflation_radius
MARGIN, CRITICAL_W, REPULSION_W, COLLISION = 0.10, 20.0, 1.5, 1e5


def critic(**params) -> ObstaclesCritic:
    return ObstaclesCritic("ObstaclesCritic", ObstaclesCritic.Params(**params))


def clearance(cost: float) -> float:
    """Nav2's distance from the robot's edge to the obstacle for a centre-point cost."""
    return (math.log(253.0) - math.log(cost)) / K


def row(y: float):
    return line(0.0, y, 0.0, 0.05, T)


def paint_row(cm, y, costs):
    for k, c in enumerate(costs):
        paint(cm, [(0.05 * k, y)], c)


def scene(track_unknown: bool = False):
    """Rollouts: in free space; in a low-cost band (clearance 0.16 m, outside the margin);
    in a high-cost band (clearance 0.024 m, inside the margin); into a lethal cell; into
    an inscribed cell; into an unknown cell."""
    cm = costmap(track_unknown)
    paint_row(cm, 0.5, [50] * T)
    paint_row(cm, 1.0, [200] * T)
    paint_row(cm, 1.5, [0, 0, LETHAL_OBSTACLE, 0])
    paint_row(cm, 2.0, [0, INSCRIBED_INFLATED_OBSTACLE, 0, 0])
    paint_row(cm, 2.5, [0, 0, 0, NO_INFORMATION])
    return [row(y) for y in (0.0, 0.5, 1.0, 1.5, 2.0, 2.5)], cm


def scored(trajs, cm, path=None, **params):
    data = make_data(trajs, cm=cm, path=straight_path(3.0) if path is None else path)
    critic(**params).score(data)
    return data


def test_defaults_are_nav2s():
    p = ObstaclesCritic.Params()
    assert (p.critical_weight, p.repulsion_weight, p.collision_cost) == (20.0, 1.5, 1e5)
    assert (p.collision_margin_distance, p.near_goal_distance) == (0.10, 0.5)
    assert p.consider_footprint is False and p.cost_power == 1


def test_free_is_free_closer_is_worse_and_collisions_are_worst():
    trajs, cm = scene()
    data = scored(trajs, cm)
    c = data.costs
    assert c[0] == 0.0
    assert 0.0 < c[1] < c[2] < COLLISION
    # Lethal, inscribed (circular robot) and untracked unknown cells are collisions.
    assert (c[3:] >= COLLISION).all()
    assert np.argmin(c) == 0
    assert not data.fail_flag


def test_fail_flag_when_every_rollout_collides():
    trajs, cm = scene()
    assert scored(trajs[3:], cm).fail_flag
    assert not scored(trajs[2:], cm).fail_flag


def test_tracked_unknown_space_is_not_a_collision():
    trajs, cm = scene(track_unknown=True)
    data = scored(trajs, cm)
    assert 0.0 < data.costs[5] < COLLISION
    assert data.costs[3] >= COLLISION


def test_near_the_goal_the_repulsive_term_is_off():
    trajs, cm = scene()
    data = scored(trajs, cm, path=straight_path(0.4))
    # The low-cost band is outside the collision margin: only repulsion ever charged it.
    assert data.costs[0] == 0.0 and data.costs[1] == 0.0
    assert data.costs[3] >= COLLISION


def test_repulsion_weight_scales_the_repulsive_term():
    trajs, cm = scene()
    base = scored(trajs[:2], cm).costs
    doubled = scored(trajs[:2], cm, repulsion_weight=3.0).costs
    assert doubled[1] == pytest.approx(2 * base[1], rel=1e-5)
    off = scored(trajs[:2], cm, repulsion_weight=0.0).costs
    assert (off == 0).all()


def test_cost_power_raises_the_whole_term():
    trajs, cm = scene()
    one = scored(trajs, cm).costs.astype(np.float64)
    two = scored(trajs, cm, cost_power=2).costs
    assert two == pytest.approx(one**2, rel=1e-5)
    assert (scored(trajs, cm, enabled=False).costs == 0).all()


# -- Nav2's numbers -------------------------------------------------------------------------


def test_repulsion_and_margin_use_the_clearance():
    trajs, cm = scene()
    data = scored(trajs[:3], cm)
    low, high = clearance(50), clearance(200)  # 0.162 m, 0.0235 m
    expected_low = REPULSION_W * (R_INFL - low)  # (4 points * (0.55 - 0.162)) / 4 points
    expected_high = CRITICAL_W * T * (MARGIN - high) + REPULSION_W * (R_INFL - high)
    assert data.costs[1] == pytest.approx(expected_low, rel=1e-4)  # 0.582
    assert data.costs[2] == pytest.approx(expected_high, rel=1e-4)  # 6.909


def test_near_the_goal_a_point_inside_the_margin_pays_the_critical_term():
    trajs, cm = scene()
    data = scored(trajs[:3], cm, path=straight_path(0.4))
    assert data.costs[2] == pytest.approx(CRITICAL_W * T * (MARGIN - clearance(200)), rel=1e-4)


def test_the_least_repelled_rollout_pays_no_repulsion():
    trajs, cm = scene()
    data = scored(trajs[1:3], cm)  # no rollout in free space
    assert data.costs[0] == pytest.approx(0.0, abs=1e-6)


def test_collision_cost_is_weighted_by_the_critical_weight():
    trajs, cm = scene()
    data = scored([trajs[0], trajs[3]], cm)  # free, then free cells into a lethal cell
    assert data.costs[1] == pytest.approx(CRITICAL_W * COLLISION, rel=1e-6)


def test_near_goal_is_judged_by_path_length():
    trajs, cm = scene()
    # 0.4 m to the goal in a straight line, 0.8 m along the path: not near the goal.
    path = polyline((0.0, 0.0), (0.0, 0.2), (0.4, 0.2), (0.4, 0.0))
    data = scored(trajs[:2], cm, path=path)
    assert data.costs[1] > 0.0


def test_consider_footprint_inscribed_centre_over_free_footprint_is_free():
    cm = costmap()
    paint(cm, [(0.05, 0.5)], INSCRIBED_INFLATED_OBSTACLE)  # a lone cell, no lethal anywhere
    data = make_data([row(0.0), row(0.5)], cm=cm, path=straight_path(3.0))
    c = critic(consider_footprint=True)
    c.configure(costmap_server([[0.2, 0.2], [0.2, -0.2], [-0.2, -0.2], [-0.2, 0.2]]))
    c.score(data)
    assert data.costs[1] == 0.0


def test_consider_footprint_sees_a_long_robots_nose_on_a_wall():
    cm = costmap()
    paint(cm, [(0.0, 0.0)], 88)  # the inflation cost 0.5 m from an obstacle (k = 3)
    paint(cm, [(0.5, 0.0)], LETHAL_OBSTACLE)  # under the footprint's front edge
    standing = [np.zeros((T, 3)), row(1.0)]
    c = critic(consider_footprint=True)
    c.configure(costmap_server(LONG_ROBOT, k=3.0, radius=0.7))
    data = make_data(standing, cm=cm, path=straight_path(3.0))
    c.score(data)
    assert data.costs[0] >= CRITICAL_W * COLLISION and not data.fail_flag
    circle = scored(standing, cm)
    assert circle.costs[0] < COLLISION


def test_the_inflation_layers_parameters_are_read_from_the_costmap():
    # Nav2's local costmap inflates with k = 3, 0.7 m; the critic has no keys of its own.
    trajs, cm = scene()
    c = critic()
    c.configure(costmap_server(k=3.0, radius=0.7))
    data = make_data(trajs[:3], cm=cm, path=straight_path(3.0))
    c.score(data)
    low = (math.log(253.0) - math.log(50)) / 3.0  # 0.54 m
    high = (math.log(253.0) - math.log(200)) / 3.0  # 0.078 m: inside the margin
    repulsion = [T * (0.7 - low) / T, T * (0.7 - high) / T]  # before the batch minimum
    assert data.costs[1] == pytest.approx(REPULSION_W * repulsion[0], rel=1e-4)
    assert data.costs[2] == pytest.approx(
        CRITICAL_W * T * (MARGIN - high) + REPULSION_W * repulsion[1], rel=1e-4
    )
    # Humble's own keys, when given, still win
    assert critic(cost_scaling_factor=10.0)._inflation()[0] == 10.0


def test_without_an_inflation_layer_only_collisions_count():
    trajs, cm = scene()
    c = critic()
    c.configure(costmap_server(k=None))
    data = make_data(trajs[:4], cm=cm, path=straight_path(3.0))
    c.score(data)
    assert data.costs.tolist()[:3] == [0.0, 0.0, 0.0]
    assert data.costs[3] == pytest.approx(CRITICAL_W * COLLISION)
