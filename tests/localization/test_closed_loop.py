"""AMCL in the closed loop, ground truth as the judge, on Nav2's own params.

The tour runs with AMCL driving (map -> odom is AMCL's); global localisation and the
kidnapped robot run a second, passive AMCL (tf_broadcast false) beside ground-truth
navigation, so the robot drives the same tour safely whatever AMCL believes.

The targets are issue 34's: with Nav2's amcl section 8 cm RMS and under 30 cm at worst;
with params/nav2_params_matched_amcl.yaml (alpha1-4 matched to the world's odometry,
the likelihood_field_prob model) 5 cm RMS; under 10 cm with five times the odometry's noise. Between updates
(nav2_amcl's gating: update_min_d 0.25 m, update_min_a 0.2 rad) odometry alone carries
the estimate, so its drift over 0.25 m bounds what any AMCL can do.
"""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np
import pytest
import yaml

from btnav.core.geometry import Pose2D
from btnav.localization.amcl import Amcl
from btnav.mission import Mission, run_mission
from btnav.mission.navigator import Navigator
from btnav.mission.runner import start_task
from btnav.nav.runtime import Stage

pytestmark = pytest.mark.slow

REPO = Path(__file__).resolve().parents[2]
TOUR = REPO / "missions" / "office_tour.yaml"
WORLD = REPO / "worlds" / "small_office.yaml"
MATCHED = REPO / "params" / "nav2_params_matched_amcl.yaml"
#: Nav2's params with Regulated Pure Pursuit in place of MPPI, for the tests below that judge
#: AMCL, not the controller: RPP drives the same tour on about a quarter of the CPU (MPPI was
#: ~75% of each run). On seeds 0-2 with RPP: 5x noise 7.2-7.4 cm RMS, global localisation
#: converged within 2-5 m of travel, its last 10 m within 0.14 m. The untouched tour below
#: and tests/mission/test_run.py still drive the office tour with MPPI.
RPP = {"mission.params": str(REPO / "params" / "nav2_params_rpp.yaml")}
#: The passive AMCL tests navigate on ground truth, so the robot drives the same tour safely.
GROUND_TRUTH = {"mission.localization": "ground_truth", **RPP}


def world_with_noise(tmp_path: Path, scale: float) -> Path:
    """The office world with its odometry alphas times `scale`."""
    doc = yaml.safe_load(WORLD.read_text())
    doc["robot"]["odometry"]["noise"] = [a * scale for a in doc["robot"]["odometry"]["noise"]]
    out = tmp_path / f"world_{scale}.yaml"
    out.write_text(yaml.safe_dump(doc, sort_keys=False))
    return out


def tour(**overrides):
    return run_mission(Mission.load(TOUR, overrides={"mission.localization": "amcl", **overrides}))


@pytest.fixture(scope="module")
def untouched_tour():
    return tour()


def test_the_office_tour_with_amcl_succeeds_untouched(untouched_tour):
    assert untouched_tour.status == "succeeded" and untouched_tour.collisions == 0
    assert untouched_tour.missed_waypoints == []


def test_the_office_tour_on_nav2s_amcl_section_holds_8_cm_rms_and_30_cm_at_worst(untouched_tour):
    # issue 34's bound for Nav2's amcl section (its alphas 20-500x this odometry's drift)
    err = untouched_tour.localization_error
    assert err["rms_xy"] <= 0.08 and err["max_xy"] < 0.30


@pytest.fixture(scope="module")
def matched_tour():
    return tour(**{"mission.params": str(MATCHED)})


def test_the_office_tour_with_alphas_matched_to_the_odometry_holds_5_cm(matched_tour):
    """params/nav2_params_matched_amcl.yaml (Nav2's file, alpha1-4 matched to the world's
    odometry and the likelihood_field_prob model): 1.7-2.0 cm RMS on seeds 0-2."""
    assert matched_tour.status == "succeeded" and matched_tour.collisions == 0
    err = matched_tour.localization_error
    assert err["rms_xy"] <= 0.05 and err["max_xy"] < 0.30


def test_five_times_the_odometry_noise_stays_under_10_cm(tmp_path):
    # RPP drives (see RPP): the noise, not the controller, is what this run is about
    report = tour(**RPP, **{"mission.world": str(world_with_noise(tmp_path, 5.0))})
    err = report.localization_error
    assert report.status == "succeeded" and report.collisions == 0
    assert err["rms_xy"] < 0.10


class Judge:
    """A MONITOR: distance travelled and the passive AMCL's error against ground truth."""

    stage = Stage.MONITOR
    rate = 10.0

    def __init__(self, nav: Navigator, amcl: Amcl) -> None:
        self.nav, self.amcl = nav, amcl
        self.travel = 0.0
        self.last = nav.world.robot_pose
        self.rows: list[tuple[float, float, float]] = []

    def update(self, now: float) -> None:
        truth = self.nav.world.robot_pose
        self.travel += truth.distance_to(self.last)
        self.last = truth
        est = self.amcl.map_to_odom
        error = (
            math.inf
            if est is None
            else (est @ self.nav.runtime.latest_odom.pose).distance_to(truth)
        )
        self.rows.append((now, self.travel, error))


def passive_amcl(nav: Navigator, **params) -> Amcl:
    base = nav.stack.params.server("amcl").model
    amcl = Amcl(
        "amcl", type(base).model_validate({**base.model_dump(), "tf_broadcast": False, **params})
    )
    amcl.configure(nav.runtime)
    nav.stack.map_server.subscribe(amcl.set_map)
    nav.runtime.add(amcl, stage=Stage.LOCALIZATION)
    return amcl


def test_global_localisation_converges_within_20_m_of_travel():
    nav = Navigator.from_mission(TOUR, overrides=GROUND_TRUTH)
    amcl = passive_amcl(nav)
    amcl.reinitialize_global_localization()
    judge = Judge(nav, amcl)
    nav.runtime.add(judge)
    assert start_task(nav, nav.mission)
    nav.wait_until_done(300)
    rows = np.array(judge.rows)
    converged = np.flatnonzero(rows[:, 2] < 0.3)
    assert converged.size and rows[converged[0], 1] < 20.0
    # and it stays: the last 10 m are tracked within 0.6 m
    late = rows[rows[:, 1] > rows[-1, 1] - 10.0]
    assert late[:, 2].max() < 0.6


def test_a_kidnapped_robot_is_found_again_with_recovery_on():
    nav = Navigator.from_mission(TOUR, overrides=GROUND_TRUTH)
    amcl = passive_amcl(nav, recovery_alpha_slow=0.001, recovery_alpha_fast=0.1)
    amcl.set_initial_pose(nav.world.robot_pose)
    judge = Judge(nav, amcl)
    nav.runtime.add(judge)
    assert start_task(nav, nav.mission)
    nav.runtime.spin_for(8.0)
    # The kidnap: the robot is carried 3 m without its odometry knowing.
    world, body = nav.world, nav.world.robot.body
    before = world.robot_pose
    target = (
        Pose2D(before.x, before.y + 3.0, before.yaw)
        if before.y < 4
        else Pose2D(before.x, before.y - 3.0, before.yaw)
    )
    body.position = (target.x, target.y)
    world.space.reindex_shapes_for_body(body)
    nav.runtime.odometry._true = (target.x, target.y, body.angle)
    t_kidnap = nav.now
    nav.runtime.spin_for(1.0)
    assert judge.rows[-1][2] > 2.0  # it is lost
    found = nav.runtime.run_until(lambda: judge.rows[-1][2] < 0.3, timeout=60.0)
    assert found, f"not found again within 60 s of the kidnap at t = {t_kidnap:.1f} s"
