"""While SLAM builds the map, a goal beyond what it has mapped is planned into the
unknown and re-planned as the map grows (Nav2 fails it: navigation2 #3992)."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest
import yaml

from btnav.costmap.cost_values import NO_INFORMATION
from btnav.costmap.costmap_2d import Costmap2D
from btnav.mission import Mission, run_mission

REPO = Path(__file__).resolve().parents[2]
#: 13-15 m apart down the corridor loop's unmapped corridors, round a corner
WAYPOINTS = [[14.0, 1.2, 0.0], [26.8, 4.0, 1.57], [26.8, 14.0, 1.57]]


def mission(folder: Path, seed: int) -> Path:
    doc = {
        "mission": "beyond_the_map",
        "world": str(REPO / "worlds" / "corridor_loop.yaml"),
        "params": str(REPO / "params" / "nav2_params.yaml"),
        "localization": "slam",
        "initial_pose": [1.2, 1.2, 0.0],
        "task": {"follow_waypoints": WAYPOINTS},
        "time_limit": 200,
        "seed": seed,
    }
    path = folder / "mission.yaml"
    path.write_text(yaml.safe_dump(doc, sort_keys=False))
    return path


@pytest.mark.slow
@pytest.mark.parametrize("seed", [0, 3])  # seeds 0-4 all pass; two keep the suite short
def test_waypoints_beyond_the_mapped_area_are_all_reached(tmp_path, seed):
    report = run_mission(Mission.load(mission(tmp_path, seed)))
    assert report.status == "succeeded" and not report.missed_waypoints, report.summary()
    assert report.collisions == 0, report.contacts


def test_a_grown_costmap_keeps_every_cell_where_it_was():
    cm = Costmap2D(np.arange(12, dtype=np.uint8).reshape(3, 4), 0.5, 1.0, 2.0)
    grown = cm.grown_to_include([(0.2, 1.0), (6.0, 2.5)], margin=0.5)
    # the old cells in the same world places, the new ones unknown
    for x, y in [(1.25, 2.25), (2.75, 3.25)]:
        assert grown.cost_at_point(x, y) == cm.cost_at_point(x, y)
    assert grown.cost_at_point(0.0, 0.6) == NO_INFORMATION
    assert grown.cost_at_point(6.4, 2.5) == NO_INFORMATION
    assert int((grown.costs != NO_INFORMATION).sum()) == 12
    assert cm.grown_to_include([(1.5, 2.5)], margin=0.1) is cm  # inside: nothing to grow
