"""Messages as plain dataclasses: what a ROS user knows, with numpy arrays inside.

Every message carries a sim-time `stamp` (seconds) and a `frame_id`, as a ROS
header does. They are produced by sensors (sim layer) and consumed by the
navigation stack, which never looks at the world itself.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from functools import cached_property

import numpy as np
from numpy.typing import NDArray

from . import fmath
from .geometry import Pose2D


@dataclass
class Twist:
    """A velocity command or measurement in the robot frame (m/s, rad/s)."""

    linear_x: float = 0.0
    linear_y: float = 0.0
    angular_z: float = 0.0


@dataclass
class LaserScan:
    """sensor_msgs/LaserScan. Ranges follow REP-117: `+inf` no return within
    `range_max`, `-inf` closer than `range_min`, NaN an invalid reading."""

    stamp: float
    frame_id: str
    angle_min: float
    angle_max: float
    angle_increment: float
    range_min: float
    range_max: float
    ranges: NDArray[np.float32]
    scan_time: float = 0.0
    time_increment: float = 0.0
    intensities: NDArray[np.float32] = field(default_factory=lambda: np.zeros(0, np.float32))

    @property
    def angles(self) -> NDArray[np.float64]:
        """The angle of each beam in the sensor frame."""
        return self.angle_min + self.angle_increment * np.arange(len(self.ranges))

    def points(self) -> NDArray[np.float64]:
        """(N, 2) end points of the finite readings, in the sensor frame."""
        r = np.asarray(self.ranges, dtype=float)
        ok = np.isfinite(r)
        s, c = fmath.sincos(self.angles[ok])
        return np.stack([r[ok] * c, r[ok] * s], axis=-1)


@dataclass
class Odometry:
    """nav_msgs/Odometry: the robot's pose in `odom` as dead reckoning sees it, and its twist."""

    stamp: float
    pose: Pose2D
    twist: Twist
    frame_id: str = "odom"
    child_frame_id: str = "base_footprint"


def _zero_cov() -> NDArray[np.float64]:
    return np.zeros((3, 3))


@dataclass
class PoseWithCovariance:
    """geometry_msgs/PoseWithCovarianceStamped in 2D: what a localiser publishes (amcl_pose)
    and what a user sets as the initial pose; covariance over (x, y, yaw)."""

    stamp: float
    pose: Pose2D
    covariance: NDArray[np.float64] = field(default_factory=_zero_cov)
    frame_id: str = "map"


@dataclass
class PoseStamped:
    stamp: float
    pose: Pose2D
    frame_id: str = "map"


@dataclass
class Path:
    """nav_msgs/Path as an (N, 3) array of x, y, yaw."""

    stamp: float
    poses: NDArray[np.float64]
    frame_id: str = "map"

    def __len__(self) -> int:
        return int(self.poses.shape[0])

    def length(self) -> float:
        if len(self) < 2:
            return 0.0
        d = self.poses[1:, :2] - self.poses[:-1, :2]  # np.diff, without its overhead
        return float(fmath.hypot(d[:, 0], d[:, 1]).sum())

    @cached_property
    def segment_lengths(self) -> NDArray[np.float64]:
        """Each segment's length in float64, worked out once per path for the tree's nodes
        that measure along it (a path is never changed in place: a new plan is a new Path)."""
        xy = np.asarray(self.poses, float)[:, :2]
        return fmath.hypot(*np.diff(xy, axis=0).T)  # type: ignore[no-any-return]


@dataclass
class TrackingFeedback:
    """nav2_msgs/TrackingFeedback: how well the controller follows its path, each cycle.

    `position_tracking_error` is the signed distance from the path (positive: the robot is
    left of it), `heading_tracking_error` the robot's yaw minus the path's there, both at
    the path segment closest to the robot (`current_path_index` is its first pose).
    """

    stamp: float
    position_tracking_error: float
    heading_tracking_error: float
    current_path_index: int
    robot_pose: Pose2D
    distance_to_goal: float
    speed: float
    remaining_path_length: float
    frame_id: str = "map"
