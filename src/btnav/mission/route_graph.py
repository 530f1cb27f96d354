"""A mission's route graph, handed to the params as nav2_bringup's launch does.

Nav2's launch files take a `graph` argument and write it into the params as
route_server's `graph_filepath`. A mission's `route_graph:` (relative to the mission)
does the same, so the route server starts with that graph; the graph is read now, so a
missing or broken file is a load error naming the mission's line.
"""

from __future__ import annotations

from collections.abc import Callable
from pathlib import Path
from typing import Any

from ..core.errors import BtnavError
from ..params.paramsfile import ParamsFile
from ..params.updates import apply_overrides
from ..route.geojson import load_graph
from .errors import MissionError
from .spec import MissionSpec, resolve


def with_route_graph(
    spec: MissionSpec, base: Path, params: ParamsFile, where: Callable[..., dict[str, Any]]
) -> ParamsFile:
    """The params with the mission's `route_graph` as route_server's `graph_filepath`."""
    if spec.route_graph is None:
        return params
    path = resolve(base, spec.route_graph).resolve()
    if not path.is_file():
        raise MissionError(f"route_graph file not found: {path}", **where("route_graph"))
    try:
        load_graph(path)
    except BtnavError as err:
        raise err if err.file else err.located(**where("route_graph")) from None
    return apply_overrides(params, {"route_server.graph_filepath": str(path)})
