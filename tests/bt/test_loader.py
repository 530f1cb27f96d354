"""Loading trees: YAML and Nav2 XML build the same py_trees tree; errors name file, line, close names."""

from __future__ import annotations

import xml.etree.ElementTree as ET
from collections.abc import Iterator
from pathlib import Path
from typing import Any

import py_trees
import pytest
import yaml
from py_trees.common import Status

from btnav import plugins
from btnav.bt import (
    TreeError,
    UnknownNodeError,
    load_document,
    load_tree,
    node_types,
    tree_text,
    unknown_nodes,
)
from btnav.core.clock import SimClock

from .fakes import Ticker
from .nav2_model import read_model, stub_class

BRIEF_YAML = """\
main_tree: NavigateToPose
trees:
  NavigateToPose:
    RecoveryNode:
      name: NavigateRecovery
      number_of_retries: 6
      children:
        - PipelineSequence:
            children:
              - RateController:
                  hz: 1.0
                  child:
                    TestWrite: {value: planned, out: "{path}"}
              - SubTree: {ID: Follow, name: follow, path: "{path}"}
        - RoundRobin:
            name: RecoveryActions
            children:
              - TestScript: {name: ClearEntireCostmap}
              - Wait
              - TestScript: {script: R}
  Follow:
    ReactiveSequence:
      children:
        - Inverter: {child: AlwaysFailure}
        - TestWrite: {value: "{path}", out: "{followed}"}
"""

BRIEF_XML = """\
<root BTCPP_format="4" main_tree_to_execute="NavigateToPose">
  <BehaviorTree ID="NavigateToPose">
    <RecoveryNode name="NavigateRecovery" number_of_retries="6">
      <PipelineSequence>
        <RateController hz="1.0">
          <TestWrite value="planned" out="{path}"/>
        </RateController>
        <SubTree ID="Follow" name="follow" path="{path}"/>
      </PipelineSequence>
      <RoundRobin name="RecoveryActions">
        <TestScript name="ClearEntireCostmap"/>
        <Wait/>
        <TestScript script="R"/>
      </RoundRobin>
    </RecoveryNode>
  </BehaviorTree>
  <BehaviorTree ID="Follow">
    <ReactiveSequence>
      <Inverter><AlwaysFailure/></Inverter>
      <TestWrite value="{path}" out="{followed}"/>
    </ReactiveSequence>
  </BehaviorTree>
</root>
"""


@pytest.fixture
def wait_leaf() -> Iterator[None]:
    """A stand-in `Wait` leaf that succeeds at once (the real one needs a behavior server);
    btnav's own Wait is put back afterwards."""
    real = plugins.lookup("bt_node", "Wait")
    cls = stub_class(
        "Wait", {"kind": "Action", "ports": {"wait_duration": ("in", "double", "1.0")}}
    )
    plugins.register("bt_node", "Wait")(cls)
    yield
    plugins.unregister("bt_node", "Wait")
    plugins.register("bt_node", "Wait")(real)


def test_yaml_and_xml_build_identical_trees(wait_leaf: None) -> None:
    from_yaml = load_tree(BRIEF_YAML, clock=SimClock())
    from_xml = load_tree(BRIEF_XML, clock=SimClock())
    assert tree_text(from_yaml) == tree_text(from_xml)
    assert "follow.ReactiveSequence" in tree_text(from_xml)
    doc_y, doc_x = load_document(BRIEF_YAML), load_document(BRIEF_XML)
    assert ET.tostring(doc_y.root) == ET.tostring(
        ET.fromstring(ET.tostring(doc_x.root).replace(b"\n", b"").replace(b"  ", b""))
    )


def test_subtree_port_remapping_reaches_the_parent_blackboard(wait_leaf: None) -> None:
    root = load_tree(BRIEF_YAML, clock=SimClock())
    root.tick_once()
    assert root.status == Status.SUCCESS
    bb = py_trees.blackboard.Blackboard
    assert bb.get("/path") == "planned"
    assert bb.get("/follow/followed") == "planned"  # the subtree's own key, in its namespace


def test_files_load_by_path(tmp_path: Path, wait_leaf: None) -> None:
    (tmp_path / "t.yaml").write_text(BRIEF_YAML)
    (tmp_path / "t.xml").write_text(BRIEF_XML)
    a = load_tree(tmp_path / "t.yaml", clock=SimClock())
    b = load_tree(str(tmp_path / "t.xml"), clock=SimClock())
    assert tree_text(a) == tree_text(b)
    with pytest.raises(TreeError, match="not found"):
        load_tree(tmp_path / "missing.yaml")


