"""Nav2's collision_monitor and collision_detector nodes on btnav's runtime.

nav2_bringup puts the monitor last on the command chain: the controller and behaviours
publish `cmd_vel_nav`, the velocity smoother `cmd_vel_smoothed`, and the monitor the
base's `cmd_vel`. `CollisionMonitorServer.command_received(cmd)` is its `cmd_vel_in`
subscription: each command is checked at once against the sources' latest data and
the zones (`collision_monitor.decide`), and the result goes to `publish` (the base,
`runtime.command_base`, by default). Nav2 has no timer here and neither has btnav: the
monitor works when a command arrives. After a stop it sends zero commands for
`stop_pub_timeout` seconds more, then falls silent until the command moves again (the
base keeps the last one, zero).

`enabled: false`, or the `toggle` service (`collision_monitor/toggle`, which the
ToggleCollisionMonitor tree node calls), turns the zones off; a source whose data is
missing or older than its timeout still stops the robot, as in Nav2. The action in
force is `action` (its type, command and polygon), every change is kept in `states`
(Nav2's `state_topic` messages, CollisionMonitorState) and counted by `count`.

`CollisionDetectorServer` is the collision_detector node: at `frequency` it checks the
same kinds of zones (action_type "none") and sources and publishes which zones hold
points (`collision_detector_state`); it never touches a command.
"""

from __future__ import annotations

from collections import Counter
from collections.abc import Callable
from typing import Any

import numpy as np
from numpy.typing import NDArray

from ..collision_monitor import (
    Action,
    ActionType,
    Polygon,
    PolygonSource,
    ScanSource,
    Source,
    decide,
    make_polygons,
    make_sources,
)
from ..collision_monitor.action import is_zero
from ..collision_monitor.costmap_source import CostmapReading
from ..collision_monitor.decide import collect_points
from ..collision_monitor.state import (
    CollisionDetectorState,
    CollisionMonitorState,
    ToggleResponse,
)
from ..core.messages import LaserScan, Twist
from ..core.yaml_io import file_of, line_at
from ..params.paramsfile import ServerParams
from .runtime import Runtime, Stage

#: Nav2's robot_action_prev_ at start: not zero, so the first stop starts the stop timer.
_NOT_YET = Twist(-1.0, -1.0, -1.0)


class _ZonesAndSources:
    """What the monitor and the detector share: zones and sources built from the params,
    fed with the runtime's scans, reading the local costmap when a source asks for it."""

    name = ""

    def __init__(self, runtime: Runtime, params: ServerParams, local_costmap_server: Any) -> None:
        self.runtime = runtime
        self.local_costmap_server = local_costmap_server
        self.polygons: list[Polygon] = []
        self.sources: list[Source] = []
        runtime.subscribe("scan", self._scan_received)

    def _build(self, params: ServerParams) -> None:
        """Zones and sources anew from `params`; scans already received are kept."""
        self.params = params
        model = params.model
        old = {s.name: s for s in self.sources if isinstance(s, ScanSource)}
        footprint = None
        if self.local_costmap_server is not None:
            footprint = self._footprint
        self.polygons = make_polygons(model, footprint)
        self.sources = make_sources(
            model,
            self.runtime.frames,
            costmap=self._costmap if self.local_costmap_server is not None else None,
            where=self._where,
        )
        for source in self.sources:
            previous = old.get(source.name)
            if isinstance(source, ScanSource) and previous is not None:
                source.keep_scan_of(previous)

    def _start(self, params: ServerParams) -> None:
        """Build from `params`, then take the runtime's latest scan (the one taken at the
        start), so a source with a timeout has data from the first command on."""
        self.set_parameters(params)
        if self.runtime.latest_scan is not None:
            self._scan_received(self.runtime.latest_scan)

    def set_parameters(self, params: ServerParams) -> None:
        raise NotImplementedError

    def _where(self, section: str, key: str) -> dict[str, Any]:
        doc = self.params.doc
        return {
            "file": file_of(doc),
            "line": line_at(doc, (section, key)),
            "key": f"{self.params.key}.{section}.{key}",
        }

    def _footprint(self) -> NDArray[np.float64]:
        """The local costmap's footprint (Nav2's local_costmap/published_footprint)."""
        return self.local_costmap_server.costmap_ros.footprint

    def _costmap(self) -> CostmapReading:
        ros = self.local_costmap_server.costmap_ros
        return ros.costmap, ros.global_frame, ros.last_update

    def _scan_received(self, scan: LaserScan) -> None:
        for source in self.sources:
            if isinstance(source, ScanSource):
                source.receive(scan)

    def polygon(self, name: str) -> Polygon:
        """A zone by its params name (to give a dynamic one its shape: `set_polygon`)."""
        return next(p for p in self.polygons if p.name == name)

    def source(self, name: str) -> Source:
        """A source by its params name (a `polygon` source is fed by `receive`)."""
        return next(s for s in self.sources if s.name == name)

    @property
    def polygon_sources(self) -> list[PolygonSource]:
        return [s for s in self.sources if isinstance(s, PolygonSource)]


