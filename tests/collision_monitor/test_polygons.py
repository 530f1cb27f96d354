"""The zones: points inside, min_points, the trigger debounce, velocity polygon selection,
and the approach action's time to collision."""

from __future__ import annotations

import numpy as np
import pytest

from btnav.collision_monitor import Circle, Polygon, VelocityPolygon
from btnav.collision_monitor.action import ActionType
from btnav.collision_monitor.kinematics import step_times
from btnav.collision_monitor.shapes import points_in_polygon
from btnav.core import fmath
from btnav.core.messages import Twist
from btnav.costmap.footprint import footprint_from_radius

from .zones import FOOTPRINT_APPROACH, POLYGON_STOP, VELOCITY_POLYGON_STOP, polygon


def wall_points(x: float, half_width: float = 0.3, n: int = 31) -> np.ndarray:
    """A flat face at distance `x` ahead of the robot, as a lidar samples it."""
    return np.stack([np.full(n, x), np.linspace(-half_width, half_width, n)], axis=-1)


def test_stop_polygon_acts_on_min_points_inside() -> None:
    zone = Polygon("PolygonStop", polygon(POLYGON_STOP), ["scan"])
    assert zone.action_type == ActionType.STOP and zone.min_points == 4
    three = np.array([[0.1, 0.0], [0.1, 0.1], [0.2, -0.1], [0.5, 0.0], [-0.1, 0.0]])
    hit, inside = zone.is_triggered({"scan": three})
    assert not hit and len(inside) == 3
    hit, inside = zone.is_triggered({"scan": np.vstack([three, [[0.25, 0.2]]])})
    assert hit and len(inside) == 4


def test_deprecated_max_points_is_min_points_minus_one() -> None:
    zone = Polygon("p", polygon(POLYGON_STOP, max_points=2, min_points=9), ["scan"])
    assert zone.min_points == 3


def test_polygon_checks_only_its_sources() -> None:
    zone = Polygon("p", polygon(POLYGON_STOP, sources_names=["front"]), ["front", "back"])
    inside = np.full((5, 2), 0.1)
    assert not zone.is_triggered({"back": inside, "front": inside[:0]})[0]
    assert zone.is_triggered({"back": inside[:0], "front": inside})[0]


def test_trigger_and_release_consecutive_points_debounce() -> None:
    zone = Polygon(
        "p",
        polygon(POLYGON_STOP, trigger_consecutive_points=3, release_consecutive_points=2),
        ["scan"],
    )
    hit = {"scan": np.full((5, 2), 0.1)}
    miss = {"scan": np.zeros((0, 2))}
    seen = [zone.is_triggered(c)[0] for c in (hit, hit, hit, miss, hit, miss, miss, hit)]
    #                                         1    2    on  1 miss reset  1    2: off  1
    assert seen == [False, False, True, True, True, True, False, False]


def test_circle_zone_and_its_radius_given_at_run_time() -> None:
    circle = Circle("c", polygon({"type": "circle", "radius": 0.3, "action_type": "stop"}), ["s"])
    pts = np.array([[0.29, 0.0], [0.0, 0.29], [-0.2, -0.2], [0.22, 0.22], [0.3, 0.0]])
    assert circle.inside(pts).tolist() == [True, True, True, False, False]
    dynamic = Circle(
        "d", polygon({"type": "circle", "polygon_sub_topic": "r", "action_type": "stop"}), ["s"]
    )
    assert not dynamic.is_shape_set()
    dynamic.set_radius(0.5)
    assert dynamic.is_shape_set() and dynamic.inside(pts).all()


def test_a_polygon_given_at_run_time() -> None:
    zone = Polygon(
        "p", polygon({"type": "polygon", "polygon_sub_topic": "t", "action_type": "stop"}), ["s"]
    )
    assert not zone.is_shape_set()
    zone.set_polygon([[1, 1], [1, -1], [-1, -1], [-1, 1]])
    assert zone.is_shape_set() and zone.inside(np.array([[0.5, 0.5]])).all()
    with pytest.raises(ValueError, match="at least 3"):
        zone.set_polygon([[1, 1], [1, -1]])