def error_of(source: str) -> TreeError:
    with pytest.raises(TreeError) as info:
        load_tree(source, clock=SimClock())
    return info.value


def test_unknown_node_type_names_line_and_close_name(tmp_path: Path) -> None:
    path = tmp_path / "t.yaml"
    path.write_text("Sequence:\n  children:\n    - AlwaysSuccess\n    - TestScirpt: {script: S}\n")
    with pytest.raises(UnknownNodeError) as info:
        load_tree(path)
    err = info.value
    assert (err.file, err.line, err.suggestion) == (str(path), 4, "TestScript")
    assert "unknown node type 'TestScirpt'" in str(err)
    assert str(err).startswith(f"{path}:4: Sequence.children[1].TestScirpt: ")

    err = error_of(
        '<root main_tree_to_execute="A">\n  <BehaviorTree ID="A">\n    <Sequense>\n'
        "      <AlwaysSuccess/>\n    </Sequense>\n  </BehaviorTree>\n</root>\n"
    )
    assert isinstance(err, UnknownNodeError)
    assert (err.line, err.suggestion) == (3, "Sequence")


def test_unknown_port_missing_port_and_bad_values() -> None:
    err = error_of("RateController:\n  hzz: 1.0\n  child: AlwaysSuccess\n")
    assert (err.line, err.suggestion) == (2, "hz")
    assert "RateController has no port 'hzz'; its ports: hz" in str(err)

    err = error_of("Repeat: {child: AlwaysSuccess}")
    assert "needs its input port 'num_cycles'" in str(err)

    err = error_of("RateController:\n  child: AlwaysSuccess\n  hz: fast\n")
    assert err.line == 3 and "takes a float, not 'fast'" in str(err)

    err = error_of("TestWrite: {value: a, out: b}")
    assert "must name a blackboard entry" in str(err)

    err = error_of('TestWrite: {value: "{a}}", out: "{b}"}')
    assert "not a blackboard reference" in str(err)


def test_structure_errors() -> None:
    assert "takes exactly 1 child" in str(
        error_of("Inverter: {children: [AlwaysSuccess, AlwaysFailure]}")
    )
    assert "takes exactly 2 children" in str(error_of("RecoveryNode: {children: [AlwaysSuccess]}"))
    err = error_of("main_tree: A\ntrees:\n  A:\n    SubTree: {ID: Bee}\n  B: AlwaysSuccess\n")
    assert err.line == 4 and err.suggestion is None and "SubTree ID 'Bee'" in str(err)
    err = error_of("trees:\n  A: AlwaysSuccess\n  B: AlwaysSuccess\n")
    assert "main_tree" in str(err)
    err = error_of("main_tre: A\ntrees:\n  A: AlwaysSuccess\n")
    assert err.suggestion == "main_tree"
    err = error_of("Sequence:\n  children:\n    - Spin:\n      spin_dist: 1.0\n")
    assert "indent the ports" in str(err)
    err = error_of("main_tree: A\ntrees:\n  A: {SubTree: {ID: B}}\n  B: {SubTree: {ID: A}}\n")
    assert "SubTree cycle: A -> B -> A" in str(err)
    assert "invalid XML" in str(error_of("<root><BehaviorTree ID='A'><Sequence></root>"))


@pytest.mark.parametrize(
    "typed, hint",
    [
        ("navigate_w_replanning_time.json", "a tree file ends in .yaml, .yml, .xml"),
        ("navigate_w_replanning_time.yaml.bak", "a tree file ends in .yaml, .yml, .xml"),
        ("elsewhere/navigate_w_replanning_time.yaml", "no folder"),
        ("elsewhere/navigate_w_replanning_time.xml", "no folder"),
    ],
)
def test_a_bundled_trees_name_with_a_wrong_suffix_or_folder_is_not_suggested_back(
    typed: str, hint: str
) -> None:
    """`did you mean 'navigate_w_replanning_time'?` after typing that name reads as nonsense:
    the message says what to change instead."""
    from btnav.bt.bundled import find_tree

    with pytest.raises(UnknownNodeError) as info:
        find_tree(typed)
    err = info.value
    assert err.suggestion is None and "did you mean" not in str(err)
    assert err.message.endswith(
        "to use the bundled tree of that name, write its bare name "
        f"'navigate_w_replanning_time' ({hint})"
    )


