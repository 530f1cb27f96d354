"""Route graphs in Nav2's GeoJSON format (nav2_route's GeoJsonGraphFileLoader and Saver).

A file is a FeatureCollection: a `Point` feature is a node (`properties.id`, optional
`frame`, `metadata`, `operations`; its `geometry.coordinates` are x, y), a
`LineString`/`MultiLineString` feature is a directed edge (`id`, `startid`, `endid`,
optional `cost`, `overridable`, `metadata`, `operations`; its geometry is not read, as
in Nav2). `operations` is an object of operations, each with a `type`, a `trigger`
(`NODE`, `ON_ENTER`, `ON_EXIT`) and its own `metadata`. Anything else is kept in
`metadata` as the file has it, so a plugin can read application data.

`save_graph` writes what Nav2's saver writes (and each edge's line, which Nav2 leaves
out, so GIS tools draw it); `load_graph(save_graph(g))` is `g` again.
"""

from __future__ import annotations

import json
from collections.abc import Mapping
from os import PathLike
from pathlib import Path
from typing import Any

from ..params.schema import ParamsModel
from ..plugins import Plugin, register
from .exceptions import GraphError
from .graph import DirectionalEdge, Graph, Node, Operation, OperationTrigger

_NODE_GEOMETRY = ("Point",)
_EDGE_GEOMETRY = ("LineString", "MultiLineString")


def load_graph(path: str | PathLike[str]) -> Graph:
    """Read a Nav2 GeoJSON route graph; a missing or malformed file is a `GraphError`."""
    file = Path(path)
    if not file.is_file():
        raise GraphError(f"route graph file not found: {file}")
    try:
        doc = json.loads(file.read_text(encoding="utf-8"))
    except json.JSONDecodeError as exc:
        raise GraphError(f"not valid JSON: {exc.msg}", file=file, line=exc.lineno) from None
    except UnicodeDecodeError as exc:
        raise GraphError(f"not a text file: {exc}", file=file) from None
    return graph_from_geojson(doc, str(file))


def graph_from_geojson(doc: Any, source: str = "") -> Graph:
    """The graph in a parsed GeoJSON document (see the module docstring for the format)."""
    file = source or None
    features = doc.get("features") if isinstance(doc, Mapping) else None
    if not isinstance(features, list):
        raise GraphError("a route graph is a GeoJSON FeatureCollection with 'features'", file=file)
    nodes, edges = [], []
    for i, feature in enumerate(features):
        kind = _geometry_type(feature, i, file)
        if kind in _NODE_GEOMETRY:
            nodes.append((i, feature))
        elif kind in _EDGE_GEOMETRY:
            edges.append((i, feature))
    if not nodes or not edges:
        raise GraphError(
            f"the graph has {len(nodes)} nodes (Point features) and {len(edges)} edges "
            "(LineString features); Nav2 needs both",
            file=file,
        )
    graph = Graph(name=str(doc.get("name", "graph")), source=source)
    for i, feature in nodes:
        props = _properties(feature, i, file)
        nodeid = _integer(props, "id", i, file)
        if nodeid in graph.id_to_index:
            raise GraphError(f"features[{i}]: node id {nodeid} is used twice", file=file)
        coords = feature["geometry"].get("coordinates")
        if not (isinstance(coords, list) and len(coords) >= 2):
            raise GraphError(f"features[{i}]: a node's coordinates are [x, y]", file=file)
        x, y = (_number(c, f"features[{i}].geometry.coordinates", file) for c in coords[:2])
        graph.add_node(
            Node(
                nodeid,
                x,
                y,
                frame_id=str(props.get("frame", "map")),
                metadata=_metadata(props, i, file),
                operations=_operations(props, i, file),
            )
        )
    for i, feature in edges:
        props = _properties(feature, i, file)
        edgeid = _integer(props, "id", i, file)
        ends = []
        for key in ("startid", "endid"):
            nodeid = _integer(props, key, i, file)
            if nodeid not in graph.id_to_index:
                raise GraphError(
                    f"features[{i}]: edge {edgeid}'s {key} {nodeid} is not a node of the graph",
                    file=file,
                )
            ends.append(graph.node(nodeid))
        cost = props.get("cost", 0.0)
        overridable = props.get("overridable", True)
        if not isinstance(overridable, bool):
            raise GraphError(f"features[{i}]: overridable is true or false", file=file)
        graph.add_edge(
            DirectionalEdge(
                edgeid,
                ends[0],
                ends[1],
                cost=_number(cost, f"features[{i}].properties.cost", file),
                overridable=overridable,
                metadata=_metadata(props, i, file),
                operations=_operations(props, i, file),
            )
        )
    return graph


def save_graph(graph: Graph, path: str | PathLike[str]) -> Path:
    """Write `graph` as Nav2's saver does (4-space indented GeoJSON); returns the path."""
    file = Path(path)
    file.write_text(json.dumps(graph_to_geojson(graph), indent=4) + "\n", encoding="utf-8")
    return file


