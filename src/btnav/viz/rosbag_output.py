"""`outputs: [bag]`: the run as a ROS 2 bag (`bag/`, MCAP storage) for Foxglove or RViz.

Written with `rosbags` (the `logs` extra), no ROS install needed: `bag/metadata.yaml`
and `bag/bag.mcap` (zstd-compressed chunks), so `ros2 bag play out/office_tour/bag
--clock` replays the run into RViz and Foxglove opens the `.mcap` as it is. The
metadata is rosbag2's format 8, the newest one Humble's `ros2 bag` still parses (format
9, Jazzy's, spells QoS in words); Jazzy and later read it too. The messages are Jazzy's.
The topics, in Nav2's names and standard types:

| topic | type | when |
|---|---|---|
| `/scan` | sensor_msgs/LaserScan | each scan of the first lidar (`/<frame>/scan` for more) |
| `/odom` | nav_msgs/Odometry | each odometry estimate (odom -> base_footprint, with twist) |
| `/tf` | tf2_msgs/TFMessage | each new value of a moving transform (map -> odom, odom -> base_footprint) |
| `/tf_static` | tf2_msgs/TFMessage | once: the mounts (base_footprint -> base_link -> laser) |
| `/map` | nav_msgs/OccupancyGrid | at the start and whenever map_server's map changes (SLAM) |
| `/plan` | nav_msgs/Path | each plan planner_server computes |
| `/cmd_vel` | geometry_msgs/Twist | each velocity command (TwistStamped with the params file's `enable_stamped_cmd_vel: true`) |
| `/amcl_pose` | geometry_msgs/PoseWithCovarianceStamped | each pose AMCL publishes |
| `/behavior_tree_log` | nav2_msgs/BehaviorTreeLog | after each tick with status changes |

Every header stamp and every record time is sim time; records are in time order, and
each topic carries the QoS a recording of Nav2 would show (`/tf_static`, `/map` and
`/amcl_pose` transient local, `/scan` best effort). The recorder only reads: it runs
last in each step (MONITOR), notices what changed since the step before, and streams
it to the file (`ros_topics` notices and builds the messages, as for Foxglove live), so
the run is the same with or without the bag and a long run keeps no history in memory.
A re-run replaces the folder.
"""

from __future__ import annotations

from pathlib import Path
from typing import Any

from ..mission.outputs import RunOutput
from ..nav.runtime import Stage
from ..plugins import register
from . import ros_messages as rm
from .ros_topics import RunTopics

BAG_DIR = "bag"
BAG_VERSION = 8  # rosbag2's metadata format: read by Humble, Jazzy and later


def _qos(*, reliable: bool = True, latched: bool = False) -> Any:
    """The QoS `ros2 bag record` keeps for a publisher: reliability and durability (history
    and depth are not visible to it), deadlines and leases infinite."""
    from rosbags.interfaces import (
        Qos,
        QosDurability,
        QosHistory,
        QosLiveliness,
        QosReliability,
        QosTime,
    )

    infinite = QosTime(sec=2147483647, nsec=4294967295)
    return Qos(
        history=QosHistory.UNKNOWN,
        depth=0,
        reliability=QosReliability.RELIABLE if reliable else QosReliability.BEST_EFFORT,
        durability=QosDurability.TRANSIENT_LOCAL if latched else QosDurability.VOLATILE,
        deadline=infinite,
        lifespan=infinite,
        liveliness=QosLiveliness.AUTOMATIC,
        liveliness_lease_duration=infinite,
        avoid_ros_namespace_conventions=False,
    )


@register("output", "bag")
class RosbagOutput:
    """Records the run into `bag/`; needs `rosbags` (the logs extra), checked before the run."""

    files = (BAG_DIR,)  # a folder: metadata.yaml and bag.mcap, as `ros2 bag record` writes

    def __init__(self) -> None:
        self.messages = rm.RosMessages()  # a missing rosbags fails here, before the run
        self.recorder: BagRecorder | None = None

    def start(self, nav: Any, out_dir: Path) -> None:
        # the runner has removed the last run's bag: rosbags writes only new ones
        self.recorder = BagRecorder(nav, Path(out_dir) / BAG_DIR, self.messages)

    def write(self, run: RunOutput) -> None:
        if self.recorder is not None:
            self.recorder.close()


class BagRecorder:
    """A MONITOR component at the physics rate: what changed this step goes into the bag."""

    stage = Stage.MONITOR

    def __init__(self, nav: Any, path: Path, messages: rm.RosMessages) -> None:
        from rosbags.rosbag2 import CompressionFormat, CompressionMode, StoragePlugin, Writer

        self.nav = nav
        rt = self.runtime = nav.runtime
        self.msgs = messages
        self.rate = 1.0 / rt.physics_dt  # every step: no scan, odometry or command missed
        self.writer: Any = Writer(path, version=BAG_VERSION, storage_plugin=StoragePlugin.MCAP)
        self.writer.set_compression(CompressionMode.STORAGE, CompressionFormat.ZSTD)
        self.writer.open()
        self._topics: dict[str, Any] = {}
        self.topics = RunTopics(nav, messages, self._put)
        self.topics.start()
        rt.add(self)

    def _put(
        self, topic: str, msgtype: str, msg: Any, t_ns: int, *, reliable: bool, latched: bool
    ) -> None:
        conn = self._topics.get(topic)
        if conn is None:
            qos = _qos(reliable=reliable, latched=latched)
            conn = self.writer.add_connection(
                topic, msgtype, typestore=self.msgs.store, offered_qos_profiles=[qos]
            )
            self._topics[topic] = conn
        self.writer.write(conn, t_ns, self.msgs.serialize(msg, msgtype))

    def update(self, now: float) -> None:
        self.topics.update(now)

    def close(self) -> None:
        """Write what is pending, close the bag (metadata.yaml), stop recording."""
        if self.writer is None:
            return
        self.topics.stop()
        self.runtime.remove(self)
        self.writer.close()
        self.writer = None
