"""Nav2's route server's algorithms (nav2_route): route graphs, their GeoJSON files,
the graph search, edge scorers, route operations, path conversion and route tracking.

A layer beside planning and control: it works on costmaps and the graph, and knows
nothing of servers or trees (`nav.route_server` serves it as Nav2's actions).

```python
from btnav.route import load_graph, RoutePlanner, EdgeScorer
from btnav.route.edge_cost_functions.distance_scorer import DistanceScorer

graph = load_graph("graphs/small_office_graph.geojson")
route = RoutePlanner(EdgeScorer([DistanceScorer("DistanceScorer")])).find_route(graph, 0, 7)
```
"""

from .edge_scorer import EdgeCostFunction, EdgeScorer
from .geojson import load_graph, save_graph
from .graph import DirectionalEdge, Graph, Node, Operation, OperationTrigger, Route
from .route_operation import RouteOperation
from .route_planner import RoutePlanner

__all__ = [
    "DirectionalEdge",
    "EdgeCostFunction",
    "EdgeScorer",
    "Graph",
    "Node",
    "Operation",
    "OperationTrigger",
    "Route",
    "RouteOperation",
    "RoutePlanner",
    "load_graph",
    "save_graph",
]
