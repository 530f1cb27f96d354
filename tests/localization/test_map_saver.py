"""Saving the map as map_saver_cli does, and localising on the saved map."""

from __future__ import annotations

from pathlib import Path

import numpy as np

from btnav.maps.map_io import load_map
from btnav.maps.occupancy_grid import OccupancyGrid
from btnav.mission import Mission, run_mission
from btnav.mission.navigator import Navigator

REPO = Path(__file__).resolve().parents[2]
TOUR = REPO / "missions" / "office_tour.yaml"


def test_save_map_writes_what_map_server_serves(tmp_path):
    nav = Navigator.from_mission(TOUR)
    yaml_path, image = nav.save_map(tmp_path / "office")
    assert (yaml_path.name, image.name) == ("office.yaml", "office.pgm")
    text = yaml_path.read_text()
    assert "mode: trinary" in text and "occupied_thresh: 0.65" in text
    served = nav.stack.map_server.map
    again = load_map(yaml_path)
    np.testing.assert_array_equal(again.data, served.data)
    assert (again.resolution, again.origin) == (served.resolution, served.origin)


def test_map_saver_thresholds_classify_the_cells(tmp_path):
    """A cell 30% occupied is unknown with map_saver's defaults (free <= 25%), free once
    `map_saver.free_thresh_default` is 0.35, and occupied with occupied_thresh_default 0.3."""
    grid = OccupancyGrid(np.array([[0, 30, 100, -1]], np.int8), 0.05)
    saved = {}
    for name, sets in {
        "default": {},
        "loose": {"map_saver.free_thresh_default": 0.35},
        "strict": {"map_saver.occupied_thresh_default": 0.3},
    }.items():
        nav = Navigator.from_mission(TOUR, overrides=sets)
        nav.stack.map_server.map = grid
        saved[name] = load_map(nav.save_map(tmp_path / name)[0]).data.tolist()
    assert saved == {
        "default": [[0, -1, 100, -1]],
        "loose": [[0, 0, 100, -1]],
        "strict": [[0, 100, 100, -1]],
    }


def test_amcl_localises_on_a_saved_map(tmp_path):
    """The map a run saves (`outputs: [map]`) is a map AMCL navigates on."""
    first = Mission.load(TOUR, overrides={"mission.outputs": ["map"], "mission.time_limit": 1})
    run_mission(first, tmp_path / "first")
    saved = tmp_path / "first" / "map.yaml"
    assert saved.exists()
    mission = Mission.load(
        TOUR,
        overrides={
            "mission.map": str(saved),
            "mission.localization": "amcl",
            "mission.task": {"navigate_to_pose": [3.0, 2.0, 1.57]},
        },
    )
    report = run_mission(mission)
    assert report.status == "succeeded" and report.collisions == 0
    assert report.localization_error["rms_xy"] < 0.10
