"""AMCL in an aisle warehouse (issue 34): the world, its map and tour, and a Spin in an aisle.

worlds/aisle_warehouse.yaml is the kind of building issue 34 describes: 24 x 16 m, two
columns of five solid 7 x 0.8 m shelf rows with 1.6-2.0 m aisles, three round pillars by
the east wall, a 360-beam 8 m lidar and a worn base's odometry ([0.005, 0.001, 0.005,
0.001]). missions/aisle_warehouse_tour.yaml drives six waypoints around it on Nav2's
params, one leg 10 m straight down an aisle.
"""

from __future__ import annotations

import itertools
import math
from pathlib import Path

import numpy as np
import pytest
import yaml

from btnav.localization.amcl.odometry_match import matched_alphas
from btnav.maps import load_map
from btnav.mission import Mission, run_mission
from btnav.mission.navigator import Navigator
from btnav.sim.rasterize import rasterize
from btnav.sim.world import World
from btnav.sim.world_sensors import make_sensors

REPO = Path(__file__).resolve().parents[2]
WORLD = REPO / "worlds" / "aisle_warehouse.yaml"
MAP = REPO / "maps" / "aisle_warehouse.yaml"
TOUR = REPO / "missions" / "aisle_warehouse_tour.yaml"


def test_the_aisle_warehouse_is_issue_34s_kind_of_building():
    world = World.from_file(WORLD)
    spec = world.spec
    assert (spec.bounds[1][0] - spec.bounds[0][0], spec.bounds[1][1] - spec.bounds[0][1]) == (
        24,
        16,
    )
    assert tuple(spec.robot.odometry.noise) == (0.005, 0.001, 0.005, 0.001)
    lidar = make_sensors(world)[0]
    assert len(lidar.angles) == 360 and lidar.range_max == 8.0
    shelves = [o.box for o in spec.obstacles if o.box is not None]
    assert len(shelves) == 10 and all(tuple(b.size) == (7.0, 0.8) for b in shelves)
    for column in (5.5, 14.5):  # five rows a column, aisles 1.6-2.0 m between them
        ys = sorted(b.center[1] for b in shelves if b.center[0] == column)
        aisles = np.diff(ys) - 0.8
        assert len(ys) == 5 and aisles.min() >= 1.6 - 1e-9 and aisles.max() <= 2.0 + 1e-9
    pillars = [o.circle for o in spec.obstacles if o.circle is not None]
    assert len(pillars) == 3 and all(p.center[0] > 21.0 for p in pillars)


def test_the_map_is_the_rasterised_world_and_the_tour_is_six_waypoints_with_a_10_m_aisle():
    shipped, fresh = load_map(MAP), rasterize(World.from_file(WORLD), resolution=0.05)
    assert np.allclose(shipped.origin.as_array(), fresh.origin.as_array())
    assert np.array_equal(shipped.data, fresh.data), (
        "maps/aisle_warehouse.* is stale: btnav map from-world worlds/aisle_warehouse.yaml "
        "-o maps/aisle_warehouse.yaml"
    )
    mission = Mission.load(TOUR)
    assert mission.spec.localization == "amcl" and mission.params.path.name == "nav2_params.yaml"
    poses = [mission.spec.initial_pose, *mission.spec.task.follow_waypoints]
    assert len(poses) - 1 == 6
    cells = shipped.world_to_cell([(x, y) for x, y, _ in poses])
    assert all(shipped.data[r, c] == 0 for r, c in cells)
    legs = [(a, b) for a, b in itertools.pairwise(poses) if a[1] == b[1]]
    aisle = [(a, b) for a, b in legs if abs(b[0] - a[0]) >= 10.0]
    assert aisle, "no 10 m straight leg"
    (x0, y, _), (x1, _, _) = aisle[0]
    # shelf rows on both sides of the leg, their faces 1 m north and south of it
    xs = np.arange(min(x0, x1) + 1.5, max(x0, x1) - 1.5, 0.5)
    for side in (-1.0, 1.0):
        band = shipped.world_to_cell([(x, y + side * 1.2) for x in xs])
        assert (shipped.data[band[:, 0], band[:, 1]] == 100).mean() > 0.6


