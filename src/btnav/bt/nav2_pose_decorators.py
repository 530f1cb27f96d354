"""Nav2's decorators that watch the robot, the goal or the path: DistanceController,
SpeedController, GoalUpdatedController, GoalUpdater, PathLongerOnApproach.

They get the runtime (robot pose from the frame tree, speed from odometry, topics)
like Nav2's leaves do (`nav2_context`). Between the ticks they give their child they
return RUNNING, as Nav2's `return status()` does.
"""

from __future__ import annotations

from typing import Any, ClassVar

from py_trees.behaviour import Behaviour
from py_trees.common import Status
from py_trees.ports import PortInformation

from ..core import fmath
from ..core.errors import BtnavError
from ..core.geometry import Pose2D
from ..core.messages import Path
from ..plugins import register
from .base import TIME_EPS, DecoratorNode, F, R, S, halt, input_port
from .nav2_context import (
    DEFAULT_GLOBAL_FRAME,
    DEFAULT_ROBOT_BASE_FRAME,
    PoseLike,
    same_goal,
)


class Nav2Decorator(DecoratorNode):
    """A decorator given the runtime and bt_navigator's frames by the loader."""

    INJECT: ClassVar[tuple[str, ...]] = ("clock", "runtime", "global_frame", "robot_base_frame")

    def __init__(
        self,
        name: str,
        child: Behaviour,
        clock: Any = None,
        runtime: Any = None,
        global_frame: str | None = None,
        robot_base_frame: str | None = None,
        **kwargs: Any,
    ) -> None:
        self.runtime = runtime
        self.global_frame = global_frame or DEFAULT_GLOBAL_FRAME
        self.robot_base_frame = robot_base_frame or DEFAULT_ROBOT_BASE_FRAME
        super().__init__(name=name, child=child, **kwargs)
        self.clock = clock if clock is not None else getattr(runtime, "clock", None)

    def robot_pose(self) -> Pose2D | None:
        if self.runtime is None:
            self.feedback_message = "no runtime: load the tree with context={'runtime': ...}"
            return None
        frame = self.optional("global_frame") or self.global_frame
        base = self.optional("robot_base_frame") or self.robot_base_frame
        try:
            return self.runtime.lookup(frame, base)
        except BtnavError as exc:
            self.feedback_message = f"cannot look up the robot pose: {exc}"
            return None


@register("bt_node", "DistanceController")
class DistanceController(Nav2Decorator):
    """Tick the child on the first tick of a run, while it runs, and each time the robot
    is `distance` metres (straight line) from where the child last succeeded."""

    INPUT_PORTS: ClassVar = {
        "distance": input_port(float, "The distance travelled to trigger the child (m)", 1.0),
        "global_frame": input_port(str, "Reference frame (bt_navigator's if not given)"),
        "robot_base_frame": input_port(str, "Robot base frame (bt_navigator's if not given)"),
    }
    OUTPUT_PORTS: ClassVar = {}

    def reset_state(self) -> None:
        self.start_pose: Pose2D | None = None
        self.first_time = False

    def tick_decorated(self) -> Status:
        if self.status == Status.INVALID:
            self.start_pose = self.robot_pose()
            if self.start_pose is None:
                return F
            self.first_time = True
        pose = self.robot_pose()
        if pose is None or self.start_pose is None:
            return F
        travelled = fmath.hypot(pose.x - self.start_pose.x, pose.y - self.start_pose.y)
        if self.first_time or self.decorated.status == R or travelled >= self.get_input("distance"):
            self.first_time = False
            status = self.tick_child()
            if status == S:
                self.start_pose = self.robot_pose()
                if self.start_pose is None:
                    return F
            return status
        return R


@register("bt_node", "SpeedController")
class SpeedController(Nav2Decorator):
    """Tick the child at a rate between `min_rate` and `max_rate` scaled with the robot's
    speed (odometry) between `min_speed` and `max_speed`; at once on a new goal."""

    INPUT_PORTS: ClassVar = {
        "min_rate": input_port(float, "The minimum rate at which the child is ticked (Hz)", 0.1),
        "max_rate": input_port(float, "The maximum rate at which the child is ticked (Hz)", 1.0),
        "min_speed": input_port(
            float, "Speed (m/s) at or below which the minimum rate applies", 0.0
        ),
        "max_speed": input_port(
            float, "Speed (m/s) at or above which the maximum rate applies", 0.5
        ),
        "goal": input_port(PoseLike, 'Destination to check; "{goal}" if not specified'),
        "goals": input_port(list, 'Vector of goals to check; "{goals}" if not specified'),
    }
    OUTPUT_PORTS: ClassVar = {}
    DEFAULT_KEYS: ClassVar = {"goal": "{goal}", "goals": "{goals}"}

    def reset_state(self) -> None:
        self.first_tick = False
        self.period = 1.0
        self.start = 0.0
        self.goal: Any = None
        self.goals: Any = None

    def _rate(self, speed: float) -> float:
        lo, hi = self.get_input("min_rate"), self.get_input("max_rate")
        smin, smax = self.get_input("min_speed"), self.get_input("max_speed")
        scaled = (speed - smin) / (smax - smin) * (hi - lo) + lo
        return max(min(scaled, hi), lo)

    def _speed(self) -> float:
        odom = getattr(self.runtime, "latest_odom", None)
        if odom is None:
            return 0.0
        return fmath.hypot(odom.twist.linear_x, odom.twist.linear_y)

    def tick_decorated(self) -> Status:
        if self.get_input("min_rate") <= 0.0 or self.get_input("max_rate") <= 0.0:
            raise BtnavError(f"SpeedController '{self.name}' cannot have a rate <= 0.0")
        goal, goals = self.optional("goal"), self.optional("goals")
        if self.status == Status.INVALID or not (
            same_goal(goal, self.goal) and same_goal(goals, self.goals)
        ):
            self.goal, self.goals = goal, goals
            self.period = 1.0 / self.get_input("max_rate")
            self.start = self.now()
            self.first_tick = True
        elapsed = self.now() - self.start
        expired = elapsed + TIME_EPS >= self.period
        if self.first_tick or self.decorated.status == R or expired:
            self.first_tick = False
            if expired:
                self.period = 1.0 / self._rate(self._speed())
                self.start = self.now()
            return self.tick_child()
        return R


