"""Nav2's action nodes that need no action server: selectors, path and goal-list nodes,
and ValidatePath on the office's global costmap."""

from __future__ import annotations

import math
from types import SimpleNamespace
from typing import Any

import numpy as np
import py_trees
from py_trees.common import Status

from btnav.bt import load_tree
from btnav.core.geometry import Pose2D
from btnav.core.messages import Path

from ..nav.navstack_helpers import office, plan
from .fakes import set_bb
from .test_nav2_conditions import FakeRuntime, straight_path, ticker

S, F = Status.SUCCESS, Status.FAILURE


def bb(key: str) -> Any:
    return py_trees.blackboard.Blackboard.get("/" + key)


def test_planner_selector_uses_the_default_until_a_selection_arrives():
    rt = FakeRuntime()
    tick = ticker(
        '<PlannerSelector selected_planner="{p}" default_planner="GridBased" '
        'topic_name="planner_selector"/>',
        rt,
    )
    assert tick() == S and bb("p") == "GridBased"
    for callback in rt.subscribers["planner_selector"]:
        callback(SimpleNamespace(data="SmacHybrid"))
    assert tick() == S and bb("p") == "SmacHybrid"


def test_a_selector_writes_its_selection_on_every_tick_as_nav2s_does():
    """An entry another node overwrote between ticks gets the selection back, and an empty
    selection is not one: the default stays."""
    rt = FakeRuntime()
    tick = ticker(
        '<ControllerSelector selected_controller="{c}" default_controller="FollowPath" '
        'topic_name="controller_selector"/>',
        rt,
    )
    assert tick() == S and bb("c") == "FollowPath"
    set_bb("c", "Overwritten")
    assert tick() == S and bb("c") == "FollowPath"
    for callback in rt.subscribers["controller_selector"]:
        callback(SimpleNamespace(data=""))
    assert tick() == S and bb("c") == "FollowPath"


def test_a_selector_reads_its_topic_when_a_run_starts_as_nav2s_initialize_does():
    rt = FakeRuntime()
    tick = ticker(
        '<ControllerSelector selected_controller="{c}" default_controller="FollowPath" '
        'topic_name="{topic}"/>',
        rt,
    )
    set_bb("topic", "first")
    assert tick() == S
    set_bb("topic", "second")
    assert tick() == S and list(rt.subscribers) == ["first"]  # mid-run: the same topic
    tick.root.stop(Status.INVALID)  # a new run (Nav2: the node is not active)
    assert tick() == S and list(rt.subscribers) == ["first", "second"]
    assert len(rt.subscribers["first"]) == 1


def test_a_selector_without_default_or_selection_fails():
    assert ticker('<ControllerSelector selected_controller="{c}"/>')() == F


def test_truncate_path_local_keeps_the_window_round_the_robot():
    rt = FakeRuntime(Pose2D(3.02, 0.1, 0.0))
    tick = ticker(
        '<TruncatePathLocal input_path="{path}" output_path="{out}" '
        'distance_forward="2.0" distance_backward="1.0"/>',
        rt,
    )
    set_bb("path", straight_path(10.0))
    assert tick() == S
    out = bb("out").poses
    assert out[0, 0] == 2.0 and out[-1, 0] == 5.0  # 1 m behind, 2 m ahead (Nav2's ends)
    tick = ticker(
        '<TruncatePathLocal input_path="{path}" output_path="{out}" '
        'distance_forward="-1" distance_backward="0.0"/>',
        rt,
    )
    assert tick() == S
    out = bb("out").poses
    assert out[0, 0] == 3.0 and out[-1, 0] == 10.0


def first_after_integrated_distance(poses: np.ndarray, begin: int, distance: float) -> int:
    """nav2_util's loop, pose by pose (the segment lengths as btnav's fmath measures them)."""
    length = 0.0
    for i in range(begin, len(poses) - 1):
        dx, dy = poses[i + 1, 0] - poses[i, 0], poses[i + 1, 1] - poses[i, 1]
        length += math.sqrt(dx * dx + dy * dy)
        if length > distance:
            return i + 1
    return len(poses)


def test_truncate_path_local_cuts_where_nav2_util_integrates_to():
    """A NavFn-like path of cell centres (windows that tie within rounding), the robot
    anywhere along it: the pose nearest the robot, then Nav2's integrated distances
    forward and back, pose for pose."""
    rng = np.random.default_rng(2)
    for _ in range(40):
        cells = np.cumsum(rng.choice([[1, 0], [0, 1], [1, 1]], size=int(rng.integers(20, 120))), 0)
        poses = np.zeros((len(cells), 3))
        poses[:, :2] = rng.uniform(-2.0, 2.0, 2) + (cells + 0.5) * 0.05
        k = int(rng.integers(len(poses)))
        robot = Pose2D(*(poses[k, :2] + rng.normal(0.0, 0.02, 2)), 0.0)
        forward = float(rng.choice([0.5, 1.0, 2.0, 0.05 * rng.integers(1, 30), -1.0]))
        backward = float(rng.choice([0.0, 0.25, 1.0, 0.05 * rng.integers(1, 30)]))
        tick = ticker(
            '<TruncatePathLocal input_path="{path}" output_path="{out}" '
            f'distance_forward="{forward}" distance_backward="{backward}"/>',
            FakeRuntime(robot),
        )
        set_bb("path", Path(0.0, poses))
        assert tick() == S
        d2 = (poses[:, 0] - robot.x) ** 2 + (poses[:, 1] - robot.y) ** 2
        current = int(np.argmin(d2))
        end = first_after_integrated_distance(poses, current, math.inf if forward < 0 else forward)
        back = (
            current + 1 - first_after_integrated_distance(poses[: current + 1][::-1], 0, backward)
        )
        assert np.array_equal(bb("out").poses, poses[back:end])


