"""What a frame of `run.gif` shows, snapshotted as the run goes (a MONITOR component).

`RunRecorder(nav, rate, max_frames)` is added to the runtime by the `gif` output's
`start`: at `rate` Hz of sim time it keeps a `Snapshot` of only what a frame draws,
as small copies (the robot's ground-truth pose, the scan's end points, the global
and local plans, a thinned particle cloud, the moving obstacles, the running BT
actions, and the shapes plugins draw of themselves: `core.drawing`). Nothing large
is kept per frame: the static map is drawn once, and a growing SLAM map is copied
only when SLAM publishes a new one (frames share it). The global plan is shared the
same way until a replan.

A long run is thinned evenly: when more than `max_frames - 1` snapshots are held,
every other one is dropped and the recorder keeps one tick in twice as many from then
on, so the frames stay evenly spaced in sim time. `close` adds the closing frame (the
end of the run, with its result), so a GIF has at most `max_frames` frames.

The recorder only reads: the run is the same, bit for bit, with or without it.
Points are in the global frame (`map`), as RViz shows them with `map` as its fixed
frame: the scan is placed where the frame tree put the laser when the scan arrived
(as RViz looks tf up at the scan's stamp; the recorder hears each scan for that), so
a scan that does not line up with the map shows the localisation error.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import Any

import numpy as np

from ..core.drawing import Drawable, Draws
from ..core.errors import FrameError
from ..core.geometry import Pose2D
from ..core.messages import LaserScan
from ..core.nav2_msgs import FollowWaypointsGoal, NavigateThroughPosesGoal
from ..mission.run_status import current_waypoint, running_actions
from ..nav.runtime import Stage

#: Particles kept per frame at most (evenly thinned beyond).
MAX_PARTICLES = 600


@dataclass
class MapVersion:
    """A copy of map_server's map as SLAM published it (int8 occupancy, row 0 at the origin)."""

    data: np.ndarray
    resolution: float
    origin: tuple[float, float]

    @property
    def extent(self) -> tuple[float, float, float, float]:
        x0, y0 = self.origin
        h, w = self.data.shape
        return (x0, x0 + w * self.resolution, y0, y0 + h * self.resolution)

    @property
    def known_cells(self) -> int:
        return int((self.data >= 0).sum())


@dataclass
class Snapshot:
    """One frame's data; arrays are (N, 2) float32 x, y in the global frame."""

    tick: int  # recorder ticks since the start (time = t0 + tick / rate)
    time: float
    robot: tuple[float, float, float]  # ground truth x, y, yaw
    scan: np.ndarray
    plan: np.ndarray
    local_plan: np.ndarray
    particles: np.ndarray | None = None
    slam_map: MapVersion | None = None
    movers: list[np.ndarray] = field(default_factory=list)  # outlines of moving solids
    actions: tuple[str, ...] = ()
    waypoint: tuple[int, int] | None = None
    result: str | None = None  # the run's result, on the closing frame only
    drawings: list[Drawable] = field(default_factory=list)  # plugins' own shapes (global frame)


def _xy(points: Any) -> np.ndarray:
    return np.asarray(points, dtype=np.float32).reshape(-1, 2)


_NONE = np.zeros((0, 2), np.float32)
_TASKS = {
    FollowWaypointsGoal: "follow_waypoints",
    NavigateThroughPosesGoal: "navigate_through_poses",
}


