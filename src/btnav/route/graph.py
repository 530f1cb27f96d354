"""The route graph as nav2_route holds it: nodes with their directed edges, metadata and
operations, and the route a search returns.

A node keeps the edges that leave it (`neighbors`), so a search expands a node by
reading its own list; every edge is one direction (a two-way lane is two edges).
Metadata is the graph file's `metadata` object as a plain dict (numbers, strings,
bools, lists, nested dicts), which scorers read and operations may write
(`TimeMarker` stores `abs_time_taken`), as Nav2's `Metadata` is shared by them.
"""

from __future__ import annotations

from collections.abc import Iterator
from dataclasses import dataclass, field
from enum import Enum, IntEnum
from typing import Any

from ..core import fmath
from ..core.geometry import Pose2D


class OperationTrigger(str, Enum):
    """When a graph operation runs: on achieving its node, entering or leaving its edge."""

    NODE = "NODE"
    ON_ENTER = "ON_ENTER"
    ON_EXIT = "ON_EXIT"


@dataclass
class Operation:
    """An operation a node or edge asks for: `type` names the route_operation plugin."""

    type: str
    trigger: OperationTrigger
    metadata: dict[str, Any] = field(default_factory=dict)
    #: Its key in the file's `operations` object (Nav2's saver writes the type there).
    key: str = ""


@dataclass(eq=False)
class Node:
    nodeid: int
    x: float
    y: float
    frame_id: str = "map"
    metadata: dict[str, Any] = field(default_factory=dict)
    operations: list[Operation] = field(default_factory=list)
    neighbors: list[DirectionalEdge] = field(default_factory=list)

    def __repr__(self) -> str:
        return f"Node({self.nodeid}, {self.x:g}, {self.y:g})"


@dataclass(eq=False)
class DirectionalEdge:
    """An edge from `start` to `end`; `cost` is used as it is when not `overridable` or
    when no edge scorer is loaded (then it must be positive)."""

    edgeid: int
    start: Node
    end: Node
    cost: float = 0.0
    overridable: bool = True
    metadata: dict[str, Any] = field(default_factory=dict)
    operations: list[Operation] = field(default_factory=list)

    @property
    def length(self) -> float:
        return fmath.hypot(self.end.x - self.start.x, self.end.y - self.start.y)

    def __repr__(self) -> str:
        return f"Edge({self.edgeid}: {self.start.nodeid} -> {self.end.nodeid})"


@dataclass(eq=False)
class Graph:
    """The nodes in file order and each node id's index among them."""

    nodes: list[Node] = field(default_factory=list)
    id_to_index: dict[int, int] = field(default_factory=dict)
    #: The file's `name` (Nav2 writes "graph"), kept for saving.
    name: str = "graph"
    #: Where the graph was read from, for messages.
    source: str = ""

    def __len__(self) -> int:
        return len(self.nodes)

    def node(self, nodeid: int) -> Node:
        return self.nodes[self.id_to_index[nodeid]]

    def add_node(self, node: Node) -> Node:
        self.id_to_index[node.nodeid] = len(self.nodes)
        self.nodes.append(node)
        return node

    def add_edge(self, edge: DirectionalEdge) -> DirectionalEdge:
        edge.start.neighbors.append(edge)
        return edge

    def edges(self) -> Iterator[DirectionalEdge]:
        for node in self.nodes:
            yield from node.neighbors

    def edge(self, edgeid: int) -> DirectionalEdge:
        for edge in self.edges():
            if edge.edgeid == edgeid:
                return edge
        raise KeyError(edgeid)


class EdgeType(IntEnum):
    """Whether an edge leaves the search's start node or reaches its goal node."""

    NONE = 0
    START = 1
    END = 2


@dataclass
class Route:
    """The search's answer: its first node and the edges from there (none: one node)."""

    start_node: Node
    edges: list[DirectionalEdge] = field(default_factory=list)
    route_cost: float = 0.0

    @property
    def nodes(self) -> list[Node]:
        return [self.start_node, *(e.end for e in self.edges)]


@dataclass(frozen=True)
class RouteRequest:
    """What the scorers may look at besides the edge: the request's ends."""

    start_nodeid: int
    goal_nodeid: int
    start_pose: Pose2D
    goal_pose: Pose2D
    use_poses: bool


@dataclass
class ReroutingState:
    """What one tracking request carries from one routing to the next (Nav2's
    ReroutingState): the edges operations found blocked, whether this is the first
    routing, the edge the robot was on and its closest point there, and where a
    reroute starts (the last node passed and the robot's pose then)."""

    blocked_ids: list[int] = field(default_factory=list)
    first_time: bool = True
    curr_edge: DirectionalEdge | None = None
    closest_pt_on_edge: tuple[float, float] = (0.0, 0.0)
    rerouting_start_id: int | None = None
    rerouting_start_pose: Pose2D | None = None

    def reset(self) -> None:
        self.blocked_ids = []
        self.first_time = True
        self.curr_edge = None
        self.closest_pt_on_edge = (0.0, 0.0)
        self.rerouting_start_id = None
        self.rerouting_start_pose = None


def closest_point(px: float, py: float, a: Node, b: Node) -> tuple[float, float]:
    """The point of segment a-b nearest (px, py) (nav2_route's utils::findClosestPoint)."""
    vx, vy = b.x - a.x, b.y - a.y
    vv = vx * vx + vy * vy
    if vv < 1e-6:
        return a.x, a.y
    t = ((px - a.x) * vx + (py - a.y) * vy) / vv
    if t <= 0.0:
        return a.x, a.y
    if t >= 1.0:
        return b.x, b.y
    return (1.0 - t) * a.x + t * b.x, (1.0 - t) * a.y + t * b.y


def normalized_dot(v1x: float, v1y: float, v2x: float, v2y: float) -> float:
    """The cosine between two vectors; 0 when either is (nearly) zero."""
    m1, m2 = fmath.hypot(v1x, v1y), fmath.hypot(v2x, v2y)
    if m1 < 1e-6 or m2 < 1e-6:
        return 0.0
    return (v1x / m1) * (v2x / m2) + (v1y / m1) * (v2y / m2)
