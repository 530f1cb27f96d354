"""btnav's messages as ROS 2 messages, in the `rosbags` typestore of ROS 2 Jazzy.

A `RosMessages` turns btnav's planar messages (`core.messages`, the frame tree's
transforms, the occupancy grid, bt_log's status changes) into the standard ROS 2
messages a bag holds and RViz or Foxglove draws, and serialises them as CDR. Poses
become 3D with z = 0 and a quaternion about z; stamps are sim time. nav2_msgs is not
in rosbags' typestore, so its two behaviour-tree log messages are registered from
their `.msg` definitions (as nav2_msgs defines them today, with the node's `uid`).
`rosbags` (the `logs` extra) is imported only here, when a bag is written.
"""

from __future__ import annotations

import math
from typing import Any

import numpy as np

from ..core.errors import BtnavError
from ..core.frames import StampedTransform
from ..core.geometry import Pose2D
from ..core.messages import LaserScan, Odometry, Path, PoseWithCovariance, Twist
from ..maps.occupancy_grid import OccupancyGrid

SCAN = "sensor_msgs/msg/LaserScan"
ODOMETRY = "nav_msgs/msg/Odometry"
TF = "tf2_msgs/msg/TFMessage"
OCCUPANCY_GRID = "nav_msgs/msg/OccupancyGrid"
PATH = "nav_msgs/msg/Path"
TWIST = "geometry_msgs/msg/Twist"
TWIST_STAMPED = "geometry_msgs/msg/TwistStamped"
POSE_WITH_COVARIANCE = "geometry_msgs/msg/PoseWithCovarianceStamped"
POSE_STAMPED = "geometry_msgs/msg/PoseStamped"
POSE_ARRAY = "geometry_msgs/msg/PoseArray"
BT_LOG = "nav2_msgs/msg/BehaviorTreeLog"
BT_STATUS_CHANGE = "nav2_msgs/msg/BehaviorTreeStatusChange"

#: nav2_msgs' field lists (the interface a subscriber expects, no more).
NAV2_MSGS = {
    BT_STATUS_CHANGE: (
        "builtin_interfaces/Time timestamp\n"
        "string node_name\n"
        "uint16 uid\n"
        "string previous_status\n"
        "string current_status\n"
    ),
    BT_LOG: "builtin_interfaces/Time timestamp\nBehaviorTreeStatusChange[] event_log\n",
}
#: x, y, yaw of a 2D covariance in ROS's 6x6 (x, y, z, roll, pitch, yaw) one.
_COV6 = (0, 1, 5)


def typestore() -> Any:
    """ROS 2 Jazzy's message types (Humble's with an older rosbags) plus nav2_msgs' BT log."""
    try:
        from rosbags.typesys import Stores, get_types_from_msg, get_typestore
    except ImportError:
        raise BtnavError(
            "writing a ROS 2 bag needs the 'rosbags' package: pip install 'btnav[logs]'"
        ) from None
    store = get_typestore(getattr(Stores, "ROS2_JAZZY", Stores.ROS2_HUMBLE))
    for name, text in NAV2_MSGS.items():
        store.register(get_types_from_msg(text, name))
    return store


def stamp_ns(seconds: float) -> int:
    """Sim seconds as integer nanoseconds (what a bag record and a header hold)."""
    return round(seconds * 1e9)


