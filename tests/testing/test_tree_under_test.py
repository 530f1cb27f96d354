"""btnav_tree: a tree on fake servers that answer as the test says, ticked on sim time."""

from __future__ import annotations

import py_trees
import pytest

from btnav import BtnavError
from btnav.testing import respond, tick_until

PLAN_AND_FOLLOW = """
Sequence:
  children:
    - ComputePathToPose: {goal: "{goal}", path: "{path}", error_code_id: "{plan_error}"}
    - FollowPath: {path: "{path}"}
"""

RETRY = """
RecoveryNode:
  number_of_retries: 2
  children:
    - Sequence:
        children:
          - ComputePathToPose: {goal: "{goal}", path: "{path}"}
          - FollowPath: {path: "{path}"}
    - Spin: {spin_dist: 1.57}
"""


def test_fake_servers_answer_success_and_the_planner_makes_a_straight_path(btnav_tree):
    tree = btnav_tree(PLAN_AND_FOLLOW, goal=(3.0, 4.0, 0.5))
    result = tick_until(tree)
    status, ticks = result
    # one tick sends the plan request, the next sees the plan and sends the path, the
    # third sees FollowPath done: RUNNING for one tick each, on sim time only
    assert (status, ticks, result.met) == ("SUCCESS", 3, True)
    assert result.sim_time == pytest.approx(0.03)
    path = tree.blackboard["path"]
    assert path.poses[0, :2] == pytest.approx([0.0, 0.0])  # from the robot at rest
    assert path.poses[-1] == pytest.approx([3.0, 4.0, 0.5])
    assert path.length() == pytest.approx(5.0)
    (goal,) = tree.servers["follow_path"].goals
    assert goal.path is path


def test_an_answer_keeps_the_node_running_for_its_ticks_then_fails_with_its_code(btnav_tree):
    tree = btnav_tree(
        PLAN_AND_FOLLOW,
        goal=(1.0, 0.0, 0.0),
        servers={"ComputePathToPose": respond("FAILURE", ticks=4, error_code="NO_VALID_PATH")},
    )
    assert [tree.tick() for _ in range(5)] == ["RUNNING"] * 4 + ["FAILURE"]
    assert tree.blackboard["plan_error"] == 208  # ComputePathToPose's NO_VALID_PATH
    assert tree.servers["follow_path"].goals == []


def test_answers_go_one_per_goal_and_a_recovery_runs_between(btnav_tree):
    tree = btnav_tree(
        RETRY,
        goal=(1.0, 0.0, 0.0),
        servers={"follow_path": ["FAILURE", respond("SUCCESS", ticks=3)], "Spin": "SUCCESS"},
    )
    result = tick_until(tree, "SUCCESS", timeout=1.0)
    assert result.met and len(tree.servers["follow_path"].goals) == 2
    assert len(tree.servers["spin"].goals) == 1
    statuses = [(r["type"], r["current_status"]) for r in tree.bt_log]
    assert statuses.index(("FollowPath", "FAILURE")) < statuses.index(("Spin", "SUCCESS"))


def test_a_running_server_times_out_on_sim_time_and_a_halt_cancels_it(btnav_tree):
    tree = btnav_tree(RETRY, goal=(1.0, 0.0, 0.0), servers={"FollowPath": "RUNNING"})
    result = tick_until(tree, timeout=2.0)
    assert (result.status, result.ticks, result.met) == ("RUNNING", 200, False)
    assert result.timed_out and tree.now == pytest.approx(2.0)
    tree.halt()
    tree.tick()
    assert tree.servers["follow_path"].canceled == 1


def test_a_condition_may_take_the_tree(btnav_tree):
    tree = btnav_tree(RETRY, goal=(1.0, 0.0, 0.0), servers={"FollowPath": "RUNNING"})
    status, ticks = tick_until(tree, lambda t: t.now >= 0.5)
    assert (status, ticks) == ("RUNNING", 50)


def test_stubs_replace_nodes_that_need_more_than_fake_servers(btnav_tree):
    tree = btnav_tree(
        "navigate_to_pose_w_replanning_and_recovery",  # a bundled tree, by its name
        goal=(1.0, 0.5, 0.0),
        nodes={"ValidatePath": "SUCCESS", "GoalUpdated": ["FAILURE"]},
    )
    assert tick_until(tree, timeout=5.0).status == "SUCCESS"
    assert type(tree.node("ValidatePath")).__name__ == "ValidatePath"


def test_misspelt_servers_and_nodes_are_named_with_the_right_spelling(btnav_tree):
    with pytest.raises(BtnavError, match="did you mean 'FollowPath'"):
        btnav_tree(PLAN_AND_FOLLOW, servers={"FolowPath": "FAILURE"})
    with pytest.raises(BtnavError, match="did you mean 'ComputePathToPose'"):
        btnav_tree(PLAN_AND_FOLLOW, nodes={"ComputePathToPos": "SUCCESS"})
    with pytest.raises(BtnavError, match="did you mean 'FAILURE'"):
        btnav_tree(PLAN_AND_FOLLOW, servers={"FollowPath": "FAILUER"})


def test_the_blackboard_is_put_back_when_the_trees_are_done():
    from btnav.testing.fixtures import trees

    storage = py_trees.blackboard.Blackboard.storage
    with trees() as make:
        tree = make(PLAN_AND_FOLLOW, goal=(1.0, 0.0, 0.0))
        tick_until(tree)
        assert "/path" in storage
        tree.blackboard["btnav_testing_probe"] = 1
    assert "/btnav_testing_probe" not in storage


def test_a_world_from_text(btnav_world):
    world = btnav_world(
        "bounds: [[0, 0], [4, 4]]\nwalls: [[[0, 0], [4, 0]]]\nrobot: {pose: [2, 2, 0]}"
    )
    assert world.robot_pose.x == pytest.approx(2.0) and len(world.solids) == 1
