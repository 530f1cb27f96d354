"""What Nav2's tree nodes get from bt_navigator, and the message helpers they share.

A Nav2 node finds its ROS node, tf buffer and frames on the blackboard; a btnav node
is given them by name through the loader's `context` (its `INJECT`):

- `runtime`: the `nav.Runtime` (action servers, frame tree, odometry, topics);
- `stack`: the `nav.NavStack` (costmap services, the costmaps for path checks);
- `global_frame` (default `map`), `robot_base_frame` (default `base_link`):
  bt_navigator's parameters of those names.

```python
root = load_tree(xml, clock=rt.clock, context={"runtime": rt, "stack": stack})
```

A tree loaded without them still builds (and can be drawn or dry-ticked): a node
that needs a missing server fails, saying what to pass. Nav2 counts recoveries on
the blackboard entry `number_recoveries`; so does btnav (`recovery_count()`).
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from typing import Any, ClassVar

import numpy as np
from py_trees.common import Status

from ..core.errors import BtnavError
from ..core.geometry import Pose2D
from ..core.messages import Path, PoseStamped
from . import blackboard
from .base import LeafNode

#: What a pose port accepts: a `Pose2D` (in the global frame) or a `PoseStamped`.
PoseLike = Pose2D | PoseStamped

#: bt_navigator's defaults for the frames a node may be given.
DEFAULT_GLOBAL_FRAME = "map"
DEFAULT_ROBOT_BASE_FRAME = "base_link"

#: The blackboard entry Nav2's recovery nodes increment (bt_navigator reports it).
RECOVERIES_KEY = "/number_recoveries"


class NumericLimitsInfinity(float):
    """`inf` as Nav2's node model spells the default: `numeric_limits<double>::infinity()`."""

    def __new__(cls) -> NumericLimitsInfinity:
        return super().__new__(cls, math.inf)

    def __str__(self) -> str:
        return "numeric_limits<double>::infinity()"

    def __repr__(self) -> str:
        return "inf"

    def __deepcopy__(self, memo: Any) -> NumericLimitsInfinity:
        return self


INFINITY = NumericLimitsInfinity()


def recovery_count() -> int:
    """Nav2's `number_recoveries` (0 when no recovery has run)."""
    return int(blackboard.read(RECOVERIES_KEY) or 0)


def increment_recovery_count() -> None:
    """What a Nav2 recovery node does when it starts (Spin, BackUp, Wait, clear costmap)."""
    blackboard.write(RECOVERIES_KEY, recovery_count() + 1)


def empty_path(frame_id: str = DEFAULT_GLOBAL_FRAME, stamp: float = 0.0) -> Path:
    """nav_msgs/Path with no poses (what Nav2 writes to `path` on failure or halt)."""
    return Path(stamp, np.zeros((0, 3)), frame_id)


def same_path(a: Path | None, b: Path | None) -> bool:
    """Nav2's `path == other` (header and poses)."""
    if a is b:
        return True
    if a is None or b is None:
        return False
    return (
        a.frame_id == b.frame_id
        and a.stamp == b.stamp
        and a.poses.shape == b.poses.shape
        and bool(np.array_equal(a.poses, b.poses))
    )


def same_goal(a: Any, b: Any) -> bool:
    """Goal (pose) or goals (list of poses) equality, as Nav2 compares them."""
    if isinstance(a, list | tuple) or isinstance(b, list | tuple):
        a = list(a or [])
        b = list(b or [])
        return len(a) == len(b) and all(same_goal(x, y) for x, y in zip(a, b, strict=True))
    return a == b


def pose_of(value: PoseLike | Sequence[float]) -> tuple[Pose2D, str | None]:
    """The pose and its frame (None: the global frame) of a pose port's value."""
    if isinstance(value, PoseStamped):
        return value.pose, value.frame_id
    if isinstance(value, Pose2D):
        return value, None
    return Pose2D(*value), None


def length_from(seg: np.ndarray, start: int) -> float:
    """nav2_util's `calculate_path_length(path, start)` on the path's segment lengths."""
    if start >= len(seg):
        return 0.0
    return float(seg[start:].sum())


class Nav2Leaf(LeafNode):
    """A Nav2 leaf that may use the runtime, the stack and bt_navigator's frames."""

    INJECT: ClassVar[tuple[str, ...]] = ("runtime", "stack", "global_frame", "robot_base_frame")

    def __init__(
        self,
        name: str,
        runtime: Any = None,
        stack: Any = None,
        global_frame: str | None = None,
        robot_base_frame: str | None = None,
        **kwargs: Any,
    ) -> None:
        super().__init__(name=name, **kwargs)
        self.runtime = runtime if runtime is not None else getattr(stack, "runtime", None)
        self.stack = stack
        self.global_frame = global_frame or DEFAULT_GLOBAL_FRAME
        self.robot_base_frame = robot_base_frame or DEFAULT_ROBOT_BASE_FRAME
        if self.runtime is not None and self.clock is None:
            self.clock = self.runtime.clock

    # -- ports --------------------------------------------------------------------------

    def frame_port(self, port: str, fallback: str) -> str:
        """Nav2's `deconflictPortAndParamFrame`: the port if given, else bt_navigator's."""
        value = self.optional(port) if port in self.input_ports() else None
        return value or fallback

    # -- the robot ----------------------------------------------------------------------

    def robot_pose(self, frame: str | None = None, base_frame: str | None = None) -> Pose2D | None:
        """The robot's pose in `frame` from the frame tree; None if it cannot be looked up."""
        if self.runtime is None:
            self.feedback_message = "no runtime: load the tree with context={'runtime': ...}"
            return None
        frame = frame or self.frame_port("global_frame", self.global_frame)
        base = base_frame or self.frame_port("robot_base_frame", self.robot_base_frame)
        try:
            return self.runtime.lookup(frame, base)
        except BtnavError as exc:
            self.feedback_message = f"cannot look up the robot pose: {exc}"
            return None

    def in_frame(self, value: PoseLike, frame: str) -> Pose2D | None:
        """A pose port's value in `frame` (an unstamped pose is in the global frame)."""
        pose, src = pose_of(value)
        src = src or self.global_frame
        if src == frame:
            return pose
        if self.runtime is None:
            return None
        try:
            return self.runtime.lookup(frame, src) @ pose
        except BtnavError as exc:
            self.feedback_message = f"cannot transform a pose from '{src}' to '{frame}': {exc}"
            return None

    def update(self) -> Status:
        raise NotImplementedError
