"""Cartographer's engine on recorded logs (`run_cartographer`), on synthetic logs whose
truth is known: a room of walls, scans ray-cast from the true poses, odometry as the
test makes it (stalled, or far from the origin)."""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np
import pytest

from btnav.core.geometry import compose_arrays, normalize_angle, relative_arrays
from btnav.core.messages import LaserScan
from btnav.slam.cartographer.config import load_cartographer_config
from btnav.slam.cartographer.offline import fresh_odometry, run_cartographer
from btnav.slam.cartographer.slam import CartographerMapper, LocalTrajectoryBuilder
from btnav.slam.cartographer.submaps import RangeData
from btnav.slam.logs import RecordedLog

pytest.importorskip("lupa")  # the `cartographer` extra

REPO = Path(__file__).resolve().parents[3]
LUA = REPO / "params" / "cartographer_2d.lua"

#: A 9 x 7 m room with a pillar, a recess and a box: no symmetry a match could slip along.
WALLS = np.array(
    [
        (0.0, 0.0, 9.0, 0.0), (9.0, 0.0, 9.0, 4.5), (9.0, 4.5, 7.5, 4.5), (7.5, 4.5, 7.5, 7.0),
        (7.5, 7.0, 0.0, 7.0), (0.0, 7.0, 0.0, 0.0),
        (3.5, 2.8, 5.0, 2.8), (5.0, 2.8, 5.0, 3.6), (5.0, 3.6, 3.5, 3.6), (3.5, 3.6, 3.5, 2.8),
        (1.0, 5.6, 1.8, 5.6), (1.8, 5.6, 1.8, 6.3), (1.8, 6.3, 1.0, 6.3), (1.0, 6.3, 1.0, 5.6),
        (6.2, 0.0, 6.2, 0.6), (6.2, 0.6, 6.9, 0.6), (6.9, 0.6, 6.9, 0.0),
    ]
)  # fmt: skip
BEAMS = 360


def scan_from(pose: np.ndarray, stamp: float) -> LaserScan:
    """A 360-beam scan ray-cast against WALLS from `pose` (no noise); +inf past 8 m."""
    angles = pose[2] + np.arange(BEAMS) * (2 * math.pi / BEAMS) - math.pi
    d = np.stack([np.cos(angles), np.sin(angles)], axis=1)[:, None, :]  # (B, 1, 2)
    a, b = WALLS[None, :, :2], WALLS[None, :, 2:]
    e = b - a
    w = a - pose[None, None, :2]
    den = d[..., 0] * e[..., 1] - d[..., 1] * e[..., 0]
    with np.errstate(divide="ignore", invalid="ignore"):
        t = (w[..., 0] * e[..., 1] - w[..., 1] * e[..., 0]) / den
        u = (w[..., 0] * d[..., 1] - w[..., 1] * d[..., 0]) / den
    t = np.where((np.abs(den) > 1e-12) & (t > 0) & (u >= 0) & (u <= 1), t, np.inf)
    r = t.min(axis=1)
    r[r >= 8.0] = np.inf
    inc = 2 * math.pi / BEAMS
    return LaserScan(stamp, "laser", -math.pi, math.pi - inc, inc, 0.12, 8.0, r.astype(np.float32))


def synthetic_log(truth: np.ndarray, odom: np.ndarray, dt: float = 0.2) -> RecordedLog:
    stamps = np.arange(len(truth)) * dt
    scans = [scan_from(p, float(t)) for p, t in zip(truth, stamps, strict=True)]
    return RecordedLog(Path("synthetic.clf"), scans, stamps, odom, duration=float(stamps[-1]))


def turn_then_drive() -> np.ndarray:
    """Turning on the spot at 10 degrees a scan for 18 scans, then 2 m ahead."""
    turn = [(2.5, 1.5, math.radians(10.0 * k)) for k in range(19)]
    yaw = turn[-1][2]
    drive = [(2.5 + 0.1 * k * math.cos(yaw), 1.5 + 0.1 * k * math.sin(yaw), yaw) for k in range(1, 21)]  # fmt: skip
    return np.array(turn + drive)


def test_a_repeated_odometry_pose_is_a_stale_reading():
    stamps = np.arange(6) * 0.2
    poses = np.array([[0, 0, 0], [0.1, 0, 0.1], [0.1, 0, 0.1], [0.1, 0, 0.1], [0.4, 0, 0.4], [0.5, 0, 0.5]], float)  # fmt: skip
    log = RecordedLog(Path("x.clf"), [], stamps, poses)
    fresh = fresh_odometry(log)
    assert fresh.odom_stamps.tolist() == stamps[[0, 1, 4, 5]].tolist()
    # the stall's scans are placed on the way from the last new pose to the next
    np.testing.assert_allclose(fresh.odom_at(0.4), [0.2, 0.0, 0.2], atol=1e-12)
    same = RecordedLog(Path("x.clf"), [], stamps[:2], poses[:2])
    assert fresh_odometry(same) is same


