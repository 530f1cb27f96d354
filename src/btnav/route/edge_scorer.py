"""Edge cost functions (plugin kind `edge_cost_function`) and the sum nav2_route's
EdgeScorer makes of them.

A scorer's `score(edge, request, edge_type)` returns its (weighted) cost of traversing
the edge, or None when the edge may not be used now (blocked, in collision, the wrong
direction); an edge any scorer refuses is not expanded. `prepare()` runs before each
edge is scored (CostmapScorer takes the newest costmap there).
"""

from __future__ import annotations

from typing import Any, ClassVar

from pydantic import Field

from ..params.schema import ParamsModel
from ..plugins import Plugin
from .context import RouteContext
from .graph import DirectionalEdge, EdgeType, RouteRequest


class EdgeCostFunction(Plugin):
    """Base of the scorers (nav2_route::EdgeCostFunction)."""

    class Params(ParamsModel):
        weight: float = Field(1.0, description="relative weight of this scorer's cost")

    context: RouteContext | None = None

    def configure(self, context: Any) -> None:
        """The server's context: costmaps by topic, sim time, services."""
        self.context = context

    def prepare(self) -> None:
        """Before each edge's scoring."""

    def score(
        self, edge: DirectionalEdge, request: RouteRequest, edge_type: EdgeType
    ) -> float | None:
        raise NotImplementedError

    def services(self) -> dict[str, Any]:
        """The scorer's services by name under its own (DynamicEdgesScorer's adjust_edges)."""
        return {}


def metadata_number(metadata: dict[str, Any], key: str, default: float) -> float:
    """A numeric metadata value as a float (Nav2 reads them as float), else `default`."""
    value = metadata.get(key, default)
    if isinstance(value, bool) or not isinstance(value, int | float):
        return default
    return float(value)


class EdgeScorer:
    """The sum of the scorers' costs, in list order; None as soon as one refuses."""

    kind: ClassVar[str] = "edge_cost_function"

    def __init__(self, plugins: list[EdgeCostFunction]) -> None:
        self.plugins = plugins

    def __len__(self) -> int:
        return len(self.plugins)

    def score(
        self, edge: DirectionalEdge, request: RouteRequest, edge_type: EdgeType
    ) -> float | None:
        for plugin in self.plugins:
            plugin.prepare()
        total = 0.0
        for plugin in self.plugins:
            cost = plugin.score(edge, request, edge_type)
            if cost is None:
                return None
            total += cost
        return total
