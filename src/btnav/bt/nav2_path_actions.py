"""Nav2's action nodes that work on poses, paths and goal lists, with no server:
TruncatePath, TruncatePathLocal, RemovePassedGoals, GetPoseFromPath, GetCurrentPose,
ConcatenatePaths, AppendGoalPoseToGoals, GetNextFewGoals."""

from __future__ import annotations

import copy
import math
from typing import Any, ClassVar

import numpy as np
from py_trees.common import Status

from ..control.path_handler import integrated_index
from ..core import fmath
from ..core.geometry import Pose2D, angle_diff
from ..core.messages import Path, PoseStamped
from ..plugins import register
from .base import F, S, input_port, output_port
from .nav2_context import (
    INFINITY,
    Nav2Leaf,
    PoseLike,
    pose_of,
    same_path,
)

#: nav2_msgs/WaypointStatus.COMPLETED
WAYPOINT_COMPLETED = 1


@register("bt_node", "TruncatePath")
class TruncatePath(Nav2Leaf):
    """Drop the poses within `distance` of the path's end; the new last pose faces the end."""

    INPUT_PORTS: ClassVar = {
        "input_path": input_port(Path, "The original path to be truncated"),
        "distance": input_port(
            float, "The distance to the original goal for truncating the path", 1.0
        ),
    }
    OUTPUT_PORTS: ClassVar = {"output_path": output_port(Path, "The resulting truncated path")}

    def update(self) -> Status:
        path = self.optional("input_path")
        if path is None or len(path) == 0:
            if path is not None:
                self._set_output("output_path", path)
            return S
        poses = np.asarray(path.poses, float)
        end = poses[-1]
        d = fmath.hypot(poses[:, 0] - end[0], poses[:, 1] - end[1])
        keep = len(poses)
        distance = self.get_input("distance")
        while keep > 2 and d[keep - 1] < distance:
            keep -= 1
        out = poses[:keep].copy()
        dx, dy = end[0] - out[-1, 0], end[1] - out[-1, 1]
        out[-1, 2] = fmath.arctan2(float(dy), float(dx)) if (dx or dy) else 0.0
        self._set_output("output_path", Path(path.stamp, out, path.frame_id))
        return S


@register("bt_node", "TruncatePathLocal")
class TruncatePathLocal(Nav2Leaf):
    """The part of `input_path` round the robot: `distance_backward` behind the pose
    nearest the robot (or `pose`) to `distance_forward` ahead (-1: to the end)."""

    INPUT_PORTS: ClassVar = {
        "input_path": input_port(Path, "The original path to be truncated"),
        "distance_forward": input_port(
            float, "Trimming distance forward; -1 for the whole path", 8.0
        ),
        "distance_backward": input_port(float, "Trimming distance backward", 4.0),
        "robot_base_frame": input_port(str, "Robot base frame (bt_navigator's if not given)"),
        "transform_tolerance": input_port(float, "Robot pose lookup tolerance", 0.2),
        "pose": input_port(PoseLike, "A pose to use instead of the robot's"),
        "angular_distance_weight": input_port(
            float, "Weight of angular distance in finding the nearest pose", 0.0
        ),
        "max_robot_pose_search_dist": input_port(
            float, "Distance along the path from the last nearest pose searched", INFINITY
        ),
    }
    OUTPUT_PORTS: ClassVar = {"output_path": output_port(Path, "The resulting truncated path")}

    def __init__(self, name: str, **kwargs: Any) -> None:
        super().__init__(name=name, **kwargs)
        self.path: Path | None = None
        self.search_begin = 0

    def update(self) -> Status:
        forward = self.get_input("distance_forward")
        backward = self.get_input("distance_backward")
        weight = self.get_input("angular_distance_weight")
        search = self.get_input("max_robot_pose_search_dist")
        pruning = math.isfinite(search)
        if forward < 0.0:
            forward = math.inf
        new_path = self.optional("input_path")
        if not pruning or not same_path(new_path, self.path):
            self.path = new_path
            self.search_begin = 0
        path = self.path
        frame = path.frame_id if path is not None else self.global_frame
        given = self.optional("pose")
        pose = self.in_frame(given, frame) if given is not None else self.robot_pose(frame)
        if pose is None:
            return F
        if path is None or len(path) == 0:
            if path is not None:
                self._set_output("output_path", path)
            return S
        poses = np.asarray(path.poses, float)
        seg = path.segment_lengths
        begin = self.search_begin
        stop = integrated_index(poses, begin, search, seg) if pruning else len(poses)
        window = poses[begin:stop]
        d2 = (window[:, 0] - pose.x) ** 2 + (window[:, 1] - pose.y) ** 2
        if weight:
            d2 = d2 + (weight * np.abs(angle_diff(window[:, 2], pose.yaw))) ** 2
        current = begin + int(np.argmin(d2))
        if pruning:
            self.search_begin = current
        end = integrated_index(poses, current, forward, seg)
        back = poses[: current + 1][::-1]  # from the current pose back: its segments reversed
        start = current + 1 - integrated_index(back, 0, backward, seg[:current][::-1])
        out = Path(path.stamp, poses[start:end].copy(), path.frame_id)
        self._set_output("output_path", out)
        return S


