"""The world file and the scene it builds: what a user sees when loading or stepping a world."""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np
import pytest

from btnav.core.errors import BtnavError, WorldError
from btnav.core.messages import Twist
from btnav.core.resources import bundled_dir
from btnav.sim.geometry import Geometry
from btnav.sim.world import World
from btnav.sim.world_spec import WorldSpec

OFFICE = bundled_dir("worlds") / "small_office.yaml"


def world_from(text: str, name: str = "test_world.yaml") -> World:
    return World(WorldSpec.from_text(text, name))


def write_variant(tmp_path: Path, old: str, new: str) -> Path:
    text = OFFICE.read_text()
    assert old in text, old
    out = tmp_path / "office_variant.yaml"
    out.write_text(text.replace(old, new, 1))
    return out


def line_of(path: Path, needle: str) -> int:
    for n, line in enumerate(path.read_text().splitlines(), 1):
        if needle in line:
            return n
    raise AssertionError(needle)


# -- loading ---------------------------------------------------------------------------


def test_small_office_loads_with_rooms_doors_and_a_mover():
    world = World.from_file(OFFICE, seed=3)
    assert world.spec.world == "small_office"
    assert world.bounds == ((0.0, 0.0), (12.0, 8.0))
    assert world.file == str(OFFICE)
    assert world.robot_pose.x == 1.0 and world.robot_pose.y == 1.0
    kinds = {o.kind for o in world.spec.obstacles}
    assert kinds == {"box", "circle", "polygon"}
    assert sum(o.moves is not None for o in world.spec.obstacles) == 1
    assert world.time == 0.0 and world.collisions == 0 and not world.in_contact
    [(name, params, line)] = world.sensor_specs()
    assert name == "lidar" and params["frame"] == "laser"
    assert line == line_of(OFFICE, "- lidar:")


def test_office_doorways_are_at_least_0_9_m_wide():
    """Three doorways join the rooms: a 0.44 m robot passes through each one."""
    world = World.from_file(OFFICE)
    g = world.geometry()
    for door in [(4.0, 3.5), (4.0, 6.5), (8.5, 4.5)]:
        # Probe points across the doorway: nothing solid within 0.45 m of its centre.
        for dx in np.linspace(-0.45, 0.45, 19):
            p = np.array(door) + (np.array([0.0, dx]) if door[0] == 4.0 else np.array([dx, 0.0]))
            assert not _inside_any(g, p), (door, p)


def _inside_any(g: Geometry, p: np.ndarray) -> bool:
    from matplotlib.path import Path as MplPath

    if len(g.circles) and np.any(np.hypot(*(g.circles[:, :2] - p).T) <= g.circles[:, 2]):
        return True
    return any(MplPath(poly).contains_point(p) for poly in g.polygons)


@pytest.mark.parametrize(
    ("old", "new", "bad", "right"),
    [
        ("obstacles:", "obstacels:", "obstacels", "obstacles"),
        ("radius: 0.25}", "raduis: 0.25}", "raduis", "radius"),
        ("footprint: {radius: 0.22}", "footprint: {raduis: 0.22}", "raduis", "radius"),
        ("thickness: 0.12}", "thicknes: 0.12}", "thicknes", "thickness"),
        ("- box: {center: [6.5", "- boxx: {center: [6.5", "boxx", "box"),
        ("limits: {v_max", "limits: {vmax", "vmax", "v_max"),
        ("speed: 0.3", "sped: 0.3", "sped", "speed"),
    ],
)
def test_misspelt_key_names_file_line_and_right_spelling(tmp_path, old, new, bad, right):
    path = write_variant(tmp_path, old, new)
    with pytest.raises(WorldError) as info:
        World.from_file(path)
    err = info.value
    assert err.file == str(path)
    assert err.line == line_of(path, bad + ":")
    assert err.suggestion == right
    assert f"{path}:{err.line}:" in str(err) and f"did you mean '{right}'" in str(err)