@register("bt_node", "GoalUpdatedController")
class GoalUpdatedController(Nav2Decorator):
    """Tick the child on the first tick of a run, while it runs, and when the goal changes."""

    INPUT_PORTS: ClassVar = {
        "goal": input_port(PoseLike, 'Destination to check; "{goal}" if not specified'),
        "goals": input_port(list, 'Vector of goals to check; "{goals}" if not specified'),
    }
    OUTPUT_PORTS: ClassVar = {}
    DEFAULT_KEYS: ClassVar = {"goal": "{goal}", "goals": "{goals}"}

    def reset_state(self) -> None:
        self.goal: Any = None
        self.goals: Any = None
        self.goal_was_updated = False

    def tick_decorated(self) -> Status:
        goal, goals = self.optional("goal"), self.optional("goals")
        if self.status == Status.INVALID:
            self.goal, self.goals = goal, goals
            self.goal_was_updated = True
        if not (same_goal(goal, self.goal) and same_goal(goals, self.goals)):
            self.goal, self.goals = goal, goals
            self.goal_was_updated = True
        if self.decorated.status == R or self.goal_was_updated:
            self.goal_was_updated = False
            return self.tick_child()
        return R


@register("bt_node", "GoalUpdater")
class GoalUpdater(Nav2Decorator):
    """Pass the goal(s) through to the child, replaced by a newer one received on the
    runtime's `goal_update` (a stamped pose) or `goals_update` topic."""

    GOAL_TOPIC: ClassVar[str] = "goal_update"
    GOALS_TOPIC: ClassVar[str] = "goals_update"
    INPUT_PORTS: ClassVar = {
        "input_goal": input_port(PoseLike, "The original goal pose"),
        "input_goals": input_port(list, "The original goals poses"),
    }
    OUTPUT_PORTS: ClassVar = {
        "output_goal": PortInformation(PoseLike, required=False, description="The updated goal"),
        "output_goals": PortInformation(list, required=False, description="The updated goals"),
    }

    def __init__(self, name: str, child: Behaviour, **kwargs: Any) -> None:
        super().__init__(name=name, child=child, **kwargs)
        self.last_goal: Any = None
        self.last_goals: Any = None
        if self.runtime is not None:
            self.runtime.subscribe(self.GOAL_TOPIC, self._on_goal)
            self.runtime.subscribe(self.GOALS_TOPIC, self._on_goals)

    def _on_goal(self, msg: Any) -> None:
        self.last_goal = msg

    def _on_goals(self, msg: Any) -> None:
        self.last_goals = msg

    def tick_decorated(self) -> Status:
        goal, goals = self.optional("input_goal"), self.optional("input_goals")
        received = self.last_goal
        stamp = getattr(received, "stamp", 0.0)
        if received is not None and stamp > 0.0 and stamp >= getattr(goal, "stamp", 0.0):
            goal = received
        if goal is not None:
            self._set_output("output_goal", goal)
        new_goals = self.last_goals
        if new_goals is not None:
            stamp = getattr(new_goals, "stamp", None)
            poses = list(getattr(new_goals, "goals", new_goals))
            if poses and (stamp is None or stamp > 0.0):
                goals = poses
        if goals is not None:
            self._set_output("output_goals", list(goals))
        return self.tick_child()


@register("bt_node", "PathLongerOnApproach")
class PathLongerOnApproach(Nav2Decorator):
    """Tick the child when, within `prox_len` of the goal, a new path to the same goal is
    more than `length_factor` times longer than the old one; SUCCESS otherwise."""

    INPUT_PORTS: ClassVar = {
        "path": input_port(Path, "The planned path"),
        "prox_len": input_port(
            float, "Proximity length (m) for the path to be longer on approach", 3.0
        ),
        "length_factor": input_port(float, "Factor by which the new path must be longer", 2.0),
    }
    OUTPUT_PORTS: ClassVar = {}

    def __init__(self, name: str, child: Behaviour, **kwargs: Any) -> None:
        self.old_path: Path | None = None
        self.first_time = True
        super().__init__(name=name, child=child, **kwargs)

    def tick_decorated(self) -> Status:
        new = self.optional("path")
        old = self.old_path
        new_n = len(new) if new is not None else 0
        old_n = len(old) if old is not None else 0
        if not self.first_time and (
            old_n == 0 or new_n == 0 or tuple(old.poses[-1]) != tuple(new.poses[-1])  # type: ignore[union-attr]
        ):
            self.first_time = True
        updated = (
            old_n != 0
            and new_n != 0
            and new_n != old_n
            and tuple(old.poses[-1, :2]) == tuple(new.poses[-1, :2])  # type: ignore[union-attr]
        )
        if (
            updated
            and old.length() < self.get_input("prox_len")  # type: ignore[union-attr]
            and new.length() > self.get_input("length_factor") * old.length()  # type: ignore[union-attr]
            and not self.first_time
        ):
            status = self.tick_child()
            if status in (S, F):
                self.old_path = new
                halt(self.decorated)
            return status
        self.old_path = new
        self.first_time = False
        return S
