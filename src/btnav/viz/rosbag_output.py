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
it to the file, so the run is the same with or without the bag and a long run keeps
no history in memory. A re-run replaces the folder.
"""

from __future__ import annotations

from collections.abc import Callable
from pathlib import Path
from typing import Any

from py_trees.common import Status

from ..core.messages import LaserScan
from ..localization.amcl.amcl import Amcl
from ..mission.bt_log import STATUS_NAMES, BtLog, depth_first
from ..mission.outputs import RunOutput
from ..nav.runtime import Stage
from ..plugins import register
from . import ros_messages as rm

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

        frames = rt.frames
        edges = [frames.edge(f) for f in frames.frames if frames.parent(f) is not None]
        self._moving = [e.child for e in edges if not e.static]
        self._last_edge: dict[str, Any] = {}
        lasers = [
            s.frame_id for s in rt.sensors if isinstance(rt.latest.get(s.frame_id), LaserScan)
        ]
        #: sensor frame -> topic: the first lidar on /scan, as a robot with one has it
        self._scans = {f: "/scan" if i == 0 else f"/{f}/scan" for i, f in enumerate(lasers)}
        controller = nav.stack.controller_server
        model = controller.params.model
        #: Nav2's default (Jazzy) is a plain Twist; the params file may ask for TwistStamped.
        self.stamped_cmd_vel = bool(
            "enable_stamped_cmd_vel" in model.model_fields_set and model.enable_stamped_cmd_vel
        )
        self._cmd_frame = nav.stack.local_costmap.robot_base_frame
        self._amcl = rt.localizer if isinstance(rt.localizer, Amcl) else None
        planner = nav.stack.planner_server
        self._planners = (planner.to_pose, planner.through_poses)
        self._plan_seen: list[Any] = [s.current for s in self._planners]
        self._last_cmd = rt.cmd_vel
        self._last_pose = self._amcl.pose if self._amcl is not None else None
        self._last_odom: Any = None
        self._last_map: Any = None
        self._last_scan: dict[str, Any] = dict.fromkeys(self._scans)

        now_ns = rt.clock.now_ns
        static = [self.msgs.transform(e, rt.now) for e in edges if e.static]
        self._put("/tf_static", rm.TF, self.msgs.tf(static), now_ns, latched=True)
        self.update(rt.now)  # the start: map, first scans, odometry, the moving transforms
        rt.add(self)
        self.bt_log = self._listen_to_the_tree(nav.bt_navigator)

    def _listen_to_the_tree(self, bt: Any) -> BagBtLog:
        log = BagBtLog(self, idle_transitions=bt.params.bt_log_idle_transitions)
        bt.tick_listeners.append(log)
        for navigator in bt.navigators.values():  # the task's tree is built already
            if navigator.root is not None:
                log(navigator, self.runtime.now)
                break
        return log

    # -- writing ----------------------------------------------------------------------------

    def _put(
        self,
        topic: str,
        msgtype: str,
        msg: Any,
        t_ns: int,
        *,
        reliable: bool = True,
        latched: bool = False,
    ) -> None:
        conn = self._topics.get(topic)
        if conn is None:
            qos = _qos(reliable=reliable, latched=latched)
            conn = self.writer.add_connection(
                topic, msgtype, typestore=self.msgs.store, offered_qos_profiles=[qos]
            )
            self._topics[topic] = conn
        self.writer.write(conn, t_ns, self.msgs.serialize(msg, msgtype))

    def put_bt_log(self, changes: list[Any]) -> None:
        rt = self.runtime
        self._put(
            "/behavior_tree_log", rm.BT_LOG, self.msgs.bt_log(rt.now, changes), rt.clock.now_ns
        )

    # -- the component ----------------------------------------------------------------------

    def update(self, now: float) -> None:
        rt, msgs = self.runtime, self.msgs
        t_ns = rt.clock.now_ns
        for frame, topic in self._scans.items():
            scan = rt.latest.get(frame)
            if scan is not self._last_scan[frame]:
                self._last_scan[frame] = scan
                self._put(topic, rm.SCAN, msgs.scan(scan), t_ns, reliable=False)
        odom = rt.latest_odom
        if odom is not self._last_odom:
            self._last_odom = odom
            self._put("/odom", rm.ODOMETRY, msgs.odometry(odom), t_ns)
        moved = []
        for child in self._moving:
            edge = rt.frames.edge(child)
            if edge is not self._last_edge.get(child):
                self._last_edge[child] = edge
                moved.append(msgs.transform(edge, edge.stamp))
        if moved:
            self._put("/tf", rm.TF, msgs.tf(moved), t_ns)
        grid = self.nav.stack.map_server.map
        if grid is not None and grid is not self._last_map:
            self._last_map = grid
            self._put("/map", rm.OCCUPANCY_GRID, msgs.occupancy_grid(grid, now), t_ns, latched=True)
        self._commands_and_plans(now, t_ns)

    def _commands_and_plans(self, now: float, t_ns: int) -> None:
        rt, msgs = self.runtime, self.msgs
        cmd = rt.cmd_vel
        if cmd is not self._last_cmd:
            self._last_cmd = cmd
            msgtype = rm.TWIST_STAMPED if self.stamped_cmd_vel else rm.TWIST
            msg = msgs.cmd_vel(cmd, now, self._cmd_frame, stamped=self.stamped_cmd_vel)
            self._put("/cmd_vel", msgtype, msg, t_ns)
        for i, server in enumerate(self._planners):
            handle = server.current
            if handle is None or handle is self._plan_seen[i] or handle.result is None:
                continue
            self._plan_seen[i] = handle
            if handle.succeeded and handle.result.value is not None:
                self._put("/plan", rm.PATH, msgs.path(handle.result.value), t_ns)
        if self._amcl is not None and self._amcl.pose is not self._last_pose:
            self._last_pose = pose = self._amcl.pose
            self._put(
                "/amcl_pose",
                rm.POSE_WITH_COVARIANCE,
                msgs.pose_with_covariance(pose),
                t_ns,
                latched=True,
            )

    def close(self) -> None:
        """Write what is pending, close the bag (metadata.yaml), stop recording."""
        if self.writer is None:
            return
        self.bt_log.flush()
        self.bt_log.detach()
        listeners = self.nav.bt_navigator.tick_listeners
        if self.bt_log in listeners:
            listeners.remove(self.bt_log)
        self.runtime.remove(self)
        self.writer.close()
        self.writer = None


class BagBtLog(BtLog):
    """bt_log's status changes as nav2_msgs/BehaviorTreeLog: one message per tick with changes.

    It shares the nodes' `status_listener` with the run's own `bt_log` (each change goes
    to both), so `bt_log.jsonl` is the same with or without the bag.
    """

    def __init__(self, recorder: BagRecorder, *, idle_transitions: bool) -> None:
        rt = recorder.runtime
        super().__init__(None, lambda: rt.now, idle_transitions=idle_transitions)  # type: ignore[arg-type]
        self.recorder = recorder
        self.pending: list[Any] = []
        self._before: dict[int, Callable[..., None] | None] = {}

    def __call__(self, navigator: Any, now: float) -> None:
        super().__call__(navigator, now)
        self.flush()

    def flush(self) -> None:
        if self.pending:
            self.recorder.put_bt_log(self.pending)
            self.pending = []

    def _attach(self, root: Any) -> None:
        self.detach()
        before = {id(n): n.__dict__.get("status_listener") for n in depth_first(root)}
        super()._attach(root)
        self._before = before
        for node in self._nodes:
            ours = node.__dict__.get("status_listener")
            theirs = before.get(id(node))
            if ours is not None and theirs is not None:
                node.status_listener = _both(theirs, ours)

    def detach(self) -> None:
        """Give the nodes back the listener they had before (the run's bt_log, or none)."""
        for node in self._nodes:
            if "status_listener" in node.__dict__:
                node.status_listener = self._before.get(id(node))
        self._before = {}

    def _write(self, uid: int, node: Any, before: Status, status: Status, now: float) -> None:
        self._last[uid] = status
        if status is Status.INVALID and not self.idle_transitions:
            return
        self.changes += 1
        change = self.recorder.msgs.bt_status_change(
            now, node.name, uid, STATUS_NAMES[before], STATUS_NAMES[status]
        )
        self.pending.append(change)


def _both(first: Callable[..., None], second: Callable[..., None]) -> Callable[..., None]:
    def both(node: Any, old: Status, new: Status) -> None:
        first(node, old, new)
        second(node, old, new)

    return both
