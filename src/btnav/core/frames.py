"""The frame tree (TF in 2D), following REP-105.

`map -> odom -> base_footprint -> base_link -> <sensor frames>`. Each frame has one
parent; a transform is either static (sensor mounts, base_footprint -> base_link)
or stamped (odom -> base_footprint from odometry, map -> odom from localisation),
and only its latest value is kept: the loop is single-threaded on sim time, so
nothing ever asks for the past.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field

from . import fmath
from .errors import FrameError
from .geometry import Pose2D, normalize_angle
from .suggest import best_match

#: The REP-105 chain btnav always has.
MAP, ODOM, BASE_FOOTPRINT, BASE_LINK = "map", "odom", "base_footprint", "base_link"


@dataclass
class StampedTransform:
    parent: str
    child: str
    transform: Pose2D  # the child's pose in the parent frame
    stamp: float
    static: bool
    #: sin and cos of the transform's yaw, for composing it: worked out once per value
    #: (odometry's edge is composed by every lookup until the next odometry)
    sin: float = field(init=False, repr=False)
    cos: float = field(init=False, repr=False)
    #: Whether the transform is all zeros (base_footprint -> base_link): from the identity,
    #: composing it gives the identity, so a walk to the root that starts there skips it
    zero: bool = field(init=False, repr=False)

    def __post_init__(self) -> None:
        tf = self.transform
        yaw = tf.yaw
        # sincos(±0.0) is (the zero, 1.0): most mounts and frames do not turn
        self.sin, self.cos = (yaw, 1.0) if yaw == 0.0 and type(yaw) is float else fmath.sincos(yaw)
        self.zero = tf.x == 0.0 and tf.y == 0.0 and yaw == 0.0


class FrameTree:
    """Frames and the transforms between them; `lookup` answers what `tf2_echo` would."""

    def __init__(self) -> None:
        self._edges: dict[str, StampedTransform] = {}  # child -> edge to its parent
        self._roots: set[str] = set()
        # lookup's answers since the last change of any transform (a step looks the same
        # pair up several times: the tree, the controller, the costmaps)
        self._lookups: dict[tuple[str, str], Pose2D] = {}

    @classmethod
    def rep105(cls) -> FrameTree:
        """The standard chain with identity transforms, ready for odometry and localisation."""
        tree = cls()
        tree.set_transform(MAP, ODOM, Pose2D(), stamp=0.0)
        tree.set_transform(ODOM, BASE_FOOTPRINT, Pose2D(), stamp=0.0)
        tree.set_static(BASE_FOOTPRINT, BASE_LINK, Pose2D())
        return tree

    # -- building -------------------------------------------------------------------

    def _set(self, parent: str, child: str, tf: Pose2D, stamp: float, static: bool) -> None:
        old = self._edges.get(child)
        if old is not None and old.parent == parent and not old.static and not static:
            # a new value of a moving transform already in the tree (odometry, localisation)
            self._edges[child] = StampedTransform(parent, child, tf, stamp, False)
            self._lookups.clear()
            return
        if parent == child:
            raise FrameError(f"frame '{child}' cannot be its own parent")
        if old is not None and old.parent != parent:
            raise FrameError(
                f"frame '{child}' already has parent '{old.parent}'; a frame has one parent"
            )
        if old is not None and old.static and not static:
            raise FrameError(f"frame '{child}' is static; it cannot be updated as stamped")
        if old is None and self._is_ancestor(child, parent):
            raise FrameError(f"'{parent}' -> '{child}' would close a loop in the frame tree")
        self._edges[child] = StampedTransform(parent, child, tf, stamp, static)
        self._lookups.clear()
        self._roots.discard(child)
        if parent not in self._edges:
            self._roots.add(parent)

    def set_static(self, parent: str, child: str, transform: Pose2D) -> None:
        """A fixed mount (a sensor on the robot), like a static_transform_publisher."""
        self._set(parent, child, transform, 0.0, True)

    def set_transform(self, parent: str, child: str, transform: Pose2D, stamp: float) -> None:
        """The latest value of a moving transform (odometry, localisation)."""
        self._set(parent, child, transform, stamp, False)

    def _is_ancestor(self, frame: str, of: str) -> bool:
        node = of
        while node in self._edges:
            node = self._edges[node].parent
            if node == frame:
                return True
        return node == frame

    # -- queries --------------------------------------------------------------------

    @property
    def frames(self) -> list[str]:
        return sorted(self._roots | set(self._edges))

    def has(self, frame: str) -> bool:
        return frame in self._edges or frame in self._roots

    def parent(self, frame: str) -> str | None:
        self.require(frame)
        edge = self._edges.get(frame)
        return edge.parent if edge else None

    def edge(self, child: str) -> StampedTransform:
        self.require(child)
        if child not in self._edges:
            raise FrameError(f"frame '{child}' is a root; it has no parent transform")
        return self._edges[child]

    def require(self, frame: str, *, key: str | None = None) -> None:
        """Fail as `tf2_echo` would, but name the frames that do exist."""
        if not self.has(frame):
            raise FrameError(
                f"frame '{frame}' does not exist; frames: {', '.join(self.frames)}",
                key=key,
                suggestion=best_match(frame, self.frames),
            )

    def _to_root(self, frame: str) -> tuple[str, float, float, float]:
        """The root of `frame`'s tree and `frame`'s pose in it, as (root, x, y, yaw): the
        arithmetic of `edge.transform @ pose` from the identity, on plain floats."""
        x = y = yaw = 0.0
        node = frame
        edges = self._edges
        edge = edges.get(node)
        # from the identity, a zero transform gives the identity: (0.0, 0.0, 0.0) exactly,
        # whatever the zeros' signs (0.0 + 1.0 * 0.0 - ±0.0 * 0.0 is 0.0)
        while edge is not None and edge.zero:
            node = edge.parent
            edge = edges.get(node)
        while edge is not None:
            tf = edge.transform
            e_yaw = tf.yaw
            s, c = edge.sin, edge.cos
            x, y, yaw = tf.x + c * x - s * y, tf.y + s * x + c * y, e_yaw + yaw
            if not -math.pi < yaw <= math.pi:
                yaw = normalize_angle(yaw)  # as Pose2D keeps its yaw
            node = edge.parent
            edge = edges.get(node)
        return node, x, y, yaw

    def lookup(self, target: str, source: str) -> Pose2D:
        """The pose of frame `source` expressed in frame `target` (tf2's lookupTransform(target, source)).

        Applied to points, it maps coordinates in `source` into `target`.
        """
        found = self._lookups.get((target, source))
        if found is not None:
            return found
        edges, roots = self._edges, self._roots
        if not (target in edges or target in roots) or not (source in edges or source in roots):
            self.require(target)
            self.require(source)
        root_s, sx, sy, syaw = self._to_root(source)
        if target == root_s:
            # the general arithmetic below with (tx, ty, tyaw) = (0.0, 0.0, 0.0): the
            # inverse is (-0.0, 0.0, -0.0), its sincos (-0.0, 1.0), and c * v is v
            found = Pose2D((-0.0 + sx) - -0.0 * sy, (0.0 + -0.0 * sx) + sy, -0.0 + syaw)
            self._lookups[(target, source)] = found
            return found
        root_t, tx, ty, tyaw = self._to_root(target)
        if root_t != root_s:
            raise FrameError(
                f"frames '{target}' and '{source}' are not connected "
                f"(their trees have roots '{root_t}' and '{root_s}')"
            )
        # Pose2D(tx, ty, tyaw).inverse() @ Pose2D(sx, sy, syaw), on plain floats
        s, c = fmath.sincos(tyaw)
        ix, iy, iyaw = -c * tx - s * ty, s * tx - c * ty, -tyaw
        if not -math.pi < iyaw <= math.pi:
            iyaw = normalize_angle(iyaw)
        s, c = fmath.sincos(iyaw)
        found = Pose2D(ix + c * sx - s * sy, iy + s * sx + c * sy, iyaw + syaw)
        self._lookups[(target, source)] = found
        return found

    def stamp(self, child: str) -> float:
        return self.edge(child).stamp

    def describe(self) -> str:
        """An indented tree like `view_frames`, with each transform and its stamp."""
        children: dict[str, list[str]] = {}
        for child, edge in self._edges.items():
            children.setdefault(edge.parent, []).append(child)
        lines: list[str] = []

        def walk(frame: str, depth: int) -> None:
            edge = self._edges.get(frame)
            text = frame
            if edge is not None:
                tf = edge.transform
                kind = "static" if edge.static else f"t={edge.stamp:.3f}"
                text += f"  [{tf.x:.3f}, {tf.y:.3f}, {tf.yaw:.3f}] ({kind})"
            lines.append("  " * depth + text)
            for c in sorted(children.get(frame, [])):
                walk(c, depth + 1)

        for root in sorted(self._roots):
            walk(root, 0)
        return "\n".join(lines)
