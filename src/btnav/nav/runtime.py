"""The runtime: one thread, one deterministic loop on simulated time.

`Runtime(world, seed=...)` owns the sim clock, the REP-105 frame tree, the sensors
and the wheel odometry, and every component added to it (localiser, costmaps,
servers, navigator). A component is anything with a `rate` (Hz of sim time) and an
`update(now)`; the scheduler calls it when it is due.

One `step()` is, in this fixed order:

1. physics: the world advances by `physics_dt` (the last `cmd_vel` applies);
2. odometry, if due: the new estimate is kept as `latest_odom` and published as
   `odom -> base_footprint` (with the world's `odometry: {source: laser}`, laser
   odometry does this instead as each scan of the first lidar arrives in 3, before the
   scan's other subscribers hear it; it is profiled as "LaserOdometry");
3. sensors, if due, in the world file's order: each measurement is kept in
   `latest[frame_id]` (a scan also as `latest_scan`) and handed to subscribers;
4. components that are due, by stage and then in the order they were added:
   LOCALIZATION (localiser or SLAM: map -> odom), COSTMAP, SERVER (planner,
   controller, behaviours, smoother), NAVIGATOR (bt_navigator, waypoint follower),
   MONITOR (metrics, recorders). So a server sees this step's costmap, and a
   command a controller sends moves the robot in the next physics step.

Profiling is opt-in: set `runtime.profile = {}` and each `step()` adds the wall seconds
(`time.perf_counter`) of every part to it, keyed by `profile_label`: "physics",
"odometry", a sensor as "Lidar/laser", a component as "CostmapServer/local_costmap",
"ControllerServer", ... (type, then name), and a scan subscriber under its
owner's label. While `profile` is None (the default) a step does nothing extra.

Rates are kept on the integer-nanosecond sim clock without drift: a component at
`hz` first runs one period after it is added, then every period, so a 10 Hz lidar
gives exactly 10 scans per sim second. A rate above `1 / physics_dt` runs once per
step. Nothing reads the wall clock; every random draw comes from a stream derived
from `seed`, so the same world, seed and commands give the same run, bit for bit.
`run_until` and `spin_for` run with the heap as it stood frozen (`core.heap`), so the
garbage collector does not rescan the bring-up's objects mid-run.
"""

from __future__ import annotations

from collections.abc import Callable
from enum import IntEnum
from time import perf_counter
from typing import Any, Protocol, runtime_checkable

from ..core.clock import SimClock
from ..core.errors import WorldError
from ..core.frames import BASE_FOOTPRINT, MAP, ODOM, FrameTree
from ..core.geometry import Pose2D
from ..core.heap import frozen_heap
from ..core.messages import LaserScan, Odometry, Twist
from ..odometry.laser_odometry import LaserOdometry
from ..plugins import lookup
from ..sim.frames import add_robot_frames
from ..sim.lidar import Lidar
from ..sim.odometry import WheelOdometry, make_odometry
from ..sim.sensor import Sensor
from ..sim.world import World
from ..sim.world_sensors import make_sensors
from .actions import ActionClient, ActionServer, ActionServers


@runtime_checkable
class Component(Protocol):
    """Anything the runtime schedules: `rate` in Hz of sim time, `update(now)` when due.

    An optional `stage` attribute (a `Stage`) places it in the step's order.
    """

    rate: float

    def update(self, now: float) -> Any: ...


class Stage(IntEnum):
    """Where in a step a component runs (lower first); ties keep the order of `add`."""

    LOCALIZATION = 10
    COSTMAP = 20
    SERVER = 30
    NAVIGATOR = 40
    MONITOR = 50


def profile_label(thing: Any) -> str:
    """The key a component (or a subscriber callback) is profiled under: its type's name,
    then "/" and its `name` if it has one ("CostmapServer/local_costmap"). A scheduling
    wrapper with a `server` is labelled as its server."""
    owner = getattr(thing, "__self__", thing)  # a bound method: its object
    owner = getattr(owner, "server", owner)
    kind = type(owner).__name__
    name = getattr(owner, "name", None)
    return f"{kind}/{name}" if isinstance(name, str) and name else kind


