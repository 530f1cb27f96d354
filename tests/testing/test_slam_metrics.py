"""SLAM metrics: Kümmerle's relation errors, pose RMS and map quality against the true map."""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np
import pytest

from btnav.core.errors import BtnavError
from btnav.core.geometry import Pose2D
from btnav.maps import OccupancyGrid
from btnav.sim.rasterize import rasterize
from btnav.sim.world_spec import WorldSpec
from btnav.testing.slam_metrics import ate_rms, map_quality, relation_errors, relations

INTEL_RELATIONS = Path("/work/shared/slam_logs/intel.relations")

WORLD = """
world: two_rooms
bounds: [[0, 0], [6, 4]]
walls:
  - [[0, 0], [6, 0], [6, 4], [0, 4], [0, 0]]
  - [[3, 0], [3, 1.5]]
  - [[3, 2.5], [3, 4]]
obstacles:
  - box: {center: [1.5, 2.0], size: [0.6, 0.4], yaw: 0.4}
  - circle: {center: [4.5, 1.0], radius: 0.3}
robot:
  drive: diff_drive
  footprint: {radius: 0.2}
  pose: [1.0, 1.0, 0.0]
  limits: {v_max: 0.5, w_max: 1.5, a_max: 1.0, alpha_max: 3.0}
  sensors:
    - lidar: {frame: laser, pose: [0.0, 0.0, 0.0], beams: 360, range: [0.1, 8.0], rate: 10}
"""


def truth_map(resolution: float = 0.05) -> OccupancyGrid:
    """The true map as `btnav map from-world` makes it."""
    return rasterize(WorldSpec.from_text(WORLD), resolution)


def write(tmp_path: Path, text: str) -> Path:
    path = tmp_path / "toy.relations"
    path.write_text(text)
    return path


# -- relations files -------------------------------------------------------------------


def test_relations_reads_t1_t2_x_y_yaw_and_skips_blank_and_comment_lines(tmp_path):
    path = write(
        tmp_path,
        "# ground truth of a toy run\n"
        "\n"
        "1.0 2.0 0.5 -0.1 0 0 0 0.25\n"
        "   \n"
        "2.0 3.5 0.4 0.0 0.0 0.0 0.0 -3.0\n",
    )
    rel = relations(path)
    assert rel.shape == (2, 5)
    np.testing.assert_array_equal(rel[0], [1.0, 2.0, 0.5, -0.1, 0.25])
    np.testing.assert_array_equal(rel[1], [2.0, 3.5, 0.4, 0.0, -3.0])


@pytest.mark.parametrize(
    ("bad", "says"),
    [
        ("1.0 2.0 0.5 -0.1 0.25", "expected 8 numbers"),
        ("1 2 3 4 5 6 7 yaw", "'yaw' is not a number"),
    ],
)
def test_a_malformed_relations_line_names_its_file_and_line(tmp_path, bad, says):
    path = write(tmp_path, "# header\n1 2 0 0 0 0 0 0\n\n" + bad + "\n3 4 0 0 0 0 0 0\n")
    with pytest.raises(BtnavError, match=says) as err:
        relations(path)
    assert err.value.line == 4
    assert f"{path}:4:" in str(err.value)


def test_a_missing_relations_file_is_named(tmp_path):
    with pytest.raises(BtnavError, match="cannot read") as err:
        relations(tmp_path / "nope.relations")
    assert "nope.relations" in str(err.value)


@pytest.mark.skipif(not INTEL_RELATIONS.exists(), reason="the Intel log is not here")
def test_the_intel_relations_file_reads():
    rel = relations(INTEL_RELATIONS)
    assert rel.shape == (2984, 5)
    assert np.all(rel[:, 1] > rel[:, 0] - 1e3) and np.all(np.abs(rel[:, 4]) <= math.pi)


# -- relation errors -------------------------------------------------------------------


def toy_trajectory() -> tuple[np.ndarray, np.ndarray]:
    """A robot driving a curve: 50 poses 0.1 s apart, heading changing."""
    stamps = 100.0 + 0.1 * np.arange(50)
    yaw = 0.5 + 0.08 * np.arange(50)
    x = np.cumsum(0.2 * np.cos(yaw))
    y = np.cumsum(0.2 * np.sin(yaw))
    return stamps, np.column_stack([x, y, yaw])


def true_relations(stamps: np.ndarray, poses: np.ndarray, pairs) -> np.ndarray:
    rows = []
    for i, j in pairs:
        d = Pose2D.from_array(poses[j]).relative_to(Pose2D.from_array(poses[i]))
        rows.append([stamps[i], stamps[j], d.x, d.y, d.yaw])
    return np.array(rows)


PAIRS = [(i, i + 1) for i in range(49)] + [(0, 25), (10, 40), (3, 49)]