@register("bt_node", "RemovePassedGoals")
class RemovePassedGoals(Nav2Leaf):
    """Drop the leading goals within `radius` of the robot (the last goal always stays);
    the matching waypoint statuses are marked COMPLETED."""

    INPUT_PORTS: ClassVar = {
        "radius": input_port(
            float, "Radius (m) round a viapoint within which it counts as passed", 0.5
        ),
        "robot_base_frame": input_port(str, "Robot base frame (bt_navigator's if not given)"),
        "input_goals": input_port(list, "The goals to check"),
        "input_waypoint_statuses": input_port(list, "Waypoint statuses to mark"),
    }
    OUTPUT_PORTS: ClassVar = {
        "output_goals": output_port(list, "The goals without the passed ones"),
        "output_waypoint_statuses": output_port(
            list, "Waypoint statuses with passed waypoints marked"
        ),
    }

    def update(self) -> Status:
        goals = list(self.optional("input_goals") or [])
        if not goals:
            self._set_output("output_goals", goals)
            return S
        _, frame = pose_of(goals[0])
        robot = self.robot_pose(frame or self.global_frame)
        if robot is None:
            return F
        statuses = self.optional("input_waypoint_statuses")
        statuses = copy.copy(list(statuses)) if statuses is not None else None
        radius = self.get_input("radius")
        while len(goals) > 1:
            pose, _ = pose_of(goals[0])
            if fmath.hypot(pose.x - robot.x, pose.y - robot.y) > radius:
                break
            if statuses is not None:
                index = _matching_status(statuses, goals[0])
                if index is None:
                    self.feedback_message = "no waypoint status matches a passed goal"
                    return F
                statuses[index] = _completed(statuses[index])
            goals.pop(0)
        self._set_output("output_goals", goals)
        if statuses is not None:
            self._set_output("output_waypoint_statuses", statuses)
        return S


def _field(status: Any, key: str) -> Any:
    return status.get(key) if isinstance(status, dict) else getattr(status, key, None)


def _matching_status(statuses: list[Any], goal: Any) -> int | None:
    for i, status in enumerate(statuses):
        if (
            _field(status, "waypoint_status") in (0, None)
            and _field(status, "waypoint_pose") == goal
        ):
            return i
    return None


def _completed(status: Any) -> Any:
    if isinstance(status, dict):
        return {**status, "waypoint_status": WAYPOINT_COMPLETED}
    out = copy.copy(status)
    out.waypoint_status = WAYPOINT_COMPLETED
    return out


