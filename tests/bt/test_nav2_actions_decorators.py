"""Nav2's decorators that watch the robot, the goal or the path, with a stand-in runtime."""

from __future__ import annotations

from types import SimpleNamespace

import numpy as np
from py_trees.common import Status

from btnav.core.geometry import Pose2D
from btnav.core.messages import Path, PoseStamped

from .fakes import find, set_bb
from .test_nav2_conditions import FakeRuntime, straight_path, ticker

S, F, R = Status.SUCCESS, Status.FAILURE, Status.RUNNING


def test_distance_controller_ticks_its_child_every_metre():
    rt = FakeRuntime(Pose2D(0.0, 0.0, 0.0))
    tick = ticker(
        '<PipelineSequence><DistanceController distance="1.0"><TestScript name="c"/>'
        '</DistanceController><TestScript script="R"/></PipelineSequence>',
        rt,
    )
    child = find(tick.root, "c")
    assert tick() == R and child.ticks == 1  # first tick of a run
    rt.pose = Pose2D(0.6, 0.0, 0.0)
    tick()
    assert child.ticks == 1
    rt.pose = Pose2D(1.0, 0.0, 0.0)
    tick()
    assert child.ticks == 2
    tick.root.stop(Status.INVALID)  # halted: a new run ticks the child at once
    tick()
    assert child.ticks == 3


# In Nav2's trees these decorators sit in a PipelineSequence, which re-ticks a child that
# succeeded without halting it: a running sibling keeps the sequence going here too.


def test_speed_controller_ticks_at_min_rate_when_stopped_and_at_once_on_a_new_goal():
    rt = FakeRuntime()
    rt.latest_odom = SimpleNamespace(twist=SimpleNamespace(linear_x=0.0, linear_y=0.0))
    tick = ticker(
        '<PipelineSequence><SpeedController min_rate="0.5" max_rate="2.0">'
        '<TestScript name="c"/></SpeedController><TestScript script="R"/></PipelineSequence>',
        rt,
    )
    child = find(tick.root, "c")
    set_bb("goal", Pose2D(1, 1, 0))
    assert tick() == R and child.ticks == 1
    rt.clock.advance(0.5)  # 1 / max_rate: the period expires, the new one is at min rate
    tick()
    assert child.ticks == 2
    rt.clock.advance(1.0)
    tick()
    assert child.ticks == 2  # 2 s period at 0 m/s
    set_bb("goal", Pose2D(2, 2, 0))
    tick()
    assert child.ticks == 3


def test_goal_updated_controller_ticks_its_child_on_new_goals_only():
    tick = ticker(
        "<PipelineSequence><GoalUpdatedController>"
        '<TestScript name="c"/></GoalUpdatedController><TestScript script="R"/></PipelineSequence>'
    )
    child = find(tick.root, "c")
    set_bb("goal", Pose2D(1, 1, 0))
    tick()
    tick()
    assert child.ticks == 1
    set_bb("goal", Pose2D(1, 2, 0))
    tick()
    assert child.ticks == 2


def test_goal_updater_passes_a_newer_goal_received_on_its_topic():
    rt = FakeRuntime()
    tick = ticker(
        '<GoalUpdater input_goal="{goal}" output_goal="{updated}"><AlwaysSuccess/></GoalUpdater>',
        rt,
    )
    set_bb("goal", PoseStamped(1.0, Pose2D(1, 1, 0)))
    assert tick() == S
    from py_trees.blackboard import Blackboard

    assert Blackboard.get("/updated").pose == Pose2D(1, 1, 0)
    for callback in rt.subscribers["goal_update"]:
        callback(PoseStamped(2.0, Pose2D(5, 5, 0)))
    tick()
    assert Blackboard.get("/updated").pose == Pose2D(5, 5, 0)


def test_path_longer_on_approach_ticks_its_child_for_a_much_longer_new_path():
    tick = ticker(
        '<PathLongerOnApproach path="{path}" prox_len="3.0" length_factor="2.0">'
        '<TestScript name="c"/></PathLongerOnApproach>'
    )
    child = find(tick.root, "c")
    short = straight_path(2.0)
    set_bb("path", short)
    assert tick() == S and child.ticks == 0
    detour = np.concatenate(
        [
            np.stack([np.zeros(30), np.linspace(0, 3, 30), np.zeros(30)], axis=1),
            np.stack([np.linspace(0, 2, 30), np.full(30, 3.0), np.zeros(30)], axis=1),
            np.stack([np.full(30, 2.0), np.linspace(3, 0, 30), np.zeros(30)], axis=1),
        ]
    )
    set_bb("path", Path(1.0, detour, "map"))  # same goal (2, 0), 8 m instead of 2
    assert tick() == S and child.ticks == 1
