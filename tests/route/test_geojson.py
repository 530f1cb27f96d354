"""Route graph files in Nav2's GeoJSON format: Nav2's own samples load, save and load again
the same; a broken file is an error that names the feature."""

from __future__ import annotations

import json
from pathlib import Path

import pytest

from btnav.route.exceptions import GraphError
from btnav.route.geojson import load_graph, save_graph
from btnav.route.graph import Graph, OperationTrigger

from .graphs import GRAPHS


def describe(g: Graph) -> tuple[list, list]:
    nodes = [
        (
            n.nodeid,
            n.x,
            n.y,
            n.frame_id,
            n.metadata,
            [(o.type, o.trigger, o.metadata) for o in n.operations],
        )
        for n in g.nodes
    ]
    edges = [
        (e.edgeid, e.start.nodeid, e.end.nodeid, e.cost, e.overridable, e.metadata,
         [(o.type, o.trigger, o.metadata) for o in e.operations])
        for e in g.edges()
    ]  # fmt: skip
    return nodes, edges


@pytest.mark.parametrize("name", ["sample_graph", "warehouse_graph", "small_office_graph"])
def test_a_nav2_graph_saves_and_loads_back_the_same(name: str, tmp_path: Path) -> None:
    first = load_graph(GRAPHS / f"{name}.geojson")
    again = load_graph(save_graph(first, tmp_path / "saved.geojson"))
    assert describe(again) == describe(first)
    # and what was written is Nav2's format: a FeatureCollection of Points and lines
    doc = json.loads((tmp_path / "saved.geojson").read_text())
    kinds = {f["geometry"]["type"] for f in doc["features"]}
    assert doc["type"] == "FeatureCollection" and kinds == {"Point", "MultiLineString"}


def test_nav2_sample_graph_keeps_its_metadata_and_operations() -> None:
    g = load_graph(GRAPHS / "sample_graph.geojson")
    assert len(g) == 9 and len(list(g.edges())) == 24
    node = g.node(0)
    assert node.metadata["region"]["properties"]["class_type"] == "living_room"
    assert node.metadata["region"]["x_values"] == [1.0, -1.0, -1.0, 1.0]
    [stop] = node.operations
    assert (stop.type, stop.trigger, stop.metadata) == (
        "stop",
        OperationTrigger.NODE,
        {"wait_for": 5.0},
    )
    edge = g.edge(9)
    assert (edge.start.nodeid, edge.end.nodeid, edge.cost, edge.overridable) == (0, 1, 10.0, False)
    assert edge.metadata == {"speed_limit": 0.85, "aisle_number": 14}
    ops = {o.type: o for o in edge.operations}
    assert ops["open_door"].trigger is OperationTrigger.ON_ENTER
    assert ops["open_door"].metadata["door_id"] == 54
    assert ops["take_picture"].metadata["resolution"] == [1080, 720]
    # edges without cost or overridable get Nav2's defaults
    other = g.edge(10)
    assert (other.cost, other.overridable) == (0.0, True)


def _write(tmp_path: Path, features: list) -> Path:
    path = tmp_path / "g.geojson"
    path.write_text(json.dumps({"type": "FeatureCollection", "features": features}))
    return path


def _node(i: int, x: float = 0.0) -> dict:
    return {
        "type": "Feature",
        "properties": {"id": i},
        "geometry": {"type": "Point", "coordinates": [x, 0.0]},
    }


def _edge(i: int, a: int, b: int, **extra: object) -> dict:
    return {
        "type": "Feature",
        "properties": {"id": i, "startid": a, "endid": b, **extra},
        "geometry": {"type": "LineString", "coordinates": []},
    }


def test_an_edge_to_a_missing_node_names_the_feature(tmp_path: Path) -> None:
    path = _write(tmp_path, [_node(0), _node(1, 1.0), _edge(5, 0, 7)])
    with pytest.raises(GraphError, match=r"features\[2\]: edge 5's endid 7 is not a node"):
        load_graph(path)


def test_a_wrong_trigger_lists_the_triggers(tmp_path: Path) -> None:
    ops = {"door": {"type": "door", "trigger": "ON_ARRIVAL"}}
    path = _write(tmp_path, [_node(0), _node(1, 1.0), _edge(5, 0, 1, operations=ops)])
    with pytest.raises(GraphError, match="triggers: NODE, ON_ENTER, ON_EXIT"):
        load_graph(path)


def test_broken_json_names_the_line_and_a_missing_file_the_path(tmp_path: Path) -> None:
    path = tmp_path / "g.geojson"
    path.write_text('{"type": "FeatureCollection",\n "features": [}\n')
    with pytest.raises(GraphError) as info:
        load_graph(path)
    assert info.value.line == 2
    with pytest.raises(GraphError, match="route graph file not found"):
        load_graph(tmp_path / "none.geojson")


def test_a_graph_without_edges_is_refused(tmp_path: Path) -> None:
    with pytest.raises(GraphError, match=r"1 nodes .* and 0 edges"):
        load_graph(_write(tmp_path, [_node(0)]))


def test_nav2s_share_folder_placeholder_finds_the_bundled_graphs(tmp_path) -> None:
    from btnav.params.loader import load_params_doc

    share = "$(find-pkg-share nav2_route)/graphs/sample_graph.geojson"
    doc = {"route_server": {"ros__parameters": {"graph_filepath": share}}}
    params = load_params_doc(doc, tmp_path / "params.yaml").server("route_server")
    path = Path(params.model.graph_filepath)
    assert path == GRAPHS / "sample_graph.geojson" and len(load_graph(path)) == 9
