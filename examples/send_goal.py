"""Send a NavigateToPose goal and watch it: the seeds' `send_nav_goal.py`, in btnav.

    python examples/send_goal.py [--goal X Y YAW] [--timeout SECONDS] [--retries N]
                                 [--every SECONDS] [--mission FILE] [--seed N]

A ROS user's script drives a running Nav2 with nav2_simple_commander's BasicNavigator
(`goToPose`, `getFeedback`, `isTaskComplete`, `cancelTask`, `getResult`). Here the
"running Nav2" is a bring-up made from a mission file in this process, and the same
calls have Python spellings (`go_to_pose`, `get_feedback`, ...). There is no
`waitUntilNav2Active()`: everything is up when `from_mission` returns. Time is sim
time: each `is_task_complete()` advances the simulation by up to 0.1 s (what
BasicNavigator's spin does), so a 20 s drive takes a few seconds of yours.

Try a goal the planner cannot reach (it fails, is retried once, and the exit code is 1):

    python examples/send_goal.py --goal 50 50 0         # outside the map: code 204
    python examples/send_goal.py --timeout 5             # canceled after 5 s of sim time
"""

from __future__ import annotations

import argparse
import sys
from pathlib import Path

from btnav import Navigator
from btnav.core.error_codes import ERROR_CODES, NavigateToPoseError, NavResult

REPO = Path(__file__).resolve().parents[1]
MISSION = REPO / "missions" / "office_tour.yaml"


def code_name(code: int) -> str:
    """Nav2's name for a NavigateToPose error code.

    Like Nav2's bt_navigator, btnav's NavigateToPose ends with the code of the tree node
    that failed: 204 is ComputePathToPose's GOAL_OUTSIDE_MAP, 105 FollowPath's
    FAILED_TO_MAKE_PROGRESS. Each action has its own hundred, so the number says which.
    """
    tables = [NavigateToPoseError] if code < 100 else ERROR_CODES.values()
    for table in tables:
        try:
            member = table(code)
        except ValueError:
            continue
        return f"{member.action} {member.name}"
    return "unknown code"


def navigate(nav: Navigator, goal: tuple[float, float, float], timeout: float, every: float) -> str:
    """One attempt: send the goal, print feedback every `every` sim seconds, cancel after
    `timeout` sim seconds. Returns "succeeded", "failed", "canceled" or "timeout"."""
    if not nav.go_to_pose(goal):  # False: the server rejected the goal
        print("  the goal was rejected")
        return "failed"
    sent = nav.now
    next_print = sent + every
    while not nav.is_task_complete():  # steps the simulation up to 0.1 s
        feedback = nav.get_feedback()  # NavigateToPose's feedback, as nav2_msgs has it
        if feedback is not None and nav.now >= next_print:
            next_print += every
            print(
                f"  t={nav.now:6.1f} s  distance remaining {feedback.distance_remaining:5.2f} m"
                f"  ETA {feedback.estimated_time_remaining:5.1f} s"
                f"  navigation time {feedback.navigation_time:5.1f} s"
                f"  recoveries {feedback.number_of_recoveries}"
            )
        if nav.now - sent >= timeout:  # the seed's "Duration(seconds=...)" check
            print(f"  timeout: {timeout:g} s of sim time passed; canceling the goal")
            nav.cancel_task()
            report(nav, nav.get_result())
            return "timeout"
    result = nav.get_result()
    report(nav, result)
    return result.outcome.value if result is not None else "failed"


def report(nav: Navigator, result: NavResult | None) -> None:
    """The result as the seed's script prints it, with Nav2's error code name."""
    if result is None:
        print("  result: none (the task is still running)")
        return
    pose = nav.robot_pose
    where = f"at t={nav.now:.1f} s, robot at ({pose.x:.2f}, {pose.y:.2f}, {pose.yaw:.2f})"
    if result.failed:
        name = code_name(result.error_code)
        print(f"  result: FAILED, error code {result.error_code} ({name}) {where}")
        print(f"    {result.error_msg}")
    else:
        print(f"  result: {result.outcome.name} {where}")


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--goal", nargs=3, type=float, default=[6.0, 3.0, 0.0], metavar="V")
    parser.add_argument("--timeout", type=float, default=120.0, help="sim seconds per attempt")
    parser.add_argument("--retries", type=int, default=1, help="retries of a failed goal")
    parser.add_argument("--every", type=float, default=2.0, help="feedback period, sim s")
    parser.add_argument("--mission", default=str(MISSION), help="the bring-up to use")
    parser.add_argument("--seed", type=int, help="the mission's seed (default: its own)")
    args = parser.parse_args()

    # The bring-up: world, Nav2's params, map, AMCL at the mission's initial pose.
    nav = Navigator.from_mission(args.mission, seed=args.seed)
    print(f"brought up {nav.mission.name} (localization: {nav.mission.spec.localization})")

    goal = (args.goal[0], args.goal[1], args.goal[2])
    attempts = 1 + max(0, args.retries)
    for attempt in range(1, attempts + 1):
        print(
            f"goal ({goal[0]:.2f}, {goal[1]:.2f}, {goal[2]:.2f}), attempt {attempt} of {attempts}"
        )
        outcome = navigate(nav, goal, args.timeout, args.every)
        if outcome == "succeeded":
            print("goal reached")
            return 0
        if attempt < attempts:
            # what a user's script does before trying again: forget stale obstacles
            nav.clear_all_costmaps()
            print("retrying (costmaps cleared)")
    print(f"gave up after {attempts} attempt(s)")
    return 1


if __name__ == "__main__":
    sys.exit(main())
