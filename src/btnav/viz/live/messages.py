"""What the page draws, as JSON messages built from the running navigator.

One `static` message (the world's bounds and walls, the footprint, the task's poses),
a `map` when the map changes (the static map once; SLAM's map as it grows), a
`costmap` (global or local, asked for by the page, only when its cells changed), a
`tree` when another tree runs, and a `frame` per update: sim time, the robot's
ground-truth pose, the task's poses, the scan, the plans, the particles, plugins' drawables, each tree
node's status as a letter (I, R, S, F: Groot's idle, running, success, failure).
Grids go as base64 bytes (row 0 at the origin); points as flat lists rounded to mm.
Building them only reads the navigator, so a run is the same with or without a view.
"""

from __future__ import annotations

import base64
from typing import Any

import numpy as np

from ...core.errors import FrameError
from ...mission.bt_log import STATUS_NAMES, depth_first
from ..run_recorder import RunRecorder, Snapshot


def flat(points: Any) -> list[float]:
    """(N, k) points as one flat list of floats rounded to mm."""
    return np.round(np.asarray(points, dtype=np.float64), 3).ravel().tolist()


def grid_message(
    kind: str, data: np.ndarray, resolution: float, origin: tuple[float, float], **more: Any
) -> dict[str, Any]:
    h, w = data.shape
    return {
        "type": kind,
        "w": int(w),
        "h": int(h),
        "res": float(resolution),
        "origin": [float(origin[0]), float(origin[1])],
        "data": base64.b64encode(np.ascontiguousarray(data).tobytes()).decode("ascii"),
        **more,
    }


class StateMessages:
    """Builds the messages of one navigator's run (see the module doc)."""

    def __init__(self, nav: Any, mission_name: str) -> None:
        self.nav = nav
        self.mission_name = mission_name
        self._goals_of: tuple[Any, list[list[float]]] = (None, [])
        # the GIF's snapshotter, kept for what a frame shows (its frames are not kept here)
        self.taker = RunRecorder(nav, rate=1.0, max_frames=2)
        self.global_frame = self.taker.global_frame
        self._map_sent: Any = None
        self._costmap_sent: dict[str, np.ndarray] = {}
        self._root_sent: Any = None
        self._nodes: list[Any] = []

    def static(self) -> dict[str, Any]:
        from ...sim.scene import solids_geometry

        world = self.nav.runtime.world
        (x0, y0), (x1, y1) = world.bounds
        static = solids_geometry([s for s in world.solids if s.moves is None])
        return {
            "type": "static",
            "mission": self.mission_name,
            "bounds": [float(x0), float(y0), float(x1), float(y1)],
            "footprint": flat(self.taker_outline()),
            "polygons": [flat(p) for p in static.polygons],
            "circles": [flat(c) for c in static.circles],
            "particles": self.taker._particles() is not None,
            "slam": self.taker.slam,
        }

    def taker_outline(self) -> np.ndarray:
        fp = self.nav.runtime.world.spec.robot.footprint
        if fp.radius is not None:
            angles = np.linspace(0.0, 2.0 * np.pi, 24, endpoint=False)
            return fp.radius * np.stack([np.cos(angles), np.sin(angles)], axis=-1)
        return np.asarray(fp.polygon, dtype=float)

    def reset(self) -> None:
        """Send everything again (a new page connected)."""
        self._map_sent = None
        self._costmap_sent = {}
        self._root_sent = None

    def map(self) -> dict[str, Any] | None:
        """The map, when it is not the one sent last."""
        grid = self.nav.stack.map_server.map
        if grid is None or grid is self._map_sent:
            return None
        self._map_sent = grid
        data = np.asarray(grid.data, dtype=np.int8)
        return grid_message("map", data, grid.resolution, (grid.origin.x, grid.origin.y))

    def costmap(self, which: str) -> dict[str, Any] | None:
        """The `which` ("global", "local") costmap, when its cells changed since sent."""
        server = (
            self.nav.stack.global_costmap if which == "global" else self.nav.stack.local_costmap
        )
        if server is None:
            return None
        costmap = server.costmap
        costs = costmap.costs
        origin = (costmap.origin_x, costmap.origin_y)
        before = self._costmap_sent.get(which)
        key = np.concatenate([costs.ravel(), np.frombuffer(np.array(origin).tobytes(), np.uint8)])
        if before is not None and np.array_equal(before, key):
            return None
        try:
            pose = self.nav.runtime.lookup(self.global_frame, server.global_frame)
        except FrameError:
            return None
        self._costmap_sent[which] = key
        return grid_message(
            "costmap",
            costs,
            costmap.resolution,
            origin,
            which=which,
            pose=[pose.x, pose.y, pose.yaw],
        )

    def tree(self) -> dict[str, Any] | None:
        """The running tree's nodes (name, type, depth), when another tree runs."""
        root = self._running_root()
        if root is None or root is self._root_sent:
            return None
        self._root_sent = root
        self._nodes = list(depth_first(root))
        depth = {id(root): 0}
        rows = []
        for node in self._nodes:
            for child in node.children:
                depth[id(child)] = depth[id(node)] + 1
            rows.append([node.name, type(node).__name__, depth[id(node)]])
        return {"type": "tree", "nodes": rows}

    def _running_root(self) -> Any:
        navigators = list(self.nav.bt_navigator.navigators.values())
        for navigator in navigators:
            if (
                navigator.current is not None
                and navigator.current.active
                and navigator.root is not None
            ):
                return navigator.root
        return self._root_sent

    def _goals(self) -> list[list[float]]:
        """The poses of the task running now (the mission's, or a goal clicked in the page)."""
        handle = self.nav.handle
        if handle is not self._goals_of[0]:
            goal = None if handle is None else handle.goal
            poses = getattr(goal, "poses", None)
            if poses is None:
                poses = [goal.pose] if hasattr(goal, "pose") else []
            self._goals_of = (handle, [_xyyaw(p) for p in poses])
        return self._goals_of[1]

    def frame(self, now: float, **more: Any) -> dict[str, Any]:
        snap: Snapshot = self.taker.snapshot_now(now)
        return {
            "type": "frame",
            "t": round(float(now), 3),
            "robot": [round(float(v), 4) for v in snap.robot],
            "scan": flat(snap.scan),
            "plan": flat(snap.plan),
            "local_plan": flat(snap.local_plan),
            "particles": None if snap.particles is None else flat(snap.particles),
            "movers": [flat(m) for m in snap.movers],
            "drawings": [
                {"kind": d.kind, "color": d.color, "label": d.label, "points": flat(d.points)}
                for d in snap.drawings
            ],
            "bt": "".join(STATUS_NAMES[n.status][0] for n in self._nodes),
            "actions": list(snap.actions),
            "waypoint": snap.waypoint,
            "goals": self._goals(),
            **more,
        }


def _xyyaw(pose: Any) -> list[float]:
    pose = getattr(pose, "pose", pose)  # a PoseStamped
    if hasattr(pose, "x"):
        return [round(float(pose.x), 3), round(float(pose.y), 3), round(float(pose.yaw), 3)]
    return [round(float(v), 3) for v in list(pose)[:3]]
