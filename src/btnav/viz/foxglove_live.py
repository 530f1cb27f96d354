"""`btnav run MISSION --foxglove`: the run live in Foxglove, steered from there.

`FoxgloveLive` is a MONITOR component at the physics rate that runs a Foxglove
WebSocket server (foxglove-sdk, the `view` extra; 127.0.0.1:8765 by default) and sends
the bag's topics as they change (`ros_topics`: the same ROS 2 messages, CDR-encoded
with ros2msg schemas, which Foxglove decodes as it decodes a bag), plus `/local_plan`
(nav_msgs/Path, at the controller's rate while it drives) and `/particle_cloud`
(geometry_msgs/PoseArray, each AMCL update). Latched topics (`/tf_static`, `/map`,
`/amcl_pose`) are sent again when a client subscribes, as a transient-local
subscriber would get them. Log times are sim time and the server's clock is sim time.

A client's `/goal_pose` is sent as a NavigateToPose goal and `/initialpose` sets the
localiser's pose (`foxglove_goals`), from the sim thread, at a step. While a client is
subscribed the run is paced to `speed` x wall time (`Pacer`); with none it is not, and
a run with the server and no client is the run without it, byte for byte.
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass
from pathlib import Path
from types import ModuleType
from typing import Any

import numpy as np

from ..core.errors import BtnavError, FrameError
from ..core.geometry import Pose2D
from ..mission.outputs import RunOutput
from ..nav.runtime import Stage
from ..plugins import register
from . import ros_messages as rm
from .foxglove_goals import GOAL_POSE, ClientPose, ClientPoses
from .pacing import Pacer
from .ros_topics import RunTopics
from .run_recorder import local_plan

DEFAULT_HOST, DEFAULT_PORT = "127.0.0.1", 8765
LOCAL_PLAN, PARTICLE_CLOUD = "/local_plan", "/particle_cloud"
IDLE_SPEED = 1.0  # after the task, with nothing to drive: real time (no busy loop)


def import_foxglove() -> ModuleType:
    """The foxglove-sdk package, or a one-line BtnavError naming the extra that brings it."""
    try:
        import foxglove
        import foxglove.websocket  # the server's types
    except ImportError:
        raise BtnavError(
            'Foxglove live needs the foxglove-sdk package: pip install "btnav[view]"'
        ) from None
    return foxglove


@dataclass(frozen=True)
class LiveSettings:
    """Where the server listens and how fast a watched run goes (0: as fast as it can)."""

    host: str = DEFAULT_HOST
    port: int = DEFAULT_PORT  # 0: a free port (`FoxgloveLive.port` says which)
    speed: float = 1.0


@register("output", "foxglove")
class FoxgloveOutput:
    """`outputs: [foxglove]`: serve the run live while it goes (no file). The CLI's
    `--foxglove` builds one with its settings and `keep_serving`, to idle on after."""

    files = ()

    def __init__(
        self,
        settings: LiveSettings | None = None,
        *,
        keep_serving: bool = False,
        serving: Callable[[FoxgloveLive], None] | None = None,
    ) -> None:
        self.settings = settings if settings is not None else LiveSettings()
        self.keep_serving = keep_serving
        self.serving = serving  # told once the server listens (the CLI prints its address)
        self.foxglove = import_foxglove()  # a missing package fails here, before the run
        self.messages = rm.RosMessages()
        self.live: FoxgloveLive | None = None

    def start(self, nav: Any, out_dir: Path) -> None:
        self.live = FoxgloveLive(nav, self.settings, self.messages, self.foxglove)
        if self.serving is not None:
            self.serving(self.live)

    def write(self, run: RunOutput) -> None:
        if self.live is not None and not self.keep_serving:
            self.live.close()


class FoxgloveLive:
    """The server and the component sending the run to it (see the module doc)."""

    stage = Stage.MONITOR

    def __init__(
        self,
        nav: Any,
        settings: LiveSettings,
        messages: rm.RosMessages | None = None,
        foxglove: ModuleType | None = None,
    ) -> None:
        fg = self.fg = foxglove if foxglove is not None else import_foxglove()
        self.nav = nav
        rt = self.runtime = nav.runtime
        self.msgs = messages if messages is not None else rm.RosMessages()
        self.settings = settings
        self.rate = 1.0 / rt.physics_dt  # every step: pacing, and nothing missed
        self.pacer = Pacer(settings.speed)
        self.idling = False
        self.clients = ClientPoses()
        self._viewers_before = 0
        self.context = fg.Context()
        caps = fg.websocket.Capability
        try:
            self.server = fg.start_server(
                name="btnav",
                host=settings.host,
                port=settings.port,
                capabilities=[caps.ClientPublish, caps.Time],
                supported_encodings=["cdr", "json"],
                server_listener=self.clients,
                context=self.context,
            )
        except (RuntimeError, OSError) as err:
            raise BtnavError(
                f"cannot serve Foxglove on {settings.host}:{settings.port} ({err}); "
                "choose another with --foxglove-port"
            ) from None
        self.port = int(self.server.port)  # the free one when settings.port is 0
        self._channels: dict[str, Any] = {}
        self._latched: dict[str, tuple[bytes, int]] = {}
        server = nav.stack.controller_server
        self._controller = server
        self._plan_period_ns = max(1, round(1e9 / server.rate))
        self._next_plan_ns = rt.clock.now_ns
        self._plan_shown = False
        self._particles = getattr(type(rt.localizer), "particles", None) is not None
        self._particles_of: Any = None
        self._global_frame = nav.bt_navigator.params.global_frame
        self._channel(LOCAL_PLAN, rm.PATH)
        if self._particles:
            self._channel(PARTICLE_CLOUD, rm.POSE_ARRAY)
        self.topics = RunTopics(nav, self.msgs, self._put)
        self.topics.start()
        rt.add(self)

    @property
    def url(self) -> str:
        return f"ws://{self.settings.host}:{self.port}"

    # -- sending ----------------------------------------------------------------------------

    def _channel(self, topic: str, msgtype: str) -> Any:
        channel = self._channels.get(topic)
        if channel is None:
            fg = self.fg
            schema = fg.Schema(
                name=msgtype, encoding="ros2msg", data=self.msgs.definition(msgtype).encode()
            )
            channel = fg.Channel(topic, schema=schema, message_encoding="cdr", context=self.context)
            self._channels[topic] = channel
        return channel

    def _put(
        self, topic: str, msgtype: str, msg: Any, t_ns: int, *, reliable: bool, latched: bool
    ) -> None:
        channel = self._channel(topic, msgtype)
        if not latched and not self.clients.subscriptions.get(channel.id()):
            return  # nobody watches it: no bytes
        data = self.msgs.serialize(msg, msgtype)
        if latched:
            self._latched[topic] = (data, t_ns)
        channel.log(data, log_time=t_ns)

    def _resend_latched(self) -> None:
        """A client that subscribed since the last step gets the latched topics' last value."""
        for topic, (data, t_ns) in self._latched.items():
            self._channels[topic].log(data, log_time=t_ns)

    # -- the component ----------------------------------------------------------------------

    def update(self, now: float) -> None:
        rt = self.runtime
        viewers = self.clients.viewers
        if viewers > self._viewers_before:
            self._resend_latched()
        self._viewers_before = viewers
        for sent in self.clients.take(self.msgs):
            self._act_on(sent)
        self.topics.update(now)
        if rt.clock.now_ns >= self._next_plan_ns:
            self._next_plan_ns = rt.clock.now_ns + self._plan_period_ns
            self._local_plan(now)
        self._particle_cloud(now)
        if viewers:
            self.server.broadcast_time(rt.clock.now_ns)
        self._pace(now, viewers)

    def _pace(self, now: float, viewers: int) -> None:
        speed = self.settings.speed
        if self.idling and not self._task_running():
            speed = IDLE_SPEED
        elif not viewers:
            self.pacer.reanchor()  # a viewer that comes starts a new stretch
            return
        if speed != self.pacer.speed:
            self.pacer.speed = speed
        self.pacer.wait(now)

    def _task_running(self) -> bool:
        handle = self.nav.handle
        return handle is not None and not handle.done

    def _local_plan(self, now: float) -> None:
        channel = self._channels[LOCAL_PLAN]
        if not self.clients.subscriptions.get(channel.id()):
            return
        server = self._controller
        frame = server.costmap.global_frame
        if not server.action.is_active or server.controller is None:
            if self._plan_shown:  # the controller stopped: an empty plan clears the view
                self._plan_shown = False
                msg = self.msgs.points_path(_no_points(), now, frame)
                channel.log(self.msgs.serialize(msg, rm.PATH), log_time=self.runtime.clock.now_ns)
            return
        try:
            pose = self.runtime.lookup(frame, server.costmap.robot_base_frame)
        except FrameError:
            return
        points = local_plan(server, pose)
        self._plan_shown = True
        msg = self.msgs.points_path(points, now, frame)
        channel.log(self.msgs.serialize(msg, rm.PATH), log_time=self.runtime.clock.now_ns)

    def _particle_cloud(self, now: float) -> None:
        """After each AMCL update (a new pose), the particles, in the map frame."""
        localizer = self.runtime.localizer
        if not self._particles:
            return
        pose = getattr(localizer, "pose", None)
        if pose is self._particles_of:
            return
        self._particles_of = pose
        channel = self._channels[PARTICLE_CLOUD]
        if not self.clients.subscriptions.get(channel.id()):
            return
        poses, _weights = localizer.particles
        msg = self.msgs.pose_array(poses, now, self._global_frame)
        channel.log(self.msgs.serialize(msg, rm.POSE_ARRAY), log_time=self.runtime.clock.now_ns)

    def _act_on(self, sent: ClientPose | str) -> None:
        if isinstance(sent, str):
            self._status(sent, warning=True)
            return
        pose = self._in_global_frame(sent)
        if pose is None:
            return
        if sent.topic == GOAL_POSE:
            accepted = self.nav.go_to_pose(pose)
            what = "NavigateToPose goal" if accepted else "NavigateToPose goal (rejected)"
        else:
            self.nav.set_initial_pose(pose, sent.covariance)
            what = "initial pose"
        self._status(f"{what} ({pose.x:.2f}, {pose.y:.2f}, {pose.yaw:.2f}) at t={self.nav.now:.2f}")

    def _in_global_frame(self, sent: ClientPose) -> Pose2D | None:
        frame = sent.frame_id or self._global_frame
        if frame == self._global_frame:
            return sent.pose
        try:
            return self.runtime.lookup(self._global_frame, frame) @ sent.pose
        except FrameError:
            self._status(
                f"{sent.topic}: no transform from '{frame}' to '{self._global_frame}'", warning=True
            )
            return None

    def _status(self, line: str, *, warning: bool = False) -> None:
        level = self.fg.StatusLevel.Warning if warning else self.fg.StatusLevel.Info
        self.server.publish_status(line, level)

    # -- after the task ---------------------------------------------------------------------

    def idle(self, until: Callable[[], bool] | None = None, step: float = 0.1) -> None:
        """Keep the sim going (paced: `speed` while a clicked goal runs, real time when
        nothing does) so a client's goals still run, until `until()` is true or Ctrl-C."""
        self.idling = True
        try:
            while until is None or not until():
                self.runtime.spin_for(step)
        finally:
            self.idling = False

    def close(self) -> None:
        """Stop sending (what is pending first) and stop the server."""
        if self.server is None:
            return
        self.topics.stop()
        self.runtime.remove(self)
        self.server.stop()
        self.server = None


def _no_points() -> np.ndarray:
    return np.zeros((0, 2))
