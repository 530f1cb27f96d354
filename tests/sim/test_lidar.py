"""The lidar reads the distances a tape measure would, with the noise and conventions asked for."""

from __future__ import annotations

import math

import numpy as np
import pytest

from btnav.core.errors import ConfigError
from btnav.core.geometry import Pose2D
from btnav.core.rng import stream
from btnav.core.validation import validate
from btnav.plugins import lookup
from btnav.sim.geometry import Geometry
from btnav.sim.lidar import Lidar
from btnav.sim.raycast import cast_from_pose

#: A float32 range is within this of the float64 distance it rounds (8 m * 2^-24 ~ 5e-7).
F32 = 1e-6


class StandIn:
    """The two things a sensor asks of a world: the robot's true pose and the geometry now."""

    def __init__(self, geometry: Geometry, pose: Pose2D) -> None:
        self._geometry = geometry
        self.robot_pose = pose

    def geometry(self) -> Geometry:
        return self._geometry


def room(w: float = 10.0, h: float = 8.0, circles=((7.0, 4.0, 0.5),)) -> Geometry:
    """The inside outline of a w x h room with its corner at the origin, and round pillars."""
    return Geometry(
        [np.array([[0.0, 0.0], [w, 0.0], [w, h], [0.0, h]])], np.array(circles, dtype=float)
    )


def analytic(x: float, y: float, angles: np.ndarray, w=10.0, h=8.0, circle=(7.0, 4.0, 0.5)):
    """Distances from (x, y) along world angles to the room's walls and one pillar."""
    c, s = np.cos(angles), np.sin(angles)
    with np.errstate(divide="ignore"):
        tx = np.where(c > 0, (w - x) / c, -x / c)
        ty = np.where(s > 0, (h - y) / s, -y / s)
    t = np.minimum(np.where(c == 0, np.inf, tx), np.where(s == 0, np.inf, ty))
    cx, cy, r = circle
    b = c * (cx - x) + s * (cy - y)
    disc = b * b - ((cx - x) ** 2 + (cy - y) ** 2 - r * r)
    with np.errstate(invalid="ignore"):
        tc = b - np.sqrt(disc)
    tc = np.where((disc >= 0) & (tc >= 0), tc, np.inf)
    return np.minimum(t, tc)


def make(world, seed: int = 0, **params) -> Lidar:
    params.setdefault("frame", "laser")
    params.setdefault("range", (0.1, 30.0))
    lidar = Lidar("lidar", validate(Lidar.Params, params))
    lidar.configure(world, stream(seed, "sensor", "laser"))
    return lidar


def test_registered_as_the_lidar_sensor_plugin():
    assert lookup("sensor", "lidar") is Lidar


def test_full_circle_beams_do_not_repeat_the_first_one():
    lidar = make(StandIn(room(), Pose2D(3, 4)))
    scan = lidar.measure(0.0)
    assert len(scan.ranges) == 360 and scan.ranges.dtype == np.float32
    assert scan.angle_min == -math.pi
    assert scan.angle_increment == pytest.approx(2 * math.pi / 360)
    assert scan.angle_max == pytest.approx(math.pi - 2 * math.pi / 360)
    np.testing.assert_allclose(scan.angles[-1], scan.angle_max)


def test_partial_span_measures_both_ends():
    lidar = make(
        StandIn(room(), Pose2D(3, 4)), beams=181, angle_min=-math.pi / 2, angle_max=math.pi / 2
    )
    scan = lidar.measure(0.0)
    assert scan.angle_increment == pytest.approx(math.pi / 180)
    assert scan.angle_max == pytest.approx(math.pi / 2)
    assert scan.ranges[0] == pytest.approx(4.0, abs=F32)  # straight down to y = 0
    assert scan.ranges[-1] == pytest.approx(4.0, abs=F32)  # straight up to y = 8


def test_noise_free_ranges_equal_the_analytic_distances():
    pose = Pose2D(3.0, 4.0, 0.3)
    lidar = make(StandIn(room(), pose))
    scan = lidar.measure(1.5)
    want = analytic(pose.x, pose.y, scan.angles + pose.yaw)
    np.testing.assert_allclose(scan.ranges, want, rtol=0, atol=F32)
    # Before the float32 rounding of the message, the lidar's distances are exact.
    np.testing.assert_allclose(lidar.true_ranges(), want, rtol=0, atol=1e-9)
    assert scan.stamp == 1.5 and scan.frame_id == "laser" and scan.scan_time == pytest.approx(0.1)
    # The end points land on the walls or the pillar.
    pts = pose.transform_points(scan.points())
    on_wall = np.minimum.reduce([pts[:, 0], 10 - pts[:, 0], pts[:, 1], 8 - pts[:, 1]])
    on_pillar = np.abs(np.hypot(pts[:, 0] - 7, pts[:, 1] - 4) - 0.5)
    assert np.all(np.minimum(np.abs(on_wall), on_pillar) < 1e-5)


