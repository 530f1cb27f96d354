"""The first seed's flow with a TurtleBot3 Burger: map turtlebot3_world with slam_toolbox
and the LDS-01, save the map, then navigate round the pillars on it with AMCL."""

from __future__ import annotations

from pathlib import Path

import pytest

from btnav.exploration.coverage import coverage
from btnav.maps.map_io import load_map
from btnav.mission import Mission
from btnav.mission.stages import run_stages
from btnav.sim.rasterize import rasterize
from btnav.sim.world_spec import load_world_spec
from btnav.testing.slam_metrics import map_quality

REPO = Path(__file__).resolve().parents[2]
MISSION = REPO / "missions" / "turtlebot3_slam_then_nav.yaml"
WORLD = REPO / "worlds" / "turtlebot3_world.yaml"
START = (-2.0, -0.5)


@pytest.fixture(scope="module")
def run(tmp_path_factory: pytest.TempPathFactory):
    out = tmp_path_factory.mktemp("tb3") / "out"
    return out, run_stages(MISSION, out)


def test_the_burger_carries_an_lds_01():
    nav = Mission.load(MISSION, stage="map").navigator()
    while nav.runtime.latest_scan is None:  # 5 Hz: the first scan within 0.2 s
        nav.runtime.step()
    scan = nav.runtime.latest_scan
    assert len(scan.ranges) == 360 and scan.range_max == pytest.approx(3.5)
    assert scan.frame_id == "base_scan"


@pytest.mark.slow
def test_slam_maps_the_turtlebot3_world(run):
    out, report = run
    name, mapping = report.stages[0]
    assert name == "map" and mapping.succeeded, mapping.summary()
    assert mapping.collisions == 0, mapping.contacts
    truth = rasterize(load_world_spec(WORLD), 0.05)
    grid = load_map(out / "map" / "map.yaml")
    mapped = coverage(grid, truth, START)
    assert mapped.fraction >= 0.90, mapped
    fine = rasterize(load_world_spec(WORLD), 0.01)
    q = map_quality(grid, fine, tolerance=0.10)
    assert q.occupied_near_surface >= 0.95 and q.free_is_free >= 0.98, q


@pytest.mark.slow
def test_nav2_with_amcl_on_the_saved_map_visits_every_waypoint(run):
    _, report = run
    assert [name for name, _ in report.stages] == ["map", "nav"]
    _, nav = report.stages[1]
    assert nav.succeeded and not nav.missed_waypoints, nav.summary()
    assert nav.collisions == 0, nav.contacts
    assert nav.localization_error["rms_xy"] <= 0.10, nav.localization_error
