"""SemanticScorer: a cost per semantic class of the edge and of the node it reaches.

With `semantic_key` (default `class`), the class is that key's value; with an empty key
every metadata key that names a class counts (`highway: ...`). Each class's cost is a
key of its own beside `semantic_classes`, as Nav2 declares it (`highway: 8.4`).
"""

from __future__ import annotations

from typing import Any

from pydantic import ConfigDict, model_validator

from ...plugins import register
from ..edge_scorer import EdgeCostFunction
from ..graph import DirectionalEdge, EdgeType, RouteRequest


@register("edge_cost_function", "nav2_route::SemanticScorer")
class SemanticScorer(EdgeCostFunction):
    class Params(EdgeCostFunction.Params):
        model_config = ConfigDict(extra="allow")
        semantic_classes: list[str] = []
        semantic_key: str = "class"

        @model_validator(mode="after")
        def _class_costs(self) -> Any:
            extra = dict(self.__pydantic_extra__ or {})
            missing = [c for c in self.semantic_classes if c not in extra]
            if missing:
                raise ValueError(
                    f"semantic class '{missing[0]}' needs its cost as a key of its own "
                    f"({missing[0]}: <cost>)"
                )
            unknown = [k for k in extra if k not in self.semantic_classes]
            if unknown:
                raise ValueError(
                    f"'{unknown[0]}' is not a key of SemanticScorer nor one of its "
                    f"semantic_classes ({', '.join(self.semantic_classes) or 'none'})"
                )
            for name in self.semantic_classes:
                value = extra[name]
                if isinstance(value, bool) or not isinstance(value, int | float):
                    raise ValueError(f"the cost of semantic class '{name}' is a number")
            return self

        def class_costs(self) -> dict[str, float]:
            extra = self.__pydantic_extra__ or {}
            return {name: float(extra[name]) for name in self.semantic_classes}

    def score(
        self, edge: DirectionalEdge, request: RouteRequest, edge_type: EdgeType
    ) -> float | None:
        costs = self.params.class_costs()
        key = self.params.semantic_key
        total = 0.0
        for metadata in (edge.end.metadata, edge.metadata):
            if not key:
                total += sum(costs[k] for k in metadata if k in costs)
            else:
                value = metadata.get(key)
                if isinstance(value, str) and value in costs:
                    total += costs[value]
        return self.params.weight * total