@pytest.mark.parametrize(
    ("old", "new", "key", "words"),
    [
        ("size: [1.0, 0.8]", "size: [-1.0, 0.8]", "obstacles[3].box.size[0]", "greater than"),
        ("radius: 0.22", "radius: -0.22", "robot.footprint.radius", "greater than"),
        ("v_max: 0.5", "v_max: fast", "robot.limits.v_max", "valid number"),
        ("v_max: 0.5", "v_max: true", "robot.limits.v_max", "true/false"),
        ("speed: 0.3", "speed: .inf", "speed", "finite"),
        ("pose: [1.0, 1.0, 0.0]", "pose: [1.0, 1.0]", "robot.pose", "[x, y, yaw]"),
        ("noise: [0.002, 0.0005, 0.0001, 0.0001]", "noise: [0.002, 0.0005]", "noise", "alpha4"),
        ("bounds: [[0, 0], [12, 8]]", "bounds: [[0, 0], [-12, 8]]", "bounds", "max > min"),
        ("  - [[4, 0], [4, 3]]", "  - [[4, 0]]", "walls[1].points", "at least 2"),
    ],
)
def test_wrong_values_are_located_errors(tmp_path, old, new, key, words):
    path = write_variant(tmp_path, old, new)
    with pytest.raises(WorldError) as info:
        World.from_file(path)
    assert key in str(info.value.key)
    assert words in str(info.value)
    assert info.value.line == line_of(path, new.split("\n")[0].strip())


def test_self_intersecting_polygon_is_a_clear_error(tmp_path):
    sofa = "[[10.0, 2.2], [11.6, 2.2], [11.6, 3.8], [11.1, 3.8], [11.1, 2.7], [10.0, 2.7]]"
    path = write_variant(tmp_path, sofa, "[[10.0, 2.2], [11.6, 3.8], [11.6, 2.2], [10.0, 3.8]]")
    with pytest.raises(WorldError, match="crosses itself") as info:
        World.from_file(path)
    assert info.value.key == "obstacles[5].polygon.points"


def test_an_obstacle_with_two_shapes_is_an_error():
    text = """
bounds: [[0, 0], [5, 5]]
obstacles:
  - box: {center: [3, 3], size: [1, 1]}
    circle: {center: [3, 3], radius: 1}
robot: {pose: [1, 1, 0]}
"""
    with pytest.raises(WorldError, match="one obstacle per list item") as info:
        world_from(text)
    assert info.value.line == 4


@pytest.mark.parametrize(
    ("pose", "hit"),
    [
        ("[2.0, 4.6, 0.0]", "obstacles[0] (box)"),  # inside the desk, centres coincide
        ("[4.0, 1.0, 0.0]", "walls[1]"),  # on the x = 4 wall
        ("[0.16, 1.0, 0.0]", "walls[0]"),  # footprint reaches into the outer wall
        ("[6.0, 5.6, 0.0]", "obstacles[8] (circle)"),  # where the moving obstacle starts
        ("[10.3, 2.45, 0.0]", "obstacles[5] (polygon)"),  # in the sofa's arm
    ],
)
def test_start_pose_overlapping_something_names_it(tmp_path, pose, hit):
    path = write_variant(tmp_path, "pose: [1.0, 1.0, 0.0]", f"pose: {pose}")
    with pytest.raises(WorldError) as info:
        World.from_file(path)
    err = info.value
    assert err.key == "robot.pose" and err.line == line_of(path, "pose: [")
    assert "overlaps" in str(err) and hit in str(err)


def test_start_pose_error_names_the_line_of_what_it_hits(tmp_path):
    path = write_variant(tmp_path, "pose: [1.0, 1.0, 0.0]", "pose: [2.0, 4.6, 0.0]")
    with pytest.raises(WorldError) as info:
        World.from_file(path)
    assert f"(line {line_of(path, 'box: {center: [2.0, 4.6]')})" in str(info.value)


def test_start_pose_just_clear_of_a_wall_is_fine(tmp_path):
    path = write_variant(tmp_path, "pose: [1.0, 1.0, 0.0]", "pose: [0.28, 1.0, 0.0]")
    assert World.from_file(path).robot_pose.x == 0.28


