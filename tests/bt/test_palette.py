"""`btnav tree palette`: Groot2's node palette from the live registry, as Nav2 spells it.

What a Groot2 user relies on: every node btnav shares with Nav2 has Nav2's kind, port
names, directions, types and defaults; a tree drawn against the palette (every port
Groot pre-fills with its default) loads in btnav; a plugin's node is in it.
"""

from __future__ import annotations

import xml.etree.ElementTree as ET
from collections.abc import Iterator
from pathlib import Path
from typing import Any, ClassVar

import pytest
from py_trees.common import Status

from btnav import plugins
from btnav.bt import LeafNode, load_tree, node_types
from btnav.bt.base import input_port, output_port
from btnav.bt.palette import palette_models, palette_xml
from btnav.cli import main
from btnav.core.clock import SimClock
from btnav.core.errors import PluginError

#: Nav2's file spells BT.CPP's `inout_port` as `bidirectional_port`.
_DIRECTION = {
    "input_port": "input_port",
    "output_port": "output_port",
    "inout_port": "inout_port",
    "bidirectional_port": "inout_port",
}


def models_of(text: str) -> dict[str, ET.Element]:
    root = ET.fromstring(text.encode())
    assert root.tag == "root" and root.attrib["BTCPP_format"] == "4"
    model = root.find("TreeNodesModel")
    assert model is not None
    return {node.attrib["ID"]: node for node in model}


def ports_of(node: ET.Element) -> list[tuple[str, str, str | None]]:
    """(direction, name, type) of each port, in order."""
    return [(_DIRECTION[p.tag], p.attrib["name"], p.get("type")) for p in node]


def same_default(nav2: str, ours: str) -> bool:
    """Nav2 writes C++ literals (`"planner_selector"`, `numeric_limits<double>::infinity()`);
    the palette writes what a tree would: equal when they mean the same value."""
    nav2 = nav2.replace("numeric_limits<double>::infinity()", "inf")
    if len(nav2) >= 2 and nav2[0] == nav2[-1] == '"':
        return nav2[1:-1] == ours
    try:
        return float(nav2) == float(ours)  # 1 == 1.0, inf == inf
    except ValueError:
        return nav2.lower() == ours.lower()  # true / false


@pytest.fixture(scope="module")
def palette() -> dict[str, ET.Element]:
    return models_of(palette_xml())


@pytest.fixture(scope="module")
def nav2_models(nav2_dir: Path) -> dict[str, ET.Element]:
    return models_of((nav2_dir / "behavior_trees" / "nav2_tree_nodes.xml").read_text())


def test_every_node_btnav_shares_with_nav2_matches_nav2s_model(
    palette: dict[str, ET.Element], nav2_models: dict[str, ET.Element]
) -> None:
    shared = [i for i in nav2_models if i in palette]
    assert len(shared) >= 55, shared
    assert [i for i in nav2_models if i in node_types() and i not in palette] == []
    for node_id in shared:
        nav2, ours = nav2_models[node_id], palette[node_id]
        assert ours.tag == nav2.tag, node_id  # Action / Condition / Control / Decorator
        assert ports_of(ours) == ports_of(nav2), node_id  # names, directions, types, order
        for theirs, mine in zip(nav2, ours, strict=True):
            where = (node_id, theirs.attrib["name"])
            if theirs.get("default") is None:
                assert mine.get("default") is None, where
            else:
                assert mine.get("default") is not None, where
                assert same_default(theirs.attrib["default"], mine.attrib["default"]), where


def test_a_tree_drawn_against_the_palette_loads_beside_it(palette: dict[str, ET.Element]) -> None:
    """Every built-in node, each input port at the default Groot fills in, outputs on
    the blackboard, in one file with the palette: btnav validates and builds it."""
    types = node_types()
    root = ET.fromstring(palette_xml().encode())
    root.set("main_tree_to_execute", "Drawn")
    sequence = ET.SubElement(ET.SubElement(root, "BehaviorTree", {"ID": "Drawn"}), "Sequence")
    own = {i: m for i, m in palette.items() if types[i].__module__.startswith("btnav.")}
    for node_id, model in own.items():
        attrib = {}
        for port in model:
            name = port.attrib["name"]
            if port.tag == "output_port":
                attrib[name] = "{" + name + "}"
            elif "default" in port.attrib:
                attrib[name] = port.attrib["default"]
            elif types[node_id].input_ports()[name].required:
                attrib[name] = "1"
        elem = ET.SubElement(sequence, node_id, attrib)
        for _ in range(types[node_id].CHILDREN[0]):
            ET.SubElement(elem, "AlwaysSuccess")
    tree = load_tree(ET.tostring(root, encoding="unicode"), clock=SimClock())
    assert len(tree.children) == len(own) >= 75


def test_every_built_in_port_has_a_type_and_a_description(palette: dict[str, ET.Element]) -> None:
    types = node_types()
    for node_id, model in palette.items():
        if not types[node_id].__module__.startswith("btnav."):
            continue
        for port in model:
            assert port.get("type"), (node_id, port.attrib["name"])
            assert (port.text or "").strip(), (node_id, port.attrib["name"])


