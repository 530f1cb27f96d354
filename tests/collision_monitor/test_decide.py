"""One monitor cycle: what each action does to the command, and which zone wins."""

from __future__ import annotations

import itertools

import numpy as np
import pytest

from btnav.collision_monitor import ActionType, decide, make_polygons
from btnav.collision_monitor.decide import INVALID_SOURCE
from btnav.core.messages import Twist
from btnav.costmap.footprint import footprint_from_radius

from .zones import (
    FOOTPRINT_APPROACH,
    POLYGON_LIMIT,
    POLYGON_SLOW,
    POLYGON_STOP,
    monitor_params,
)

FOOTPRINT = footprint_from_radius(0.22)


def zones(**sections: dict) -> list:
    return make_polygons(monitor_params(sections), lambda: FOOTPRINT)


def cluster(x: float, y: float = 0.0, n: int = 8) -> dict[str, np.ndarray]:
    return {"scan": np.array([[x, y + 0.01 * i] for i in range(n)])}


def test_nothing_sensed_passes_the_command_through() -> None:
    cmd = Twist(0.4, 0.0, 0.2)
    action, cause = decide(zones(PolygonStop=POLYGON_STOP), {"scan": np.zeros((0, 2))}, cmd)
    assert (action.action_type, action.req_vel, cause) == (ActionType.DO_NOTHING, cmd, None)


def test_stop_zone_zeroes_the_command() -> None:
    action, cause = decide(zones(PolygonStop=POLYGON_STOP), cluster(0.2), Twist(0.5, 0, 0.3))
    assert action.action_type == ActionType.STOP and action.req_vel == Twist()
    assert cause is not None and cause.name == action.polygon_name == "PolygonStop"
    assert len(action.triggering_points) == 8


def test_slowdown_multiplies_every_axis_by_the_ratio() -> None:
    action, _ = decide(zones(PolygonSlow=POLYGON_SLOW), cluster(-0.3), Twist(0.5, 0.0, -0.4))
    assert action.action_type == ActionType.SLOWDOWN
    assert action.req_vel.linear_x == pytest.approx(0.15)
    assert action.req_vel.angular_z == pytest.approx(-0.12)


def test_limit_keeps_the_curvature() -> None:
    # 0.8 m/s and 0.4 rad/s: linear_limit 0.4 asks for half; the turn is scaled alike
    action, _ = decide(zones(PolygonLimit=POLYGON_LIMIT), cluster(0.45), Twist(0.8, 0.0, 0.4))
    assert action.action_type == ActionType.LIMIT
    assert (action.req_vel.linear_x, action.req_vel.angular_z) == pytest.approx((0.4, 0.2))
    # a fast turn: angular_limit 0.5 of 2.0 rad/s is a quarter of both
    action, _ = decide(zones(PolygonLimit=POLYGON_LIMIT), cluster(0.45), Twist(0.2, 0.0, 2.0))
    assert (action.req_vel.linear_x, action.req_vel.angular_z) == pytest.approx((0.05, 0.5))
    # already within the limits: the command is not slower, so the zone does not act
    action, _ = decide(zones(PolygonLimit=POLYGON_LIMIT), cluster(0.45), Twist(0.3, 0.0, 0.1))
    assert action.action_type == ActionType.DO_NOTHING


def test_the_slowest_command_wins_and_a_stop_ends_the_cycle() -> None:
    three = zones(PolygonLimit=POLYGON_LIMIT, PolygonSlow=POLYGON_SLOW, PolygonStop=POLYGON_STOP)
    action, _ = decide(three, cluster(0.35), Twist(0.8, 0.0, 0.0))  # in limit and slowdown
    assert (action.polygon_name, action.req_vel.linear_x) == ("PolygonSlow", pytest.approx(0.24))
    action, _ = decide(three, cluster(0.1), Twist(0.8, 0.0, 0.0))  # in all three
    assert action.polygon_name == "PolygonStop" and action.req_vel == Twist()


def test_disabled_monitor_and_disabled_zone_do_nothing() -> None:
    cmd = Twist(0.5, 0.0, 0.0)
    assert (
        decide(zones(PolygonStop=POLYGON_STOP), cluster(0.2), cmd, enabled=False)[0].req_vel == cmd
    )
    off = zones(PolygonStop={**POLYGON_STOP, "enabled": False})
    assert decide(off, cluster(0.2), cmd)[0].action_type == ActionType.DO_NOTHING


def test_an_invalid_source_stops_the_robot_even_when_disabled() -> None:
    action, cause = decide(
        zones(PolygonStop=POLYGON_STOP), {}, Twist(0.5), enabled=False, invalid_sources=["scan"]
    )
    assert (action.action_type, action.polygon_name, cause) == (
        ActionType.STOP,
        INVALID_SOURCE,
        None,
    )


def test_approach_scales_by_time_to_collision() -> None:
    approach = zones(FootprintApproach=FOOTPRINT_APPROACH)
    face = {"scan": np.stack([np.full(31, 0.72), np.linspace(-0.3, 0.3, 31)], axis=-1)}
    action, _ = decide(approach, face, Twist(0.5, 0.0, 0.0))
    # the 16-gon's nose (0.22) touches 0.72 after 1.0 s, but holds 6 points only in the
    # step after (to 1.1 s), and Nav2 reports that step's start: 1.0 s of the 2.0 s
    assert action.action_type == ActionType.APPROACH
    assert action.req_vel.linear_x == pytest.approx(0.5 * 1.0 / 2.0)


@pytest.mark.parametrize("speed", [0.2, 0.5, 1.0])
def test_approach_never_lets_the_footprint_reach_the_obstacle(speed: float) -> None:
    """The robot driven at `speed` toward a wall, moving by what the monitor lets through
    each 50 ms: it slows as the gap closes and stops short, never touching."""
    approach = zones(FootprintApproach=FOOTPRINT_APPROACH)
    wall = np.stack([np.full(61, 1.5), np.linspace(-0.3, 0.3, 61)], axis=-1)
    x, dt, gaps, speeds = 0.0, 0.05, [], []
    for _ in range(400):
        action, _ = decide(approach, {"scan": wall - [x, 0.0]}, Twist(speed, 0.0, 0.0))
        x += action.req_vel.linear_x * dt
        gaps.append(1.5 - (x + 0.22))
        speeds.append(action.req_vel.linear_x)
    assert min(gaps) > 0.0
    assert speeds[-1] == 0.0 and gaps[-1] < 0.1
    assert all(b <= a + 1e-12 for a, b in itertools.pairwise(speeds))  # only slows


def test_a_standing_robot_with_points_in_its_footprint_is_left_alone() -> None:
    # a zero command is as slow as any approach can make it: no action, as in Nav2 (and
    # after a slowdown to zero, the approach zone does not act either)
    inside = cluster(0.1)
    action, cause = decide(zones(FootprintApproach=FOOTPRINT_APPROACH), inside, Twist())
    assert (action.action_type, cause) == (ActionType.DO_NOTHING, None)
    stopped = dict(POLYGON_SLOW, slowdown_ratio=0.0)
    both = zones(PolygonSlow=stopped, FootprintApproach=FOOTPRINT_APPROACH)
    action, cause = decide(both, inside, Twist(0.3, 0.0, 0.0))
    assert action.action_type == ActionType.SLOWDOWN and cause is both[0]
