"""Poses a Foxglove client publishes, as RViz's "2D Goal Pose" and "2D Pose Estimate" do.

Foxglove's "Publish" panel (pose mode) advertises a client channel and sends
geometry_msgs/PoseStamped on `/goal_pose` or PoseWithCovarianceStamped on
`/initialpose`, CDR-encoded (or JSON). The server hears them on its own thread, so
`ClientPoses` (the server's listener) only queues the raw bytes; the sim thread takes
them with `take()` in its component's update and decodes them there, so nothing of
the run is touched from another thread and a goal starts at a step boundary.
"""

from __future__ import annotations

import json
import queue
from dataclasses import dataclass
from typing import Any

import numpy as np

from ..core import fmath
from ..core.geometry import Pose2D
from . import ros_messages as rm

GOAL_POSE, INITIAL_POSE = "/goal_pose", "/initialpose"
#: The topics a client may publish to, and the type each expects.
CLIENT_TOPICS = {GOAL_POSE: rm.POSE_STAMPED, INITIAL_POSE: rm.POSE_WITH_COVARIANCE}
#: x, y, yaw of a 2D covariance in ROS's 6x6 (x, y, z, roll, pitch, yaw) one.
_COV6 = (0, 1, 5)


@dataclass(frozen=True)
class ClientPose:
    """A pose a client sent: the topic, the frame it is in, and (for /initialpose) its covariance."""

    topic: str
    frame_id: str
    pose: Pose2D
    covariance: np.ndarray | None = None  # 3x3 over x, y, yaw


class ClientPoses:
    """The server's listener: client channels on `/goal_pose` and `/initialpose`, and their
    messages queued (raw) for the sim thread. Its methods run on the server's thread."""

    def __init__(self) -> None:
        self._channels: dict[tuple[int, int], tuple[str, str]] = {}  # (client, channel) -> ...
        self._queue: queue.SimpleQueue[tuple[str, str, bytes]] = queue.SimpleQueue()
        self.subscriptions: dict[int, int] = {}  # channel id -> subscribed clients

    # -- foxglove.websocket.ServerListener ------------------------------------------------

    def on_subscribe(self, client: Any, channel: Any) -> None:
        self.subscriptions[channel.id] = self.subscriptions.get(channel.id, 0) + 1

    def on_unsubscribe(self, client: Any, channel: Any) -> None:
        self.subscriptions[channel.id] = max(0, self.subscriptions.get(channel.id, 0) - 1)

    def on_client_advertise(self, client: Any, channel: Any) -> None:
        if channel.topic in CLIENT_TOPICS:
            self._channels[(client.id, channel.id)] = (channel.topic, channel.encoding)

    def on_client_unadvertise(self, client: Any, client_channel_id: int) -> None:
        self._channels.pop((client.id, client_channel_id), None)

    def on_message_data(self, client: Any, client_channel_id: int, data: bytes) -> None:
        known = self._channels.get((client.id, client_channel_id))
        if known is not None:
            self._queue.put((*known, bytes(data)))

    # -- the sim thread -------------------------------------------------------------------

    @property
    def viewers(self) -> int:
        """Subscriptions open now (a client watching something)."""
        return sum(self.subscriptions.values())

    def take(self, messages: rm.RosMessages) -> list[ClientPose | str]:
        """The poses sent since the last call, decoded; a message that does not decode is
        a line saying why (for the server's status)."""
        out: list[ClientPose | str] = []
        while True:
            try:
                topic, encoding, data = self._queue.get_nowait()
            except queue.Empty:
                return out
            try:
                out.append(decode(topic, encoding, data, messages))
            except Exception as err:  # a client's bad message must not stop the run
                out.append(f"{topic}: cannot decode a {encoding} {CLIENT_TOPICS[topic]}: {err}")


def decode(topic: str, encoding: str, data: bytes, messages: rm.RosMessages) -> ClientPose:
    """A /goal_pose or /initialpose message (CDR, or JSON with the same fields)."""
    msgtype = CLIENT_TOPICS[topic]
    cov: Any = None
    if encoding == "json":
        msg = json.loads(data)
        header, pose = msg["header"], msg["pose"]
        frame = str(header.get("frame_id", ""))
        if topic == INITIAL_POSE:
            cov, pose = msg["pose"].get("covariance"), pose["pose"]
        p, q = pose["position"], pose["orientation"]
        xyz = (p["x"], p["y"])
        quat = (q.get("x", 0.0), q.get("y", 0.0), q["z"], q["w"])
    else:
        msg = messages.deserialize(data, msgtype)
        frame = msg.header.frame_id
        pose = msg.pose
        if topic == INITIAL_POSE:
            cov, pose = msg.pose.covariance, pose.pose
        p, q = pose.position, pose.orientation
        xyz, quat = (p.x, p.y), (q.x, q.y, q.z, q.w)
    x, y = float(xyz[0]), float(xyz[1])
    qx, qy, qz, qw = (float(v) for v in quat)
    yaw = float(fmath.arctan2(2.0 * (qw * qz + qx * qy), 1.0 - 2.0 * (qy * qy + qz * qz)))
    covariance = None
    if topic == INITIAL_POSE:
        full = np.asarray(cov, dtype=float).reshape(6, 6)
        covariance = full[np.ix_(_COV6, _COV6)].copy()
    return ClientPose(topic, frame, Pose2D(x, y, yaw), covariance)
