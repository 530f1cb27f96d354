"""Spin, BackUp, DriveOnHeading and Wait as a user sees them through their action clients."""

from __future__ import annotations

import math

import pytest

from btnav.core.error_codes import BackUpError, DriveOnHeadingError, SpinError, WaitError
from btnav.core.errors import ParamsError
from btnav.core.geometry import angle_diff
from btnav.core.nav2_msgs import BackUpGoal, DriveOnHeadingGoal, SpinGoal, WaitGoal
from btnav.nav import GoalStatus
from btnav.params import load_params

from .stack import NAV2_PARAMS, make_stack, nav2_doc, params_from, write_world


def test_server_serves_nav2s_behaviours_from_the_params_file(office):
    stack = office()
    assert stack.server.names == ["spin", "backup", "drive_on_heading", "assisted_teleop", "wait"]
    assert stack.server.not_implemented == []
    for name in stack.server.names:
        assert stack.runtime.action_client(name).wait_for_server()
    backup = stack.server.behaviors["backup"].params
    assert (backup.acceleration_limit, backup.deceleration_limit, backup.minimum_speed) == (
        2.5,
        -2.5,
        0.10,
    )
    assert stack.server.rate == 10.0


def test_a_wrong_backup_limit_is_a_params_error(tmp_path):
    doc = nav2_doc()
    doc["behavior_server"]["ros__parameters"]["backup"]["deceleration_limit"] = 2.5
    with pytest.raises(ParamsError, match="deceleration_limit"):
        params_from(doc, tmp_path)
    load_params(NAV2_PARAMS)  # the file as Nav2 ships it validates


@pytest.mark.parametrize("target", [1.57, -2.5])
def test_spin_turns_by_spin_dist_and_reports_the_angle_turned(office, target):
    stack = office()
    start = stack.world.robot_pose
    handle = stack.send("spin", SpinGoal(target_yaw=target))
    seen = []
    while not handle.done:
        stack.runtime.step()
        if handle.feedback is not None:
            seen.append(handle.feedback.angular_distance_traveled)
    stack.runtime.spin_for(0.5)  # let the base settle
    assert handle.succeeded, handle.result
    turned = angle_diff(stack.world.robot_pose.yaw, start.yaw)
    # Nav2's profile brakes at rotational_acc_lim on a base that lags one cycle behind:
    # it stops within ~0.1 rad past the target.
    assert turned == pytest.approx(target, abs=0.12)
    assert math.copysign(1, turned) == math.copysign(1, target)
    assert seen == sorted(seen) and seen[-1] == pytest.approx(abs(target), abs=0.06)
    assert stack.world.robot_pose.distance_to(start) < 0.01  # in place
    assert stack.world.collisions == 0
    assert stack.runtime.cmd_vel.angular_z == 0.0
    # braking into the target: never above max_rotational_vel (1.0) and done in ~ |target| s
    assert handle.result.value.total_elapsed_time < abs(target) / 1.0 + 1.5


def test_backup_moves_back_by_backup_dist_at_about_backup_speed(office):
    stack = office((2.0, 1.5, 0.0))
    start = stack.world.robot_pose
    handle = stack.run(stack.send("backup", BackUpGoal(target=0.3, speed=0.2)))
    stack.runtime.spin_for(0.5)
    assert handle.succeeded, handle.result
    end = stack.world.robot_pose
    assert start.distance_to(end) == pytest.approx(0.3, abs=0.03)
    assert end.x < start.x  # backwards, along the heading
    assert abs(end.y - start.y) < 0.01
    elapsed = handle.result.value.total_elapsed_time
    assert 0.3 / 0.2 <= elapsed <= 0.3 / 0.2 + 0.6  # about backup_speed, plus braking
    assert handle.feedback.distance_traveled == pytest.approx(0.3, abs=0.03)
    assert stack.world.collisions == 0


def test_drive_on_heading_drives_forward_and_checks_its_input(office):
    stack = office((2.0, 1.5, 0.0))
    start = stack.world.robot_pose
    handle = stack.run(stack.send("drive_on_heading", DriveOnHeadingGoal(target=0.4, speed=0.25)))
    stack.runtime.spin_for(0.5)
    assert handle.succeeded, handle.result
    assert stack.world.robot_pose.x - start.x == pytest.approx(0.4, abs=0.03)

    bad = stack.run(stack.send("drive_on_heading", DriveOnHeadingGoal(target=0.4, speed=-0.2)))
    assert bad.status is GoalStatus.ABORTED
    assert bad.error_code == DriveOnHeadingError.INVALID_INPUT
    sideways = stack.run(stack.send("backup", BackUpGoal(target=(0.0, 0.3, 0.0), speed=0.1)))
    assert sideways.error_code == BackUpError.INVALID_INPUT


def test_backup_stops_short_of_a_wall_behind(office):
    # 1 m in front of the x = 0 wall, facing away from it: backing up 1.5 m would hit it.
    stack = office((1.0, 1.5, 0.0))
    handle = stack.run(stack.send("backup", BackUpGoal(target=1.5, speed=0.2)))
    stack.runtime.spin_for(1.0)
    assert handle.status is GoalStatus.ABORTED
    assert handle.error_code == BackUpError.COLLISION_AHEAD
    assert stack.world.collisions == 0
    x = stack.world.robot_pose.x
    assert 0.05 + 0.22 < x < 1.0  # it moved back some, and stopped clear of the wall
    assert stack.runtime.cmd_vel.linear_x == 0.0
    assert stack.world.robot_pose.x == pytest.approx(x, abs=1e-6)  # and stays stopped