class RunRecorder:
    """A MONITOR component keeping one `Snapshot` per frame (see the module doc)."""

    stage = Stage.MONITOR

    def __init__(self, nav: Any, rate: float, max_frames: int) -> None:
        if max_frames < 2:
            raise ValueError(f"a GIF needs at least 2 frames, got max_frames={max_frames}")
        self.nav = nav
        self.rate = float(rate)
        self.max_frames = int(max_frames)
        self.global_frame = nav.bt_navigator.params.global_frame
        self.t0 = nav.now
        self.stride = 1  # keep one tick in `stride`
        self.ticks = 0
        self.snapshots: list[Snapshot] = []
        self.slam = callable(getattr(nav.runtime.localizer, "subscribe_map", None))
        self._plan_of: tuple[Any, np.ndarray] = (None, _NONE)
        self._map_of: tuple[Any, MapVersion | None] = (None, None)
        self._static_count: tuple[int, int] | None = None
        self._scan_at: tuple[LaserScan, Pose2D] | None = None
        self.drawing_plugins = drawing_plugins(nav)
        if nav.runtime.latest_scan is not None:
            self._scan_received(nav.runtime.latest_scan)
        nav.runtime.subscribe("scan", self._scan_received)
        self.snapshot(self.t0)

    def _scan_received(self, scan: LaserScan) -> None:
        """Keep the scan and where its laser was then (no copy: scans are not changed)."""
        laser = self._to_global(scan.frame_id)
        self._scan_at = None if laser is None else (scan, laser)

    def update(self, now: float) -> None:
        self.ticks += 1
        if self.ticks % self.stride == 0:
            self.snapshot(now)

    def snapshot(self, now: float, result: str | None = None) -> Snapshot:
        """Keep what a frame at `now` draws (and thin when over the cap)."""
        snap = self.snapshot_now(now, result)
        if result is not None:
            return snap
        self.snapshots.append(snap)
        if len(self.snapshots) > self.max_frames - 1:  # room for the closing frame
            self.stride *= 2
            self.snapshots = [s for s in self.snapshots if s.tick % self.stride == 0]
        return snap

    def snapshot_now(self, now: float, result: str | None = None) -> Snapshot:
        """What a frame at `now` draws, not kept (the live view's frames)."""
        nav, rt = self.nav, self.nav.runtime
        gt = rt.world.robot_pose
        return Snapshot(
            tick=self.ticks,
            time=now,
            robot=(gt.x, gt.y, gt.yaw),
            scan=self._scan(),
            plan=self._plan(),
            local_plan=self._local_plan(),
            particles=self._particles(),
            slam_map=self._slam_map() if self.slam else None,
            movers=self._movers(),
            actions=tuple(running_actions(nav)),
            waypoint=self._waypoint(),
            result=result,
            drawings=plugin_drawables(nav, self.drawing_plugins, self.global_frame),
        )

    def close(self, result: str) -> list[Snapshot]:
        """The frames: the snapshots, then the end of the run with its result."""
        last = self.snapshots[-1]
        if self.nav.now > last.time:
            return [*self.snapshots, self.snapshot(self.nav.now, result)]
        last.result = result
        return list(self.snapshots)

    # -- what a frame shows -----------------------------------------------------------

    def _to_global(self, frame: str) -> Pose2D | None:
        try:
            return self.nav.runtime.lookup(self.global_frame, frame)
        except FrameError:
            return None

    def _scan(self) -> np.ndarray:
        if self._scan_at is None:
            return _NONE
        scan, laser = self._scan_at
        return _xy(laser.transform_points(scan.points()))

    def _plan(self) -> np.ndarray:
        """The global plan the controller follows (a copy kept until the next plan)."""
        handle = self.nav.stack.controller_server.action.current
        path = None if handle is None else handle.goal.path
        if path is self._plan_of[0]:
            return self._plan_of[1]
        points = _NONE
        if path is not None and len(path):
            to_global = self._to_global(path.frame_id or self.global_frame)
            if to_global is not None:
                points = _xy(to_global.transform_points(np.asarray(path.poses)[:, :2]))
        self._plan_of = (path, points)
        return points

    def _local_plan(self) -> np.ndarray:
        """What the running controller means to do next, in the global frame."""
        server = self.nav.stack.controller_server
        if not server.action.is_active or server.controller is None:
            return _NONE
        frame = server.costmap.global_frame
        to_global = self._to_global(frame)
        if to_global is None:
            return _NONE
        points = local_plan(server, self.nav.runtime.lookup(frame, server.costmap.robot_base_frame))
        return _xy(to_global.transform_points(points)) if len(points) else _NONE

    def _particles(self) -> np.ndarray | None:
        localizer = self.nav.runtime.localizer
        if getattr(type(localizer), "particles", None) is None:
            return None
        poses, _weights = localizer.particles
        if len(poses) > MAX_PARTICLES:
            poses = poses[:: -(-len(poses) // MAX_PARTICLES)]
        return _xy(poses[:, :2])

    def _slam_map(self) -> MapVersion | None:
        grid = self.nav.stack.map_server.map
        if grid is self._map_of[0]:
            return self._map_of[1]
        version = None
        if grid is not None:
            version = MapVersion(
                np.array(grid.data, dtype=np.int8, copy=True),
                float(grid.resolution),
                (grid.origin.x, grid.origin.y),
            )
        self._map_of = (grid, version)
        return version

    def _waypoint(self) -> tuple[int, int] | None:
        """(1-based pose being driven to, number of poses), for a task through several poses."""
        handle = self.nav.handle
        task = None if handle is None else _TASKS.get(type(handle.goal))
        if task is None:
            return None
        return current_waypoint(self.nav, task, len(handle.goal.poses))

    def _movers(self) -> list[np.ndarray]:
        """The outlines of the moving solids where they are now (their circles as polygons)."""
        world = self.nav.runtime.world
        if not any(s.moves is not None for s in world.solids):
            return []
        if self._static_count is None:
            from ..sim.scene import solids_geometry

            static = solids_geometry([s for s in world.solids if s.moves is None])
            self._static_count = (len(static.polygons), len(static.circles))
        n_poly, n_circ = self._static_count
        here = world.geometry()
        out = [_xy(p) for p in here.polygons[n_poly:]]
        angles = np.linspace(0.0, 2.0 * np.pi, 24, endpoint=False)
        ring = np.stack([np.cos(angles), np.sin(angles)], axis=-1)
        out += [_xy(ring * r + (cx, cy)) for cx, cy, r in here.circles[n_circ:]]
        return out


def local_plan(server: Any, pose: Pose2D) -> np.ndarray:
    """(N, 2) the local plan of the controller `server` runs, in its costmap's frame.

    The controller's own `local_plan(pose)` (MPPI's optimal trajectory, DWB's best
    trajectory, Regulated Pure Pursuit's path to its carrot); a controller with none
    (None, or no such method) shows the global plan as the controller server cut it.
    """
    own = getattr(server.controller, "local_plan", None)
    points = own(pose) if callable(own) else None
    if points is None:
        cut = server.local_plan
        return np.zeros((0, 2)) if cut is None else np.asarray(cut.poses)[:, :2]
    return np.asarray(points, dtype=float).reshape(len(points), -1)[:, :2]


def drawing_plugins(nav: Any) -> list[Any]:
    """The plugins that may draw themselves: the costmaps' layers and filters (asked once,
    as they do not change during a run); the running controller is asked each time."""
    found = []
    for server in (nav.stack.global_costmap, nav.stack.local_costmap):
        ros = getattr(server, "costmap_ros", None)
        if ros is not None:
            found += [p for p in (*ros.layers, *ros.filters) if isinstance(p, Draws)]
    return found


def plugin_drawables(nav: Any, plugins: list[Any], global_frame: str) -> list[Drawable]:
    """What `plugins` and the running controller draw, moved into `global_frame` (a shape in
    a frame the tree does not know is left out)."""
    controller = nav.stack.controller_server.controller
    sources = [*plugins, controller] if isinstance(controller, Draws) else plugins
    out: list[Drawable] = []
    moved: dict[str, Pose2D | None] = {}
    for plugin in sources:
        for d in plugin.drawables():
            if d.frame not in moved:
                try:
                    moved[d.frame] = nav.runtime.lookup(global_frame, d.frame)
                except FrameError:
                    moved[d.frame] = None
            to_global = moved[d.frame]
            if to_global is not None:
                pts = _xy(to_global.transform_points(d.points)) if len(d.points) else _NONE
                out.append(Drawable(d.kind, pts, global_frame, d.color, d.label))
    return out
