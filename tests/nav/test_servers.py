"""The servers through their action clients: controller cancel/preempt/ids, smoother,
map_server, costmap components, and dynamic parameters (set_parameters)."""

from __future__ import annotations

import numpy as np
import pytest

from btnav.core.error_codes import FollowPathError, SmoothPathError
from btnav.core.errors import ParamsError
from btnav.core.geometry import Pose2D
from btnav.core.messages import Path
from btnav.core.nav2_msgs import FollowPathGoal, SmoothPathGoal, SpinGoal
from btnav.costmap.cost_values import FREE_SPACE
from btnav.nav import GoalStatus
from btnav.nav.stack import NavStack

from .navstack_helpers import DWB, office, params_with_controller, plan

GOAL = Pose2D(3.0, 1.0, 0.0)


def test_stack_has_nav2s_servers_and_costmap_frames():
    _w, rt, stack = office()
    for name in (
        "compute_path_to_pose",
        "compute_path_through_poses",
        "follow_path",
        "smooth_path",
    ):
        assert rt.action_client(name).wait_for_server()
    assert stack.global_costmap.global_frame == "map"
    assert stack.local_costmap.global_frame == "odom"
    assert stack.global_costmap.rate == 1.0 and stack.local_costmap.rate == 5.0
    assert stack.controller_server.rate == 20.0
    g = stack.global_costmap.costmap
    assert g.size_in_meters[0] > 12.0  # the whole office map
    assert "local_costmap/clear_entirely_local_costmap" in stack.services()


def test_follow_path_cancel_leaves_zero_velocity():
    _w, rt, _stack = office()
    path = plan(rt, GOAL).result.value
    h = rt.action_client("follow_path").send_goal(FollowPathGoal(path))
    rt.spin_for(1.0)
    assert h.status is GoalStatus.EXECUTING and rt.cmd_vel.linear_x > 0.0
    assert isinstance(h.feedback.distance_to_goal, float)
    h.cancel()
    rt.spin_for(0.1)
    assert h.status is GoalStatus.CANCELED
    assert (rt.cmd_vel_nav.linear_x, rt.cmd_vel_nav.angular_z) == (0.0, 0.0)
    rt.spin_for(0.2)  # the velocity smoother ramps the base down (3 m/s^2, Nav2's file)
    assert (rt.cmd_vel.linear_x, rt.cmd_vel.angular_z) == (0.0, 0.0)


def test_preemption_swaps_the_path_and_keeps_progress_state():
    _w, rt, stack = office()
    path = plan(rt, GOAL).result.value
    client = rt.action_client("follow_path")
    first = client.send_goal(FollowPathGoal(path))
    rt.spin_for(1.0)
    checker = stack.controller_server.progress_checker
    baseline = checker.baseline_time
    second = client.send_goal(FollowPathGoal(path))
    rt.spin_for(0.1)
    assert first.status is GoalStatus.ABORTED and first.error_code == 0
    assert second.status is GoalStatus.EXECUTING
    assert checker.baseline_time == baseline  # not reset by the new path


def test_unknown_controller_or_checker_id_and_empty_path():
    _w, rt, _stack = office()
    path = plan(rt, GOAL).result.value
    client = rt.action_client("follow_path")
    for goal in (
        FollowPathGoal(path, controller_id="FollowPth"),
        FollowPathGoal(path, goal_checker_id="precise_goal_checker"),
    ):
        h = client.send_goal(goal)
        rt.spin_for(0.1)
        assert h.error_code == FollowPathError.INVALID_CONTROLLER, h.result
    h = client.send_goal(FollowPathGoal(Path(0.0, np.zeros((0, 3)))))
    rt.spin_for(0.1)
    assert h.error_code == FollowPathError.INVALID_PATH


def test_no_progress_aborts_with_failed_to_make_progress():
    _w, rt, stack = office()
    path = plan(rt, GOAL).result.value
    stack.set_parameters(
        "controller_server",
        {
            "progress_checker.required_movement_radius": 50.0,
            "progress_checker.movement_time_allowance": 1.0,
        },
    )
    h = rt.action_client("follow_path").send_goal(FollowPathGoal(path))
    rt.run_until(lambda: h.done, 5.0)
    assert h.error_code == FollowPathError.FAILED_TO_MAKE_PROGRESS
    assert rt.cmd_vel_nav.linear_x == 0.0