@pytest.mark.parametrize(
    ("cmd", "chosen"),
    [
        (Twist(0.0, 0.0, 0.5), "rotation"),
        (Twist(0.3, 0.0, 0.2), "translation_forward"),
        (Twist(-0.3, 0.0, 0.0), "translation_backward"),
        (Twist(0.0, 0.0, 0.0), "rotation"),  # the first match wins: (0, 0) is in rotation
        (Twist(1.5, 0.0, 0.0), "rotation"),  # out of every range: the previous shape stays
    ],
)
def test_velocity_polygon_chooses_the_sub_polygon_by_velocity(cmd: Twist, chosen: str) -> None:
    zone = VelocityPolygon("v", polygon(VELOCITY_POLYGON_STOP), ["scan"])
    assert not zone.is_shape_set()
    zone.update_polygon(Twist(0.0, 0.0, 0.5))  # rotation first
    zone.update_polygon(cmd)
    assert zone.sub_polygon == chosen
    np.testing.assert_array_equal(zone.vertices, zone.params.sub_polygons[chosen].points)


def test_holonomic_velocity_polygon_uses_speed_and_direction() -> None:
    sub = {"linear_min": 0.0, "linear_max": 1.0, "theta_min": -1.0, "theta_max": 1.0}
    square = "[[0.3, 0.3], [0.3, -0.3], [-0.3, -0.3], [-0.3, 0.3]]"
    zone = VelocityPolygon(
        "v",
        polygon(
            {
                "type": "velocity_polygon",
                "action_type": "stop",
                "holonomic": True,
                "velocity_polygons": ["left", "back"],
                # start > end: the range wraps through pi
                "back": {
                    **sub,
                    "points": square,
                    "direction_start_angle": 2.5,
                    "direction_end_angle": -2.5,
                },
                "left": {
                    **sub,
                    "points": square,
                    "direction_start_angle": 1.0,
                    "direction_end_angle": 2.0,
                },
            }
        ),
        ["scan"],
    )
    for cmd, chosen in [
        (Twist(0.0, 0.5, 0.0), "left"),
        (Twist(-0.5, 0.01, 0.0), "back"),
        (Twist(-0.5, -0.01, 0.0), "back"),
    ]:
        zone.update_polygon(cmd)
        assert zone.sub_polygon == chosen, cmd
    zone.update_polygon(Twist(0.5, 0.0, 0.0))  # direction 0 is in neither: kept
    assert zone.sub_polygon == "back"


def footprint_zone(**changes: object) -> Polygon:
    fp = footprint_from_radius(0.22)
    return Polygon(
        "FootprintApproach", polygon(FOOTPRINT_APPROACH, **changes), ["scan"], lambda: fp
    )


def test_approach_polygon_is_the_footprint() -> None:
    zone = footprint_zone()
    assert zone.follows_footprint and not zone.is_shape_set()
    zone.update_polygon(Twist())
    np.testing.assert_array_equal(zone.vertices, footprint_from_radius(0.22))


def test_time_to_collision_straight_ahead() -> None:
    zone = footprint_zone()
    zone.update_polygon(Twist(0.5, 0.0, 0.0))
    # face 0.42 m ahead: the footprint's front (0.22) reaches it after 0.4 s at 0.5 m/s; the
    # step that first holds the points is the one ending at 0.5 s, and Nav2 reports its start
    time, points = zone.collision_time({"scan": wall_points(0.42)}, Twist(0.5, 0.0, 0.0))
    assert time == pytest.approx(0.4)
    assert len(points) >= 6 and np.all(points[:, 0] == 0.42)
    # already inside: 0; beyond time_before_collision, or moving away: -1
    assert zone.collision_time({"scan": wall_points(0.1)}, Twist(0.5, 0, 0))[0] == 0.0
    assert zone.collision_time({"scan": wall_points(1.5)}, Twist(0.5, 0, 0))[0] == -1.0
    assert zone.collision_time({"scan": wall_points(0.42)}, Twist(-0.5, 0, 0))[0] == -1.0
    assert zone.collision_time({"scan": np.zeros((0, 2))}, Twist(0.5, 0, 0))[0] == -1.0


def test_time_to_collision_follows_a_turn() -> None:
    zone = footprint_zone()
    zone.update_polygon(Twist())
    # a post at (0.5, 0.5): driving straight passes it; an arc of radius 0.5 to the left
    # (v = 0.5, w = 1) runs into it
    post = 0.5 + 0.03 * np.array([[np.cos(a), np.sin(a)] for a in np.linspace(0, 6.2, 12)])
    assert zone.collision_time({"scan": post}, Twist(0.5, 0.0, 0.0))[0] == -1.0
    time, _ = zone.collision_time({"scan": post}, Twist(0.5, 0.0, 1.0))
    assert 0.5 < time < 1.6