class _Scheduled:
    __slots__ = ("component", "label", "next_ns", "order", "period_ns", "stage")

    def __init__(self, component: Any, stage: int, order: int, period_ns: int, now_ns: int):
        self.component = component
        self.stage = stage
        self.order = order
        self.period_ns = period_ns
        self.next_ns = now_ns + period_ns
        self.label: str | None = None

    def due(self, now_ns: int) -> bool:
        if now_ns < self.next_ns:
            return False
        missed = (now_ns - self.next_ns) // self.period_ns  # never burst to catch up
        self.next_ns += (missed + 1) * self.period_ns
        return True

    def profiled_as(self) -> str:
        if self.label is None:
            self.label = profile_label(self.component)
        return self.label


def _run(part: Any, fn: Callable[[Any], Any], arg: Any) -> Any:
    """One part of a step, `fn(arg)` (`part` names it for `_Profiler`)."""
    return fn(arg)


class _Profiler:
    """`_run` adding each part's wall seconds to `spent` (the runtime's `profile`): a part
    is a label, a scheduled slot, or a subscriber (under its owner's `profile_label`)."""

    __slots__ = ("spent",)

    def __init__(self, spent: dict[str, float]) -> None:
        self.spent = spent

    def __call__(self, part: Any, fn: Callable[[Any], Any], arg: Any) -> Any:
        t0 = perf_counter()
        out = fn(arg)
        seconds = perf_counter() - t0
        if isinstance(part, str):
            label = part
        elif isinstance(part, _Scheduled):
            label = part.profiled_as()
        else:
            label = profile_label(part)
        self.spent[label] = self.spent.get(label, 0.0) + seconds
        return out


def _period_ns(rate: float, what: str) -> int:
    try:
        hz = float(rate)
    except (TypeError, ValueError):
        raise ValueError(f"{what}: a rate is a number of Hz, got {rate!r}") from None
    if not hz > 0:
        raise ValueError(f"{what}: a rate must be positive, got {rate!r}")
    return max(1, round(1e9 / hz))