def test_smooth_path_action():
    _w, rt, _stack = office()
    path = plan(rt, Pose2D(6.0, 3.0, 0.0)).result.value
    h = rt.action_client("smooth_path").send_goal(SmoothPathGoal(path, "simple_smoother"))
    rt.spin_for(0.02)
    assert h.succeeded, h.result
    assert h.result.value.path.length() <= path.length() + 1e-6
    bad = rt.action_client("smooth_path").send_goal(SmoothPathGoal(path, "nope"))
    rt.spin_for(0.02)
    assert bad.error_code == SmoothPathError.INVALID_SMOOTHER


def test_map_server_yaml_filename(tmp_path):
    from btnav.nav.runtime import Runtime
    from btnav.params import apply_overrides, load_params
    from btnav.sim.world import World

    from .navstack_helpers import MAP, PARAMS, WORLD

    params = apply_overrides(load_params(PARAMS), {"map_server.yaml_filename": str(MAP)})
    rt = Runtime(World.from_file(WORLD, seed=0), seed=0)
    stack = NavStack.build(rt, params)
    assert stack.map_server.map is not None
    assert stack.global_costmap.costmap.size_in_meters[0] > 12.0


def test_inflation_radius_changes_the_local_costmap_mid_run():
    _w, rt, stack = office()
    path = plan(rt, Pose2D(6.0, 3.0, 0.0)).result.value
    h = rt.action_client("follow_path").send_goal(FollowPathGoal(path))
    rt.spin_for(2.0)
    local = stack.local_costmap.costmap
    inflated_before = int((local.costs > FREE_SPACE).sum())
    assert inflated_before > 0
    with pytest.raises(ParamsError):
        stack.set_parameters("local_costmap", {"inflation_layer.inflation_radius": -1.0})
    assert int((stack.local_costmap.costmap.costs > FREE_SPACE).sum()) == inflated_before

    stack.set_parameters("local_costmap", {"inflation_layer.inflation_radius": 0.3})
    after = int((stack.local_costmap.costmap.costs > FREE_SPACE).sum())
    assert after < inflated_before  # a thinner band of inflated cells round the walls
    rt.spin_for(0.5)  # and it stays so after the next updates
    assert int((stack.local_costmap.costmap.costs > FREE_SPACE).sum()) < inflated_before
    assert stack.local_costmap.costmap_ros.layer("inflation_layer").params.inflation_radius == 0.3
    assert h.active


def test_a_path_is_set_once_and_only_refreshed_as_map_to_odom_moves(tmp_path):
    """Nav2 calls setPlan for a new path only; DWB's critics keep their state in between."""
    _w, rt, stack = office(params_with_controller(tmp_path, DWB))
    path = plan(rt, GOAL).result.value
    rt.action_client("follow_path").send_goal(FollowPathGoal(path))
    rt.spin_for(0.2)  # the controller exists once the goal has started
    controller = stack.controller_server.controller
    calls = {"set": 0, "refresh": 0}
    set_plan, refresh_plan = controller.set_plan, controller.refresh_plan

    def counting_set(p):
        calls["set"] += 1
        set_plan(p)

    def counting_refresh(p):
        calls["refresh"] += 1
        refresh_plan(p)

    controller.set_plan, controller.refresh_plan = counting_set, counting_refresh
    rt.spin_for(3.0)  # odometry drifts, the localiser moves map -> odom
    assert calls["set"] == 0 and calls["refresh"] > 0
    rt.action_client("follow_path").send_goal(FollowPathGoal(plan(rt, GOAL).result.value))
    rt.spin_for(0.2)
    assert calls["set"] == 1


def test_the_stack_serves_nav2s_behaviors_on_its_local_costmap():
    from btnav.core.error_codes import SpinError

    world, rt, stack = office()
    assert set(stack.behavior_server.servers) == {
        "spin",
        "backup",
        "drive_on_heading",
        "assisted_teleop",
        "wait",
    }
    assert stack.behavior_server.not_implemented == []
    rt.spin_for(0.5)  # the local costmap has seen the walls
    h = rt.action_client("spin").send_goal(SpinGoal(target_yaw=1.57, time_allowance=10.0))
    assert rt.run_until(lambda: h.done, 15.0)
    assert h.succeeded and h.error_code == SpinError.NONE
    assert world.collisions == 0


def test_behavior_server_takes_new_parameters_live():
    _w, _rt, stack = office()
    stack.set_parameters(
        "behavior_server", {"max_rotational_vel": 0.5, "backup.minimum_speed": 0.05}
    )
    assert stack.behavior_server.behaviors["spin"].server.max_rotational_vel == 0.5
    assert stack.behavior_server.behaviors["backup"].params.minimum_speed == 0.05