def test_kinds_aliases_and_order(palette: dict[str, ET.Element]) -> None:
    kinds = {i: e.tag for i, e in palette.items()}
    assert kinds["SequenceStar"] == kinds["SequenceWithMemory"] == "Control"  # an alias too
    assert kinds["AlwaysSuccess"] == "Action" and kinds["Inverter"] == "Decorator"
    assert kinds["GoalUpdated"] == "Condition" and kinds["PipelineSequence"] == "Control"
    order = ["Action", "Condition", "Control", "Decorator"]
    keys = [(order.index(e.tag), i) for i, e in palette.items()]
    assert keys == sorted(keys)
    assert palette_xml() == palette_xml()  # deterministic
    assert set(palette) == set(node_types())
    no_builtin = {m.id for m in palette_models(builtin=False)}
    assert "Sequence" not in no_builtin and "PipelineSequence" in no_builtin


class _Counter(LeafNode):
    """A user's node: a condition with an input (with a default) and outputs."""

    NODE_KIND: ClassVar[str] = "Condition"
    INPUT_PORTS: ClassVar = {"limit": input_port(int, "How far to count", 3)}
    OUTPUT_PORTS: ClassVar = {
        "count": output_port(list[int], "The counts so far"),
        "done": output_port(bool, "Whether the limit is reached"),
    }

    def update(self) -> Status:
        return Status.SUCCESS


@pytest.fixture
def user_node() -> Iterator[str]:
    plugins.register("bt_node", "TestPaletteCounter")(_Counter)
    try:
        yield "TestPaletteCounter"
    finally:
        plugins.unregister("bt_node", "TestPaletteCounter")


def test_a_registered_plugin_node_appears_with_its_ports(user_node: str) -> None:
    node = models_of(palette_xml())[user_node]
    assert node.tag == "Condition"
    ports = [(p.tag, p.attrib["name"], p.get("type"), p.get("default"), p.text) for p in node]
    assert ports == [
        ("input_port", "limit", "int", "3", "How far to count"),
        ("output_port", "count", "vector<int>", None, "The counts so far"),
        ("output_port", "done", "bool", None, "Whether the limit is reached"),
    ]


def test_a_leaf_with_an_unknown_kind_is_named(user_node: str, monkeypatch: Any) -> None:
    monkeypatch.setattr(_Counter, "NODE_KIND", "Condtion")
    with pytest.raises(PluginError, match=r"TestPaletteCounter.*did you mean 'Condition'"):
        palette_models()


# -- the command -------------------------------------------------------------------------


def test_the_command_writes_the_file_or_prints_it(tmp_path: Path, capsys: Any) -> None:
    out = tmp_path / "nodes.xml"
    assert main(["tree", "palette", "-o", str(out)]) == 0
    said = capsys.readouterr().out
    assert said.startswith(f"wrote {out}: {len(node_types())} node types (")
    assert main(["tree", "palette"]) == 0
    printed = capsys.readouterr().out
    assert printed == out.read_text(encoding="utf-8")
    assert printed.startswith('<?xml version="1.0"?>\n<!-- Groot2 palette of btnav')
    assert "ComputePathToPose" in models_of(printed)


def test_the_command_loads_a_plugin_file_and_can_leave_out_btcpps_nodes(
    tmp_path: Path, capsys: Any
) -> None:
    plugin = tmp_path / "my_nodes.py"
    plugin.write_text(
        "from typing import ClassVar\n"
        "from py_trees.common import Status\n"
        "from btnav.bt import LeafNode\n"
        "from btnav.bt.base import input_port\n"
        "from btnav.plugins import register\n\n\n"
        '@register("bt_node", "TestPaletteBeep")\n'
        "class Beep(LeafNode):\n"
        '    INPUT_PORTS: ClassVar = {"pitch": input_port(float, "Pitch (Hz)", 440.0)}\n'
        "    OUTPUT_PORTS: ClassVar = {}\n\n"
        "    def update(self) -> Status:\n"
        "        return Status.SUCCESS\n"
    )
    try:
        assert main(["tree", "palette", "--plugin", str(plugin), "--skip-builtin"]) == 0
    finally:
        plugins.unregister("bt_node", "TestPaletteBeep")
    models = models_of(capsys.readouterr().out)
    beep = models["TestPaletteBeep"]
    assert beep.tag == "Action"
    assert [(p.tag, p.attrib) for p in beep] == [
        ("input_port", {"name": "pitch", "type": "double", "default": "440.0"})
    ]
    assert "Sequence" not in models and "RecoveryNode" in models


def test_a_missing_plugin_file_is_a_user_error(tmp_path: Path, capsys: Any) -> None:
    assert main(["tree", "palette", "--plugin", str(tmp_path / "nope.py")]) == 2
    err = capsys.readouterr().err
    assert err.startswith("btnav: error: ") and "nope.py" in err and len(err.splitlines()) == 1
