"""Small route graphs for the route tests, built in code."""

from __future__ import annotations

from pathlib import Path
from typing import Any

from btnav.route.graph import DirectionalEdge, Graph, Node

GRAPHS = Path(__file__).resolve().parents[2] / "graphs"


def graph(
    nodes: dict[int, tuple[float, float]],
    edges: list[tuple[int, int]],
    metadata: dict[tuple[int, int], dict[str, Any]] | None = None,
    *,
    both_ways: bool = True,
) -> Graph:
    """Nodes by id, edges as (start, end) pairs (and back, unless not `both_ways`); edge ids
    are 100 + 10 * start + end, so a test can name one."""
    g = Graph()
    for i, (x, y) in nodes.items():
        g.add_node(Node(i, x, y))
    meta = metadata or {}
    for a, b in edges:
        for s, e in ((a, b), (b, a)) if both_ways else ((a, b),):
            m = meta.get((s, e), meta.get((a, b), {}))
            g.add_edge(DirectionalEdge(edge_id(s, e), g.node(s), g.node(e), metadata=dict(m)))
    return g


def edge_id(start: int, end: int) -> int:
    return 100 + 10 * start + end


def diamond(metadata: dict[tuple[int, int], dict[str, Any]] | None = None) -> Graph:
    """0 at the left, 3 at the right, 1 above (the short way: 2 x 2.24 m) and 2 below
    (the long way: 2 x 3.16 m)."""
    return graph(
        {0: (0.0, 0.0), 1: (2.0, 1.0), 2: (2.0, -3.0), 3: (4.0, 0.0)},
        [(0, 1), (1, 3), (0, 2), (2, 3)],
        metadata,
    )
