"""Nav2's condition nodes (nav2_behavior_tree/plugins/condition), on sim time and btnav's frames.

Where Nav2 reads the robot's pose from tf, these read it from the runtime's frame
tree (`global_frame` / `robot_base_frame`: the port, else bt_navigator's, given in the
loader's context); a pose that cannot be looked up makes the condition FAILURE, as
in Nav2. "Not active" in Nav2 (status IDLE) is a node that was halted or never
ticked here (py_trees' INVALID): GoalUpdated and DistanceTraveled start over then.
"""

from __future__ import annotations

from collections import deque
from typing import Any, ClassVar

import numpy as np
from py_trees.common import Status
from py_trees.ports import PortInformation

from ..control.path_handler import integrated_index
from ..core import fmath
from ..core.error_codes import (
    ComputePathThroughPosesError,
    ComputePathToPoseError,
    FollowPathError,
    SmoothPathError,
)
from ..core.errors import BtnavError
from ..core.geometry import Pose2D
from ..core.messages import Path
from ..plugins import register
from .base import F, S, input_port
from .nav2_context import (
    Nav2Leaf,
    PoseLike,
    length_from,
    pose_of,
    same_goal,
    same_path,
)


def _status(ok: bool) -> Status:
    return S if ok else F


# -- goals ---------------------------------------------------------------------------------

_GOAL_PORTS: dict[str, PortInformation] = {
    "goal": input_port(PoseLike, 'Destination to check; "{goal}" if not specified'),
    "goals": input_port(list, 'Vector of goals to check; "{goals}" if not specified'),
}


@register("bt_node", "GoalUpdated")
class GoalUpdated(Nav2Leaf):
    """SUCCESS when `goal` or `goals` changed since the previous tick of this run.

    The first tick of a run (after a halt) records them and fails.
    """

    NODE_KIND: ClassVar[str] = "Condition"
    INPUT_PORTS: ClassVar = dict(_GOAL_PORTS)
    OUTPUT_PORTS: ClassVar = {}
    DEFAULT_KEYS: ClassVar = {"goal": "{goal}", "goals": "{goals}"}

    def __init__(self, name: str, **kwargs: Any) -> None:
        super().__init__(name=name, **kwargs)
        self.goal: Any = None
        self.goals: Any = None

    def update(self) -> Status:
        goal, goals = self.optional("goal"), self.optional("goals")
        if self.status == Status.INVALID:
            self.goal, self.goals = goal, goals
            return F
        if not same_goal(self.goal, goal) or not same_goal(self.goals, goals):
            self.goal, self.goals = goal, goals
            return S
        return F


@register("bt_node", "GlobalUpdatedGoal")
class GlobalUpdatedGoal(GoalUpdated):
    """SUCCESS on its very first tick and whenever `goal` or `goals` changed since its
    previous tick (halts do not reset it: Nav2's GloballyUpdatedGoalCondition)."""

    def __init__(self, name: str, **kwargs: Any) -> None:
        super().__init__(name=name, **kwargs)
        self.first_time = True

    def update(self) -> Status:
        goal, goals = self.optional("goal"), self.optional("goals")
        if self.first_time:
            self.first_time = False
            self.goal, self.goals = goal, goals
            return S
        if not same_goal(self.goal, goal) or not same_goal(self.goals, goals):
            self.goal, self.goals = goal, goals
            return S
        return F


@register("bt_node", "GoalReached")
class GoalReached(Nav2Leaf):
    """SUCCESS when the robot is within `goal_reached_tol` (0.25 m) of `goal`."""

    #: bt_navigator's `goal_reached_tol` parameter default.
    GOAL_REACHED_TOL: ClassVar[float] = 0.25
    NODE_KIND: ClassVar[str] = "Condition"
    INPUT_PORTS: ClassVar = {
        "goal": input_port(PoseLike, "Destination to check"),
        "robot_base_frame": input_port(str, "Robot base frame (bt_navigator's if not given)"),
    }
    OUTPUT_PORTS: ClassVar = {}

    def update(self) -> Status:
        goal = self.optional("goal")
        if goal is None:
            return F
        pose, frame = pose_of(goal)
        robot = self.robot_pose(frame or self.global_frame)
        if robot is None:
            return F
        return _status(fmath.hypot(pose.x - robot.x, pose.y - robot.y) <= self.GOAL_REACHED_TOL)