class Runtime:
    """The scheduler on sim time, owner of clock, frames, sensors, odometry and components."""

    def __init__(
        self,
        world: World,
        *,
        seed: int = 0,
        physics_dt: float = 0.01,
        initial_pose: Pose2D | None = None,
    ) -> None:
        if not physics_dt > 0:
            raise ValueError(f"physics_dt must be positive, got {physics_dt}")
        self.world = world
        self.seed = seed
        self.physics_dt = float(physics_dt)
        self._dt_ns = round(self.physics_dt * 1e9)
        self.clock = SimClock(world.time)
        self.step_count = 0

        self.sensors: list[Sensor] = make_sensors(world, seed)
        # odometry: `source: laser` estimates odom -> base_footprint from the lidar's scans
        # (published as each scan arrives), otherwise the wheels at their own rate
        lidar = self._laser_odometry_lidar()
        self.odometry: WheelOdometry | LaserOdometry
        if lidar is None:
            self.odometry = make_odometry(world, seed)
        else:
            self.odometry = LaserOdometry(
                lidar.mount, stamp=self.now, publish=self._odometry_received
            )

        # map -> odom starts at the start pose (odometry starts at identity there), which
        # is what a perfect localiser would publish; a localiser overwrites it.
        start = initial_pose if initial_pose is not None else Pose2D(*world.spec.robot.pose)
        self.frames = FrameTree()
        self.frames.set_transform(MAP, ODOM, start, stamp=self.now)
        self.frames.set_transform(ODOM, BASE_FOOTPRINT, Pose2D(), stamp=self.now)
        add_robot_frames(self.frames, world, self.sensors)

        self.latest: dict[str, Any] = {"odom": self.odometry.last}
        self.latest_odom: Odometry = self.odometry.last
        self.latest_scan: LaserScan | None = None
        #: The base's command (`cmd_vel`) and the servers' (`cmd_vel_nav`), the last sent.
        self.cmd_vel = Twist()
        self.cmd_vel_nav = Twist()
        self._cmd_vel_chain: Callable[[Twist], None] = self.command_base
        self._subscribers: dict[str, list[Callable[[Any], None]]] = {}
        self.action_servers = ActionServers()
        self.localizer: Any = None
        #: Wall seconds per part of the step (see the module doc); None: not profiling.
        self.profile: dict[str, float] | None = None

        now_ns = self.clock.now_ns
        self._odometry_slot: _Scheduled | None = None
        if lidar is None:
            self._odometry_slot = _Scheduled(
                self.odometry, -2, 0, _period_ns(self.odometry.rate, "odometry"), now_ns
            )
        else:  # subscribed first: whoever hears the scan sees this scan's odom
            self.subscribe(lidar.frame_id, self.odometry.scan_received)
        self._sensor_slots = [
            _Scheduled(s, -1, i, _period_ns(s.rate, f"sensor '{s.frame_id}'"), now_ns)
            for i, s in enumerate(self.sensors)
        ]
        for slot in self._sensor_slots:
            slot.label = f"{type(slot.component).__name__}/{slot.component.frame_id}"
        self._components: list[_Scheduled] = []
        self._added = 0
        # The first measurements, at the start time, so nothing starts with no data.
        for sensor in self.sensors:
            self._publish(sensor.frame_id, sensor.measure(self.now))

    def _laser_odometry_lidar(self) -> Lidar | None:
        """The lidar that laser odometry matches (the first one), or None for wheels."""
        spec = self.world.spec
        if spec.robot.odometry.source != "laser":
            return None
        lidar = next((s for s in self.sensors if isinstance(s, Lidar)), None)
        if lidar is None:
            raise WorldError(
                "odometry source 'laser' needs a lidar in robot.sensors",
                file=spec.file,
                line=spec.line_of("robot", "odometry", "source"),
                key=["robot", "odometry", "source"],
            )
        return lidar

    def _odometry_received(self, odom: Odometry) -> None:
        """Laser odometry's estimate: kept, set as odom -> base_footprint, published."""
        self.latest_odom = odom
        self.frames.set_transform(ODOM, BASE_FOOTPRINT, odom.pose, stamp=odom.stamp)
        self._publish("odom", odom)

    # -- time ---------------------------------------------------------------------------

    @property
    def now(self) -> float:
        return self.clock.now

    # -- components ---------------------------------------------------------------------

    def add(self, component: Any, *, stage: int | None = None, rate: float | None = None) -> Any:
        """Schedule `component` (its own `rate` unless `rate` is given); returns it.

        `stage` defaults to the component's `stage` attribute, else `Stage.SERVER`.
        An `ActionServer` added here is also registered under its name for clients.
        """
        hz = rate if rate is not None else getattr(component, "rate", None)
        if hz is None:
            raise ValueError(f"{component!r} has no rate; pass rate=... to add()")
        if not callable(getattr(component, "update", None)):
            raise TypeError(f"{component!r} has no update(now) method")
        if stage is None:
            stage = int(getattr(component, "stage", Stage.SERVER))
        name = type(component).__name__
        slot = _Scheduled(
            component, int(stage), self._added, _period_ns(hz, name), self.clock.now_ns
        )
        self._added += 1
        self._components.append(slot)
        self._components.sort(key=lambda s: (s.stage, s.order))
        if isinstance(component, ActionServer):
            self.action_servers.add(component)
        return component

    def remove(self, component: Any) -> None:
        self._components = [s for s in self._components if s.component is not component]

    @property
    def components(self) -> list[Any]:
        """The scheduled components in the order a step runs them."""
        return [s.component for s in self._components]

    def add_action_server(self, server: ActionServer[Any]) -> ActionServer[Any]:
        """Register a server its owner updates (no rate of its own) so clients can find it."""
        self.action_servers.add(server)
        return server

    def action_client(self, name: str) -> ActionClient[Any]:
        """A client for the server `name` (a BT node's `server_name`)."""
        return self.action_servers.client(name)

    def use_localizer(self, name: str, params: Any = None, *, kind: str = "localizer") -> Any:
        """Create the `localizer` (or `slam`) plugin `name` (e.g. "ground_truth") and schedule it.

        Built as every plugin is, `cls(name, params)`, then `configure(runtime)`; `params`
        may be None (defaults), a mapping (validated by the plugin's `Params`) or a model.
        """
        cls = lookup(kind, name)
        if self.localizer is not None:
            self.remove(self.localizer)
        self.localizer = cls(name, params)
        self.localizer.configure(self)
        self.add(self.localizer, stage=Stage.LOCALIZATION)
        return self.localizer

    # -- messages -----------------------------------------------------------------------

    def subscribe(self, topic: str, callback: Callable[[Any], None]) -> None:
        """Call `callback(msg)` on each new message: topic "odom", "scan" (any
        LaserScan), or a sensor's frame id ("laser")."""
        self._subscribers.setdefault(topic, []).append(callback)

    def publish(self, topic: str, msg: Any) -> None:
        """Hand `msg` to the topic's subscribers now (and keep it in `latest`)."""
        self._publish(topic, msg)

    def _publish(self, topic: str, msg: Any, run: Callable[..., Any] = _run) -> None:
        self.latest[topic] = msg
        for cb in self._subscribers.get(topic, ()):
            run(cb, cb, msg)
        if isinstance(msg, LaserScan):
            self.latest_scan = msg
            for cb in self._subscribers.get("scan", ()):
                run(cb, cb, msg)

    def set_cmd_vel(self, cmd: Twist) -> None:
        """A navigation server's velocity command (the controller's, a behaviour's): Nav2's
        `cmd_vel_nav`. It goes down the command chain (velocity smoother, collision
        monitor, when the params file brings them up) to the base, else straight there."""
        self.cmd_vel_nav = cmd
        self._cmd_vel_chain(cmd)

    def route_cmd_vel(self, first: Callable[[Twist], None]) -> None:
        """Send `set_cmd_vel`'s commands to `first` (the chain's first stage) instead of
        the base; the chain's last stage calls `command_base`."""
        self._cmd_vel_chain = first

    def command_base(self, cmd: Twist) -> None:
        """The base's `cmd_vel`, followed from the next physics step on (the end of the
        chain, and what publishes to the base directly: teleop, the docking server)."""
        self.cmd_vel = cmd
        self.world.set_cmd_vel(cmd)

    def lookup(self, target: str, source: str) -> Pose2D:
        """The frame tree's transform (tf2's lookupTransform(target, source))."""
        return self.frames.lookup(target, source)

    def robot_pose(self, frame: str = MAP, base_frame: str = BASE_FOOTPRINT) -> Pose2D:
        """The robot's pose in `frame` as the frame tree has it (an estimate, not ground truth)."""
        return self.frames.lookup(frame, base_frame)

    # -- the loop -----------------------------------------------------------------------

    def step(self) -> float:
        """One physics step, then odometry, sensors and due components (see the module doc)."""
        run = _run if self.profile is None else _Profiler(self.profile)
        run("physics", self._advance, self.physics_dt)
        now_ns = self.clock.now_ns
        now = self.clock.now
        if self._odometry_slot is not None and self._odometry_slot.due(now_ns):
            self._publish("odom", run("odometry", self._odometry_update, now), run)
        for slot in self._sensor_slots:
            if slot.due(now_ns):
                sensor = slot.component
                self._publish(sensor.frame_id, run(slot, sensor.measure, now), run)
        for slot in list(self._components):
            if now_ns >= slot.next_ns and slot.due(now_ns):  # (most are not due: no call)
                run(slot, slot.component.update, now)
        return now

    def _advance(self, dt: float) -> None:
        """Physics and the clock, one step on."""
        self.world.step(dt)
        self.clock.advance(dt)
        self.step_count += 1

    def _odometry_update(self, now: float) -> Odometry:
        """The wheels' estimate: kept and set as odom -> base_footprint (then published)."""
        odom = self.odometry.update(now)
        self.latest_odom = odom
        self.frames.set_transform(ODOM, BASE_FOOTPRINT, odom.pose, stamp=now)
        return odom

    def spin_for(self, seconds: float) -> float:
        """Step for `seconds` of sim time (rounded to whole physics steps); returns the time."""
        if seconds < 0:
            raise ValueError(f"cannot spin for a negative time ({seconds} s)")
        with frozen_heap():
            for _ in range(round(seconds * 1e9 / self._dt_ns)):
                self.step()
        return self.now

    def run_until(self, predicate: Callable[[], bool], timeout: float) -> bool:
        """Step until `predicate()` is true (checked before each step) or `timeout` sim
        seconds have passed; returns whether the predicate came true."""
        end_ns = self.clock.now_ns + round(timeout * 1e9)
        with frozen_heap():
            while True:
                if predicate():
                    return True
                if self.clock.now_ns >= end_ns:
                    return False
                self.step()

    def __repr__(self) -> str:
        return (
            f"Runtime(world={self.world.spec.world!r}, seed={self.seed}, t={self.now:.3f}, "
            f"components={len(self._components)})"
        )