def test_simulation_horizon_is_nav2s_float_loop() -> None:
    # Nav2 adds simulation_time_step to a double while <= time_before_collision
    assert step_times(0.3, 0.1) == [0.0, 0.1, 0.2]  # 0.1 + 0.1 + 0.1 > 0.3
    assert len(step_times(1.2, 0.1)) == 13
    zone = footprint_zone(time_before_collision=0.3)
    zone.update_polygon(Twist())
    # the third step ends 0.15 m on (at 0.5 m/s): a face it overlaps by 3 cm is found (at
    # the step's start, 0.2 s); one a fourth step would reach is not
    assert zone.collision_time({"scan": wall_points(0.22 + 0.12)}, Twist(0.5))[0] == 0.2
    assert zone.collision_time({"scan": wall_points(0.22 + 0.2)}, Twist(0.5))[0] == -1.0


def nav2_collision_time(
    vertices: np.ndarray, points: np.ndarray, v: Twist, horizon: float, dt: float, min_points: int
) -> tuple[float, np.ndarray]:
    """Nav2's getCollisionTime as it is written: every point seen from every pose in turn."""
    if len(points) == 0:
        return -1.0, points[:0]
    inside = points_in_polygon(points, vertices)
    if np.count_nonzero(inside) >= min_points:
        return 0.0, points[inside]
    x = y = theta = time = 0.0
    vx, vy = v.linear_x, v.linear_y
    s_step, c_step = fmath.sincos(v.angular_z * dt)
    while time <= horizon:
        x, y, theta = x + vx * dt, y + vy * dt, theta + v.angular_z * dt  # projectState
        vx, vy = vx * c_step - vy * s_step, vx * s_step + vy * c_step
        s, c = fmath.sincos(theta)
        dx, dy = points[:, 0] - x, points[:, 1] - y
        seen = np.stack([dx * c + dy * s, -dx * s + dy * c], axis=-1)
        inside = points_in_polygon(seen, vertices)
        if np.count_nonzero(inside) >= min_points:
            return time, points[inside]
        time += dt
    return -1.0, points[:0]


def test_time_to_collision_is_nav2s_loop_on_random_scenes() -> None:
    # the zone leaves out points beyond its reach of each pose and poses that cannot hold
    # min_points: on scenes where it does and does not collide, the answer stays Nav2's
    rng = np.random.default_rng(11)
    footprint = footprint_from_radius(0.22)
    found = {"now": 0, "ahead": 0, "none": 0}
    for trial in range(300):
        vertices = footprint if trial % 2 else rng.uniform(-0.4, 0.4, (5, 2))
        points = rng.uniform(-1.0, 1.0, (int(rng.integers(0, 100)), 2))
        v = Twist(rng.uniform(-0.8, 0.8), rng.uniform(-0.3, 0.3) * (trial % 3 == 0))
        v.angular_z = rng.uniform(-2.5, 2.5) * (trial % 4 != 0)
        horizon, dt = [(1.2, 0.1), (2.0, 0.05), (0.5, 0.2)][trial % 3]
        zone = footprint_zone(time_before_collision=horizon, simulation_time_step=dt)
        zone.set_polygon(vertices)
        zone.min_points = int(rng.integers(1, 8))
        time, inside = zone.collision_time({"scan": points}, v)
        want, want_inside = nav2_collision_time(vertices, points, v, horizon, dt, zone.min_points)
        assert time == want, trial
        np.testing.assert_array_equal(inside, want_inside)
        found["now" if time == 0.0 else "ahead" if time > 0.0 else "none"] += 1
    assert min(found.values()) >= 30, found


def test_a_footprint_zone_follows_a_new_footprint() -> None:
    shape = {"footprint": footprint_from_radius(0.22)}
    zone = Polygon("F", polygon(FOOTPRINT_APPROACH), ["scan"], lambda: shape["footprint"])
    face = {"scan": wall_points(0.3)}
    zone.update_polygon(Twist())
    assert zone.collision_time(face, Twist())[0] == -1.0  # the face is 8 cm ahead
    shape["footprint"] = footprint_from_radius(0.35)  # the costmap's new footprint
    zone.update_polygon(Twist())
    assert zone.collision_time(face, Twist())[0] == 0.0
