"""Nav2's own default trees, as Nav2 ships them (XML), on the small office stack.

The tree is ticked at bt_navigator's `bt_loop_duration` (10 ms of sim time: once per
physics step). The blackboard is set up as bt_navigator does it for a new goal: the
goal (or goals) and every `<prefix>_error_code` at 0.
"""

from __future__ import annotations

import time
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import py_trees
import pytest
from py_trees.common import Status

from btnav.bt import load_tree
from btnav.bt.nav2_context import recovery_count
from btnav.core.error_codes import ComputePathToPoseError
from btnav.core.geometry import Pose2D

from ..nav.navstack_helpers import office, xy_dist
from .fakes import find, set_bb

TREES = Path(__file__).resolve().parents[3] / "shared" / "nav2" / "behavior_trees"
TO_POSE = "navigate_to_pose_w_replanning_and_recovery.xml"
THROUGH_POSES = "navigate_through_poses_w_replanning_and_recovery.xml"
BT_LOOP_DURATION = 0.010  # bt_navigator's default, seconds
ERROR_CODE_PREFIXES = ("backup", "compute_path", "drive_on_heading", "follow_path", "spin", "wait")


def trees_dir(nav2_dir: Path) -> Path:
    return nav2_dir / "behavior_trees"


@dataclass
class Run:
    status: Status
    sim_time: float
    wall_time: float
    ticks: int
    world: Any
    root: Any


def navigate(tree_file: Path, *, timeout: float = 90.0, **goal: Any) -> Run:
    world, rt, stack = office()
    root = load_tree(tree_file, clock=rt.clock, context={"runtime": rt, "stack": stack})
    for key, value in goal.items():
        set_bb(key, value)
    for prefix in ERROR_CODE_PREFIXES:
        set_bb(f"{prefix}_error_code", 0)
        set_bb(f"{prefix}_error_msg", "")
    t0, w0, ticks = rt.now, time.perf_counter(), 0
    next_tick = rt.now
    while rt.now - t0 < timeout:
        if rt.now + 1e-9 >= next_tick:
            root.tick_once()
            ticks += 1
            next_tick += BT_LOOP_DURATION
            if root.status != Status.RUNNING:
                break
        rt.step()
    return Run(root.status, rt.now - t0, time.perf_counter() - w0, ticks, world, root)


@pytest.mark.slow
def test_navigate_to_pose_tree_reaches_the_goal_through_the_doorway(nav2_dir: Path):
    goal = Pose2D(6.0, 3.0, 0.0)
    run = navigate(trees_dir(nav2_dir) / TO_POSE, goal=goal)
    print(f"to pose: {run.status.name}, sim {run.sim_time:.2f} s, wall {run.wall_time:.2f} s")
    assert run.status == Status.SUCCESS
    assert xy_dist(run.world.robot_pose, goal) <= 0.25 + 0.02
    assert run.world.collisions == 0
    assert recovery_count() == 0
    follow = find(run.root, "FollowPath")  # the RecoveryNode; its child is the action
    follow_action = next(n for n in follow.iterate() if type(n).__name__ == "FollowPath")
    planner = next(n for n in run.root.iterate() if type(n).__name__ == "ComputePathToPose")
    assert planner.goals_sent >= 2  # replanned at 1 Hz on the way
    assert follow_action.goals_sent >= 2  # and each new path went to the controller
    assert py_trees.blackboard.Blackboard.get("/follow_path_error_code") == 0


@pytest.mark.slow
def test_navigate_through_poses_tree_passes_the_viapoint(nav2_dir: Path):
    goals = [Pose2D(3.0, 3.5, 0.0), Pose2D(6.0, 3.0, 0.0)]
    run = navigate(trees_dir(nav2_dir) / THROUGH_POSES, goals=goals, goal=goals[-1])
    print(f"through poses: {run.status.name}, sim {run.sim_time:.2f} s, wall {run.wall_time:.2f} s")
    assert run.status == Status.SUCCESS
    assert xy_dist(run.world.robot_pose, goals[-1]) <= 0.25 + 0.02
    assert run.world.collisions == 0
    planner = next(n for n in run.root.iterate() if type(n).__name__ == "ComputePathThroughPoses")
    assert planner.goals_sent >= 1
    path = planner.get_last_output("path")
    # the plan went through the viapoint
    assert min(xy_dist(Pose2D(*p), goals[0]) for p in path.poses) < 0.1


@pytest.mark.slow
def test_unreachable_goal_fails_after_the_recovery_branch_ran(nav2_dir: Path):
    run = navigate(trees_dir(nav2_dir) / TO_POSE, goal=Pose2D(6.5, 1.2, 0.0))
    print(
        f"unreachable: {run.status.name}, sim {run.sim_time:.2f} s, recoveries {recovery_count()}"
    )
    assert run.status == Status.FAILURE
    bb = py_trees.blackboard.Blackboard
    assert bb.get("/compute_path_error_code") == ComputePathToPoseError.NO_VALID_PATH
    assert run.world.collisions == 0
    actions = {type(n).__name__: n for n in find(run.root, "RecoveryActions").iterate()}
    # Nav2 1.5's RoundRobin (wrap_around false) tries each recovery once, then fails
    assert actions["Spin"].goals_sent == 1
    assert actions["Wait"].goals_sent == 1
    assert actions["BackUp"].goals_sent == 1
    # clearing (2) + spin + wait + backup, and the planner's own global clear before
    # each of the 4 planning attempts
    assert recovery_count() == 9
    assert run.sim_time > 5.0  # the 5 s Wait ran in sim time


@pytest.mark.slow
@pytest.mark.parametrize(
    "tree_name",
    [
        "navigate_w_replanning_distance.xml",  # DistanceController
        "navigate_w_replanning_speed.xml",  # SpeedController
        "navigate_to_pose_w_replanning_goal_patience_and_recovery.xml",  # PathLongerOnApproach
        "navigate_w_replanning_only_if_path_becomes_invalid.xml",  # ValidatePath
    ],
)
def test_other_nav2_trees_reach_the_goal(nav2_dir: Path, tree_name: str):
    goal = Pose2D(6.0, 3.0, 0.0)
    run = navigate(trees_dir(nav2_dir) / tree_name, goal=goal)
    print(f"{tree_name}: {run.status.name}, sim {run.sim_time:.2f} s")
    assert run.status == Status.SUCCESS
    assert xy_dist(run.world.robot_pose, goal) <= 0.25 + 0.02
    assert run.world.collisions == 0