def test_tree_suggestions_are_close_names_never_the_typed_one() -> None:
    from btnav.bt.bundled import find_tree

    with pytest.raises(UnknownNodeError) as info:
        find_tree("navigate_w_replanning_tim")
    assert info.value.suggestion == "navigate_w_replanning_time"
    with pytest.raises(UnknownNodeError) as info:
        find_tree("elsewhere/navigate_w_replaning_time.yaml")
    assert info.value.suggestion == "navigate_w_replanning_time"
    # Surrounding spaces (a quoted YAML value, a shell argument) do not hide a bundled name.
    assert find_tree(" navigate_w_replanning_time ").stem == "navigate_w_replanning_time"


def test_time_nodes_need_a_clock() -> None:
    root = load_tree("Delay: {delay_msec: 10, child: AlwaysSuccess}")
    with pytest.raises(RuntimeError, match="clock"):
        root.tick_once()
    t = Ticker("Delay: {delay_msec: 0, child: AlwaysSuccess}")
    assert t.tick() == Status.SUCCESS


# --- Nav2's own files -------------------------------------------------------------


def nav2_trees(nav2_dir: Path) -> list[Path]:
    return sorted(
        p for p in (nav2_dir / "behavior_trees").glob("*.xml") if p.name != "nav2_tree_nodes.xml"
    )


@pytest.fixture
def nav2_stubs(nav2_dir: Path) -> Iterator[dict[str, Any]]:
    """Stand-ins for every node of Nav2's model that btnav does not register yet."""
    model = read_model(nav2_dir / "behavior_trees" / "nav2_tree_nodes.xml")
    added = [i for i in model if i not in node_types()]
    for node_id in added:
        plugins.register("bt_node", node_id)(stub_class(node_id, model[node_id]))
    yield model
    for node_id in added:
        plugins.unregister("bt_node", node_id)


def test_every_nav2_tree_parses_and_names_its_unregistered_nodes(nav2_dir: Path) -> None:
    files = nav2_trees(nav2_dir)
    assert len(files) == 15
    for path in files:
        doc = load_document(path)
        assert doc.main_tree in doc.trees
        missing = unknown_nodes(path)
        if missing:
            with pytest.raises(UnknownNodeError) as info:
                load_tree(path, clock=SimClock())
            msg = str(info.value)
            assert str(path) in msg
            assert all(f"'{n}'" in msg or f" {n}" in msg for n in missing), msg
        else:
            load_tree(path, clock=SimClock())


def to_yaml(doc_root: ET.Element) -> str:
    """A Nav2 XML document in btnav's YAML spelling (test helper)."""

    def node(elem: ET.Element) -> dict[str, Any]:
        body: dict[str, Any] = dict(elem.attrib)
        kids = [node(c) for c in elem]
        if kids:
            body["children"] = kids
        return {elem.tag: body}

    trees = {bt.attrib["ID"]: node(bt[0]) for bt in doc_root.findall("BehaviorTree")}
    data = {"main_tree": doc_root.attrib["main_tree_to_execute"], "trees": trees}
    return yaml.safe_dump(data, sort_keys=False)


def test_every_nav2_tree_builds_with_nav2_nodes_standing_in(
    nav2_dir: Path, nav2_stubs: dict[str, Any]
) -> None:
    """With Nav2's leaves stubbed, py_trees' parser builds all 15 trees with btnav's
    controls, and each tree's YAML spelling builds the same tree."""
    for path in nav2_trees(nav2_dir):
        from_xml = load_tree(path, clock=SimClock())
        yaml_text = to_yaml(load_document(path).root)
        from_yaml = load_tree(yaml_text, clock=SimClock())
        assert tree_text(from_xml) == tree_text(from_yaml), path.name
        from_xml.tick_once()  # ports resolve: a first tick runs without error


def test_nav2_nodes_btnav_implements_have_nav2s_ports_and_defaults(nav2_dir: Path) -> None:
    model = read_model(nav2_dir / "behavior_trees" / "nav2_tree_nodes.xml")
    implemented = [i for i in model if i in node_types()]
    assert {"PipelineSequence", "RecoveryNode", "RoundRobin", "RateController"} <= set(implemented)
    for node_id in implemented:
        cls = node_types()[node_id]
        ports = {**cls.input_ports(), **cls.output_ports()}
        assert set(ports) == set(model[node_id]["ports"]), node_id
        for name, (_, _, default) in model[node_id]["ports"].items():
            if default is not None:
                declared = ports[name].default_value
                assert str(declared).lower() == default.strip('"').lower(), (node_id, name)
