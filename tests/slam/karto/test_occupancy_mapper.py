"""Karto's occupancy grid from scans: walls where the beams end, free where they pass."""

from __future__ import annotations

import numpy as np
import pytest

from btnav.core import fmath
from btnav.maps import FREE, OCCUPIED, UNKNOWN
from btnav.slam.karto.occupancy_mapper import MapTooLargeError, OccupancyMapper

RES = 0.05
#: A square room's walls: x = X0, x = X1, y = Y0, y = Y1 (off the cell borders on purpose).
X0, X1, Y0, Y1 = -2.01, 2.52, -1.51, 2.02
ANGLES = np.linspace(-np.pi, np.pi, 720, endpoint=False)
LIDAR = np.array([0.1, 0.0, 0.0])  # the sensor in the base frame
POSES = np.array(
    [[0.0, 0.0, 0.0], [1.0, 0.5, 0.7], [-1.0, 1.0, -2.0], [1.5, -0.8, 2.9], [-1.2, -0.9, 1.4]]
)


def room_ranges(pose: np.ndarray, offset: np.ndarray = LIDAR, box=(X0, Y0, X1, Y1)) -> np.ndarray:
    """Exact ranges from the sensor of a robot at `pose` to the walls of an empty box room."""
    x0, y0, x1, y1 = box
    s0, c0 = fmath.sincos(pose[2])
    sx = pose[0] + c0 * offset[0] - s0 * offset[1]
    sy = pose[1] + s0 * offset[0] + c0 * offset[1]
    s, c = fmath.sincos(pose[2] + offset[2] + ANGLES)
    with np.errstate(divide="ignore"):
        tx = np.where(c > 0, (x1 - sx) / c, np.where(c < 0, (x0 - sx) / c, np.inf))
        ty = np.where(s > 0, (y1 - sy) / s, np.where(s < 0, (y0 - sy) / s, np.inf))
    return np.minimum(tx, ty)


def room_map(poses: np.ndarray = POSES, **kwargs) -> OccupancyMapper:
    mapper = OccupancyMapper(RES, 25.0, **kwargs)
    for p in poses:
        mapper.add_scan(p, room_ranges(p), ANGLES, LIDAR)
    return mapper


def centres_of(grid, value: int) -> np.ndarray:
    return grid.cell_to_world(np.argwhere(grid.data == value))


def distance_to_walls(pts: np.ndarray, box=(X0, Y0, X1, Y1)) -> np.ndarray:
    x0, y0, x1, y1 = box
    x, y = pts[:, 0], pts[:, 1]
    inside_x = np.clip(x, x0, x1)
    inside_y = np.clip(y, y0, y1)
    d_vertical = np.minimum(np.abs(x - x0), np.abs(x - x1)) + np.abs(y - inside_y)
    d_horizontal = np.minimum(np.abs(y - y0), np.abs(y - y1)) + np.abs(x - inside_x)
    return np.minimum(d_vertical, d_horizontal)


def test_walls_are_occupied_inside_free_and_outside_unknown():
    grid = room_map().grid()
    assert grid.resolution == RES and grid.frame_id == "map"

    occupied = centres_of(grid, OCCUPIED)
    assert len(occupied) > 0
    # every occupied cell lies on a wall, within one cell
    assert distance_to_walls(occupied).max() <= RES
    # and the walls are drawn: cells along each wall (corners aside) are nearly all occupied
    t = np.linspace(0.1, 0.9, 200)
    walls = np.concatenate(
        [
            np.column_stack([np.full_like(t, X0), Y0 + t * (Y1 - Y0)]),
            np.column_stack([np.full_like(t, X1), Y0 + t * (Y1 - Y0)]),
            np.column_stack([X0 + t * (X1 - X0), np.full_like(t, Y0)]),
            np.column_stack([X0 + t * (X1 - X0), np.full_like(t, Y1)]),
        ]
    )
    cells = grid.world_to_cell(walls)
    assert grid.in_bounds(cells).all()
    assert np.mean(grid.data[cells[:, 0], cells[:, 1]] == OCCUPIED) > 0.95

    # the inside (two cells away from the walls) is free, and nothing there is occupied
    rows, cols = np.indices(grid.data.shape)
    centres = grid.cell_to_world(np.stack([rows.ravel(), cols.ravel()], -1))
    values = grid.data.ravel()
    x, y = centres[:, 0], centres[:, 1]
    inside = (x > X0 + 2 * RES) & (x < X1 - 2 * RES) & (y > Y0 + 2 * RES) & (y < Y1 - 2 * RES)
    assert np.all(values[inside] == FREE)
    # no beam went through a wall: everything more than a cell outside is unknown
    outside = (x < X0 - RES) | (x > X1 + RES) | (y < Y0 - RES) | (y > Y1 + RES)
    assert np.all(values[outside] == UNKNOWN)
    # and the map is cropped to what the beams reached: the room plus at most a cell
    assert grid.origin.x >= X0 - 2 * RES and grid.origin.y >= Y0 - 2 * RES
    assert grid.origin.x + grid.width * RES <= X1 + 2 * RES
    assert grid.origin.y + grid.height * RES <= Y1 + 2 * RES


