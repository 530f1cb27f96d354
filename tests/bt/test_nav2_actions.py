"""Nav2's action nodes on a real runtime and navigation stack (the small office):
RUNNING while the server works, Nav2's outputs on the result, cancel on halt, new goal
when the inputs change, and what happens when there is no server."""

from __future__ import annotations

from typing import Any

import numpy as np
import py_trees
import pytest
from py_trees.common import Status

from btnav.bt import load_tree
from btnav.bt.nav2_context import recovery_count
from btnav.core.error_codes import ComputePathToPoseError, FollowPathError, SpinError
from btnav.core.errors import UnknownNameError
from btnav.core.geometry import Pose2D
from btnav.core.messages import Path
from btnav.nav import GoalStatus

from ..nav.navstack_helpers import office, plan
from .fakes import find, set_bb

S, F, R = Status.SUCCESS, Status.FAILURE, Status.RUNNING
DOORWAY_GOAL = Pose2D(6.0, 3.0, 0.0)
IN_THE_TABLE = Pose2D(6.5, 1.2, 0.0)  # the middle of a table: no path (NO_VALID_PATH)


def bb(key: str) -> Any:
    return py_trees.blackboard.Blackboard.get("/" + key)


@pytest.fixture(scope="module")
def stack() -> Any:
    return office()


def tree(xml_body: str, stack: Any) -> Any:
    _world, rt, nav = stack
    xml = f'<root BTCPP_format="4"><BehaviorTree ID="T">{xml_body}</BehaviorTree></root>'
    return load_tree(xml, clock=rt.clock, context={"runtime": rt, "stack": nav})


def run(root: Any, rt: Any, max_ticks: int = 100) -> list[Status]:
    """Tick (one physics step between ticks) until the root finishes; the statuses seen."""
    seen = []
    for _ in range(max_ticks):
        root.tick_once()
        seen.append(root.status)
        if root.status != R:
            break
        rt.step()
    return seen


COMPUTE = (
    '<ComputePathToPose goal="{goal}" path="{path}" planner_id="GridBased" '
    'error_code_id="{ec}" error_msg="{em}"/>'
)


def test_compute_path_to_pose_runs_then_writes_the_path_and_no_error(stack):
    _world, rt, _nav = stack
    root = tree(COMPUTE, stack)
    set_bb("goal", DOORWAY_GOAL)
    statuses = run(root, rt)
    assert statuses == [R, S]  # the planner answers on its next cycle
    path = bb("path")
    assert isinstance(path, Path) and path.frame_id == "map" and len(path) > 10
    assert np.hypot(*(path.poses[-1, :2] - [6.0, 3.0])) < 0.1
    assert bb("ec") == 0 and bb("em") == ""


def test_compute_path_to_pose_failure_writes_nav2s_error_code_and_an_empty_path(stack):
    _world, rt, _nav = stack
    root = tree(COMPUTE, stack)
    set_bb("path", Path(0.0, np.ones((3, 3)), "map"))
    set_bb("goal", IN_THE_TABLE)
    assert run(root, rt)[-1] == F
    assert bb("ec") == ComputePathToPoseError.NO_VALID_PATH
    assert "tolerance" in bb("em")
    assert len(bb("path")) == 0


def test_follow_path_halt_cancels_the_goal_and_stops_the_robot():
    _world, rt, _nav = stack = office()
    path = plan(rt, DOORWAY_GOAL).result.value
    root = tree(
        '<FollowPath path="{path}" controller_id="FollowPath" error_code_id="{ec}" '
        'error_msg="{em}" tracking_feedback="{fb}"/>',
        stack,
    )
    set_bb("path", path)
    statuses = run(root, rt, max_ticks=100)
    assert set(statuses) == {R}  # one second of following
    node = find(root, "FollowPath")
    handle = node.handle
    assert handle.status is GoalStatus.EXECUTING
    assert rt.cmd_vel.linear_x > 0.0
    assert bb("fb").distance_to_goal > 1.0  # the controller's feedback, passed on
    root.stop(Status.INVALID)  # a parent halts it
    assert handle.status is GoalStatus.CANCELING and node.handle is None
    assert bb("ec") == 0
    rt.step()
    rt.spin_for(0.1)
    assert handle.status is GoalStatus.CANCELED
    assert rt.cmd_vel_nav.linear_x == 0.0 and rt.cmd_vel_nav.angular_z == 0.0
    rt.spin_for(0.2)  # the velocity smoother's ramp down (3 m/s^2 from 0.5 m/s at most)
    assert rt.cmd_vel.linear_x == 0.0 and rt.cmd_vel.angular_z == 0.0


