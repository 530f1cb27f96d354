"""Nav2's node model (nav2_tree_nodes.xml) read for tests: ports per node ID, and stand-in nodes."""

from __future__ import annotations

import xml.etree.ElementTree as ET
from pathlib import Path
from typing import Any

from py_trees.common import Status
from py_trees.ports import PortInformation

from btnav.bt import ControlNode, DecoratorNode, LeafNode

PORT_TAGS = {
    "input_port": "in",
    "output_port": "out",
    "inout_port": "in",
    "bidirectional_port": "in",
}


def read_model(path: Path) -> dict[str, dict[str, Any]]:
    """`{ID: {"kind": "Action", "ports": {name: (direction, type, default or None)}}}`."""
    model = ET.parse(path).getroot().find("TreeNodesModel")
    assert model is not None
    out = {}
    for node in model:
        ports = {
            p.attrib["name"]: (PORT_TAGS[p.tag], p.attrib.get("type"), p.attrib.get("default"))
            for p in node
            if p.tag in PORT_TAGS
        }
        out[node.attrib["ID"]] = {"kind": node.tag, "ports": ports}
    return out


class _StubLeaf(LeafNode):
    def update(self) -> Status:
        return Status.SUCCESS


class _StubDecorator(DecoratorNode):
    def tick_decorated(self) -> Status:
        return self.tick_child()


class _StubControl(ControlNode):
    def tick_children(self) -> Status:
        return self.tick_child(self.children[0])


def stub_class(node_id: str, spec: dict[str, Any]) -> type:
    """A stand-in node with the model's port names (string-typed, optional)."""
    base = {"Decorator": _StubDecorator, "Control": _StubControl}.get(spec["kind"], _StubLeaf)
    inputs = {
        n: PortInformation(str, required=False) for n, p in spec["ports"].items() if p[0] == "in"
    }
    outputs = {
        n: PortInformation(str, required=False) for n, p in spec["ports"].items() if p[0] == "out"
    }
    return type(node_id, (base,), {"INPUT_PORTS": inputs, "OUTPUT_PORTS": outputs})