def test_start_pose_outside_the_bounds_is_an_error(tmp_path):
    path = write_variant(tmp_path, "pose: [1.0, 1.0, 0.0]", "pose: [20.0, 1.0, 0.0]")
    with pytest.raises(WorldError, match="outside the world's bounds"):
        World.from_file(path)


def test_missing_file_and_empty_file_are_btnav_errors(tmp_path):
    with pytest.raises(BtnavError, match="not found"):
        World.from_file(tmp_path / "nope.yaml")
    (tmp_path / "empty.yaml").write_text("")
    with pytest.raises(WorldError, match="empty"):
        World.from_file(tmp_path / "empty.yaml")
    (tmp_path / "list.yaml").write_text("- 1\n- 2\n")
    with pytest.raises(WorldError, match="is a mapping"):
        World.from_file(tmp_path / "list.yaml")


# -- walls and polygons ------------------------------------------------------------------


def test_thick_wall_is_centred_with_closed_joints():
    world = world_from(
        """
bounds: [[-1, -1], [5, 5]]
walls:
  - {points: [[0, 0], [4, 0], [4, 4]], thickness: 0.4}
robot: {pose: [2, 2, 0], footprint: {radius: 0.1}}
"""
    )
    g = world.geometry()
    assert _inside_any(g, np.array([2.0, 0.19])) and _inside_any(g, np.array([2.0, -0.19]))
    assert not _inside_any(g, np.array([2.0, 0.21]))
    # The outer corner is closed (round join), the far ends are butt ends.
    assert _inside_any(g, np.array([4.1, -0.1]))
    assert not _inside_any(g, np.array([-0.05, 0.0]))
    assert not _inside_any(g, np.array([4.0, 4.05]))


def test_concave_polygon_is_solid_only_where_drawn():
    """A robot fits into the notch of an L-shaped obstacle but not into its arms."""
    text = """
bounds: [[0, 0], [6, 6]]
obstacles:
  - polygon: {points: [[1, 1], [5, 1], [5, 2], [2, 2], [2, 5], [1, 5]]}
robot: {pose: %s, footprint: {radius: 0.3}}
"""
    assert world_from(text % "[3.5, 3.5, 0]").robot_pose.x == 3.5  # in the notch: fine
    with pytest.raises(WorldError, match="obstacles"):
        world_from(text % "[1.5, 4.0, 0]")  # in the vertical arm
    with pytest.raises(WorldError, match="obstacles"):
        world_from(text % "[4.0, 1.5, 0]")  # in the horizontal arm


def test_robot_drives_into_the_notch_of_a_concave_polygon_and_stops_at_its_inner_corner():
    world = world_from(
        """
bounds: [[0, 0], [6, 6]]
obstacles:
  - polygon: {points: [[1, 1], [5, 1], [5, 2], [2, 2], [2, 5], [1, 5]]}
robot: {pose: [4.0, 4.0, -2.356194490192345], footprint: {radius: 0.2},
        limits: {v_max: 0.5, a_max: 2.0}}
"""
    )
    world.set_cmd_vel(Twist(0.5, 0.0, 0.0))
    for _ in range(800):
        world.step(0.01)
    pose = world.robot_pose
    assert world.collisions >= 1
    assert pose.x >= 2.2 - 0.005 and pose.y >= 2.2 - 0.005
    assert pose.x < 2.5 and pose.y < 2.5  # it did get into the corner


# -- moving obstacles --------------------------------------------------------------------


MOVER = """
bounds: [[0, 0], [10, 10]]
obstacles:
  - box: {center: [2, 8], size: [0.4, 0.4],
          moves: {path: [[2, 8], [6, 8], [6, 9]], speed: 0.5, loop: %s}}
robot: {pose: [1, 1, 0]}
"""


def _mover_centre(world: World) -> np.ndarray:
    box = world.geometry().polygons[-1]
    return box.mean(axis=0)


