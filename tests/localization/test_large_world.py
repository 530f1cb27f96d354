"""AMCL on a long tour of a larger, cluttered world, ground truth as the judge.

The warehouse (worlds/warehouse.yaml, 30 x 20 m: a rack hall, a loading dock, a
corridor and four rooms) and its tour (missions/warehouse_tour.yaml: eight waypoints,
about 85 m) with `localization: amcl`. Issue 34's bounds: with Nav2's amcl section 8 cm
RMS and under 30 cm at worst; with alpha1-4 matched to the world's odometry
(params/nav2_params_matched_amcl.yaml) 5 cm RMS; success, no collision.

AMCL is what these tests judge, not the controller: the tour runs on Nav2's params with
Regulated Pure Pursuit (params/nav2_params_rpp.yaml) in place of the mission's MPPI,
which was ~75% of the run's CPU (90 s -> 21 s). With RPP the tour succeeds without a
contact on seeds 0-2 as with MPPI; MPPI drives the office tour in
tests/mission/test_run.py and tests/localization/test_closed_loop.py.
"""

from __future__ import annotations

import warnings
from pathlib import Path

import numpy as np
import pytest
import yaml

from btnav.maps import load_map
from btnav.mission import Mission, run_mission
from btnav.sim.rasterize import rasterize
from btnav.sim.world import World

REPO = Path(__file__).resolve().parents[2]
TOUR = REPO / "missions" / "warehouse_tour.yaml"
WORLD = REPO / "worlds" / "warehouse.yaml"
MAP = REPO / "maps" / "warehouse.yaml"
MATCHED = REPO / "params" / "nav2_params_matched_amcl.yaml"


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
def test_the_warehouse_tour_on_nav2s_amcl_section_holds_8_cm_rms_and_30_cm_at_worst(tour_report):
    # issue 34's bound for Nav2's amcl section (its alphas 20-500x this odometry's drift)
    err = tour_report.localization_error
    assert err["rms_xy"] <= 0.08 and err["max_xy"] < 0.30


def matched_amcl_of_the_shipped_file() -> dict[str, float | str]:
    """params/nav2_params_matched_amcl.yaml's alpha1-4 and laser model, as `--set amcl.*`
    overrides (the tour keeps its RPP params file)."""
    amcl = yaml.safe_load(MATCHED.read_text())["amcl"]["ros__parameters"]
    keys = ("alpha1", "alpha2", "alpha3", "alpha4", "laser_model_type")
    return {f"amcl.{k}": amcl[k] for k in keys}


@pytest.mark.slow
def test_the_warehouse_tour_with_the_matched_files_amcl_holds_5_cm():
    """The shipped matched file's amcl (RPP driving, as above): 1.2-1.3 cm RMS, 3 cm at
    worst on seeds 0-2 (its alphas alone 2.9-3.3 cm, Nav2's section 6.2-8.4 cm)."""
    rpp = REPO / "params" / "nav2_params_rpp.yaml"
    overrides = {"mission.localization": "amcl", "mission.params": str(rpp)}
    report = run_mission(
        Mission.load(TOUR, overrides={**overrides, **matched_amcl_of_the_shipped_file()})
    )
    assert report.status == "succeeded" and report.collisions == 0
    err = report.localization_error
    assert err["rms_xy"] <= 0.05 and err["max_xy"] < 0.30