RECT_ROBOT = """
world: corridor
bounds: [[0, 0], [4, 3]]
walls:
  - [[0, 0], [4, 0], [4, 3], [0, 3], [0, 0]]
robot:
  drive: diff_drive
  footprint: {{polygon: [[0.4, 0.15], [0.4, -0.15], [-0.4, -0.15], [-0.4, 0.15]]}}
  pose: [2.0, {y}, 0.0]
  limits: {{v_max: 0.5, w_max: 1.5, a_max: 1.0, alpha_max: 3.0}}
  odometry: {{noise: [0.0, 0.0, 0.0, 0.0], rate: 50}}
  sensors:
    - lidar: {{frame: laser, pose: [0.0, 0.0, 0.0], beams: 360, range: [0.12, 8.0],
              rate: 10, noise_std: 0.0}}
"""


def _rect_params(tmp_path):
    doc = nav2_doc()
    local = doc["local_costmap"]["local_costmap"]["ros__parameters"]
    local["footprint"] = "[[0.4, 0.15], [0.4, -0.15], [-0.4, -0.15], [-0.4, 0.15]]"
    return params_from(doc, tmp_path)


def test_spin_of_a_long_robot_stops_short_of_a_wall_its_corners_would_sweep(tmp_path):
    # The long side is 0.22 m from the wall; the corners sweep 0.43 m from the centre.
    world = write_world(tmp_path, RECT_ROBOT.format(y=0.42))
    stack = make_stack(world, _rect_params(tmp_path))
    yaw0 = world.robot_pose.yaw
    handle = stack.run(stack.send("spin", SpinGoal(target_yaw=1.57)))
    stack.runtime.spin_for(0.5)
    assert handle.status is GoalStatus.ABORTED
    assert handle.error_code == SpinError.COLLISION_AHEAD
    assert world.collisions == 0
    assert abs(angle_diff(world.robot_pose.yaw, yaw0)) < 1.0


def test_without_collision_checks_the_same_spin_hits_the_wall(tmp_path):
    world = write_world(tmp_path, RECT_ROBOT.format(y=0.42))
    stack = make_stack(world, _rect_params(tmp_path))
    stack.run(stack.send("spin", SpinGoal(target_yaw=1.57, disable_collision_checks=True)))
    assert world.collisions > 0


def test_spin_of_a_long_robot_with_room_turns(tmp_path):
    world = write_world(tmp_path, RECT_ROBOT.format(y=1.5))
    stack = make_stack(world, _rect_params(tmp_path))
    handle = stack.run(stack.send("spin", SpinGoal(target_yaw=1.57)))
    assert handle.succeeded, handle.result
    assert world.collisions == 0


def test_time_allowance_expiry_is_timeout(office):
    stack = office()
    handle = stack.run(stack.send("spin", SpinGoal(target_yaw=3 * math.pi, time_allowance=1.0)))
    assert handle.status is GoalStatus.ABORTED
    assert handle.error_code == SpinError.TIMEOUT
    assert 1.0 <= handle.result.value.total_elapsed_time <= 1.2
    assert stack.runtime.cmd_vel.angular_z == 0.0
    stack.runtime.spin_for(1.0)
    assert abs(stack.world.robot_twist.angular_z) < 1e-3

    slow = stack.run(stack.send("backup", BackUpGoal(target=0.5, speed=0.1, time_allowance=0.5)))
    assert slow.error_code == BackUpError.TIMEOUT


def test_wait_waits_wait_duration_of_sim_time(office):
    stack = office()
    start_pose = stack.world.robot_pose
    t0 = stack.runtime.now
    handle = stack.send("wait", WaitGoal(time=2.0))
    left = []
    while not handle.done:
        stack.runtime.step()
        if handle.feedback is not None:
            left.append(handle.feedback.time_left)
    assert handle.succeeded and handle.error_code == WaitError.NONE
    assert 2.0 <= stack.runtime.now - t0 <= 2.0 + 0.1 + 1e-9  # within one cycle
    assert left == sorted(left, reverse=True) and left[-1] == 0.0
    assert stack.world.robot_pose.distance_to(start_pose) < 1e-6


def test_cancel_stops_the_robot(office):
    stack = office((2.0, 1.5, 0.0))
    handle = stack.send("backup", BackUpGoal(target=1.0, speed=0.2))
    stack.runtime.spin_for(1.0)
    assert handle.status is GoalStatus.EXECUTING
    assert stack.world.robot_pose.x < 2.0 - 0.1
    assert handle.cancel()
    stack.run(handle)
    assert handle.status is GoalStatus.CANCELED
    assert stack.runtime.cmd_vel.linear_x == 0.0
    stack.runtime.spin_for(0.5)  # the base brakes to a stop
    x = stack.world.robot_pose.x
    stack.runtime.spin_for(1.0)
    assert stack.world.robot_pose.x == pytest.approx(x, abs=1e-6)


def test_server_without_a_params_file_uses_nav2s_defaults():
    from btnav.nav import Runtime
    from btnav.nav.behavior_server import BehaviorServer
    from btnav.params.navigation import BehaviorServerParams
    from btnav.sim.world import World

    from .stack import OFFICE

    runtime = Runtime(World.from_file(OFFICE), seed=0)
    model = BehaviorServerParams(behavior_plugins=["wait", "assisted_teleop"])
    server = BehaviorServer(runtime, model)
    assert runtime.action_client("wait").wait_for_server()
    # Nav2 gives a type only to its four default names: the fifth has none, and is skipped
    assert server.names == ["wait"] and server.not_implemented == ["assisted_teleop"]
