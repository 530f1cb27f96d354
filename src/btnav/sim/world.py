"""The pymunk world: static walls and obstacles, kinematic moving obstacles, the robot.

The simulator knows nothing of navigation. It steps physics on sim time, takes a
velocity command, records the robot's contacts and hands out its solid geometry
(for sensors and maps) and the ground-truth pose (for tests, metrics and the
ground-truth localiser only).
"""

from __future__ import annotations

from dataclasses import dataclass
from os import PathLike
from typing import Any

import numpy as np
import pymunk

from ..core.clock import NS_PER_S
from ..core.errors import WorldError
from ..core.geometry import Pose2D
from ..core.messages import Twist
from .docks import dock_solids
from .drive import make_drive, set_velocity
from .geometry import Geometry
from .moving import Route
from .robot import ROBOT_COLLISION_TYPE, Robot
from .scene import Solid, build_solids, solids_geometry
from .world_spec import WorldSpec, load_world_spec

#: The longest physics step; a longer `step(dt)` is split into equal sub-steps so a
#: coarse caller does not let the robot tunnel through a thin wall.
MAX_SUBSTEP_NS = 10_000_000  # 0.01 s
#: How deep the start footprint may touch something before it counts as overlapping.
START_OVERLAP_TOLERANCE = 1e-6


@dataclass(frozen=True)
class Contact:
    """One contact of the robot with a wall or obstacle, as it began.

    A count says that something went wrong; this says when, where the robot was and
    what it hit, down to the item and line of the world file a user looks at.
    """

    time: float  # sim seconds at the end of the physics step that made the contact
    pose: Pose2D  # the robot's ground-truth pose then
    hit: str  # "wall", "obstacle", or "map" (a world made from a map image)
    index: int  # in the world file's `walls:` or `obstacles:` list (a map: its rectangle)
    kind: str  # box, circle or polygon; a wall is a "polyline", a map's cells "map cells"
    line: int | None  # of that list item in the world file

    @property
    def label(self) -> str:
        """`obstacles[3] (box)`: the item's key path, as errors name it."""
        return f"{self.hit}s[{self.index}]" + (f" ({self.kind})" if self.hit == "obstacle" else "")

    def to_dict(self) -> dict[str, Any]:
        """The record `report.json` lists under `contacts`."""
        return {
            "time": self.time,
            "pose": [self.pose.x, self.pose.y, self.pose.yaw],
            "hit": self.hit,
            "index": self.index,
            "kind": self.kind,
            "line": self.line,
        }


class _Mover:
    """A kinematic body carrying one moving obstacle along its route.

    `position` is where the route puts it (exact, from sim time); the body is given the
    velocity that takes it there in one step, so it pushes what it meets. Reading the
    body back is never needed: a kinematic body integrates exactly the velocity it gets.
    """

    __slots__ = ("body", "index", "position", "route")

    def __init__(self, index: int, body: pymunk.Body, route: Route) -> None:
        self.index = index
        self.body = body
        self.route = route
        self.position = route.position_at(0.0)