def test_follow_path_sends_a_new_goal_when_the_path_changes():
    _world, rt, _nav = stack = office()
    first = plan(rt, DOORWAY_GOAL).result.value
    root = tree('<FollowPath path="{path}" error_code_id="{ec}"/>', stack)
    set_bb("path", first)
    run(root, rt, max_ticks=20)
    node = find(root, "FollowPath")
    old = node.handle
    assert node.goals_sent == 1
    root.tick_once()  # the same path: nothing new
    assert node.goals_sent == 1
    second = plan(rt, Pose2D(6.0, 3.5, 0.0)).result.value
    set_bb("path", second)
    root.tick_once()
    assert root.status == R and node.goals_sent == 2
    assert node.handle is not old and node.handle.goal.path is second
    rt.spin_for(0.1)
    assert old.status is GoalStatus.ABORTED  # preempted by the new path, as in Nav2
    assert node.handle.status is GoalStatus.EXECUTING
    root.stop(Status.INVALID)


def test_follow_path_sends_a_new_goal_when_an_id_or_the_path_changes_between_feedbacks():
    """With every port bound (as in Nav2's trees) a tick that brings no feedback takes the
    short way: it still sees a new controller id or path at once."""
    _world, rt, _nav = stack = office()
    first = plan(rt, DOORWAY_GOAL).result.value
    root = tree(
        '<FollowPath path="{path}" controller_id="{c}" goal_checker_id="{g}" '
        'progress_checker_id="{p}" error_code_id="{ec}"/>',
        stack,
    )
    set_bb("c", "FollowPath")
    set_bb("g", "general_goal_checker")
    set_bb("p", "progress_checker")
    set_bb("path", first)
    run(root, rt, max_ticks=20)
    node = find(root, "FollowPath")
    for _ in range(3):  # no step between them: no new feedback, nothing new
        root.tick_once()
    assert root.status == R and node.goals_sent == 1
    set_bb("c", "FollowPath")  # an equal id in a new str: still the same goal
    root.tick_once()
    assert node.goals_sent == 1
    set_bb("g", "stopped_goal_checker")
    root.tick_once()
    assert node.goals_sent == 2 and node.handle.goal.goal_checker_id == "stopped_goal_checker"
    second = plan(rt, Pose2D(6.0, 3.5, 0.0)).result.value
    set_bb("path", second)
    root.tick_once()
    assert node.goals_sent == 3 and node.handle.goal.path is second
    root.tick_once()
    assert root.status == R and node.goals_sent == 3
    root.stop(Status.INVALID)


def test_follow_path_with_an_empty_path_fails_with_invalid_path(stack):
    _world, rt, _nav = stack
    root = tree('<FollowPath path="{path}" error_code_id="{ec}" error_msg="{em}"/>', stack)
    set_bb("path", Path(0.0, np.zeros((0, 3)), "map"))
    assert run(root, rt)[-1] == F
    assert bb("ec") == FollowPathError.INVALID_PATH


def test_spin_is_a_recovery_and_reports_success(stack):
    _world, rt, _nav = stack
    root = tree('<Spin spin_dist="0.5" error_code_id="{ec}" error_msg="{em}"/>', stack)
    before = recovery_count()
    statuses = run(root, rt, max_ticks=500)
    assert statuses[0] == R and statuses[-1] == S and len(statuses) > 10
    assert recovery_count() == before + 1
    assert bb("ec") == 0
    root = tree('<Spin spin_dist="0.5" is_recovery="false"/>', stack)
    run(root, rt, max_ticks=500)
    assert recovery_count() == before + 1


