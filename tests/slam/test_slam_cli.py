"""`btnav slam LOG -o OUT`: SLAM on a recorded log, and what a bad input says."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

from btnav.cli import main
from btnav.maps import load_map
from btnav.slam.karto.graph_io import load_pose_graph
from btnav.slam.karto.slam_toolbox import default_slam_params

INTEL = Path(__file__).resolve().parents[2].parent / "shared" / "slam_logs" / "intel.clf"
needs_intel = pytest.mark.skipif(not INTEL.is_file(), reason="../shared/slam_logs is not here")


def head_of_intel(tmp_path: Path, scans: int = 400) -> Path:
    """The first `scans` laser scans of the Intel log, with its odometry, as a CARMEN file."""
    out, seen = [], 0
    with INTEL.open() as f:
        for line in f:
            seen += line.startswith("FLASER")
            if seen > scans:
                break
            out.append(line)
    path = tmp_path / "intel_head.clf"
    path.write_text("".join(out))
    return path


@needs_intel
def test_slam_on_a_carmen_log_writes_map_trajectory_and_graph(tmp_path, capsys):
    log = head_of_intel(tmp_path)
    assert main(["slam", str(log), "-o", str(tmp_path / "out")]) == 0
    summary = capsys.readouterr().out
    assert "400 scans" in summary and "processed" in summary
    grid = load_map(tmp_path / "out" / "map.yaml")
    assert (grid.data == 100).sum() > 500 and (grid.data == 0).sum() > 5000
    rows = np.loadtxt(tmp_path / "out" / "trajectory.csv", delimiter=",", skiprows=1)
    assert rows.shape == (400, 4)  # one row per scan, at the scan's time
    assert np.all(np.diff(rows[:, 0]) > 0)
    mapper = load_pose_graph(tmp_path / "out" / "pose_graph.npz", default_slam_params())
    assert len(mapper.scans) == mapper.graph.num_nodes > 10


@needs_intel
def test_an_odometry_trajectory_agrees_with_the_matched_one_at_the_nodes(tmp_path, capsys):
    log = head_of_intel(tmp_path, scans=150)
    for kind in ("matched", "odometry"):
        argv = ["slam", str(log), "-o", str(tmp_path / kind), "--trajectory", kind]
        assert main(argv) == 0
    matched, odometry = (
        np.loadtxt(tmp_path / k / "trajectory.csv", delimiter=",", skiprows=1)
        for k in ("matched", "odometry")
    )
    assert matched.shape == odometry.shape == (150, 4)
    gap = np.hypot(*(matched[:, 1:3] - odometry[:, 1:3]).T)
    assert np.median(gap) < 0.05 and gap.max() < 0.5  # the same run, placed two ways


@needs_intel
def test_a_broken_log_line_is_one_error_and_nothing_is_written(tmp_path, capsys):
    log = head_of_intel(tmp_path, scans=50)
    lines = log.read_text().splitlines(keepends=True)
    bad = next(i for i, line in enumerate(lines) if line.startswith("FLASER"))
    lines[bad] = lines[bad].replace(" 1.", " x.", 1)
    log.write_text("".join(lines))
    assert main(["slam", str(log), "-o", str(tmp_path / "out")]) == 2
    err = capsys.readouterr().err
    assert err.startswith("btnav: error: ") and f"{log}:{bad + 1}" in err
    assert len(err.strip().splitlines()) == 1
    assert not (tmp_path / "out").exists()


def test_an_unknown_slam_toolbox_key_names_its_line(tmp_path, capsys):
    params = tmp_path / "slam.yaml"
    params.write_text("slam_toolbox:\n  ros__parameters:\n    minimum_travel_distanse: 0.3\n")
    log = tmp_path / "empty.clf"
    log.write_text("# nothing\n")
    assert main(["slam", str(log), "--params", str(params), "-o", str(tmp_path / "out")]) == 2
    err = capsys.readouterr().err
    assert f"{params}:3" in err and "minimum_travel_distance" in err
    assert not (tmp_path / "out").exists()


def test_a_bag_without_a_scan_topic_is_one_error(tmp_path, capsys):
    rosbags = pytest.importorskip("rosbags.rosbag2")
    from rosbags.typesys import Stores, get_typestore

    store = get_typestore(Stores.ROS2_HUMBLE)
    bag = tmp_path / "no_scan"
    with rosbags.Writer(bag, version=8) as writer:  # an odometry topic, no LaserScan
        writer.add_connection("/odom", "nav_msgs/msg/Odometry", typestore=store)
    assert main(["slam", str(bag), "-o", str(tmp_path / "out")]) == 2
    err = capsys.readouterr().err
    assert err.startswith("btnav: error: ") and "LaserScan" in err
    assert not (tmp_path / "out").exists()


CARTOGRAPHER_LUA = Path(__file__).resolve().parents[2] / "params" / "cartographer_2d.lua"


@needs_intel
def test_slam_with_a_cartographer_lua_maps_the_log_and_places_every_scan(tmp_path, capsys):
    from btnav.slam.logs import read_log
    from btnav.testing.slam_metrics import relation_errors, relations

    log = head_of_intel(tmp_path, scans=800)
    out = tmp_path / "carto"
    assert main(["slam", str(log), "--lua", str(CARTOGRAPHER_LUA), "-o", str(out)]) == 0
    assert "800 scans" in capsys.readouterr().out
    grid = load_map(out / "map.yaml")
    assert (grid.data == 100).sum() > 500 and (grid.data == 0).sum() > 5000
    rows = np.loadtxt(out / "trajectory.csv", delimiter=",", skiprows=1)
    assert rows.shape == (800, 4) and np.all(np.diff(rows[:, 0]) > 0)
    # Kümmerle's relations inside the head (77, short ones): measured 2.6 cm / 0.33 deg
    # against the odometry's 2.9 cm / 1.4 deg
    rel = relations(INTEL.with_suffix(".relations"))
    rel = rel[(rel[:, :2] <= rows[-1, 0]).all(axis=1)]
    assert len(rel) > 50
    mapped = relation_errors(rows[:, 0], rows[:, 1:], rel)
    odometry = relation_errors(rows[:, 0], read_log(log).odom_at(rows[:, 0]), rel)
    assert mapped.trans_mean < min(0.04, odometry.trans_mean)
    assert mapped.rot_mean < min(np.radians(0.5), odometry.rot_mean / 3)
    with np.load(out / "pose_graph.npz", allow_pickle=False) as graph:
        assert str(graph["format"]) == "btnav-cartographer-graph-1"
        assert len(graph["stamps"]) == len(graph["graph_poses"]) > 10


def test_slam_with_a_lua_takes_no_trajectory_choice(tmp_path, capsys):
    argv = ["slam", "x.clf", "--lua", str(CARTOGRAPHER_LUA), "--trajectory", "odometry"]
    assert main([*argv, "-o", str(tmp_path / "out")]) == 2
    err = capsys.readouterr().err.strip()
    assert err.startswith("btnav: error: --trajectory") and len(err.splitlines()) == 1
    assert not (tmp_path / "out").exists()
