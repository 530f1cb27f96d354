"""The second seed's flow with its own robot: the fishbot's xacro, Cartographer maps its
room, the map is saved, then Nav2 with DWB navigates it with AMCL."""

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
MISSION = REPO / "missions" / "fishbot_cartographer_then_nav.yaml"
WORLD = REPO / "worlds" / "fishbot_room.yaml"


@pytest.fixture(scope="module")
def run(tmp_path_factory: pytest.TempPathFactory):
    out = tmp_path_factory.mktemp("fishbot") / "out"
    return out, run_stages(MISSION, out)


def test_the_fishbot_is_its_xacro():
    spec = load_world_spec(WORLD)
    assert spec.robot.footprint.radius == pytest.approx(0.2)
    nav = Mission.load(MISSION, stage="map").navigator()
    while nav.runtime.latest_scan is None:
        nav.runtime.step()
    scan = nav.runtime.latest_scan
    assert scan.frame_id == "laser_link" and len(scan.ranges) == 360
    assert scan.range_min == pytest.approx(0.1) and scan.range_max == pytest.approx(10.0)
    assert {"left_wheel_link", "right_wheel_link", "laser_link"} <= set(nav.runtime.frames.frames)


@pytest.mark.slow
def test_cartographer_maps_the_room(run):
    out, report = run
    name, mapping = report.stages[0]
    assert name == "map" and mapping.succeeded, mapping.summary()
    assert mapping.collisions == 0, mapping.contacts
    grid = load_map(out / "map" / "map.yaml")
    mapped = coverage(grid, rasterize(load_world_spec(WORLD), 0.05), (1.0, 1.0))
    assert mapped.fraction >= 0.90, mapped
    q = map_quality(grid, rasterize(load_world_spec(WORLD), 0.01), tolerance=0.10)
    assert q.occupied_near_surface >= 0.90 and q.free_is_free >= 0.98, q


@pytest.mark.slow
def test_dwb_with_amcl_on_the_saved_map_visits_every_waypoint(run):
    _, report = run
    _, nav = report.stages[1]
    assert nav.succeeded and not nav.missed_waypoints, nav.summary()
    assert nav.collisions == 0, nav.contacts
    assert nav.localization_error["rms_xy"] <= 0.10, nav.localization_error