def test_a_spin_in_place_in_an_aisle_does_not_split_the_cloud():
    """Nav2's Spin, a full turn, in the 2 m aisle after 2.4 m down it, on Nav2's amcl
    section: at every filter update of the turn the heaviest cluster (the estimate) holds
    nearly all the weight, stays on the robot and never jumps, and the cloud does not
    stretch along the aisle (each 0.2 rad of turning adds alpha4's ~9 cm of translation
    noise to every particle; measured on seed 0: the heaviest cluster >= 99.8%, within
    8.6 cm, the cloud 0.35 m along the aisle; with alpha4 ten times Nav2's, 0.75 m)."""
    nav = Navigator.from_mission(TOUR, overrides={"mission.initial_pose": [3.0, 9.0, 0.0]})
    amcl = nav.runtime.localizer
    assert nav.drive([[0.3, 0.0, 8.0]]) and nav.wait_until_done(20.0)
    rows = []
    hear = amcl.laser_received

    def heard(scan):
        before = amcl.updates
        hear(scan)
        if amcl.updates == before:
            return
        truth, best = nav.world.robot_pose, amcl.pf.best_cluster()
        along = amcl.pf.poses[:, 0]
        rows.append((best.weight, *best.mean[:2], math.dist(best.mean[:2], (truth.x, truth.y))))
        rows[-1] += (along.std(),)

    amcl.laser_received = heard
    assert nav.spin(2.0 * math.pi, time_allowance=20.0)
    nav.wait_until_done(25.0)
    assert nav.get_result() is not None and nav.get_result().succeeded
    assert abs(math.remainder(nav.world.robot_pose.yaw, 2.0 * math.pi)) < 0.1
    weight, x, y, error, spread = (np.array(c) for c in zip(*rows, strict=True))
    assert len(rows) >= 20  # a filter update every update_min_a (0.2 rad) of the turn
    assert weight.min() >= 0.95, weight
    assert error.max() < 0.15, error
    assert np.hypot(np.diff(x), np.diff(y)).max() < 0.1  # the estimate never jumps
    assert spread.max() < 0.5, spread  # along the aisle, the direction the shelves leave open


# -- the tour, on AMCL, with ground truth as the judge -----------------------------------
#
# Regulated Pure Pursuit drives (params/nav2_params_rpp.yaml: Nav2's file with its RPP
# section; the amcl section is Nav2's): these judge AMCL, and RPP costs a quarter of
# MPPI's CPU. The bounds are issue 34's: with Nav2's amcl section 8 cm RMS and under
# 30 cm at worst; with the shipped matched file 5 cm RMS.

RPP = REPO / "params" / "nav2_params_rpp.yaml"
MATCHED = REPO / "params" / "nav2_params_matched_amcl.yaml"

#: Why Nav2's amcl section does not hold 8 cm here (measured on seeds 0-4).
NAV2_LAG = (
    "nav2_amcl's likelihood_field model with Nav2's amcl section: 15-19 cm RMS, 48-66 cm at "
    "worst on seeds 0-4, all along the aisles (across them 4-5 cm). Its weight 1 + sum(pz^3) "
    "over 60 beams varies by a third between a particle on the robot and one 10 cm off, so "
    "resampling barely corrects the odometry's drift down an aisle, where only the few beams "
    "reaching its ends see the error; the worn odometry drifts 3.5% over the 8.7 m aisle "
    "and the estimate follows it. Nav2's fix is documented params: laser_model_type "
    "likelihood_field_prob, 4.2-4.8 cm (params/nav2_params_matched_amcl.yaml)"
)


def aisle_tour(**overrides):
    return run_mission(Mission.load(TOUR, overrides={"mission.params": str(RPP), **overrides}))


@pytest.fixture(scope="module")
def nav2_tour():
    return aisle_tour()


@pytest.mark.slow
def test_the_aisle_tour_on_nav2s_amcl_section_reaches_every_waypoint(nav2_tour):
    """Before the likelihood field measured distance to surfaces, the cloud slid into the
    solid shelf rows and the tour missed every waypoint (2.5-9.8 m RMS on seeds 0-2)."""
    assert nav2_tour.status == "succeeded" and nav2_tour.missed_waypoints == []
    assert nav2_tour.collisions == 0
    assert nav2_tour.localization_error["rms_xy"] < 0.25


@pytest.mark.slow
@pytest.mark.xfail(strict=True, reason=NAV2_LAG)
def test_the_aisle_tour_on_nav2s_amcl_section_holds_8_cm(nav2_tour):
    err = nav2_tour.localization_error
    assert err["rms_xy"] <= 0.08 and err["max_xy"] < 0.30


@pytest.mark.slow
def test_the_aisle_tour_with_the_matched_files_model_and_its_odometrys_alphas_holds_5_cm():
    """The shipped matched file's laser model (likelihood_field_prob) with the alphas
    btnav's note gives for this world's odometry: 4.2-4.4 cm RMS, 14-18 cm at worst on
    seeds 0-4 (the prob model alone, Nav2's alphas: 4.3-4.8 cm)."""
    model = yaml.safe_load(MATCHED.read_text())["amcl"]["ros__parameters"]["laser_model_type"]
    noise = World.from_file(WORLD).spec.robot.odometry.noise
    alphas = matched_alphas(noise, 0.25, 0.2)  # Nav2's update_min_d, update_min_a
    amcl = {f"amcl.alpha{i}": a for i, a in enumerate(alphas, 1)}
    report = aisle_tour(**amcl, **{"amcl.laser_model_type": model})
    assert report.status == "succeeded" and report.collisions == 0
    err = report.localization_error
    assert err["rms_xy"] <= 0.05 and err["max_xy"] < 0.30