@register("bt_node", "GetPoseFromPath")
class GetPoseFromPath(Nav2Leaf):
    """The pose at `index` of `path` (-1: the last), stamped with the path's frame."""

    INPUT_PORTS: ClassVar = {
        "path": input_port(Path, "Path to extract pose from"),
        "index": input_port(int, "Index from path to use; -1 for the last pose", 0),
    }
    OUTPUT_PORTS: ClassVar = {
        "pose": output_port(PoseStamped, "Pose from path, with the path's frame")
    }

    def update(self) -> Status:
        path = self.optional("path")
        if path is None or len(path) == 0:
            return F
        index = self.get_input("index")
        if not -len(path) <= index < len(path):
            return F
        pose = Pose2D.from_array(path.poses[index])
        self._set_output("pose", PoseStamped(path.stamp, pose, path.frame_id))
        return S


@register("bt_node", "GetCurrentPose")
class GetCurrentPose(Nav2Leaf):
    """The robot's pose in `global_frame`, stamped (FAILURE if it cannot be looked up)."""

    INPUT_PORTS: ClassVar = {
        "robot_base_frame": input_port(str, "Robot base frame (bt_navigator's if not given)"),
        "global_frame": input_port(str, "Global frame (bt_navigator's if not given)"),
    }
    OUTPUT_PORTS: ClassVar = {"current_pose": output_port(PoseStamped, "The current pose")}

    def update(self) -> Status:
        frame = self.frame_port("global_frame", self.global_frame)
        pose = self.robot_pose(frame)
        if pose is None:
            return F
        stamp = float(self.runtime.clock.now) if self.runtime is not None else 0.0
        self._set_output("current_pose", PoseStamped(stamp, pose, frame))
        return S


@register("bt_node", "ConcatenatePaths")
class ConcatenatePaths(Nav2Leaf):
    """`input_path1` then `input_path2` (the first path's frame); FAILURE if both are empty."""

    INPUT_PORTS: ClassVar = {
        "input_path1": input_port(Path, "First path to concatenate"),
        "input_path2": input_port(Path, "Second path to concatenate"),
    }
    OUTPUT_PORTS: ClassVar = {"output_path": output_port(Path, "Output concatenated path")}

    def update(self) -> Status:
        paths = [p for p in (self.optional("input_path1"), self.optional("input_path2")) if p]
        poses = [np.asarray(p.poses, float).reshape(-1, 3) for p in paths]
        if not paths or sum(len(p) for p in poses) == 0:
            return F
        head = paths[0]
        self._set_output("output_path", Path(head.stamp, np.concatenate(poses), head.frame_id))
        return S


@register("bt_node", "AppendGoalPoseToGoals")
class AppendGoalPoseToGoals(Nav2Leaf):
    """`input_goals` with `goal_pose` appended."""

    INPUT_PORTS: ClassVar = {
        "goal_pose": input_port(PoseLike, "Goal pose to append"),
        "input_goals": input_port(list, "Input goals to append to"),
    }
    OUTPUT_PORTS: ClassVar = {"output_goals": output_port(list, "Goals with the pose appended")}

    def update(self) -> Status:
        goals = list(self.optional("input_goals") or [])
        pose = self.optional("goal_pose")
        if pose is not None:
            goals.append(pose)
        self._set_output("output_goals", goals)
        return S


@register("bt_node", "GetNextFewGoals")
class GetNextFewGoals(Nav2Leaf):
    """The first `num_goals` of `input_goals`; FAILURE if there are none."""

    INPUT_PORTS: ClassVar = {
        "num_goals": input_port(int, "How many of the goals to take"),
        "input_goals": input_port(list, "Input goals list"),
    }
    OUTPUT_PORTS: ClassVar = {"output_goals": output_port(list, "The first goals")}

    def update(self) -> Status:
        goals = list(self.optional("input_goals") or [])
        if not goals:
            return F
        self._set_output("output_goals", goals[: max(0, int(self.optional("num_goals") or 0))])
        return S