def test_noise_has_the_configured_mean_and_spread():
    sigma = 0.05
    pose = Pose2D(5.0, 2.0, 0.0)
    lidar = make(StandIn(room(), pose), noise_std=sigma)
    want = analytic(pose.x, pose.y, lidar.angles)
    errors = np.concatenate([lidar.measure(0.1 * i).ranges - want for i in range(40)])
    assert abs(errors.mean()) < 4 * sigma / math.sqrt(errors.size)
    assert errors.std() == pytest.approx(sigma, rel=0.05)


def test_out_of_range_conventions_rep117():
    # From (1, 4): the left wall is 1 m away, the right wall 9 m, the pillar 5.5 m.
    world = StandIn(room(), Pose2D(1.0, 4.0, 0.0))
    lidar = make(world, range=(1.5, 6.0), beams=4)  # beams at -pi, -pi/2, 0, pi/2
    r = lidar.measure(0.0).ranges
    assert r[0] == -np.inf  # 1 m: closer than range_min
    assert r[2] == pytest.approx(5.5, abs=F32)
    lidar = make(world, range=(0.5, 5.0), beams=4)
    r = lidar.measure(0.0).ranges
    assert r[0] == pytest.approx(1.0, abs=F32)
    assert r[1] == pytest.approx(4.0, abs=F32) and r[3] == pytest.approx(4.0, abs=F32)
    assert r[2] == np.inf  # the pillar at 5.5 m is beyond range_max


def test_noise_never_changes_a_readings_category():
    # Walls at exactly range_min and range_max from the sensor, heavy noise.
    world = StandIn(room(w=4.0, h=8.0, circles=np.zeros((0, 3))), Pose2D(1.0, 4.0, 0.0))
    lidar = make(world, range=(1.0, 3.0), beams=4, noise_std=0.5)
    lo, hi = np.float32(1.0), np.float32(3.0)
    for i in range(200):
        r = lidar.measure(float(i)).ranges
        assert lo <= r[0] <= hi and lo <= r[2] <= hi  # left wall 1 m, right wall 3 m
        assert r[1] == -np.inf or r[1] == np.inf or lo <= r[1] <= hi
    # A reading clipped to range_max stays <= range_max even after rounding to float32.
    lidar = make(world, range=(0.1, 2.9999999), beams=4, noise_std=0.5)
    for i in range(50):
        r = lidar.measure(float(i)).ranges
        assert float(r[2]) == np.inf or float(r[2]) <= 2.9999999


def test_mounting_pose_is_honoured():
    robot = Pose2D(4.0, 3.0, 0.4)
    mount = (0.3, -0.1, math.pi / 2)
    lidar = make(StandIn(room(), robot), pose=mount)
    sensor = robot @ Pose2D(*mount)
    scan = lidar.measure(0.0)
    np.testing.assert_allclose(
        scan.ranges, analytic(sensor.x, sensor.y, scan.angles + sensor.yaw), rtol=0, atol=F32
    )
    # The same as an unmounted lidar on a robot standing where the sensor is.
    plain = make(StandIn(room(), sensor)).measure(0.0)
    np.testing.assert_allclose(scan.ranges, plain.ranges, rtol=0, atol=F32)


def test_a_moving_obstacle_is_seen_where_it_is_now():
    class Moving(StandIn):
        def __init__(self) -> None:
            super().__init__(room(circles=np.zeros((0, 3))), Pose2D(1.0, 4.0, 0.0))
            self.box_x = 3.0

        def geometry(self) -> Geometry:
            x = self.box_x
            box = np.array([[x, 3.5], [x + 0.5, 3.5], [x + 0.5, 4.5], [x, 4.5]])
            return self._geometry.merged(Geometry([box]))

    world = Moving()
    lidar = make(world, beams=4)
    assert lidar.measure(0.0).ranges[2] == pytest.approx(2.0, abs=F32)
    world.box_x = 6.0
    assert lidar.measure(1.0).ranges[2] == pytest.approx(5.0, abs=F32)


def test_same_seed_same_scans_other_seed_other_noise():
    def scans(seed: int) -> list[np.ndarray]:
        lidar = make(StandIn(room(), Pose2D(3, 4, 0.2)), seed=seed, noise_std=0.02)
        return [lidar.measure(0.1 * i).ranges for i in range(5)]

    a, b, c = scans(11), scans(11), scans(12)
    assert all(np.array_equal(x, y) for x, y in zip(a, b, strict=True))
    assert not np.array_equal(a[0], c[0])


