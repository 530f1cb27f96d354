"""Nav2's condition nodes, ticked with a stand-in runtime (a robot pose and a sim clock)."""

from __future__ import annotations

from typing import Any

import numpy as np
import pytest
from py_trees.common import Status

from btnav.bt import load_tree
from btnav.core.clock import SimClock
from btnav.core.errors import FrameError
from btnav.core.geometry import Pose2D
from btnav.core.messages import Path, PoseStamped, TrackingFeedback

from .fakes import set_bb

S, F, R = Status.SUCCESS, Status.FAILURE, Status.RUNNING


class FakeRuntime:
    """What the nodes use of a Runtime: the robot pose in `map`, a clock, topics."""

    def __init__(self, pose: Pose2D | None = None) -> None:
        self.pose = pose if pose is not None else Pose2D()
        self.clock = SimClock()
        self.subscribers: dict[str, list[Any]] = {}

    def lookup(self, target: str, source: str) -> Pose2D:
        if target == source:
            return Pose2D()
        if (target, source) in (("map", "base_link"), ("odom", "base_link")):
            return self.pose
        raise FrameError(f"no transform {target} <- {source}")

    def subscribe(self, topic: str, callback: Any) -> None:
        self.subscribers.setdefault(topic, []).append(callback)


def ticker(body: str, runtime: FakeRuntime | None = None) -> Any:
    rt = runtime or FakeRuntime()
    xml = f'<root BTCPP_format="4"><BehaviorTree ID="T">{body}</BehaviorTree></root>'
    root = load_tree(xml, clock=rt.clock, context={"runtime": rt})

    def tick() -> Status:
        root.tick_once()
        return root.status

    tick.root = root  # type: ignore[attr-defined]
    return tick


def straight_path(length: float = 10.0, step: float = 0.1) -> Path:
    xs = np.arange(0.0, length + 1e-9, step)
    return Path(0.0, np.stack([xs, np.zeros_like(xs), np.zeros_like(xs)], axis=1), "map")


def test_goal_updated_succeeds_on_a_new_goal_and_starts_over_after_a_halt():
    tick = ticker("<GoalUpdated/>")  # reads {goal} and {goals} by default
    set_bb("goal", Pose2D(1, 1, 0))
    assert tick() == F  # first tick of a run: records the goal
    assert tick() == F
    set_bb("goal", Pose2D(2, 1, 0))
    assert tick() == S
    assert tick() == F
    set_bb("goals", [Pose2D(3, 3, 0)])
    assert tick() == S
    tick.root.stop(Status.INVALID)  # halted: the next tick records again
    set_bb("goal", Pose2D(5, 5, 0))
    assert tick() == F


def test_global_updated_goal_succeeds_first_then_on_changes_even_across_halts():
    tick = ticker("<GlobalUpdatedGoal/>")
    set_bb("goal", PoseStamped(0.0, Pose2D(1, 1, 0)))
    assert [tick(), tick()] == [S, F]
    tick.root.stop(Status.INVALID)
    assert tick() == F
    set_bb("goal", PoseStamped(0.0, Pose2D(1, 2, 0)))
    assert [tick(), tick()] == [S, F]


@pytest.mark.parametrize(
    ("node", "code", "expected"),
    [
        ("WouldAPlannerRecoveryHelp", 208, S),  # NO_VALID_PATH
        ("WouldAPlannerRecoveryHelp", 206, F),  # GOAL_OCCUPIED: a recovery would not help
        ("WouldAPlannerRecoveryHelp", 308, S),  # ComputePathThroughPoses NO_VALID_PATH
        ("WouldAPlannerRecoveryHelp", 0, F),
        ("WouldAControllerRecoveryHelp", 105, S),  # FAILED_TO_MAKE_PROGRESS
        ("WouldAControllerRecoveryHelp", 103, F),  # INVALID_PATH
        ("WouldASmootherRecoveryHelp", 503, S),
    ],
)
def test_would_a_recovery_help(node, code, expected):
    tick = ticker(f'<{node} error_code="{{ec}}"/>')
    set_bb("ec", code)
    assert tick() == expected


def test_would_a_recovery_help_reads_a_code_never_written_as_none():
    assert ticker('<WouldAControllerRecoveryHelp error_code="{follow_path_error_code}"/>')() == F


def test_are_error_codes_present_with_a_constant_list():
    tick = ticker('<AreErrorCodesPresent error_code="{ec}" error_codes_to_check="101;107;119"/>')
    set_bb("ec", 107)
    assert tick() == S
    set_bb("ec", 108)
    assert tick() == F


def test_is_goal_nearby_measures_the_path_left_from_the_robot():
    rt = FakeRuntime(Pose2D(5.0, 0.2, 0.0))
    tick = ticker('<IsGoalNearby path="{path}" proximity_threshold="4.0"/>', rt)
    set_bb("path", straight_path(10.0))
    assert tick() == F  # 5 m left
    rt.pose = Pose2D(6.5, -0.1, 0.0)
    assert tick() == S  # 3.5 m left
    set_bb("path", Path(0.0, np.zeros((0, 3)), "map"))
    assert tick() == F