def test_moving_obstacle_follows_its_path_and_ping_pongs_when_looping():
    world = world_from(MOVER % "true")
    route_len = 5.0  # 4 m along x, then 1 m up
    expect = {
        0.0: (2, 8),
        4.0: (4, 8),
        8.0: (6, 8),
        9.0: (6, 8.5),
        10.0: (6, 9),  # the end: turns back
        11.0: (6, 8.5),
        14.0: (5, 8),
        20.0: (2, 8),  # back at the start after 2 * route_len / speed
        24.0: (4, 8),
    }
    for when, where in expect.items():
        while world.time < when - 1e-9:
            world.step(0.05)
        assert world.time == pytest.approx(when)
        assert _mover_centre(world) == pytest.approx(where, abs=1e-9), when
    # After a whole period (2 * route_len / speed) it is back where it started.
    assert 2 * route_len / 0.5 == 20.0


def test_moving_obstacle_stops_at_the_last_point_without_loop():
    world = world_from(MOVER % "false")
    for _ in range(300):  # 15 s, route takes 10 s
        world.step(0.05)
    assert _mover_centre(world) == pytest.approx((6, 9), abs=1e-12)


def test_position_does_not_depend_on_the_step_size():
    a, b = world_from(MOVER % "true"), world_from(MOVER % "true")
    for _ in range(700):
        a.step(0.01)
    for _ in range(7):
        b.step(1.0)  # split into 0.01 s sub-steps internally
    assert a.time == b.time == 7.0
    np.testing.assert_array_equal(_mover_centre(a), _mover_centre(b))


def test_a_moving_obstacle_pushes_a_robot_and_counts_as_a_collision():
    world = world_from(
        """
bounds: [[0, 0], [10, 10]]
obstacles:
  - circle: {center: [2, 5], radius: 0.3, moves: {path: [[8, 5]], speed: 0.5}}
robot: {pose: [4, 5, 1.57], footprint: {radius: 0.2}}
"""
    )
    for _ in range(600):
        world.step(0.01)
    assert world.collisions == 1
    assert world.robot_pose.x > 4.5  # it was shoved along


def test_geometry_has_the_mover_where_it_is_and_caches_the_static_part():
    world = World.from_file(OFFICE)
    g0 = world.geometry()
    static = world._static_geometry
    n_static = len(static.polygons)
    assert len(g0.polygons) == n_static and len(g0.circles) == len(static.circles) + 1
    assert g0.circles[-1].tolist() == [6.0, 5.6, 0.25]
    for _ in range(100):
        world.step(0.01)
    g1 = world.geometry()
    assert g1.circles[-1, 0] == pytest.approx(6.3) and g1.circles[-1, 1] == 5.6
    assert world._static_geometry is static
    assert g1.segments.shape == (len(static.segments), 4)


def test_time_is_exact_after_many_steps():
    world = world_from(MOVER % "true")
    for _ in range(1000):
        world.step(0.01)
    assert world.time == 10.0
    with pytest.raises(ValueError):
        world.step(-0.01)


# -- determinism -------------------------------------------------------------------------


def _command(k: int) -> Twist:
    """A fixed command sequence: into the x = 4 wall, back out, then a long curve."""
    if k < 800:
        return Twist(0.5, 0, 0.0)
    if k < 1000:
        return Twist(-0.3, 0, 1.0)
    return Twist(0.5, 0, 0.4)


def test_two_runs_with_one_seed_are_bit_identical():
    a = World.from_file(OFFICE, seed=7)
    b = World.from_file(OFFICE, seed=7)
    other = World.from_file(OFFICE, seed=1)  # stepped in between: shared state would show
    ta, tb = [], []
    for k in range(1500):
        for world, out in ((a, ta), (other, None), (b, tb)):
            world.set_cmd_vel(_command(k) if out is not None else Twist(0.3, 0, -0.5))
            world.step(0.01)
            if out is not None:
                p = world.robot_pose
                out.append((p.x, p.y, p.yaw, world.robot_twist.linear_x))
    assert ta == tb  # exact float equality
    assert a.collisions == b.collisions and a.collisions > 0
    np.testing.assert_array_equal(a.geometry().circles, b.geometry().circles)


def test_cmd_vel_must_be_finite():
    world = World.from_file(OFFICE)
    with pytest.raises(ValueError):
        world.set_cmd_vel(Twist(math.nan, 0, 0))
