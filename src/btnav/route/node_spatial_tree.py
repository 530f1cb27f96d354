"""nav2_route's NodeSpatialTree: the graph nodes nearest a pose, nearest first.

Nav2 builds a k-d tree (nanoflann); route graphs have hundreds to thousands of nodes,
so one vectorised distance over all of them answers as fast here, and ties keep the
file's order.
"""

from __future__ import annotations

import numpy as np

from .graph import Graph


class NodeSpatialTree:
    def __init__(self, graph: Graph | None = None, num_nearest_nodes: int = 5) -> None:
        self.num_nearest_nodes = num_nearest_nodes
        self.xy = np.zeros((0, 2))
        if graph is not None:
            self.compute_tree(graph)

    def compute_tree(self, graph: Graph) -> None:
        self.xy = np.array([(n.x, n.y) for n in graph.nodes], dtype=float).reshape(-1, 2)

    def find_nearest_graph_nodes(self, x: float, y: float) -> list[int]:
        """Indices (into `graph.nodes`) of up to `num_nearest_nodes` nodes, nearest first;
        empty when there are none to give."""
        if self.num_nearest_nodes <= 0 or len(self.xy) == 0:
            return []
        d2 = np.square(self.xy[:, 0] - x) + np.square(self.xy[:, 1] - y)
        order = np.argsort(d2, kind="stable")[: self.num_nearest_nodes]
        return [int(i) for i in order]