def test_is_goal_nearby_with_a_search_window_follows_the_robot_round_a_loop():
    # out 5 m and back along the same line: on the way back, the nearest pose overall
    # is on the way out; the search window from the last nearest pose is not fooled
    out = np.stack([np.arange(0, 5.01, 0.1), np.zeros(51), np.zeros(51)], axis=1)
    back = out[::-1].copy()
    back[:, 1] = 0.05
    path = Path(0.0, np.concatenate([out, back]), "map")
    rt = FakeRuntime()
    windowed = ticker(
        '<IsGoalNearby path="{path}" proximity_threshold="4.0" max_robot_pose_search_dist="1.5"/>',
        rt,
    )
    whole = ticker('<IsGoalNearby path="{path}" proximity_threshold="4.0"/>', rt)
    set_bb("path", path)
    for x, y in [(0.5, 0), (1.5, 0), (2.5, 0), (3.5, 0), (4.5, 0), (5.0, 0), (4.0, 0.05)]:
        rt.pose = Pose2D(x, y, 0.0)
        assert windowed() == F
    for x in (3.0, 2.0, 1.0):
        rt.pose = Pose2D(x, 0.0, 0.0)  # on the way back (4 m from the end at most)
        assert windowed() == S
        assert whole() == F  # the whole-path search picks the pose on the way out


def test_robot_pose_conditions_fail_without_a_transform():
    rt = FakeRuntime()
    tick = ticker('<IsGoalNearby path="{path}" robot_base_frame="no_such_frame"/>', rt)
    set_bb("path", straight_path(1.0))
    assert tick() == F


def test_goal_reached_within_a_quarter_metre():
    rt = FakeRuntime(Pose2D(1.0, 1.0, 0.0))
    tick = ticker('<GoalReached goal="{goal}"/>', rt)
    set_bb("goal", Pose2D(1.2, 1.1, 0.0))
    assert tick() == S
    set_bb("goal", Pose2D(1.3, 1.2, 0.0))
    assert tick() == F


def test_time_expired_on_sim_time():
    rt = FakeRuntime()
    tick = ticker('<TimeExpired seconds="1.0"/>', rt)
    assert tick() == F  # starts the timer
    rt.clock.advance(0.5)
    assert tick() == F
    rt.clock.advance(0.5)
    assert tick() == S
    assert tick() == F  # restarted


def test_distance_traveled_succeeds_each_metre():
    rt = FakeRuntime(Pose2D(0.0, 0.0, 0.0))
    tick = ticker('<DistanceTraveled distance="1.0"/>', rt)
    assert tick() == F
    rt.pose = Pose2D(0.6, 0.0, 0.0)
    assert tick() == F
    rt.pose = Pose2D(1.0, 0.0, 0.0)
    assert tick() == S
    rt.pose = Pose2D(1.5, 0.0, 0.0)
    assert tick() == F


def test_path_expiring_timer_restarts_on_a_new_path():
    rt = FakeRuntime()
    tick = ticker('<PathExpiringTimer seconds="1.0" path="{path}"/>', rt)
    set_bb("path", straight_path(1.0))
    assert tick() == F
    rt.clock.advance(0.8)
    set_bb("path", straight_path(2.0))
    assert tick() == F
    rt.clock.advance(0.8)
    assert tick() == F
    rt.clock.advance(0.3)
    assert tick() == S


def test_initial_pose_received_and_transform_available():
    tick = ticker("<InitialPoseReceived/>")
    assert tick() == F
    set_bb("initial_pose_received", True)
    assert tick() == S
    tick = ticker('<TransformAvailable parent="map" child="base_link"/>')
    assert tick() == S
    tick = ticker('<TransformAvailable parent="map" child="gripper"/>')
    assert tick() == F


def test_are_poses_near():
    tick = ticker('<ArePosesNear ref_pose="{a}" target_pose="{b}" tolerance="0.5"/>')
    set_bb("a", Pose2D(0, 0, 0))
    set_bb("b", Pose2D(0.3, 0.3, 1.0))
    assert tick() == S
    set_bb("b", Pose2D(0.4, 0.4, 0.0))
    assert tick() == F


def feedback(error: float, heading: float = 0.0) -> TrackingFeedback:
    return TrackingFeedback(0.0, error, heading, 0, Pose2D(), 1.0, 0.3, 1.0)


def test_is_within_path_tracking_bounds_reads_the_controllers_feedback():
    tick = ticker(
        '<IsWithinPathTrackingBounds max_error_left="0.2" max_error_right="-0.1" '
        'max_error_heading="1.0" tracking_feedback="{tracking_feedback}"/>'
    )
    assert tick() == S  # no feedback yet
    for error, heading, expected in [
        (0.15, 0.0, S),  # left of the path, within 0.2
        (0.25, 0.0, F),
        (-0.05, 0.0, S),  # right, within |-0.1|
        (-0.15, 0.0, F),
        (0.0, -1.2, F),  # heading off by more than 1 rad
    ]:
        set_bb("tracking_feedback", feedback(error, heading))
        assert tick() == expected, (error, heading)
    set_bb("tracking_feedback", {})  # what FollowPath writes when it ends
    assert tick() == S