class RosMessages:
    """Builds ROS 2 messages from btnav's, and serialises them, with one typestore."""

    def __init__(self, store: Any | None = None) -> None:
        self.store = store if store is not None else typestore()
        t = self.store.types
        self._time = t["builtin_interfaces/msg/Time"]
        self._header = t["std_msgs/msg/Header"]
        self._point = t["geometry_msgs/msg/Point"]
        self._quaternion = t["geometry_msgs/msg/Quaternion"]
        self._pose = t["geometry_msgs/msg/Pose"]
        self._vector3 = t["geometry_msgs/msg/Vector3"]
        self._twist = t[TWIST]
        self._t = t

    def serialize(self, msg: Any, msgtype: str) -> bytes:
        return bytes(self.store.serialize_cdr(msg, msgtype))

    def deserialize(self, data: bytes, msgtype: str) -> Any:
        return self.store.deserialize_cdr(data, msgtype)

    def definition(self, msgtype: str) -> str:
        """The type's `.msg` text with its dependencies, as a ros2msg schema holds it."""
        return self.store.generate_msgdef(msgtype, ros_version=2)[0]

    # -- pieces ---------------------------------------------------------------------------

    def time(self, seconds: float) -> Any:
        sec, nanosec = divmod(stamp_ns(seconds), 1_000_000_000)
        return self._time(sec=sec, nanosec=nanosec)

    def header(self, seconds: float, frame_id: str) -> Any:
        return self._header(stamp=self.time(seconds), frame_id=frame_id)

    def quaternion(self, yaw: float) -> Any:
        return self._quaternion(x=0.0, y=0.0, z=math.sin(yaw / 2.0), w=math.cos(yaw / 2.0))

    def pose(self, p: Pose2D) -> Any:
        point = self._point(x=float(p.x), y=float(p.y), z=0.0)
        return self._pose(position=point, orientation=self.quaternion(p.yaw))

    def twist(self, t: Twist) -> Any:
        return self._twist(
            linear=self._vector3(x=float(t.linear_x), y=float(t.linear_y), z=0.0),
            angular=self._vector3(x=0.0, y=0.0, z=float(t.angular_z)),
        )

    def transform(self, edge: StampedTransform, seconds: float) -> Any:
        """geometry_msgs/TransformStamped of a frame-tree edge (parent -> child)."""
        tf = edge.transform
        return self._t["geometry_msgs/msg/TransformStamped"](
            header=self.header(seconds, edge.parent),
            child_frame_id=edge.child,
            transform=self._t["geometry_msgs/msg/Transform"](
                translation=self._vector3(x=float(tf.x), y=float(tf.y), z=0.0),
                rotation=self.quaternion(tf.yaw),
            ),
        )

    # -- messages -------------------------------------------------------------------------

    def tf(self, transforms: list[Any]) -> Any:
        return self._t[TF](transforms=transforms)

    def scan(self, s: LaserScan) -> Any:
        return self._t[SCAN](
            header=self.header(s.stamp, s.frame_id),
            angle_min=float(s.angle_min),
            angle_max=float(s.angle_max),
            angle_increment=float(s.angle_increment),
            time_increment=float(s.time_increment),
            scan_time=float(s.scan_time),
            range_min=float(s.range_min),
            range_max=float(s.range_max),
            ranges=np.asarray(s.ranges, dtype=np.float32),
            intensities=np.asarray(s.intensities, dtype=np.float32),
        )

    def odometry(self, o: Odometry) -> Any:
        zeros = np.zeros(36)
        t = self._t
        return t[ODOMETRY](
            header=self.header(o.stamp, o.frame_id),
            child_frame_id=o.child_frame_id,
            pose=t["geometry_msgs/msg/PoseWithCovariance"](
                pose=self.pose(o.pose), covariance=zeros
            ),
            twist=t["geometry_msgs/msg/TwistWithCovariance"](
                twist=self.twist(o.twist), covariance=zeros
            ),
        )

    def cmd_vel(self, cmd: Twist, seconds: float, frame_id: str, *, stamped: bool) -> Any:
        """A Twist, or (Nav2's `enable_stamped_cmd_vel`) a TwistStamped in `frame_id`."""
        if not stamped:
            return self.twist(cmd)
        return self._t[TWIST_STAMPED](header=self.header(seconds, frame_id), twist=self.twist(cmd))

    def pose_with_covariance(self, p: PoseWithCovariance) -> Any:
        cov = np.zeros((6, 6))
        cov[np.ix_(_COV6, _COV6)] = np.asarray(p.covariance, dtype=float).reshape(3, 3)
        t = self._t
        return t[POSE_WITH_COVARIANCE](
            header=self.header(p.stamp, p.frame_id),
            pose=t["geometry_msgs/msg/PoseWithCovariance"](
                pose=self.pose(p.pose), covariance=cov.ravel()
            ),
        )

    def occupancy_grid(self, grid: OccupancyGrid, seconds: float) -> Any:
        t = self._t
        info = t["nav_msgs/msg/MapMetaData"](
            map_load_time=self.time(seconds),
            resolution=float(grid.resolution),
            width=grid.width,
            height=grid.height,
            origin=self.pose(grid.origin),
        )
        return t[OCCUPANCY_GRID](
            header=self.header(seconds, grid.frame_id),
            info=info,
            data=np.ascontiguousarray(grid.data, dtype=np.int8).ravel(),
        )

    def path(self, p: Path) -> Any:
        """nav_msgs/Path: each pose stamped with the path's header, as Nav2's planners do."""
        header = self.header(p.stamp, p.frame_id)
        poses = np.asarray(p.poses, dtype=float).reshape(-1, 3)
        half = poses[:, 2] / 2.0
        stamped = self._t["geometry_msgs/msg/PoseStamped"]
        point, quaternion, pose = self._point, self._quaternion, self._pose
        return self._t[PATH](
            header=header,
            poses=[
                stamped(
                    header=header,
                    pose=pose(
                        position=point(x=x, y=y, z=0.0),
                        orientation=quaternion(x=0.0, y=0.0, z=qz, w=qw),
                    ),
                )
                for x, y, qz, qw in zip(
                    poses[:, 0].tolist(),
                    poses[:, 1].tolist(),
                    np.sin(half).tolist(),
                    np.cos(half).tolist(),
                    strict=True,
                )
            ],
        )

    def points_path(self, points: np.ndarray, seconds: float, frame_id: str) -> Any:
        """nav_msgs/Path through (N, 2) points, each pose facing the next (a local plan)."""
        xy = np.asarray(points, dtype=float).reshape(-1, 2)
        yaw = np.zeros(len(xy))
        if len(xy) > 1:
            step = np.diff(xy, axis=0)
            yaw[:-1] = np.arctan2(step[:, 1], step[:, 0])
            yaw[-1] = yaw[-2]
        return self.path(Path(seconds, np.column_stack([xy, yaw]), frame_id=frame_id))

    def pose_array(self, poses: np.ndarray, seconds: float, frame_id: str) -> Any:
        """geometry_msgs/PoseArray of (N, 3) x, y, yaw poses (AMCL's particle cloud)."""
        rows = np.asarray(poses, dtype=float).reshape(-1, 3)
        half = rows[:, 2] / 2.0
        point, quaternion, pose = self._point, self._quaternion, self._pose
        return self._t[POSE_ARRAY](
            header=self.header(seconds, frame_id),
            poses=[
                pose(
                    position=point(x=x, y=y, z=0.0),
                    orientation=quaternion(x=0.0, y=0.0, z=qz, w=qw),
                )
                for x, y, qz, qw in zip(
                    rows[:, 0].tolist(),
                    rows[:, 1].tolist(),
                    np.sin(half).tolist(),
                    np.cos(half).tolist(),
                    strict=True,
                )
            ],
        )

    def bt_status_change(
        self, seconds: float, node_name: str, uid: int, previous: str, current: str
    ) -> Any:
        return self._t[BT_STATUS_CHANGE](
            timestamp=self.time(seconds),
            node_name=node_name,
            uid=uid,
            previous_status=previous,
            current_status=current,
        )

    def bt_log(self, seconds: float, changes: list[Any]) -> Any:
        return self._t[BT_LOG](timestamp=self.time(seconds), event_log=changes)