@register("bt_node", "ArePosesNear")
class ArePosesNear(Nav2Leaf):
    """SUCCESS when `ref_pose` and `target_pose` are within `tolerance` (in `global_frame`
    when their frames differ)."""

    NODE_KIND: ClassVar[str] = "Condition"
    INPUT_PORTS: ClassVar = {
        "ref_pose": input_port(PoseLike, "The pose to check"),
        "target_pose": input_port(PoseLike, "The other pose to check against"),
        "global_frame": input_port(str, "Frame to compare in when the poses' frames differ"),
        "tolerance": input_port(float, "Distance under which the poses are near", 0.5),
    }
    OUTPUT_PORTS: ClassVar = {}

    def update(self) -> Status:
        a, b = self.optional("ref_pose"), self.optional("target_pose")
        if a is None or b is None:
            return F
        (pa, fa), (pb, fb) = pose_of(a), pose_of(b)
        if (fa or self.global_frame) != (fb or self.global_frame):
            frame = self.frame_port("global_frame", self.global_frame)
            pa, pb = self.in_frame(a, frame), self.in_frame(b, frame)
            if pa is None or pb is None:
                return F
        tol = self.get_input("tolerance")
        return _status(fmath.hypot(pa.x - pb.x, pa.y - pb.y) <= tol)


@register("bt_node", "IsGoalNearby")
class IsGoalNearby(Nav2Leaf):
    """SUCCESS when the path left from the pose nearest the robot is shorter than
    `proximity_threshold`. With `max_robot_pose_search_dist` > 0 the search for the
    nearest pose starts where the previous one was found and looks that far ahead."""

    NODE_KIND: ClassVar[str] = "Condition"
    INPUT_PORTS: ClassVar = {
        "path": input_port(Path, "The planned path to evaluate"),
        "proximity_threshold": input_port(
            float, "Remaining path length (m) that counts as nearby", 1.0
        ),
        "max_robot_pose_search_dist": input_port(
            float, "Distance along the path searched for the nearest pose (<0: all)", -1.0
        ),
        "global_frame": input_port(str, "The global reference frame (bt_navigator's if not given)"),
        "robot_base_frame": input_port(str, "Robot base frame (bt_navigator's if not given)"),
    }
    OUTPUT_PORTS: ClassVar = {}

    def __init__(self, name: str, **kwargs: Any) -> None:
        super().__init__(name=name, **kwargs)
        self.path: Path | None = None
        self.search_begin = 0

    def update(self) -> Status:
        new_path = self.optional("path")
        threshold = self.get_input("proximity_threshold")
        search = self.get_input("max_robot_pose_search_dist")
        if new_path is None or len(new_path) == 0:
            self.feedback_message = "path is empty"
            return F
        pruning = search >= 0.0
        if not pruning or not same_path(new_path, self.path):
            self.path = new_path
            self.search_begin = 0
        robot = self.robot_pose()
        if robot is None:
            return F
        robot = self.in_frame(robot, new_path.frame_id)
        if robot is None:
            return F
        poses = np.asarray(self.path.poses, float)
        seg = self.path.segment_lengths
        begin = self.search_begin
        stop = integrated_index(poses, begin, search, seg) if pruning else len(poses)
        window = poses[begin:stop]
        closest = begin + int(
            np.argmin(fmath.hypot(window[:, 0] - robot.x, window[:, 1] - robot.y))
        )
        self.search_begin = closest
        return _status(length_from(seg, closest) < threshold)


@register("bt_node", "InitialPoseReceived")
class InitialPoseReceived(Nav2Leaf):
    """SUCCESS when `initial_pose_received` (default entry `{initial_pose_received}`) is true."""

    NODE_KIND: ClassVar[str] = "Condition"
    INPUT_PORTS: ClassVar = {
        "initial_pose_received": input_port(
            bool, 'Whether an initial pose was received; "{initial_pose_received}" if not specified'
        ),
    }
    OUTPUT_PORTS: ClassVar = {}
    DEFAULT_KEYS: ClassVar = {"initial_pose_received": "{initial_pose_received}"}

    def update(self) -> Status:
        return _status(bool(self.optional("initial_pose_received")))


# -- error codes ---------------------------------------------------------------------------


@register("bt_node", "AreErrorCodesPresent")
class AreErrorCodesPresent(Nav2Leaf):
    """SUCCESS when `error_code` is one of `error_codes_to_check` (e.g. "101;107;119").

    An `error_code` entry nobody has written yet reads as 0 (NONE), as bt_navigator
    sets every `<prefix>_error_code` to 0 when a goal starts.
    """

    #: The codes a WouldA...RecoveryHelp checks (it ignores `error_codes_to_check`, as in Nav2).
    DEFAULT_CODES: ClassVar[frozenset[int] | None] = None
    NODE_KIND: ClassVar[str] = "Condition"
    INPUT_PORTS: ClassVar = {
        "error_code": input_port(int, "The active error code to compare against"),
        "error_codes_to_check": input_port(
            list[int], "The error codes to compare the active one against"
        ),
    }
    OUTPUT_PORTS: ClassVar = {}

    def update(self) -> Status:
        if self.DEFAULT_CODES is not None:
            wanted = set(self.DEFAULT_CODES)
        else:
            wanted = set(self.optional("error_codes_to_check") or ())
        code = self.optional("error_code")
        return _status(int(code or 0) in wanted)