class CollisionMonitorServer(_ZonesAndSources):
    """collision_monitor: `command_received` takes `cmd_vel_smoothed`, `publish` gets `cmd_vel`."""

    name = "collision_monitor"
    stage = Stage.SERVER

    def __init__(
        self,
        runtime: Runtime,
        params: ServerParams,
        local_costmap_server: Any = None,
        *,
        publish: Callable[[Twist], None] | None = None,
    ) -> None:
        super().__init__(runtime, params, local_costmap_server)
        self.publish = publish if publish is not None else runtime.command_base
        self.enabled: bool = params.model.enabled
        self._start(params)
        #: The action in force (Nav2's robot_action_prev_) and the zone that set it.
        self.action = Action(ActionType.DO_NOTHING, _NOT_YET)
        self.action_polygon: Polygon | None = None
        #: Every change of action, as Nav2 publishes it on `state_topic`.
        self.states: list[CollisionMonitorState] = []
        self._counts: Counter[ActionType] = Counter()
        self.stop_stamp = runtime.now
        #: Commands received and published (a stopped monitor falls silent).
        self.received = 0
        self.published = 0

    def set_parameters(self, params: ServerParams) -> None:
        """New params (validated as the file is): zones and sources are rebuilt."""
        self._build(params)
        self.stop_pub_timeout = float(params.model.stop_pub_timeout)

    # -- the command chain ---------------------------------------------------------------

    def command_received(self, cmd: Twist) -> None:
        """A `cmd_vel_in` message (Nav2's cmdVelInCallback): decide, report, publish."""
        self.received += 1
        now = self.runtime.now
        points, invalid = collect_points(self.sources, now)
        action, cause = decide(
            self.polygons, points, cmd, enabled=self.enabled, invalid_sources=invalid
        )
        if action.polygon_name != self.action.polygon_name and self.enabled:
            self.states.append(CollisionMonitorState(now, action.action_type, action.polygon_name))
            self._counts[action.action_type] += 1
        self._publish_velocity(action, now)
        self.action, self.action_polygon = action, cause

    def _publish_velocity(self, action: Action, now: float) -> None:
        if is_zero(action.req_vel):
            if not is_zero(self.action.req_vel):
                self.stop_stamp = now  # just stopped: zeros go out for stop_pub_timeout
            elif now - self.stop_stamp > self.stop_pub_timeout:
                return
        self.published += 1
        self.publish(action.req_vel)

    # -- state ---------------------------------------------------------------------------

    @property
    def state(self) -> CollisionMonitorState:
        """The last reported state (DO_NOTHING before any change)."""
        return self.states[-1] if self.states else CollisionMonitorState(0.0, ActionType(0), "")

    def count(self, action_type: ActionType) -> int:
        """How many times the monitor switched to `action_type` (a stop, a slowdown, ...)."""
        return self._counts[action_type]

    # -- services ------------------------------------------------------------------------

    def toggle(self, enable: bool = True) -> ToggleResponse:
        """Nav2's `~/toggle` service (nav2_msgs/srv/Toggle)."""
        self.enabled = bool(enable)
        word = "on" if self.enabled else "off"
        return ToggleResponse(True, f"Collision monitor toggled {word} successfully")

    def services(self) -> dict[str, Callable[..., Any]]:
        return {f"{self.name}/toggle": self.toggle}

    def __repr__(self) -> str:
        on = "enabled" if self.enabled else "disabled"
        return (
            f"CollisionMonitorServer({len(self.polygons)} zones, {len(self.sources)} sources, "
            f"{on}, {self.action.action_type.name} {self.action.polygon_name!r})"
        )


class CollisionDetectorServer(_ZonesAndSources):
    """collision_detector: each tick, which zones hold points; `publish` gets the state."""

    name = "collision_detector"
    stage = Stage.SERVER

    def __init__(
        self,
        runtime: Runtime,
        params: ServerParams,
        local_costmap_server: Any = None,
        *,
        publish: Callable[[CollisionDetectorState], None] | None = None,
    ) -> None:
        super().__init__(runtime, params, local_costmap_server)
        self.publish = publish
        self._start(params)
        self.state = CollisionDetectorState(runtime.now, (), ())
        #: Ticks each polygon detected points in, and the sources found invalid per tick.
        self.detections: Counter[str] = Counter()
        self.invalid_sources: list[str] = []

    def set_parameters(self, params: ServerParams) -> None:
        self._build(params)
        self.rate = float(params.model.frequency)

    def update(self, now: float) -> None:
        points, self.invalid_sources = collect_points(self.sources, now, stop_at_invalid=False)
        names: list[str] = []
        found: list[bool] = []
        for polygon in self.polygons:
            if not polygon.enabled:
                continue
            detected, _ = polygon.is_triggered(points)
            names.append(polygon.name)
            found.append(detected)
            if detected:
                self.detections[polygon.name] += 1
        self.state = CollisionDetectorState(now, tuple(names), tuple(found))
        if self.publish is not None:
            self.publish(self.state)

    def __repr__(self) -> str:
        return f"CollisionDetectorServer({self.rate:g} Hz, {len(self.polygons)} zones)"