def test_the_cell_lattice_is_anchored_at_the_first_pose():
    poses = POSES + np.array([0.013, -0.027, 0.0])
    grid = room_map(poses).grid()
    cells_x = (grid.origin.x - poses[0, 0]) / RES
    cells_y = (grid.origin.y - poses[0, 1]) / RES
    assert cells_x == pytest.approx(round(cells_x), abs=1e-9)
    assert cells_y == pytest.approx(round(cells_y), abs=1e-9)


def test_a_max_range_reading_marks_free_space_but_no_wall():
    mapper = OccupancyMapper(RES, 1.0)
    far = np.full(ANGLES.shape, 1.5)  # beyond max_laser_range: traced to 1.0 m, no hit
    for _ in range(3):
        mapper.add_scan((0.0, 0.0, 0.0), far, ANGLES)
    grid = mapper.grid()
    assert not np.any(grid.data == OCCUPIED)
    free = centres_of(grid, FREE)
    radius = np.hypot(free[:, 0], free[:, 1])
    assert radius.max() <= 1.0 + RES
    cells = grid.world_to_cell([[0.0, 0.0], [0.5, 0.0], [0.0, -0.6]])
    assert np.all(grid.data[cells[:, 0], cells[:, 1]] == FREE)

    # the same beams ending just short of max_laser_range draw a ring of wall
    near = OccupancyMapper(RES, 1.0)
    for _ in range(3):
        near.add_scan((0.0, 0.0, 0.0), np.full(ANGLES.shape, 0.9), ANGLES)
    ring = centres_of(near.grid(), OCCUPIED)
    assert len(ring) > 50
    assert np.abs(np.hypot(ring[:, 0], ring[:, 1]) - 0.9).max() <= RES


def test_readings_that_are_not_readings_mark_nothing():
    mapper = OccupancyMapper(RES, 10.0)
    bad = np.array([np.nan, np.inf, -np.inf, 0.0, -1.0] * 20)
    angles = np.linspace(-1.0, 1.0, bad.size)
    for _ in range(3):
        mapper.add_scan((0.0, 0.0, 0.0), bad, angles)
    assert np.all(mapper.grid().data == UNKNOWN)


def test_a_wall_needs_more_than_min_pass_through_and_a_hit_ratio_above_the_threshold():
    # one beam straight ahead, ending 1 m away: its end cell counts a pass and, as Karto,
    # a pass and a hit more, i.e. 2 passes and 1 hit per scan
    angles = np.array([0.0])
    mapper = OccupancyMapper(RES, 10.0)
    mapper.add_scan((0.0, 0.0, 0.0), np.array([1.02]), angles)
    wall = mapper.grid()
    end = wall.world_to_cell([[1.02, 0.0]])[0]
    assert wall.data[end[0], end[1]] == UNKNOWN  # 2 passes: not more than min_pass_through
    mapper.add_scan((0.0, 0.0, 0.0), np.array([1.02]), angles)
    wall = mapper.grid()
    assert wall.data[end[0], end[1]] == OCCUPIED  # 4 passes, 2 hits
    # beams passing through it afterwards wear it down to free (hits/passes <= 0.1)
    for _ in range(16):
        mapper.add_scan((0.0, 0.0, 0.0), np.array([3.0]), angles)
    wall = mapper.grid()
    assert wall.data[end[0], end[1]] == FREE  # 20 passes, 2 hits: ratio 0.1 is not above


