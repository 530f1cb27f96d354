"""SLAM round the corridor loop, the world's ground truth as the judge (slam_toolbox defaults).

The wheel odometry drifts by metres over the lap; the loop closes when the robot comes
back past its start. The targets are the issue's: the SLAM trajectory within 10 cm RMS
and a quarter of odometry's error, the loop closure in the pose graph, >= 95% of the
occupied cells within 10 cm of a true surface and >= 98% of the free cells free.
"""

from __future__ import annotations

import math

import numpy as np
import pytest

from btnav.core.errors import ParamsError
from btnav.core.geometry import Pose2D
from btnav.maps.map_io import load_map, save_map
from btnav.params.loader import load_params
from btnav.params.localization import SlamToolboxParams
from btnav.sim.rasterize import rasterize
from btnav.sim.world_spec import load_world_spec
from btnav.testing.slam_metrics import ate_rms, map_quality

from ..loop_drive import LOOP, LOOP_WORLD, REPO, drive_loop


@pytest.fixture(scope="module")
def loop():
    return drive_loop(seed=0)


def test_the_loop_closes_and_the_trajectory_holds(loop):
    mapper = loop.slam.mapper
    stamps = np.array([s.stamp for s in mapper.scans])
    truth = loop.truth_at(stamps)
    slam_xy, _ = ate_rms(mapper.poses, truth)
    odom_xy, _ = ate_rms(loop.odom, loop.truth[:, 1:])
    assert mapper.loop_closures >= 1
    assert odom_xy > 1.0, "the world's odometry should drift by metres over the lap"
    assert slam_xy <= 0.10, f"SLAM ATE {slam_xy:.3f} m RMS"
    assert slam_xy <= odom_xy / 4
    # what the robot believed while driving (map -> base_footprint) also beats odometry
    online_xy, _ = ate_rms(loop.estimate, loop.truth[:, 1:])
    assert online_xy <= odom_xy / 4


def test_loop_closure_edges_join_the_lap_s_two_ends(loop):
    edges = loop.slam.mapper.graph.edges
    gap = np.abs(edges.i - edges.j)
    assert gap.max() > len(loop.slam.mapper.scans) // 2


def test_the_map_matches_the_world(loop):
    slam = loop.slam
    slam._rebuild()
    grid = slam.occupancy.grid()
    # the true surfaces, to a centimetre (`btnav map from-world --resolution 0.01`)
    truth = rasterize(load_world_spec(LOOP_WORLD), 0.01)
    q = map_quality(grid, truth, tolerance=0.10)
    assert q.occupied_near_surface >= 0.95, q
    assert q.free_is_free >= 0.98, q


def test_amcl_localises_on_the_saved_slam_map(loop, tmp_path):
    loop.slam._rebuild()
    yaml_path, _ = save_map(loop.slam.occupancy.grid(), tmp_path / "slam_map.yaml")
    grid = load_map(yaml_path)

    def start(amcl):
        amcl.set_map(grid)
        amcl.set_initial_pose(Pose2D(*LOOP[0], 0.0))

    params = load_params(REPO / "params" / "nav2_params.yaml").server("amcl").model
    route = [(1.2, 1.2), (26.8, 1.2), (26.8, 8.0)]  # a third of the lap, round a corner
    run = drive_loop(
        seed=1, kind="localizer", name="amcl", params=params, route=route, on_start=start
    )
    xy, yaw = ate_rms(run.estimate, run.truth[:, 1:])
    # judged against the world, AMCL inherits the map's own error (its nodes up to 9 cm
    # off) on top of its own on the world's map: 13.0 cm RMS on this drive with the world
    # rasterised at 5 cm (`rasterize(load_world_spec(LOOP_WORLD), 0.05)`; 13.8 at seed 2)
    nodes = loop.slam.mapper
    stamps = np.array([s.stamp for s in nodes.scans])
    map_err = np.hypot(*(nodes.poses[:, :2] - loop.truth_at(stamps)[:, :2]).T).max()
    assert xy <= 0.14 + map_err, f"AMCL on the SLAM map: {xy:.3f} m RMS (map {map_err:.3f})"
    assert yaw <= math.radians(2.0)


def test_localization_mode_tracks_on_the_serialised_graph(loop, tmp_path):
    graph = loop.slam.serialize_pose_graph(tmp_path / "loop")  # slam_toolbox adds the suffix
    assert graph.name == "loop.npz"
    params = SlamToolboxParams(mode="localization", map_file_name=str(tmp_path / "loop"))
    route = [(1.2, 1.2), (26.8, 1.2), (26.8, 8.0)]
    run = drive_loop(seed=2, params=params, route=route)
    xy, yaw = ate_rms(run.estimate, run.truth[:, 1:])
    assert xy <= 0.10, f"localization mode: {xy:.3f} m RMS"
    assert yaw <= math.radians(2.0)
    assert len(run.slam.mapper.scans) == len(loop.slam.mapper.scans)  # the graph is unchanged


def test_localization_mode_without_a_graph_names_the_key():
    with pytest.raises(ParamsError, match="map_file_name"):
        drive_loop(params=SlamToolboxParams(mode="localization"), route=[(1.2, 1.2), (2.0, 1.2)])


@pytest.mark.slow
@pytest.mark.parametrize("seed", range(1, 10))
def test_the_issue_s_bounds_hold_at_other_seeds(seed):
    """Seed 0's bounds (the tests above) at seeds 1-9: other odometry drifts and lidar
    noise. Before the mapper held its matches along the corridors to the odometry
    (`odometry_fusion.OPEN_DIRECTION_GATE`) seeds 3, 5 and 9 failed: node ATE 9.5, 11.1 and
    12.1 cm, 88-93% of the occupied cells near a wall (now 7.4, 5.6 and 2.6 cm, 97-100%)."""
    run = drive_loop(seed=seed)
    mapper = run.slam.mapper
    stamps = np.array([s.stamp for s in mapper.scans])
    slam_xy, _ = ate_rms(mapper.poses, run.truth_at(stamps))
    odom_xy, _ = ate_rms(run.odom, run.truth[:, 1:])
    online_xy, _ = ate_rms(run.estimate, run.truth[:, 1:])
    assert odom_xy > 1.0
    assert slam_xy <= 0.10, f"SLAM ATE {slam_xy:.3f} m RMS"
    assert slam_xy <= odom_xy / 4
    assert online_xy <= odom_xy / 4
    assert mapper.loop_closures >= 1
    gap = np.abs(mapper.graph.edges.i - mapper.graph.edges.j)
    assert gap.max() > len(mapper.scans) // 2
    run.slam._rebuild()
    truth = rasterize(load_world_spec(LOOP_WORLD), 0.01)
    q = map_quality(run.slam.occupancy.grid(), truth, tolerance=0.10)
    assert q.occupied_near_surface >= 0.95, q
    assert q.free_is_free >= 0.98, q


def test_same_seed_same_map_and_trajectory():
    a = drive_loop(seed=3, route=[(1.2, 1.2), (12.0, 1.2)])
    b = drive_loop(seed=3, route=[(1.2, 1.2), (12.0, 1.2)])
    assert a.slam.mapper.poses.tobytes() == b.slam.mapper.poses.tobytes()
    assert a.slam.occupancy.grid().data.tobytes() == b.slam.occupancy.grid().data.tobytes()
