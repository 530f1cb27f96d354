"""The obstacle and voxel layers mark what a scan hits and clear what its beams pass through."""

from __future__ import annotations

import numpy as np
import pytest

from btnav.core.errors import FrameError
from btnav.costmap import (
    FREE_SPACE,
    LETHAL_OBSTACLE,
    NO_INFORMATION,
    CostmapROS,
    ObstacleLayer,
    VoxelLayer,
)
from btnav.costmap.costmap_2d import Costmap2D
from btnav.costmap.obstacle_layer import trace_cells
from btnav.params.costmap import CostmapParams


def obstacle_costmap(layer_cls=ObstacleLayer, robot_radius=0.1, **source) -> CostmapROS:
    params = CostmapParams(
        width=6,
        height=6,
        origin_x=-3.0,
        origin_y=-3.0,
        resolution=0.05,
        track_unknown_space=True,
        robot_radius=robot_radius,
    )
    layer_params = layer_cls.Params.model_validate(
        {"observation_sources": "scan", "scan": {"clearing": True, "marking": True, **source}}
    )
    return CostmapROS("c", params, [layer_cls("obstacle_layer", layer_params)])


def lethal_xy(cm: CostmapROS) -> np.ndarray:
    ys, xs = np.nonzero(cm.costmap.costs == LETHAL_OBSTACLE)
    return cm.costmap.map_to_world(np.stack([xs, ys], -1))


def test_marks_the_hits(scan_of, tree_at) -> None:
    cm = obstacle_costmap()
    cm.update(None, [scan_of(1.01)], tree_at(0.0, 0.0, 0.0), now=0.0)
    hits = lethal_xy(cm)
    assert len(hits) > 10
    assert np.allclose(hits[:, 0], 1.025)  # the wall at x = 1.01 m
    assert np.abs(hits[:, 1]).max() <= 0.55
    # The beams cleared the space in front; the space behind the wall stays unknown.
    assert cm.costmap.cost_at([[0.5, 0.0]])[0] == FREE_SPACE
    assert cm.costmap.cost_at([[1.5, 0.0]])[0] == NO_INFORMATION


def test_scan_is_placed_with_the_frame_tree(scan_of, tree_at) -> None:
    cm = obstacle_costmap()
    # Robot at (0.5, -1) facing +y: the wall 1 m ahead is at y = 0.
    cm.update(None, [scan_of(1.01)], tree_at(0.5, -1.0, np.pi / 2), now=0.0)
    hits = lethal_xy(cm)
    assert np.allclose(hits[:, 1], 0.025)
    assert np.abs(hits[:, 0] - 0.5).max() <= 0.55


def test_a_removed_obstacle_is_cleared_by_a_later_scan(scan_of, tree_at) -> None:
    cm = obstacle_costmap()
    tree = tree_at()
    cm.update(None, [scan_of(1.01)], tree, now=0.0)
    assert cm.costmap.cost_at([[1.02, 0.0]])[0] == LETHAL_OBSTACLE
    cm.update(None, [scan_of(2.01)], tree, now=1.0)  # the obstacle moved away
    assert cm.costmap.cost_at([[1.02, 0.0]])[0] == FREE_SPACE
    assert cm.costmap.cost_at([[2.02, 0.0]])[0] == LETHAL_OBSTACLE


def test_ranges_limit_marking_and_clearing(scan_of, tree_at) -> None:
    cm = obstacle_costmap(obstacle_max_range=1.5, raytrace_max_range=1.0)
    cm.update(None, [scan_of(2.01)], tree_at(), now=0.0)
    assert not (cm.costmap.costs == LETHAL_OBSTACLE).any()  # beyond obstacle_max_range
    assert cm.costmap.cost_at([[0.9, 0.0]])[0] == FREE_SPACE
    assert cm.costmap.cost_at([[1.3, 0.0]])[0] == NO_INFORMATION  # beyond raytrace_max_range


def _behind(near, far):
    """A scan that sees `near` where it has returns and `far` elsewhere."""
    ranges = np.where(np.isfinite(near.ranges), near.ranges, far.ranges).astype(np.float32)
    near.ranges = ranges
    return near


def test_an_obstacle_too_far_to_mark_is_not_cleared_while_seen(scan_of, tree_at) -> None:
    # Nav2's ranges: marks to 2.5 m, clears to 3 m. Walking away from a door seen at
    # 1 m, the door must stay in the costmap once it is 2.5-3 m away (Nav2 issue 5476).
    cm = obstacle_costmap(obstacle_max_range=2.5, raytrace_max_range=3.0)
    cm.update(None, [scan_of(1.01)], tree_at(), now=0.0)
    door = lethal_xy(cm)
    for step, x in enumerate((-1.0, -1.7, -1.9), start=1):  # 2.0, 2.7 and 2.9 m away
        cm.update(None, [scan_of(1.01 - x)], tree_at(x, 0.0, 0.0), now=float(step))
        assert (cm.costmap.cost_at(door) == LETHAL_OBSTACLE).all(), f"door lost from x = {x}"
    # Beyond marking range a beam still frees space it has not seen as an obstacle.
    assert cm.costmap.cost_at([[-1.9 + 2.8, 0.7]])[0] == NO_INFORMATION  # no beam went there
    cm.update(None, [scan_of(5.0, half_width=3.0)], tree_at(-1.9, 0.0, 0.0), now=4.0)
    assert cm.costmap.cost_at([[-1.9 + 2.8, 0.7]])[0] == FREE_SPACE


