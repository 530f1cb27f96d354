"""The docking server on the office with a dock: docking ends on the dock within Nav2's
tolerances, undocking ends at the staging pose, and a dock never seen fails as Nav2 fails."""

from __future__ import annotations

import math
import warnings
from pathlib import Path

import pytest

from btnav.core.error_codes import DockRobotError
from btnav.core.geometry import Pose2D, angle_diff
from btnav.core.nav2_docking_msgs import DockRobotGoal, UndockRobotGoal
from btnav.mission import Mission
from btnav.mission.runner import run_mission
from btnav.navigators.basic_navigator import BasicNavigator
from btnav.sim.world import World
from btnav.sim.world_spec import load_world_spec

REPO = Path(__file__).resolve().parents[2]
WORLD = REPO / "worlds" / "office_dock.yaml"
PARAMS = REPO / "params" / "nav2_params_dock.yaml"
MAP = REPO / "maps" / "small_office.yaml"
DOCK = Pose2D(11.6, 1.0, 0.0)  # the world's home_dock (and the params' dock database)
DOCKING_THRESHOLD = 0.05  # nav2_params.yaml's simple_charging_dock
PERCEPTION = 0.02  # m the detected dock pose may be off the true one (detector noise)


def stack(pose, *, detector: bool = True) -> BasicNavigator:
    spec = load_world_spec(WORLD)
    spec.robot.pose = pose
    if not detector:
        spec.robot.sensors = [s for s in spec.robot.sensors if "dock_detector" not in s]
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        return BasicNavigator.from_files(World(spec), PARAMS, MAP)


def dock(nav: BasicNavigator, goal: DockRobotGoal, timeout: float = 60.0):
    handle = nav.runtime.action_client("dock_robot").send_goal(goal)
    nav.runtime.run_until(lambda: handle.done, timeout)
    return handle


def docked_within_tolerance(pose: Pose2D) -> bool:
    return (
        math.hypot(pose.x - DOCK.x, pose.y - DOCK.y) < DOCKING_THRESHOLD + PERCEPTION
        and abs(angle_diff(pose.yaw, DOCK.yaw)) < 0.1
    )


@pytest.mark.slow
def test_the_office_dock_mission_ends_docked():
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        mission = Mission.load(REPO / "missions" / "office_dock.yaml")
        nav = mission.navigator()
    from btnav.mission.runner import start_task

    assert start_task(nav, mission)
    result = nav.wait_until_done(mission.spec.time_limit)
    assert result is not None and result.succeeded, result
    assert result.value.success and result.value.num_retries == 0
    assert docked_within_tolerance(nav.robot_pose), nav.robot_pose
    assert nav.world.collisions == 0
    server = nav.stack.servers["docking_server"]
    assert server.plugins["simple_charging_dock"].is_charging()
    assert server.curr_dock_type == "simple_charging_dock"


@pytest.mark.slow
def test_the_mission_report_says_succeeded_without_contact():
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        report = run_mission(Mission.load(REPO / "missions" / "office_dock.yaml"), None)
    assert report.status == "succeeded" and report.task == "dock"
    assert report.collisions == 0 and report.sim_time < 60.0


def test_docking_from_near_the_staging_pose_then_undocking_back_to_it():
    nav = stack((10.8, 1.05, 0.1))  # within dock_prestaging_tolerance: no navigation
    handle = dock(nav, DockRobotGoal(dock_id="home_dock"))
    assert handle.succeeded, handle.result
    assert docked_within_tolerance(nav.robot_pose), nav.robot_pose
    assert nav.runtime.action_servers.get("navigate_to_pose").current is None  # not needed

    docked_at = nav.robot_pose
    undo = nav.runtime.action_client("undock_robot").send_goal(UndockRobotGoal())
    nav.runtime.run_until(lambda: undo.done, 40.0)
    assert undo.succeeded, undo.result
    # back at the staging pose, 0.7 m in front of where it docked, facing the dock
    staging = docked_at @ Pose2D(-0.7, 0.0, 0.0)
    here = nav.robot_pose
    assert math.hypot(here.x - staging.x, here.y - staging.y) < 0.05 + 0.01
    assert abs(angle_diff(here.yaw, staging.yaw)) < 0.1 + 0.01
    assert nav.world.collisions == 0
    assert nav.stack.servers["docking_server"].curr_dock_type == ""


def test_a_dock_never_detected_fails_after_the_initial_perception_timeout():
    nav = stack((10.9, 1.0, 0.0), detector=False)
    handle = dock(nav, DockRobotGoal(dock_id="home_dock"))
    assert handle.status.name == "ABORTED"
    assert handle.error_code == DockRobotError.FAILED_TO_DETECT_DOCK == 904
    assert "Failed initial dock detection" in handle.error_msg
    # initial_perception_timeout is 5 s (nav2_params.yaml); the server runs at 50 Hz
    assert handle.end_time - handle.start_time == pytest.approx(5.0, abs=0.05)
    assert nav.world.robot_twist.linear_x == 0.0


def test_an_unknown_dock_id_is_dock_not_in_db():
    nav = stack((10.9, 1.0, 0.0))
    handle = dock(nav, DockRobotGoal(dock_id="garage_dock"), timeout=1.0)
    assert handle.error_code == DockRobotError.DOCK_NOT_IN_DB
    assert "garage_dock" in handle.error_msg
    bad_type = dock(nav, DockRobotGoal(use_dock_id=False, dock_pose=DOCK, dock_type="charger"))
    assert bad_type.error_code == DockRobotError.DOCK_NOT_VALID


def test_the_dock_robot_tree_node_docks_and_writes_nav2s_outputs():
    from btnav.bt import load_tree

    nav = stack((10.8, 1.0, 0.0))
    tree = """
main_tree: Dock
trees:
  Dock:
    DockRobot: {dock_id: home_dock, success: "{docked}", num_retries: "{retries}",
                error_code_id: "{code}"}
"""
    root = load_tree(tree, clock=nav.runtime.clock, context={"runtime": nav.runtime})
    import py_trees

    bb = py_trees.blackboard.Client(name="test")
    for key in ("docked", "retries", "code"):
        bb.register_key(key, access=py_trees.common.Access.READ)
    for _ in range(4000):
        root.tick_once()
        if root.status != py_trees.common.Status.RUNNING:
            break
        nav.runtime.step()
    assert root.status == py_trees.common.Status.SUCCESS
    assert (bb.docked, bb.retries, bb.code) == (True, 0, 0)