def test_matches_a_direct_ray_cast_in_a_cluttered_scene():
    rng = np.random.default_rng(0)
    polys = [c + rng.uniform(-0.3, 0.3, (4, 2)) for c in rng.uniform(1, 9, (30, 2))]
    g = Geometry([*room(circles=np.zeros((0, 3))).polygons, *polys])
    pose = Pose2D(0.5, 0.5, 0.1)
    lidar = make(StandIn(g, pose), range=(0.0, 8.0))
    want = cast_from_pose(g, pose.as_array(), lidar.angles, 8.0)
    np.testing.assert_allclose(lidar.true_ranges(), want, rtol=0, atol=1e-12)


@pytest.mark.parametrize(
    "params",
    [
        {"range": [2.0, 1.0]},
        {"range": [-0.1, 1.0]},
        {"angle_min": 1.0, "angle_max": 0.5},
        {"angle_min": -4.0, "angle_max": 4.0},
        {"beams": 0},
        {"noise_std": -0.1},
        {"bemas": 10},
    ],
)
def test_bad_params_are_config_errors(params):
    with pytest.raises(ConfigError):
        validate(Lidar.Params, {"frame": "laser", **params})


def test_misspelt_key_suggests_the_right_one():
    with pytest.raises(ConfigError, match="beams"):
        validate(Lidar.Params, {"frame": "laser", "bemas": 10})


# -- with the real World ------------------------------------------------------------------

ROOM_WORLD = """
world: room
bounds: [[0, 0], [10, 8]]
walls: [[[0, 0], [10, 0], [10, 8], [0, 8], [0, 0]]]   # 0.10 thick: inner faces 0.05 in
obstacles:
  - circle: {center: [7.0, 4.0], radius: 0.5}
  - box: {center: [5.0, 1.0], size: [0.4, 0.4], moves: {path: [[5.0, 7.0]], speed: 1.0, loop: true}}
robot:
  footprint: {radius: 0.2}
  pose: [3.0, 4.0, 0.3]
  sensors:
    - lidar: {frame: laser, pose: [0.1, 0.0, 0.0], beams: 360, range: [0.05, 20.0], noise_std: NOISE}
"""


def room_world(noise: float = 0.0, seed: int = 0):
    from btnav.sim.world import World
    from btnav.sim.world_sensors import make_sensors
    from btnav.sim.world_spec import WorldSpec

    world = World(WorldSpec.from_text(ROOM_WORLD.replace("NOISE", str(noise))), seed=seed)
    (lidar,) = make_sensors(world, seed=seed)
    return world, lidar


def test_real_world_scan_matches_the_rooms_inner_faces():
    world, lidar = room_world()
    assert isinstance(lidar, Lidar)
    scan = lidar.measure(world.time)
    sensor = world.robot_pose @ Pose2D(0.1, 0.0, 0.0)
    angles = scan.angles + sensor.yaw
    # Inner faces are 0.05 inside the wall lines: a 9.9 x 7.9 room from (0.05, 0.05).
    want = analytic(
        sensor.x - 0.05, sensor.y - 0.05, angles, w=9.9, h=7.9, circle=(6.95, 3.95, 0.5)
    )
    # The moving box starts at (5, 1): beams that pass it are checked against it instead.
    box = Geometry([np.array([[4.8, 0.8], [5.2, 0.8], [5.2, 1.2], [4.8, 1.2]])])
    want = np.minimum(want, cast_from_pose(box, sensor.as_array(), scan.angles, 20.0))
    np.testing.assert_allclose(scan.ranges, want, rtol=0, atol=F32)


def test_real_world_moving_box_is_seen_where_it_is():
    world, lidar = room_world()
    sensor = world.robot_pose @ Pose2D(0.1, 0.0, 0.0)
    # The beam whose world direction points at x = 5 on the box's route, below the robot.
    target = np.arctan2(1.0 - sensor.y, 5.0 - sensor.x) - sensor.yaw
    beam = int(np.argmin(np.abs(np.angle(np.exp(1j * (lidar.angles - target))))))
    before = float(lidar.measure(world.time).ranges[beam])
    world.step(3.0)  # the box has moved 3 m up its route, out of that beam
    after = float(lidar.measure(world.time).ranges[beam])
    assert after > before + 1.0
    g = world.geometry()
    x, y, yaw = lidar.sensor_pose()
    assert after == pytest.approx(
        float(cast_from_pose(g, (x, y, yaw), lidar.angles[beam : beam + 1], 20.0)[0]), abs=F32
    )


def test_real_world_same_seed_same_noisy_scans():
    def run(seed: int) -> list[np.ndarray]:
        world, lidar = room_world(noise=0.02, seed=seed)
        out = []
        for _ in range(40):  # past the first batch of pre-drawn noise
            world.step(0.1)
            out.append(lidar.measure(world.time).ranges)
        return out

    a, b, c = run(3), run(3), run(4)
    assert all(np.array_equal(x, y) for x, y in zip(a, b, strict=True))
    assert not np.array_equal(a[-1], c[-1])