class World:
    """A world file brought to life: `step(dt)`, `set_cmd_vel`, `robot_pose`, `geometry()`."""

    def __init__(
        self, spec: WorldSpec, *, seed: int = 0, file: str | PathLike[str] | None = None
    ) -> None:
        self.spec = spec
        self.seed = seed
        self.file: str | None = str(file) if file is not None else spec.file
        self.bounds: tuple[tuple[float, float], tuple[float, float]] = spec.bounds
        self._ns = 0

        space = pymunk.Space()
        space.gravity = (0.0, 0.0)
        space.damping = 1.0
        # pymunk's default slop (0.1 m) would let the robot sink 10 cm into a wall.
        space.collision_slop = 0.001
        space.iterations = 20
        self.space = space

        self.solids: list[Solid] = build_solids(spec) + dock_solids(spec)
        #: The solids that are docks (index -> dock name): touching one is docking, not a
        #: collision, so it is neither counted in `collisions` nor listed in `contacts`.
        self.dock_solids = {
            i: spec.docks[int(s.key[1])].name
            for i, s in enumerate(self.solids)
            if s.key[0] == "docks"
        }
        self._owner: dict[pymunk.Shape, int] = {}
        self._movers: list[_Mover] = []
        for index, solid in enumerate(self.solids):
            self._add_solid(index, solid)

        #: Where the robot block was written: the world file, or a mission's `robot:`.
        self.robot_file = spec.robot_file if spec.robot_replaced else self.file
        self.robot = Robot(spec.robot, make_drive(spec, self.robot_file))
        space.add(self.robot.body, *self.robot.shapes)
        self._check_start_pose()

        self.collisions = 0
        #: Every contact, in the order they began (`collisions` is their count).
        self.contacts: list[Contact] = []
        self._ns_after_step = 0  # sim time the physics step now running ends at
        self._touching: dict[int, int] = {}  # solid index -> shape pairs in contact
        space.on_collision(
            ROBOT_COLLISION_TYPE, None, begin=self._on_begin, separate=self._on_separate
        )

        static = [s for s in self.solids if s.moves is None]
        self._static_geometry = solids_geometry(static)
        _ = self._static_geometry.segments  # computed once; merged() reuses it
        # The moving solids' shapes relative to their reference point, placed by offset.
        moving = solids_geometry(
            [self.solids[m.index] for m in self._movers], [np.zeros(2)] * len(self._movers)
        )
        self._moving_segments = moving.segments.copy()
        self._moving_circles = moving.circles.copy()
        self._moving_polygons = moving.polygons
        self._geometry: tuple[int, Geometry] | None = None

    @classmethod
    def from_file(cls, path: str | PathLike[str], *, seed: int = 0) -> World:
        """Load, validate and build a world file; every mistake is a located `WorldError`."""
        spec = load_world_spec(path)
        return cls(spec, seed=seed, file=path)

    # -- building -----------------------------------------------------------------------

    def _add_solid(self, index: int, solid: Solid) -> None:
        if solid.moves is None:
            body = self.space.static_body
            offset = solid.origin
        else:
            body = pymunk.Body(body_type=pymunk.Body.KINEMATIC)
            body.position = (float(solid.origin[0]), float(solid.origin[1]))
            self.space.add(body)
            offset = np.zeros(2)
            self._movers.append(_Mover(index, body, Route(solid.origin, solid.moves)))
        shapes: list[pymunk.Shape] = [
            pymunk.Poly(body, [(float(x), float(y)) for x, y in part + offset])
            for part in solid.parts
        ]
        shapes += [
            pymunk.Circle(body, float(r), (float(x + offset[0]), float(y + offset[1])))
            for x, y, r in solid.circles
        ]
        for s in shapes:
            s.friction = 0.0
            s.elasticity = 0.0
            self._owner[s] = index
        self.space.add(*shapes)

    def _describe(self, solid: Solid) -> str:
        line = self.spec.line_of(*solid.key)
        return solid.label + (f" (line {line})" if line else "")

    def _check_start_pose(self) -> None:
        """A start pose outside the bounds or overlapping anything solid is the user's mistake."""
        x, y, yaw = self.spec.robot.pose
        line = self.spec.line_of("robot", "pose")
        where = dict(file=self.robot_file, line=line, key="robot.pose")
        (x0, y0), (x1, y1) = self.bounds
        if not (x0 <= x <= x1 and y0 <= y <= y1):
            raise WorldError(
                f"the start pose ({x:g}, {y:g}) is outside the world's bounds "
                f"[[{x0:g}, {y0:g}], [{x1:g}, {y1:g}]]",
                **where,
            )
        hits: list[int] = []
        own = set(self.robot.shapes)
        for shape in self.robot.shapes:
            for info in self.space.shape_query(shape):
                if info.shape in own or info.shape not in self._owner:
                    continue
                cps = info.contact_point_set
                depth = min((p.distance for p in cps.points), default=0.0)
                # pymunk reports a zero normal (and depth 0) when the centres coincide.
                degenerate = cps.normal.length == 0.0
                index = self._owner[info.shape]
                if (depth < -START_OVERLAP_TOLERANCE or degenerate) and index not in hits:
                    hits.append(index)
        if hits:
            names = ", ".join(self._describe(self.solids[i]) for i in sorted(hits))
            raise WorldError(
                f"the robot's footprint at its start pose ({x:g}, {y:g}, {yaw:g}) overlaps {names}; "
                "move the robot or the obstacle",
                **where,
            )

    # -- contacts -----------------------------------------------------------------------

    def _on_begin(self, arbiter: pymunk.Arbiter, space: pymunk.Space, data: Any) -> None:
        index = self._other(arbiter)
        if index is None:
            return
        n = self._touching.get(index, 0)
        if n == 0 and index not in self.dock_solids:  # a new contact with a wall or obstacle
            self.collisions += 1
            self.contacts.append(self._contact(index))
        self._touching[index] = n + 1

    def _contact(self, index: int) -> Contact:
        solid = self.solids[index]
        what, i = solid.key[0], int(solid.key[1])
        if what == "obstacles":
            hit, kind = "obstacle", self.spec.obstacles[i].kind
        elif what == "walls":
            hit, kind = "wall", "polyline"
        elif what == "added_obstacles":  # add_box while running: not in the world file
            hit, kind = "obstacle", "box"
        else:  # a world made from a map image
            hit, kind = "map", "map cells"
        return Contact(
            time=self._ns_after_step / NS_PER_S,
            pose=self.robot.pose,
            hit=hit,
            index=i,
            kind=kind,
            line=self.spec.line_of(*solid.key),
        )

    def _on_separate(self, arbiter: pymunk.Arbiter, space: pymunk.Space, data: Any) -> None:
        index = self._other(arbiter)
        if index is None:
            return
        n = self._touching.get(index, 0) - 1
        if n <= 0:
            self._touching.pop(index, None)
        else:
            self._touching[index] = n

    def _other(self, arbiter: pymunk.Arbiter) -> int | None:
        a, b = arbiter.shapes
        other = b if a.collision_type == ROBOT_COLLISION_TYPE else a
        return self._owner.get(other)

    @property
    def touching_docks(self) -> list[str]:
        """The names of the docks the robot touches right now."""
        return [self.dock_solids[i] for i in self._touching if i in self.dock_solids]

    @property
    def in_contact(self) -> bool:
        """Whether the robot touches anything right now."""
        return bool(self._touching)

    # -- stepping -----------------------------------------------------------------------

    @property
    def time(self) -> float:
        """Sim seconds since the start (kept in integer nanoseconds)."""
        return self._ns / NS_PER_S

    @property
    def time_ns(self) -> int:
        return self._ns

    def step(self, dt: float) -> None:
        """Advance physics by `dt` seconds (split into sub-steps of at most 0.01 s)."""
        total = round(dt * NS_PER_S)
        if total < 0:
            raise ValueError(f"sim time never runs backwards (dt={dt})")
        if total == 0:
            return
        n = -(-total // MAX_SUBSTEP_NS)
        base, extra = divmod(total, n)
        for i in range(n):
            self._substep(base + (1 if i < extra else 0))

    def _substep(self, ns: int) -> None:
        h = ns / NS_PER_S
        t_next = (self._ns + ns) / NS_PER_S
        self.robot.control(h, free=not self._touching)
        for m in self._movers:
            (px, py), (tx, ty) = m.position, m.route.position_at(t_next)
            set_velocity(m.body, ((tx - px) / h, (ty - py) / h))
            m.position = (tx, ty)
        self._ns_after_step = self._ns + ns
        self.space.step(h)
        self._ns += ns

    # -- robot --------------------------------------------------------------------------

    def set_cmd_vel(self, cmd: Twist) -> None:
        """The velocity command the robot follows (within its limits) until the next one."""
        self.robot.set_cmd_vel(cmd)

    @property
    def robot_pose(self) -> Pose2D:
        """Ground truth: base_footprint in world (= map) coordinates."""
        return self.robot.pose

    @property
    def robot_twist(self) -> Twist:
        """Ground-truth velocity in the robot frame."""
        if not self._touching:  # nothing pushed it: the velocity set in the last step
            return self.robot.last_control
        return self.robot.twist

    # -- changing the scene while it runs -----------------------------------------------

    def add_box(
        self, center: tuple[float, float], size: tuple[float, float], yaw: float = 0.0
    ) -> int:
        """Put a static box into the world now (an obstacle dropped in the robot's way);
        returns its solid index. Sensors see it from their next measurement. It is not in
        the world file: a contact with it is `added_obstacles[k] (box)` with no line. A
        box that would overlap the robot is refused (ValueError)."""
        from .scene import box_corners

        if not (size[0] > 0 and size[1] > 0):
            raise ValueError(f"a box's size must be positive, got {size}")
        k = sum(1 for s in self.solids if s.key[0] == "added_obstacles")
        origin = np.array([float(center[0]), float(center[1])])
        corners = box_corners((float(center[0]), float(center[1])), size, yaw) - origin
        solid = Solid(
            f"added_obstacles[{k}] (box)", ("added_obstacles", k), origin, [corners], [corners]
        )
        index = len(self.solids)
        self.solids.append(solid)
        self._add_solid(index, solid)
        new = [s for s, i in self._owner.items() if i == index]
        if any(info.shape in new for r in self.robot.shapes for info in self.space.shape_query(r)):
            self.space.remove(*new)
            for s in new:
                del self._owner[s]
            self.solids.pop()
            raise ValueError(f"a box at {tuple(center)} would overlap the robot")
        self._static_geometry = solids_geometry([s for s in self.solids if s.moves is None])
        _ = self._static_geometry.segments
        self._geometry = None  # the merged geometry with moving obstacles is built anew
        return index

    # -- what sensors and maps see ------------------------------------------------------

    def geometry(self) -> Geometry:
        """Everything solid except the robot, now (moving obstacles where they are)."""
        if not self._movers:
            return self._static_geometry
        if self._geometry is not None and self._geometry[0] == self._ns:
            return self._geometry[1]
        # One offset per moving solid, repeated over its segments, circles and outlines.
        seg_off: list[tuple[float, ...]] = []
        circ_off: list[tuple[float, ...]] = []
        polygons: list[np.ndarray] = []
        for m in self._movers:
            solid = self.solids[m.index]
            x, y = m.position
            if solid.outlines:
                seg_off += [(x, y, x, y)] * sum(len(o) for o in solid.outlines)
                polygons += [o + np.array((x, y)) for o in solid.outlines]
            circ_off += [(x, y, 0.0)] * len(solid.circles)
        static = self._static_geometry
        circles = static.circles
        if circ_off:
            circles = np.concatenate([circles, self._moving_circles + circ_off])
        geometry = Geometry(static.polygons + polygons, circles, one_sided=True)
        geometry._segments = static.segments
        if seg_off:
            geometry._segments = np.concatenate([static.segments, self._moving_segments + seg_off])
        self._geometry = (self._ns, geometry)
        return geometry

    def sensor_specs(self) -> list[tuple[str, Any, int | None]]:
        """The robot's sensor entries as written: (plugin name, params document, line)."""
        out = []
        for i, entry in enumerate(self.spec.robot.sensors):
            name, params = next(iter(entry.items()))
            out.append((name, params, self.spec.line_of("robot", "sensors", i)))
        return out

    def __repr__(self) -> str:
        return f"World({self.spec.world!r}, t={self.time:.3f}, robot={self.robot_pose})"