def test_a_server_name_the_runtime_lacks_is_a_load_error(stack):
    with pytest.raises(UnknownNameError) as info:
        tree('<Spin server_name="spinn"/>', stack)
    assert "spinn" in str(info.value) and "did you mean 'spin'" in str(info.value)


def test_without_a_runtime_an_action_node_fails_with_send_goal_failure():
    root = load_tree(
        '<root BTCPP_format="4"><BehaviorTree ID="T">'
        '<Spin error_code_id="{ec}" error_msg="{em}"/></BehaviorTree></root>'
    )
    root.tick_once()
    assert root.status == F
    assert bb("ec") == SpinError.SEND_GOAL_FAILURE
    assert "context={'runtime'" in bb("em")


def test_clear_entire_costmap_calls_the_stacks_service_and_counts_a_recovery(stack):
    _world, _rt, nav = stack
    called = []
    ros = nav.local_costmap.costmap_ros
    real = ros.clear_entirely
    ros.clear_entirely = lambda: called.append(1) or real()
    try:
        root = tree(
            '<ClearEntireCostmap service_name="local_costmap/clear_entirely_local_costmap"/>',
            stack,
        )
        before = recovery_count()
        root.tick_once()
        assert root.status == S and called == [1]
        assert recovery_count() == before + 1
    finally:
        del ros.clear_entirely
    with pytest.raises(UnknownNameError) as info:
        tree('<ClearEntireCostmap service_name="local_costmap/clear_entirely"/>', stack)
    assert "clear_entirely_local_costmap" in str(info.value)


def test_cancel_control_cancels_the_controllers_goal(stack):
    _world, rt, _nav = stack
    from btnav.core.nav2_msgs import FollowPathGoal

    path = plan(rt, DOORWAY_GOAL).result.value
    handle = rt.action_client("follow_path").send_goal(FollowPathGoal(path))
    rt.spin_for(0.2)
    assert handle.status is GoalStatus.EXECUTING
    root = tree("<CancelControl/>", stack)
    root.tick_once()
    assert root.status == S
    rt.spin_for(0.1)
    assert handle.status is GoalStatus.CANCELED


@pytest.mark.parametrize(("is_recovery", "status"), [("false", S), ("true", F)])
def test_assisted_teleop_times_out_with_nav2s_code_and_fails_only_as_a_recovery(
    is_recovery, status
):
    _world, rt, _nav = stack = office()
    root = tree(
        f'<AssistedTeleop time_allowance="0.5" is_recovery="{is_recovery}" '
        'error_code_id="{ec}" error_msg="{em}"/>',
        stack,
    )
    count = recovery_count()
    statuses = run(root, rt, max_ticks=200)
    assert statuses[-1] == status and statuses[:-1] == [R] * (len(statuses) - 1)
    assert 0.5 <= rt.now <= 0.75  # the allowance, then the next cycle of the server (10 Hz)
    assert bb("ec") == 731  # AssistedTeleop's TIMEOUT
    assert recovery_count() == count + (1 if is_recovery == "true" else 0)


def test_cancel_assisted_teleop_ends_the_running_goal():
    _world, rt, _nav = stack = office()
    root = tree(
        '<Sequence><AssistedTeleop time_allowance="0" error_code_id="{ec}" error_msg="{em}"/>'
        "</Sequence>",
        stack,
    )
    run(root, rt, max_ticks=20)
    handle = find(root, "AssistedTeleop").handle
    assert handle.status is GoalStatus.EXECUTING
    cancel = tree("<CancelAssistedTeleop/>", stack)
    assert run(cancel, rt)[-1] == S
    rt.spin_for(0.2)
    assert handle.status is GoalStatus.CANCELED