def test_rebuild_with_the_same_poses_gives_the_same_map():
    incremental = room_map()
    scans = [(room_ranges(p), ANGLES, LIDAR) for p in POSES]
    before = incremental.grid()
    incremental.rebuild(POSES, scans)
    assert incremental.grid() == before
    fresh = OccupancyMapper(RES, 25.0)
    fresh.rebuild(POSES, scans)
    assert fresh.grid() == before


def test_rebuild_with_shifted_poses_moves_the_walls():
    mapper = room_map()
    scans = [(room_ranges(p), ANGLES, LIDAR) for p in POSES]
    before = mapper.grid()
    shift = np.array([0.3, -0.2, 0.0])
    mapper.rebuild(POSES + shift, scans)
    after = mapper.grid()
    # the same room, 0.3 m right and 0.2 m down
    moved = centres_of(after, OCCUPIED)
    box = (X0 + 0.3, Y0 - 0.2, X1 + 0.3, Y1 - 0.2)
    assert distance_to_walls(moved, box).max() <= RES
    # and off the old walls (but where a moved wall crosses an old one)
    assert np.mean(distance_to_walls(moved) <= RES) < 0.05
    # on the same lattice: the origins differ by whole cells
    dx = (after.origin.x - before.origin.x) / RES
    assert dx == pytest.approx(round(dx), abs=1e-9)


def test_a_rotated_sensor_mount_is_taken_into_account():
    mount = np.array([0.2, 0.1, np.pi / 2])
    mapper = OccupancyMapper(RES, 25.0)
    for p in POSES:
        mapper.add_scan(p, room_ranges(p, mount), ANGLES, mount)
    occupied = centres_of(mapper.grid(), OCCUPIED)
    assert len(occupied) > 100
    assert distance_to_walls(occupied).max() <= RES


def test_the_map_grows_to_rooms_far_apart():
    mapper = room_map()
    far_room = (X0 + 40.0, Y0 - 30.0, X1 + 40.0, Y1 - 30.0)
    for p in POSES + np.array([40.0, -30.0, 0.0]):
        mapper.add_scan(p, room_ranges(p, LIDAR, far_room), ANGLES, LIDAR)
    grid = mapper.grid()
    occupied = centres_of(grid, OCCUPIED)
    d = np.minimum(distance_to_walls(occupied), distance_to_walls(occupied, far_room))
    assert d.max() <= RES
    assert (occupied[:, 0] > 30).sum() > 100 and (occupied[:, 0] < 5).sum() > 100


def test_bad_arguments_are_refused():
    with pytest.raises(ValueError, match="resolution"):
        OccupancyMapper(0.0, 10.0)
    mapper = OccupancyMapper(RES, 10.0)
    with pytest.raises(ValueError, match="differ in length"):
        mapper.add_scan((0, 0, 0), np.ones(3), np.zeros(4))
    with pytest.raises(ValueError, match="one row per scan"):
        mapper.rebuild(np.zeros((2, 3)), [(np.ones(3), np.zeros(3), (0, 0, 0))])
    with pytest.raises(MapTooLargeError, match="diverged, or the area needs a coarser resolution"):
        mapper.add_scan((0, 0, 0), np.ones(3), np.zeros(3))
        mapper.add_scan((1e6, 0, 0), np.ones(3), np.zeros(3))


def test_a_building_complex_fits():
    """Freiburg's hospital log spans ~400 m of odometry: its map is large, not diverged."""
    mapper = OccupancyMapper(RES, 20.0)
    mapper.add_scan((0, 0, 0), np.ones(3), np.zeros(3))
    mapper.add_scan((420.0, -130.0, 0), np.ones(3), np.zeros(3))
    assert mapper.grid().size_m[0] > 420.0
