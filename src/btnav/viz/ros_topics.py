"""The run's ROS 2 topics as they change: what the bag records and Foxglove live shows.

`RunTopics(nav, messages, put)` notices, once per physics step (it is called from a
MONITOR component), what changed since the step before: a new scan, odometry estimate,
moving transform, map, plan, velocity command or AMCL pose, and each tick's behaviour
tree status changes. It builds each as a ROS 2 message (`RosMessages`) and hands it to
`put(topic, msgtype, msg, t_ns, reliable=..., latched=...)`: the bag writes it, the
Foxglove server sends it. So the two show the same messages, built in one place. It
only reads the run. The topics and their types are listed in `rosbag_output`.
"""

from __future__ import annotations

from collections.abc import Callable
from typing import Any, Protocol

from py_trees.common import Status

from ..core.messages import LaserScan
from ..localization.amcl.amcl import Amcl
from ..mission.bt_log import STATUS_NAMES, BtLog, depth_first
from . import ros_messages as rm


class Put(Protocol):
    def __call__(
        self, topic: str, msgtype: str, msg: Any, t_ns: int, *, reliable: bool, latched: bool
    ) -> None: ...


class RunTopics:
    """Hands each new message of the run to `put` (see the module doc)."""

    def __init__(self, nav: Any, messages: rm.RosMessages, put: Put) -> None:
        self.nav = nav
        rt = self.runtime = nav.runtime
        self.msgs = messages
        self.put = put

        frames = rt.frames
        edges = [frames.edge(f) for f in frames.frames if frames.parent(f) is not None]
        self._static = [e for e in edges if e.static]
        self._moving = [e.child for e in edges if not e.static]
        self._last_edge: dict[str, Any] = {}
        lasers = [
            s.frame_id for s in rt.sensors if isinstance(rt.latest.get(s.frame_id), LaserScan)
        ]
        #: sensor frame -> topic: the first lidar on /scan, as a robot with one has it
        self.scans = {f: "/scan" if i == 0 else f"/{f}/scan" for i, f in enumerate(lasers)}
        controller = nav.stack.controller_server
        model = controller.params.model
        #: Nav2's default (Jazzy) is a plain Twist; the params file may ask for TwistStamped.
        self.stamped_cmd_vel = bool(
            "enable_stamped_cmd_vel" in model.model_fields_set and model.enable_stamped_cmd_vel
        )
        self._cmd_frame = nav.stack.local_costmap.robot_base_frame
        self.amcl = rt.localizer if isinstance(rt.localizer, Amcl) else None
        planner = nav.stack.planner_server
        self._planners = (planner.to_pose, planner.through_poses)
        self._plan_seen: list[Any] = [s.current for s in self._planners]
        self._last_cmd = rt.cmd_vel
        self._last_pose = self.amcl.pose if self.amcl is not None else None
        self._last_odom: Any = None
        self._last_map: Any = None
        self._last_scan: dict[str, Any] = dict.fromkeys(self.scans)
        self.bt_log: TopicsBtLog | None = None

    def start(self) -> None:
        """The start: the mounts once, then the map, first scans, odometry and moving
        transforms; from then on each tick's status changes go to /behavior_tree_log."""
        rt = self.runtime
        static = [self.msgs.transform(e, rt.now) for e in self._static]
        self._put("/tf_static", rm.TF, self.msgs.tf(static), rt.clock.now_ns, latched=True)
        self.update(rt.now)
        self.bt_log = self._listen_to_the_tree(self.nav.bt_navigator)

    def _listen_to_the_tree(self, bt: Any) -> TopicsBtLog:
        log = TopicsBtLog(self, idle_transitions=bt.params.bt_log_idle_transitions)
        bt.tick_listeners.append(log)
        for navigator in bt.navigators.values():  # the task's tree is built already
            if navigator.root is not None:
                log(navigator, self.runtime.now)
                break
        return log

    def stop(self) -> None:
        """Send what is pending; the tree's nodes get their listeners back."""
        if self.bt_log is None:
            return
        self.bt_log.flush()
        self.bt_log.detach()
        listeners = self.nav.bt_navigator.tick_listeners
        if self.bt_log in listeners:
            listeners.remove(self.bt_log)
        self.bt_log = None

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
        self.put(topic, msgtype, msg, t_ns, reliable=reliable, latched=latched)

    def put_bt_log(self, changes: list[Any]) -> None:
        rt = self.runtime
        self._put(
            "/behavior_tree_log", rm.BT_LOG, self.msgs.bt_log(rt.now, changes), rt.clock.now_ns
        )

    def update(self, now: float) -> None:
        """What changed since the last call, in a fixed order."""
        rt, msgs = self.runtime, self.msgs
        t_ns = rt.clock.now_ns
        for frame, topic in self.scans.items():
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
        if self.amcl is not None and self.amcl.pose is not self._last_pose:
            self._last_pose = pose = self.amcl.pose
            self._put(
                "/amcl_pose",
                rm.POSE_WITH_COVARIANCE,
                msgs.pose_with_covariance(pose),
                t_ns,
                latched=True,
            )


class TopicsBtLog(BtLog):
    """bt_log's status changes as nav2_msgs/BehaviorTreeLog: one message per tick with changes.

    It shares the nodes' `status_listener` with the run's own `bt_log` (each change goes
    to both), so `bt_log.jsonl` is the same with or without the bag or the live view.
    """

    def __init__(self, topics: RunTopics, *, idle_transitions: bool) -> None:
        rt = topics.runtime
        super().__init__(None, lambda: rt.now, idle_transitions=idle_transitions)  # type: ignore[arg-type]
        self.topics = topics
        self.pending: list[Any] = []
        self._before: dict[int, Callable[..., None] | None] = {}

    def __call__(self, navigator: Any, now: float) -> None:
        super().__call__(navigator, now)
        self.flush()

    def flush(self) -> None:
        if self.pending:
            self.topics.put_bt_log(self.pending)
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
        change = self.topics.msgs.bt_status_change(
            now, node.name, uid, STATUS_NAMES[before], STATUS_NAMES[status]
        )
        self.pending.append(change)


def _both(first: Callable[..., None], second: Callable[..., None]) -> Callable[..., None]:
    def both(node: Any, old: Status, new: Status) -> None:
        first(node, old, new)
        second(node, old, new)

    return both