def graph_to_geojson(graph: Graph) -> dict[str, Any]:
    features: list[dict[str, Any]] = []
    for node in graph.nodes:
        props: dict[str, Any] = {"id": node.nodeid, "frame": node.frame_id}
        _put_extras(props, node.metadata, node.operations)
        features.append(
            {
                "type": "Feature",
                "properties": props,
                "geometry": {"type": "Point", "coordinates": [node.x, node.y]},
            }
        )
    for edge in graph.edges():
        props = {"id": edge.edgeid, "startid": edge.start.nodeid, "endid": edge.end.nodeid}
        _put_extras(props, edge.metadata, edge.operations)
        props["cost"] = edge.cost
        props["overridable"] = edge.overridable
        line = [[edge.start.x, edge.start.y], [edge.end.x, edge.end.y]]
        features.append(
            {
                "type": "Feature",
                "properties": props,
                "geometry": {"type": "MultiLineString", "coordinates": [line]},
            }
        )
    return {
        "type": "FeatureCollection",
        "name": graph.name,
        "crs": {"type": "name", "properties": {"name": "urn:ogc:def:crs:EPSG::3857"}},
        "features": features,
    }


def _put_extras(props: dict[str, Any], metadata: dict[str, Any], ops: list[Operation]) -> None:
    if metadata:
        props["metadata"] = metadata
    if ops:
        props["operations"] = {
            op.key or op.type: {
                "type": op.type,
                "trigger": op.trigger.value,
                **({"metadata": op.metadata} if op.metadata else {}),
            }
            for op in ops
        }


# -- reading pieces, each error naming the feature -------------------------------------------


def _geometry_type(feature: Any, i: int, file: str | None) -> str:
    geometry = feature.get("geometry") if isinstance(feature, Mapping) else None
    kind = geometry.get("type") if isinstance(geometry, Mapping) else None
    if not isinstance(kind, str):
        raise GraphError(f"features[{i}] has no geometry type", file=file)
    return kind


def _properties(feature: Mapping[str, Any], i: int, file: str | None) -> Mapping[str, Any]:
    props = feature.get("properties")
    if not isinstance(props, Mapping):
        raise GraphError(f"features[{i}] has no properties (id is required)", file=file)
    return props


def _integer(props: Mapping[str, Any], key: str, i: int, file: str | None) -> int:
    value = props.get(key)
    if isinstance(value, bool) or not isinstance(value, int) or value < 0:
        what = "missing" if value is None else f"{value!r}, not a non-negative integer"
        raise GraphError(f"features[{i}].properties.{key} is {what}", file=file)
    return value


def _number(value: Any, where: str, file: str | None) -> float:
    if isinstance(value, bool) or not isinstance(value, int | float):
        raise GraphError(f"{where} is {value!r}, not a number", file=file)
    return float(value)


def _metadata(props: Mapping[str, Any], i: int, file: str | None) -> dict[str, Any]:
    metadata = props.get("metadata", {})
    if not isinstance(metadata, Mapping):
        raise GraphError(f"features[{i}].properties.metadata is not an object", file=file)
    return dict(metadata)


def _operations(props: Mapping[str, Any], i: int, file: str | None) -> list[Operation]:
    given = props.get("operations", {})
    items = given.items() if isinstance(given, Mapping) else enumerate(given or [])
    out = []
    for key, op in items:
        where = f"features[{i}].properties.operations.{key}"
        if not isinstance(op, Mapping) or "type" not in op or "trigger" not in op:
            raise GraphError(f"{where} needs a type and a trigger", file=file)
        try:
            trigger = OperationTrigger(op["trigger"])
        except ValueError:
            choices = ", ".join(t.value for t in OperationTrigger)
            raise GraphError(
                f"{where}.trigger is {op['trigger']!r}; triggers: {choices}", file=file
            ) from None
        metadata = op.get("metadata", {})
        if not isinstance(metadata, Mapping):
            raise GraphError(f"{where}.metadata is not an object", file=file)
        named = isinstance(given, Mapping) and key != op["type"]
        out.append(Operation(str(op["type"]), trigger, dict(metadata), str(key) if named else ""))
    return out


# -- the plugins (graph_file_loader: "GeoJsonGraphFileLoader", as Nav2's params name it) ----


@register(
    "graph_file_loader",
    "btnav/GeoJsonGraphFileLoader",
    aliases=["nav2_route::GeoJsonGraphFileLoader"],
)
class GeoJsonGraphFileLoader(Plugin):
    """Nav2's default graph file loader."""

    class Params(ParamsModel):
        pass

    def load_graph(self, path: str | PathLike[str]) -> Graph:
        return load_graph(path)


@register(
    "graph_file_saver", "btnav/GeoJsonGraphFileSaver", aliases=["nav2_route::GeoJsonGraphFileSaver"]
)
class GeoJsonGraphFileSaver(Plugin):
    """Nav2's default graph file saver."""

    class Params(ParamsModel):
        pass

    def save_graph(self, graph: Graph, path: str | PathLike[str]) -> Path:
        return save_graph(graph, path)