def _codes(*codes: int) -> frozenset[int]:
    return frozenset(int(c) for c in codes)


@register("bt_node", "WouldAControllerRecoveryHelp")
class WouldAControllerRecoveryHelp(AreErrorCodesPresent):
    """SUCCESS when FollowPath's `error_code` is one a recovery may fix."""

    DEFAULT_CODES = _codes(
        FollowPathError.UNKNOWN,
        FollowPathError.PATIENCE_EXCEEDED,
        FollowPathError.FAILED_TO_MAKE_PROGRESS,
        FollowPathError.NO_VALID_CONTROL,
    )


@register("bt_node", "WouldAPlannerRecoveryHelp")
class WouldAPlannerRecoveryHelp(AreErrorCodesPresent):
    """SUCCESS when a planner's `error_code` is one a recovery may fix."""

    DEFAULT_CODES = _codes(
        ComputePathToPoseError.UNKNOWN,
        ComputePathToPoseError.NO_VALID_PATH,
        ComputePathToPoseError.TIMEOUT,
        ComputePathThroughPosesError.UNKNOWN,
        ComputePathThroughPosesError.TIMEOUT,
        ComputePathThroughPosesError.NO_VALID_PATH,
    )


@register("bt_node", "WouldASmootherRecoveryHelp")
class WouldASmootherRecoveryHelp(AreErrorCodesPresent):
    """SUCCESS when SmoothPath's `error_code` is one a recovery may fix."""

    DEFAULT_CODES = _codes(
        SmoothPathError.UNKNOWN,
        SmoothPathError.TIMEOUT,
        SmoothPathError.FAILED_TO_SMOOTH_PATH,
        SmoothPathError.SMOOTHED_PATH_IN_COLLISION,
    )


# -- time and motion -----------------------------------------------------------------------


@register("bt_node", "TimeExpired")
class TimeExpired(Nav2Leaf):
    """SUCCESS once every `seconds` of sim time; the first tick of a run starts the timer."""

    NODE_KIND: ClassVar[str] = "Condition"
    INPUT_PORTS: ClassVar = {
        "seconds": input_port(float, "The time passed to return success (s)", 1.0)
    }
    OUTPUT_PORTS: ClassVar = {}
    INJECT: ClassVar = ("clock", *Nav2Leaf.INJECT)

    def __init__(self, name: str, clock: Any = None, **kwargs: Any) -> None:
        super().__init__(name=name, **kwargs)
        self.clock = clock if clock is not None else self.clock
        self.start = 0.0

    def update(self) -> Status:
        if self.status == Status.INVALID:
            self.start = self.now()
            return F
        if self.now() - self.start + 1e-9 < self.get_input("seconds"):
            return F
        self.start = self.now()
        return S


@register("bt_node", "PathExpiringTimer")
class PathExpiringTimer(TimeExpired):
    """SUCCESS once every `seconds` of sim time; a new `path` restarts the timer."""

    INPUT_PORTS: ClassVar = {
        "seconds": input_port(float, "Time to check if expired", 1.0),
        "path": input_port(Path, "Check if path has been updated to enable timer reset"),
    }

    def __init__(self, name: str, **kwargs: Any) -> None:
        super().__init__(name=name, **kwargs)
        self.first_time = True
        self.prev_path: Path | None = None

    def update(self) -> Status:
        path = self.optional("path")
        if self.first_time:
            self.first_time = False
            self.prev_path = path
            self.start = self.now()
            return F
        if not same_path(self.prev_path, path):
            self.prev_path = path
            self.start = self.now()
        if self.now() - self.start + 1e-9 < self.get_input("seconds"):
            return F
        self.start = self.now()
        return S