def test_an_odometry_stall_while_turning_does_not_turn_the_map():
    """Odometry that repeats one pose for five scans of a 10-degree-a-scan turn, then
    jumps by 60 degrees at once (as MIT CSAIL's log does), would have local SLAM turn
    50 degrees too far, outside its real-time matcher's window."""
    truth = turn_then_drive()
    odom = truth.copy()
    odom[5:10] = odom[4]  # stalled for five scans, caught up at scan 10
    log = synthetic_log(truth, odom)
    result = run_cartographer(log, load_cartographer_config(LUA))
    err = relative_arrays(result.poses[:1], result.poses) - relative_arrays(truth[:1], truth)
    assert np.abs(normalize_angle(err[:, 2])).max() < math.radians(1.5)
    assert np.hypot(err[:, 0], err[:, 1]).max() < 0.05


def room_tour() -> np.ndarray:
    """Twice round the room's free ring, 0.1 m a scan, turning smoothly at the corners."""
    corners = [(1.3, 1.4), (7.8, 1.4), (7.8, 3.5), (6.3, 5.2), (2.8, 5.2), (2.4, 1.4)]
    pts = []
    for _lap in range(2):
        for (ax, ay), (bx, by) in zip(corners, corners[1:] + corners[:1], strict=True):
            n = max(1, int(math.hypot(bx - ax, by - ay) / 0.1))
            pts += [(ax + (bx - ax) * k / n, ay + (by - ay) * k / n) for k in range(n)]
    xy = np.array(pts)
    step = np.diff(xy, axis=0, append=xy[:1])
    yaw = np.unwrap(np.arctan2(step[:, 1], step[:, 0]))
    # a heading that follows the path, smoothed so no scan turns by more than ~15 degrees
    kernel = np.ones(5) / 5
    yaw = np.convolve(np.pad(yaw, 2, mode="edge"), kernel, mode="valid")
    return np.column_stack([xy, normalize_angle(yaw)])


def test_a_loop_closure_relates_the_poses_it_joins_far_from_the_origin(tmp_path):
    """A constraint between a node and a finished submap is formed in the submap's own
    frame: after the whole graph is moved 60 m and turned 2 rad away from local SLAM's
    frame (as an optimisation may move it after a long drift), every loop closure still
    equals the true pose of its node seen from its submap's first node."""
    text = LUA.read_text().replace("return options", "\n".join([
        "TRAJECTORY_BUILDER_2D.submaps.num_range_data = 20",
        "POSE_GRAPH.optimize_every_n_nodes = 0",
        "POSE_GRAPH.constraint_builder.sampling_ratio = 1.",
        "return options",
    ]))  # fmt: skip
    lua = tmp_path / "small_submaps.lua"
    lua.write_text(text)
    config = load_cartographer_config(lua)
    truth = room_tour()
    # odometry in a frame of its own: 30 m off and turned, as a log's odometry is
    odom = compose_arrays(np.array([30.0, -20.0, 0.7]), truth)
    log = synthetic_log(truth, odom)
    tb = config.trajectory_builder_2d
    local = LocalTrajectoryBuilder(tb, True, np.zeros(3))
    mapper = CartographerMapper(config.pose_graph, True, local.submaps.submaps)
    moved = np.array([60.0, 25.0, 2.0])  # the graph, as if an optimisation had moved it
    nodes_truth = []
    for k, scan in enumerate(log.scans):
        data = RangeData.from_scan(scan, np.zeros(3), tb.min_range, tb.max_range, tb.missing_data_ray_length)  # fmt: skip
        out = local.add_range_data(scan.stamp, odom[k], data)
        if out is not None and out[1] is not None:
            mapper.add_node(out[1])
            nodes_truth.append(truth[k])
            if len(nodes_truth) == 40:
                mapper.graph.set_poses(compose_arrays(moved, mapper.graph.poses))
                mapper.local_to_global = compose_arrays(moved, mapper.local_to_global[None])[0]
    assert mapper.loop_closures >= 10
    t = np.array(nodes_truth)
    edges = mapper.graph.edges
    loops = np.array(mapper.loop_edges)
    i, j, z = edges.i[loops], edges.j[loops], edges.measurement[loops]
    assert (i != j).all() and (np.abs(i - j) > 20).any()  # some join the two laps
    want = relative_arrays(t[i], t[j])
    err = z - want
    assert np.hypot(err[:, 0], err[:, 1]).max() < 0.05
    assert np.abs(normalize_angle(err[:, 2])).max() < math.radians(1.0)


def test_odometry_that_counts_reversing_as_forward_does_not_fold_the_path():
    """FR079's odometry never moves backwards: the robot backs up and the odometry says
    it drove ahead. Cartographer's 0.1 m real-time window and its Ceres pull towards the
    prediction would follow the odometry; the wider search on a poor match does not."""
    yaw = 0.3
    s = np.r_[np.arange(0, 31) * 0.1, 3.0 - np.arange(1, 19) * 0.1]  # 3 m ahead, 1.8 m back
    truth = np.column_stack([1.5 + s * math.cos(yaw), 1.2 + s * math.sin(yaw), np.full(len(s), yaw)])  # fmt: skip
    travelled = np.r_[0.0, np.cumsum(np.abs(np.diff(s)))]  # |v|: always ahead
    odom = np.column_stack([travelled * math.cos(yaw), travelled * math.sin(yaw), np.full(len(s), yaw)])  # fmt: skip
    result = run_cartographer(synthetic_log(truth, odom), load_cartographer_config(LUA))
    err = relative_arrays(result.poses[:1], result.poses) - relative_arrays(truth[:1], truth)
    assert np.hypot(err[:, 0], err[:, 1]).max() < 0.05