def test_truncate_path_drops_the_end_and_faces_the_goal():
    tick = ticker('<TruncatePath input_path="{path}" output_path="{out}" distance="1.0"/>')
    set_bb("path", straight_path(5.0))
    assert tick() == S
    out = bb("out").poses
    assert np.isclose(out[-1, 0], 4.0) and out[-1, 2] == 0.0


def test_remove_passed_goals_drops_the_goals_the_robot_reached():
    rt = FakeRuntime(Pose2D(1.0, 1.0, 0.0))
    tick = ticker(
        '<RemovePassedGoals input_goals="{goals}" output_goals="{goals}" radius="0.7"/>', rt
    )
    goals = [Pose2D(1.3, 1.2, 0.0), Pose2D(3.0, 1.0, 0.0), Pose2D(6.0, 1.0, 0.0)]
    set_bb("goals", goals)
    assert tick() == S
    assert bb("goals") == goals[1:]
    rt.pose = Pose2D(6.0, 1.0, 0.0)
    set_bb("goals", goals[2:])
    assert tick() == S and bb("goals") == goals[2:]  # the last goal always stays


def test_remove_passed_goals_marks_waypoint_statuses():
    rt = FakeRuntime(Pose2D(1.0, 1.0, 0.0))
    tick = ticker(
        '<RemovePassedGoals input_goals="{goals}" output_goals="{goals}" radius="0.5" '
        'input_waypoint_statuses="{ws}" output_waypoint_statuses="{ws}"/>',
        rt,
    )
    goals = [Pose2D(1.0, 1.0, 0.0), Pose2D(3.0, 1.0, 0.0)]
    set_bb("goals", goals)
    set_bb("ws", [{"waypoint_pose": g, "waypoint_status": 0} for g in goals])
    assert tick() == S
    assert [w["waypoint_status"] for w in bb("ws")] == [1, 0]


def test_get_pose_from_path():
    tick = ticker('<GetPoseFromPath path="{path}" index="-1" pose="{pose}"/>')
    set_bb("path", straight_path(2.0))
    assert tick() == S
    assert bb("pose").pose.x == 2.0 and bb("pose").frame_id == "map"


def test_validate_path_on_the_global_costmap():
    _world, rt, nav = office()
    path = plan(rt, Pose2D(6.0, 3.0, 0.0)).result.value
    root = load_tree(
        '<root BTCPP_format="4"><BehaviorTree ID="T">'
        '<ValidatePath path="{path}" collision_poses="{hits}"/></BehaviorTree></root>',
        clock=rt.clock,
        context={"runtime": rt, "stack": nav},
    )
    set_bb("path", path)
    root.tick_once()
    assert root.status == S and bb("hits") == []
    through_the_table = Path(
        0.0, np.array([[5.5, 1.2, 0.0], [6.5, 1.2, 0.0], [7.5, 1.2, 0.0]]), "map"
    )
    set_bb("path", through_the_table)
    root.tick_once()
    assert root.status == F
    assert len(bb("hits")) == 1 and bb("hits")[0].pose.x == 6.5


def test_goal_list_and_pose_nodes():
    rt = FakeRuntime(Pose2D(1.0, 2.0, 0.5))
    tick = ticker('<GetCurrentPose current_pose="{here}"/>', rt)
    assert tick() == S and bb("here").pose == Pose2D(1.0, 2.0, 0.5)
    a, b = Pose2D(1, 1, 0), Pose2D(2, 2, 0)
    set_bb("goals", [a])
    set_bb("g", b)
    tick = ticker(
        '<AppendGoalPoseToGoals goal_pose="{g}" input_goals="{goals}" output_goals="{all}"/>'
    )
    assert tick() == S and bb("all") == [a, b]
    tick = ticker('<GetNextFewGoals num_goals="1" input_goals="{all}" output_goals="{few}"/>')
    assert tick() == S and bb("few") == [a]
    set_bb("p1", straight_path(1.0))
    set_bb("p2", straight_path(2.0))
    tick = ticker('<ConcatenatePaths input_path1="{p1}" input_path2="{p2}" output_path="{p}"/>')
    assert tick() == S and len(bb("p")) == 11 + 21
