"""The Navigator API (BasicNavigator in Python) on the small office with Nav2's params."""

from __future__ import annotations

import itertools
import math
import time
from pathlib import Path

import pytest

from btnav import Navigator
from btnav.core.error_codes import ComputePathToPoseError, Outcome
from btnav.core.geometry import Pose2D
from btnav.navigators.waypoint_follower import WaitAtWaypoint
from btnav.plugins import lookup

REPO = Path(__file__).resolve().parents[2]
WORLD = REPO / "worlds" / "small_office.yaml"
MAP = REPO / "maps" / "small_office.yaml"
PARAMS = REPO / "params" / "nav2_params.yaml"
TOLERANCE = 0.25 + 0.02  # Nav2's xy_goal_tolerance, and a margin for the last step


def office() -> Navigator:
    return Navigator.from_files(WORLD, PARAMS, MAP, seed=0)


def xy_dist(a: Pose2D, b: Pose2D) -> float:
    return math.hypot(a.x - b.x, a.y - b.y)


def test_wait_at_waypoint_is_nav2s_task_executor():
    assert (
        lookup("waypoint_task_executor", "nav2_waypoint_follower::WaitAtWaypoint") is WaitAtWaypoint
    )
    wait = WaitAtWaypoint("wait_at_waypoint", WaitAtWaypoint.Params(waypoint_pause_duration=200))
    assert wait.start(Pose2D(), 0, 1.0) is None
    assert wait.update(1.1) is None
    assert wait.update(1.2) is True
    off = WaitAtWaypoint("w", WaitAtWaypoint.Params(enabled=False, waypoint_pause_duration=200))
    assert off.start(Pose2D(), 0, 1.0) is True


def test_params_name_the_task_executor_and_the_navigators():
    nav = office()
    assert nav.waypoint_follower.executor.params.waypoint_pause_duration == 200  # Nav2's file
    assert set(nav.bt_navigator.navigators) == {"navigate_to_pose", "navigate_through_poses"}
    nav.set_parameters("waypoint_follower", {"wait_at_waypoint.waypoint_pause_duration": 50})
    assert nav.waypoint_follower.executor.params.waypoint_pause_duration == 50
    assert nav.is_task_complete()  # no task yet
    assert nav.get_result() is None


@pytest.mark.slow
def test_go_to_pose_reaches_the_goal_with_sensible_feedback():
    nav = office()
    goal = Pose2D(6.0, 3.0, 0.0)
    w0 = time.perf_counter()
    assert nav.go_to_pose(goal)
    feedback = []
    while not nav.is_task_complete():
        feedback.append(nav.get_feedback())
    result = nav.get_result()
    print(f"go_to_pose: {result}, sim {nav.now:.1f} s, wall {time.perf_counter() - w0:.1f} s")
    assert result.outcome is Outcome.SUCCEEDED and result.error_code == 0
    assert xy_dist(nav.robot_pose, goal) <= TOLERANCE
    assert nav.world.collisions == 0
    assert len(feedback) > 50
    remaining = [f.distance_remaining for f in feedback]
    assert remaining[0] > 5.0  # the way round through the doorway, longer than the 5 m line
    assert remaining[-1] < 1.0
    # decreasing along the way (sampled every 2 s; replanning may add a little)
    sampled = remaining[::20]
    assert all(b < a + 0.05 for a, b in itertools.pairwise(sampled))
    times = [f.navigation_time for f in feedback]
    assert times == sorted(times)
    assert times[-1] == pytest.approx(nav.now, abs=0.2)  # sim seconds since the goal
    assert all(f.number_of_recoveries == 0 for f in feedback)
    assert xy_dist(feedback[-1].current_pose, nav.robot_pose) < 0.1


@pytest.mark.slow
def test_unreachable_goal_fails_with_nav2s_error_code_after_recoveries():
    nav = office()
    assert nav.go_to_pose((6.5, 1.2, 0.0))  # inside an obstacle
    result = nav.wait_until_done(120.0)
    feedback = nav.get_feedback()
    print(f"unreachable: {result}, sim {nav.now:.1f} s, recoveries {feedback.number_of_recoveries}")
    assert result.outcome is Outcome.FAILED
    assert result.error_code == ComputePathToPoseError.NO_VALID_PATH  # compute_path_error_code
    assert result.error_msg
    assert feedback.number_of_recoveries > 0
    assert nav.world.collisions == 0


@pytest.mark.slow
def test_follow_waypoints_visits_each_and_misses_none():
    nav = office()
    nav.set_parameters("waypoint_follower", {"wait_at_waypoint.waypoint_pause_duration": 100})
    waypoints = [Pose2D(3.0, 3.5, 0.0), Pose2D(6.0, 3.0, 0.0)]
    assert nav.follow_waypoints(waypoints)
    seen = set()
    while not nav.is_task_complete():
        if nav.get_feedback() is not None:
            seen.add(nav.get_feedback().current_waypoint)
    result = nav.get_result()
    print(f"waypoints: {result}, sim {nav.now:.1f} s")
    assert result.outcome is Outcome.SUCCEEDED
    assert result.value.missed_waypoints == []
    assert seen >= {0, 1}
    assert xy_dist(nav.robot_pose, waypoints[-1]) <= TOLERANCE
    assert nav.world.collisions == 0


@pytest.mark.slow
def test_follow_waypoints_records_a_missed_waypoint_and_goes_on():
    nav = office()  # Nav2's file: stop_on_failure false
    nav.set_parameters("bt_navigator", {})
    waypoints = [Pose2D(6.5, 1.2, 0.0), Pose2D(2.0, 1.5, 0.0)]
    assert nav.follow_waypoints(waypoints)
    result = nav.wait_until_done(150.0)
    assert result.outcome is Outcome.SUCCEEDED
    assert [m.index for m in result.value.missed_waypoints] == [0]
    assert result.value.missed_waypoints[0].error_code == ComputePathToPoseError.NO_VALID_PATH
    assert xy_dist(nav.robot_pose, waypoints[1]) <= TOLERANCE


@pytest.mark.slow
def test_cancel_task_stops_the_robot():
    nav = office()
    assert nav.go_to_pose((6.0, 3.0, 0.0))
    nav.runtime.spin_for(4.0)
    assert nav.world.robot_twist.linear_x > 0.1  # driving
    moved = nav.robot_pose
    assert xy_dist(moved, Pose2D(1.0, 1.0, 0.0)) > 0.3  # under way
    assert nav.cancel_task()
    assert nav.get_result().outcome is Outcome.CANCELED
    assert nav.is_task_complete()
    assert nav.runtime.cmd_vel.linear_x == 0.0 and nav.runtime.cmd_vel.angular_z == 0.0
    nav.runtime.spin_for(1.0)  # braking within the drive's acceleration limit
    stopped = nav.robot_pose
    nav.runtime.spin_for(3.0)
    assert xy_dist(nav.robot_pose, stopped) < 0.01
    assert abs(nav.world.robot_twist.linear_x) < 1e-3
    assert nav.world.collisions == 0


@pytest.mark.slow
def test_a_new_goal_preempts_the_running_one():
    nav = office()
    assert nav.go_to_pose((6.0, 3.0, 0.0))
    first = nav.handle
    nav.runtime.spin_for(2.0)
    goal = Pose2D(2.0, 2.0, 0.0)
    assert nav.go_to_pose(goal)
    result = nav.wait_until_done(60.0)
    assert first.done and first.result.error_code == 0  # ABORTED by preemption, as in Nav2
    assert result.outcome is Outcome.SUCCEEDED
    assert xy_dist(nav.robot_pose, goal) <= TOLERANCE