@register("bt_node", "DistanceTraveled")
class DistanceTraveled(Nav2Leaf):
    """SUCCESS each time the robot is `distance` metres (straight line) from where it was
    when the run started or the condition last succeeded."""

    NODE_KIND: ClassVar[str] = "Condition"
    INPUT_PORTS: ClassVar = {
        "distance": input_port(
            float, "The distance that must be travelled before success (m)", 1.0
        ),
        "global_frame": input_port(str, "Reference frame (bt_navigator's if not given)"),
        "robot_base_frame": input_port(str, "Robot base frame (bt_navigator's if not given)"),
    }
    OUTPUT_PORTS: ClassVar = {}

    def __init__(self, name: str, **kwargs: Any) -> None:
        super().__init__(name=name, **kwargs)
        self.start_pose: Pose2D | None = None

    def update(self) -> Status:
        if self.status == Status.INVALID:
            self.start_pose = self.robot_pose() or Pose2D()
            return F
        pose = self.robot_pose()
        if pose is None:
            return F
        start = self.start_pose or Pose2D()
        if fmath.hypot(pose.x - start.x, pose.y - start.y) < self.get_input("distance"):
            return F
        self.start_pose = pose
        return S


@register("bt_node", "TransformAvailable")
class TransformAvailable(Nav2Leaf):
    """SUCCESS once the frame tree can transform between `parent` and `child` (and from then on)."""

    NODE_KIND: ClassVar[str] = "Condition"
    INPUT_PORTS: ClassVar = {
        "child": input_port(str, "Child frame for transform", ""),
        "parent": input_port(str, "Parent frame for transform", ""),
    }
    OUTPUT_PORTS: ClassVar = {}

    def __init__(self, name: str, **kwargs: Any) -> None:
        super().__init__(name=name, **kwargs)
        self.was_found = False

    def update(self) -> Status:
        child, parent = self.get_input("child"), self.get_input("parent")
        if not child or not parent:
            raise BtnavError(
                f"TransformAvailable '{self.name}': child frame ({child!r}) or parent frame "
                f"({parent!r}) not given"
            )
        if self.was_found:
            return S
        if self.runtime is None:
            return F
        try:
            self.runtime.lookup(parent, child)
        except BtnavError as exc:
            self.feedback_message = str(exc)
            return F
        self.was_found = True
        return S


@register("bt_node", "IsStuck")
class IsStuck(Nav2Leaf):
    """SUCCESS when the odometry shows a deceleration harsher than -10 m/s² (a bump)."""

    BRAKE_ACCEL_LIMIT: ClassVar[float] = -10.0
    ODOM_HISTORY_SIZE: ClassVar[int] = 10
    NODE_KIND: ClassVar[str] = "Condition"
    INPUT_PORTS: ClassVar = {}
    OUTPUT_PORTS: ClassVar = {}

    def __init__(self, name: str, **kwargs: Any) -> None:
        super().__init__(name=name, **kwargs)
        self.history: deque[Any] = deque(maxlen=self.ODOM_HISTORY_SIZE)
        self.current_accel = 0.0
        if self.runtime is not None:
            self.runtime.subscribe("odom", self._on_odom)

    def _on_odom(self, odom: Any) -> None:
        self.history.append(odom)
        if len(self.history) > 2:
            cur, prev = self.history[-1], self.history[-2]
            dt = cur.stamp - prev.stamp
            if dt > 0:
                self.current_accel = (cur.twist.linear_x - prev.twist.linear_x) / dt

    def update(self) -> Status:
        return _status(self.current_accel < self.BRAKE_ACCEL_LIMIT)


@register("bt_node", "IsWithinPathTrackingBounds")
class IsWithinPathTrackingBounds(Nav2Leaf):
    """FAILURE when the controller's `tracking_feedback` puts the robot farther than
    `max_error_left`/`max_error_right` beside its path or `max_error_heading` off its
    direction; SUCCESS otherwise, and while there is no feedback yet. Negative bounds
    count as their absolute value, as in Nav2."""

    NODE_KIND: ClassVar[str] = "Condition"
    INPUT_PORTS: ClassVar = {
        "max_error_left": input_port(float, "Largest tracking error (m) left of the path", 0.5),
        "max_error_right": input_port(float, "Largest tracking error (m) right of the path", 0.5),
        "max_error_heading": input_port(float, "Largest heading error (rad)", 3.14),
        "tracking_feedback": input_port(object, "The controller server's tracking feedback"),
    }
    OUTPUT_PORTS: ClassVar = {}

    def update(self) -> Status:
        feedback = self.optional("tracking_feedback")
        error = getattr(feedback, "position_tracking_error", None)
        if error is None:
            return S
        bound = (
            self.get_input("max_error_left") if error >= 0.0 else self.get_input("max_error_right")
        )
        heading = abs(feedback.heading_tracking_error)
        return _status(
            abs(error) <= abs(bound) and heading <= abs(self.get_input("max_error_heading"))
        )
