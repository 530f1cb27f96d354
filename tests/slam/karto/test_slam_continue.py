"""Continued mapping: `mode: mapping` with `map_file_name` goes on from a saved pose graph.

slam_toolbox's semantics: the graph is deserialised, the new session's first scan is
placed at `map_start_pose` and matched against the graph's nearest scan, and mapping goes
on in the same map frame. Here a first session maps the lower corridor's first 10 m, and
a second one, started 5 m along it, drives on to 18 m: one map, one graph.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest
import yaml

from btnav.params.localization import SlamToolboxParams
from btnav.sim.rasterize import rasterize
from btnav.sim.world_spec import load_world_spec
from btnav.testing.slam_metrics import ate_rms, map_quality

from ..loop_drive import LOOP_WORLD, Drive, drive_loop

START = (6.0, 1.2, 0.0)  # where the second session starts, inside the first one's map


def world_starting_at(folder: Path, pose: tuple[float, float, float]) -> Path:
    doc = yaml.safe_load(LOOP_WORLD.read_text())
    doc["robot"]["pose"] = list(pose)
    path = folder / "corridor_loop.yaml"
    path.write_text(yaml.safe_dump(doc, sort_keys=False))
    return path


@pytest.fixture(scope="module")
def sessions(tmp_path_factory: pytest.TempPathFactory) -> tuple[Drive, Drive, int]:
    tmp = tmp_path_factory.mktemp("continue")
    first = drive_loop(seed=4, route=[(1.2, 1.2), (10.0, 1.2)])
    first.slam.serialize_pose_graph(tmp / "corridor")
    params = SlamToolboxParams(map_file_name=str(tmp / "corridor"), map_start_pose=list(START))
    second = drive_loop(
        world_starting_at(tmp, START), seed=5, params=params, route=[START[:2], (18.0, 1.2)]
    )
    return first, second, len(first.slam.mapper.scans)


def test_the_old_nodes_stay_and_new_ones_follow(sessions: tuple[Drive, Drive, int]) -> None:
    first, second, old = sessions
    before, after = first.slam.mapper, second.slam.mapper
    assert len(after.scans) > old + 10
    stamps = [s.stamp for s in after.scans[:old]]
    assert stamps == [s.stamp for s in before.scans]
    moved = np.hypot(*(after.poses[:old, :2] - before.poses[:, :2]).T)
    assert moved.max() < 0.05, f"the old nodes moved {moved.max():.3f} m"


def test_the_first_new_node_is_linked_to_the_old_graph_where_it_starts(
    sessions: tuple[Drive, Drive, int],
) -> None:
    _, second, old = sessions
    graph = second.slam.mapper.graph
    linked = graph.neighbours(old)
    assert linked and all(j < old or j == old + 1 for j in linked)
    near = [j for j in linked if j < old]
    assert near, "the session's first node has no edge to the saved graph"
    assert old - 1 not in near, "linked to the first session's last node, 4 m away"
    poses = second.slam.mapper.poses
    assert np.hypot(*(poses[near, :2] - poses[old, :2]).T).max() < 1.5


def test_the_map_frame_is_the_first_session_s(sessions: tuple[Drive, Drive, int]) -> None:
    _, second, old = sessions
    mapper = second.slam.mapper
    stamps = np.array([s.stamp for s in mapper.scans[old:]])
    xy, yaw = ate_rms(mapper.poses[old:], second.truth_at(stamps))
    assert xy <= 0.10 and yaw <= np.radians(2.0), (xy, yaw)
    online, _ = ate_rms(second.estimate, second.truth[:, 1:])
    assert online <= 0.10, f"map -> base_footprint {online:.3f} m RMS from the truth"
    assert mapper.poses[old:, 0].max() > 17.0  # mapped on past the first session's end


def test_the_map_holds_both_sessions_on_the_world(sessions: tuple[Drive, Drive, int]) -> None:
    first, second, _ = sessions
    first.slam._rebuild()
    before, after = first.slam.occupancy.grid(), second.slam.map
    assert after is not None and after.size_m[0] > before.size_m[0] + 5.0
    # one map: no wall drawn twice where the two sessions overlap
    q = map_quality(after, rasterize(load_world_spec(LOOP_WORLD), 0.01), tolerance=0.10)
    assert q.occupied_near_surface >= 0.95 and q.free_is_free >= 0.98, q