def test_an_obstacle_that_left_is_cleared_within_marking_range_only(scan_of, tree_at) -> None:
    cm = obstacle_costmap(obstacle_max_range=2.5, raytrace_max_range=3.0)
    cm.update(None, [scan_of(1.01)], tree_at(), now=0.0)  # a wall |y| <= 0.5 at 1 m
    gone = [[1.025, 0.4]]  # its end, which leaves: the beams there now reach 4 m
    assert cm.costmap.cost_at(gone)[0] == LETHAL_OBSTACLE
    shorter = _behind(scan_of(2.71, half_width=0.25), scan_of(4.7, half_width=2.0))
    cm.update(None, [shorter], tree_at(-1.7, 0.0, 0.0), now=1.0)  # 2.7 m away
    assert cm.costmap.cost_at(gone)[0] == LETHAL_OBSTACLE  # seen too far to judge
    shorter = _behind(scan_of(1.51, half_width=0.25), scan_of(3.5, half_width=2.0))
    cm.update(None, [shorter], tree_at(-0.5, 0.0, 0.0), now=2.0)  # 1.5 m away
    assert cm.costmap.cost_at(gone)[0] == FREE_SPACE
    assert cm.costmap.cost_at([[1.025, 0.0]])[0] == LETHAL_OBSTACLE  # what is left stays


def test_no_return_clears_only_when_inf_is_valid(scan_of, tree_at) -> None:
    for valid, behind in ((False, NO_INFORMATION), (True, FREE_SPACE)):
        cm = obstacle_costmap(inf_is_valid=valid)
        cm.update(None, [scan_of(None)], tree_at(), now=0.0)
        assert cm.costmap.cost_at([[-2.0, 0.0]])[0] == behind
        assert not (cm.costmap.costs == LETHAL_OBSTACLE).any()


def test_footprint_is_cleared(scan_of, tree_at) -> None:
    cm = obstacle_costmap(robot_radius=0.3)
    cm.update(None, [scan_of(0.2, half_width=0.1)], tree_at(), now=0.0)  # a hit under the robot
    assert not (cm.costmap.costs == LETHAL_OBSTACLE).any()
    cm.update(None, [scan_of(0.5, half_width=0.1)], tree_at(), now=1.0)  # one beyond it
    assert cm.costmap.cost_at([[0.52, 0.0]])[0] == LETHAL_OBSTACLE


def test_voxel_layer_marks_like_the_obstacle_layer(scan_of, tree_at) -> None:
    cm = obstacle_costmap(VoxelLayer)
    cm.update(None, [scan_of(1.01)], tree_at(), now=0.0)
    assert cm.costmap.cost_at([[1.02, 0.0]])[0] == LETHAL_OBSTACLE
    # A planar scan fills one voxel per column: Nav2 marks only when mark_threshold is 0.
    strict = obstacle_costmap(VoxelLayer)
    strict.layer("obstacle_layer").params.mark_threshold = 1
    strict.update(None, [scan_of(1.01)], tree_at(), now=0.0)
    assert not (strict.costmap.costs == LETHAL_OBSTACLE).any()


def test_an_unknown_sensor_frame_names_the_frames(scan_of, tree_at) -> None:
    cm = obstacle_costmap(sensor_frame="lidar_link")
    with pytest.raises(FrameError, match="lidar_link"):
        cm.update(None, [scan_of(1.01)], tree_at(), now=0.0)


def test_traced_cells_are_a_connected_line_per_beam() -> None:
    grid = Costmap2D.empty(100, 100, 0.1)
    origin = np.array([5.05, 5.05])
    angles = np.linspace(0, 2 * np.pi, 37)
    ends = origin + 3.0 * np.stack([np.cos(angles), np.sin(angles)], -1)
    for end in ends:  # each beam: cells step by at most one along each axis
        ys, xs = trace_cells(grid, origin, origin[None], end[None])
        steps = np.abs(np.diff(np.stack([xs, ys], -1), axis=0))
        assert steps.max() <= 1 and (xs[0], ys[0]) == (50, 50)
        assert (xs[-1], ys[-1]) == tuple(np.floor(end / 0.1).astype(int))
    # A ray leaving the map is cut at its edge.
    ys, xs = trace_cells(grid, origin, origin[None], np.array([[50.0, 5.05]]))
    assert xs.max() == 99 and (ys == 50).all()