def test_the_true_trajectory_scores_zero():
    stamps, poses = toy_trajectory()
    rel = true_relations(stamps, poses, PAIRS)
    err = relation_errors(stamps, poses, rel)
    assert err.used == len(PAIRS) and err.skipped == 0
    for value in (err.trans_mean, err.trans_std, err.rot_mean, err.rot_sq_mean):
        assert value == pytest.approx(0.0, abs=1e-12)


def test_known_errors_are_measured_in_the_frame_of_the_first_pose():
    stamps, poses = toy_trajectory()
    rel = true_relations(stamps, poses, [(i, i + 1) for i in range(49)])
    # the estimate drives 10 % too far on every step and turns 0.01 rad too much,
    # i.e. each estimated step is the true one, scaled by 1.1, and rotated by 0.01
    est = [Pose2D.from_array(poses[0])]
    for i in range(49):
        d = Pose2D.from_array(poses[i + 1]).relative_to(Pose2D.from_array(poses[i]))
        est.append(est[-1] @ Pose2D(1.1 * d.x, 1.1 * d.y, d.yaw + 0.01))
    estimate = np.array([p.as_array() for p in est])
    # stamps a little off: the nearest pose within max_dt is used
    err = relation_errors(stamps + 0.01, estimate, rel)
    steps = np.hypot(rel[:, 2], rel[:, 3])
    assert err.used == 49 and err.skipped == 0
    assert err.trans_mean == pytest.approx(np.mean(0.1 * steps), rel=1e-9)
    assert err.trans_sq_mean == pytest.approx(np.mean((0.1 * steps) ** 2), rel=1e-9)
    assert err.trans_std == pytest.approx(np.std(0.1 * steps), abs=1e-12)
    assert err.rot_mean == pytest.approx(0.01, abs=1e-12)
    assert err.rot_std == pytest.approx(0.0, abs=1e-12)
    assert err.rot_sq_mean == pytest.approx(1e-4, abs=1e-12)
    assert err.rot_mean_deg == pytest.approx(math.degrees(0.01))


def test_relations_without_poses_near_both_stamps_are_skipped():
    stamps, poses = toy_trajectory()
    rel = true_relations(stamps, poses, PAIRS)
    rel[0, 1] = stamps[-1] + 0.06  # no pose within 0.05 s of this t2
    rel[1, 0] = 10.0  # long before the trajectory starts
    err = relation_errors(stamps, poses, rel)
    assert (err.used, err.skipped) == (len(PAIRS) - 2, 2)
    assert err.trans_mean == pytest.approx(0.0, abs=1e-12)
    # shuffled stamps are fine too
    order = np.random.default_rng(3).permutation(len(stamps))
    again = relation_errors(stamps[order], poses[order], rel)
    assert again == err


# -- trajectories ----------------------------------------------------------------------


def test_ate_rms_of_known_offsets():
    _, truth = toy_trajectory()
    estimate = truth + np.array([0.3, -0.4, 0.1])
    pos, yaw = ate_rms(estimate, truth)
    assert pos == pytest.approx(0.5) and yaw == pytest.approx(0.1)
    # yaw errors wrap: pi - 0.05 against -pi + 0.05 is 0.1 apart
    a = np.array([[0.0, 0.0, math.pi - 0.05]])
    b = np.array([[0.0, 0.0, -math.pi + 0.05]])
    assert ate_rms(a, b)[1] == pytest.approx(0.1)
    assert ate_rms(truth, truth) == (0.0, 0.0)


# -- maps ------------------------------------------------------------------------------


def test_the_true_map_against_itself_is_perfect():
    truth = truth_map()
    q = map_quality(truth, truth)
    assert q.occupied_near_surface == 1.0 and q.free_is_free == 1.0
    assert q.coverage == 1.0 and q.slam_free_m2 == q.truth_free_m2 > 20.0


def test_a_coarser_map_of_the_same_world_scores_high():
    q = map_quality(truth_map(0.1), truth_map(0.05))
    assert q.occupied_near_surface > 0.95
    assert q.free_is_free > 0.95
    assert q.coverage == pytest.approx(1.0, abs=0.1)


def test_a_map_shifted_by_20_cm_scores_low():
    truth = truth_map()
    o = truth.origin
    shifted = OccupancyGrid(truth.data, truth.resolution, Pose2D(o.x + 0.2, o.y + 0.2, 0.0))
    q = map_quality(shifted, truth)
    assert q.occupied_near_surface < 0.3
    assert q.free_is_free < 1.0
    # half the map unknown: half the coverage
    half = truth.data.copy()
    half[:, half.shape[1] // 2 :] = -1
    q = map_quality(OccupancyGrid(half, truth.resolution, truth.origin), truth)
    assert q.coverage == pytest.approx(0.5, abs=0.05)
    assert q.occupied_near_surface == 1.0 and q.free_is_free == 1.0
