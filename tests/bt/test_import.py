"""Nav2 XML -> btnav YAML (`btnav tree import`): same trees, readable YAML, bundled trees in step."""

from __future__ import annotations

import io
import re
import xml.etree.ElementTree as ET
from collections.abc import Iterator
from pathlib import Path
from typing import Any

import pytest

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
from btnav.bt.bundled import (
    BTNAV_TREES,
    NAV2_COMMIT,
    bundled_trees,
    bundled_yaml,
    find_tree,
    nav2_tree_files,
    trees_dir,
)
from btnav.bt.document import TreeDocument, parse_xml_text
from btnav.bt.xml_to_yaml import import_xml
from btnav.bt.yaml_tree import yaml_to_document
from btnav.cli.tree import tree_import_main, tree_show_main
from btnav.core.clock import SimClock
from btnav.core.yaml_io import load_yaml_text
from btnav.core.yaml_io import to_plain as plain

from . import fakes  # noqa: F401  (registers TestScript, TestWrite)
from .nav2_model import read_model, stub_class


def nav2_files(nav2_dir: Path) -> list[Path]:
    files = nav2_tree_files(nav2_dir / "behavior_trees")
    assert len(files) == 15
    return files


def from_yaml(text: str) -> TreeDocument:
    return yaml_to_document(load_yaml_text(text))


def same_text(a: str, b: str) -> bool:
    """Attribute texts mean the same: equal, or equal numbers (`0.30` and `0.3`)."""
    if a == b:
        return True
    try:
        return float(a) == float(b)
    except ValueError:
        return False


def assert_same_element(a: ET.Element, b: ET.Element, where: str) -> None:
    assert a.tag == b.tag, where
    where = f"{where}/{a.tag}"
    assert a.attrib.keys() == b.attrib.keys(), where
    for key, value in a.attrib.items():
        assert same_text(value, b.attrib[key]), (where, key, value, b.attrib[key])
    assert len(a) == len(b), where
    for i, (ca, cb) in enumerate(zip(a, b, strict=True)):
        assert_same_element(ca, cb, f"{where}[{i}]")


def assert_same_trees(xml_doc: TreeDocument, yaml_doc: TreeDocument) -> None:
    assert yaml_doc.main_tree == xml_doc.main_tree
    assert list(yaml_doc.trees) == list(xml_doc.trees)
    for tree_id, bt in xml_doc.trees.items():
        assert_same_element(bt, yaml_doc.trees[tree_id], tree_id)


# --- every Nav2 tree --------------------------------------------------------------------


def test_every_nav2_tree_round_trips_to_the_same_element_tree(nav2_dir: Path) -> None:
    for path in nav2_files(nav2_dir):
        xml_doc = parse_xml_text(path.read_bytes(), path)
        text = import_xml(path.read_bytes(), path)
        assert_same_trees(xml_doc, from_yaml(text))
        assert "<" not in text.split("main_tree:")[1], path.name  # no XML left in the YAML


def test_values_are_typed_where_unambiguous(nav2_dir: Path) -> None:
    path = nav2_dir / "behavior_trees" / "odometry_calibration.xml"
    data = plain(load_yaml_text(import_xml(path.read_bytes(), path)))
    assert data["main_tree"] == "OdometryCalibration"
    repeat = data["trees"]["OdometryCalibration"]["Repeat"]
    assert repeat["num_cycles"] == 3
    square = repeat["child"]["Sequence"]
    assert square["name"] == "Drive in a square"
    drive, spin = square["children"][0]["DriveOnHeading"], square["children"][1]["Spin"]
    assert drive == {
        "dist_to_travel": 2.0,
        "speed": 0.2,
        "time_allowance": 12,
        "error_code_id": "{drive_on_heading_error_code}",
        "error_msg": "{drive_on_heading_error_msg}",
    }
    assert spin["spin_dist"] == 1.570796 and spin["is_recovery"] is False


def test_comments_are_kept(nav2_dir: Path) -> None:
    path = nav2_dir / "behavior_trees" / "navigate_on_route_graph_w_recovery.xml"
    text = import_xml(path.read_bytes(), path)
    lines = text.splitlines()
    assert (
        lines[0] == "# This Behavior Tree uses the route server to route the robot through a space"
    )
    i = lines.index("                                    # Compute the route")
    assert lines[i + 1].strip() == "- ComputeRoute:"
    # A comment sharing a line with an element goes above that element.
    j = next(k for k, ln in enumerate(lines) if "Base it on the complete connected" in ln)
    assert lines[j + 1].strip() == '- ValidatePath: {path: "{path}"}'


# --- the YAML's shape -------------------------------------------------------------------

SMALL_XML = """\
<!-- A small tree. -->
<root BTCPP_format="4" main_tree_to_execute="Main">
  <BehaviorTree ID="Main">
    <RecoveryNode number_of_retries="6" name="NavigateRecovery">
      <PipelineSequence>
        <RateController hz="1.0">
          <TestWrite value="planned" out="{path}"/>
        </RateController>
        <!-- follow it -->
        <SubTree ID="Follow" path="{path}" name="follow"/>
      </PipelineSequence>
      <RoundRobin name="RecoveryActions">
        <Inverter><AlwaysFailure/></Inverter>
        <TestScript script="1.10" name="a name that is long enough to need a line of its own"/>
        <BackUp backup_dist="0.30" speed="1.10" yes="yes" empty="" colon="a: b" hash="#x"/>
      </RoundRobin>
    </RecoveryNode>
  </BehaviorTree>
  <BehaviorTree ID="Follow">
    <AlwaysSuccess/>
  </BehaviorTree>
  <TreeNodesModel><Action ID="BackUp"/></TreeNodesModel>
</root>
"""

SMALL_YAML = """\
# Imported.
#
# A small tree.

main_tree: Main
trees:
  Main:
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
              # follow it
              - SubTree: {ID: Follow, name: follow, path: "{path}"}
        - RoundRobin:
            name: RecoveryActions
            children:
              - Inverter: {child: AlwaysFailure}
              - TestScript:
                  name: a name that is long enough to need a line of its own
                  script: "1.10"
              - BackUp:
                  backup_dist: 0.30
                  speed: 1.10
                  "yes": "yes"
                  empty: ""
                  colon: "a: b"
                  hash: "#x"

  Follow: AlwaysSuccess
"""


def test_small_tree_reads_as_the_brief_writes_it() -> None:
    text = import_xml(SMALL_XML, header=["Imported."])
    assert text == SMALL_YAML
    assert_same_trees(parse_xml_text(SMALL_XML), from_yaml(text))
    # `script` is a string port of a registered node, so "1.10" stays text; BackUp's
    # `speed` is not known to btnav here, so 1.10 is a number (the same number).
    back = from_yaml(text)
    leaves = {e.tag: e.attrib for e in back.root.iter()}
    assert leaves["TestScript"]["script"] == "1.10"
    assert leaves["BackUp"]["speed"] == "1.1"


def test_without_a_registry_the_trees_are_the_same() -> None:
    text = import_xml(SMALL_XML, types={})
    assert "script: 1.10" in text
    assert_same_trees(parse_xml_text(SMALL_XML), from_yaml(text))


def test_bare_tree_and_single_tree_files() -> None:
    text = import_xml('<BehaviorTree ID="T"><Sequence><AlwaysSuccess/></Sequence></BehaviorTree>')
    assert text == "main_tree: T\ntrees:\n  T:\n    Sequence: {children: [AlwaysSuccess]}\n"
    text = import_xml('<root><BehaviorTree ID="Only"><AlwaysSuccess/></BehaviorTree></root>')
    assert text == "main_tree: Only\ntrees:\n  Only: AlwaysSuccess\n"


def test_odd_text_and_comments_round_trip() -> None:
    xml = (
        "<!-- lead -->\n"
        '<BehaviorTree ID="T"><Sequence name="Grüße 1">\n'
        '<TestScript script="a&#10;b\u2028c\x85d" name="1"/><!-- trailing -->\n'
        "<!-- before\n     ok --><AlwaysSuccess/>\n"
        "</Sequence></BehaviorTree>"
    )
    text = import_xml(xml)
    assert text == (
        "# lead\n\nmain_tree: T\ntrees:\n  T:\n    Sequence:\n      name: Grüße 1\n"
        "      children:\n        # trailing\n"
        '        - TestScript: {name: "1", script: "a\\nb\\u2028c\\u0085d"}\n'
        "        # before\n        #     ok\n        - AlwaysSuccess\n"
    )
    assert_same_trees(parse_xml_text(xml), from_yaml(text))


@pytest.mark.parametrize(
    ("xml", "message"),
    [
        (
            '<root><BehaviorTree ID="A"><AlwaysSuccess/></BehaviorTree>'
            '<BehaviorTree ID="B"><AlwaysSuccess/></BehaviorTree></root>',
            "several trees (A, B) and no main_tree_to_execute",
        ),
        (
            '<root main_tree_to_execute="A">\n<include path="other.xml"/>\n'
            '<BehaviorTree ID="A"><AlwaysSuccess/></BehaviorTree></root>',
            "btnav's YAML has no include",
        ),
        (
            '<root><BehaviorTree ID="A"><Sequence children="3"><AlwaysSuccess/></Sequence>'
            "</BehaviorTree></root>",
            "an attribute 'children'",
        ),
        ("<root><TreeNodesModel/></root>", "no <BehaviorTree>"),
        ('<root><BehaviorTree ID="A"/></root>', "exactly one root node"),
        ("<root><BehaviorTree ID='A'><Sequence></root>", "invalid XML"),
    ],
)
def test_what_yaml_cannot_hold_is_an_error(xml: str, message: str) -> None:
    with pytest.raises(TreeError, match=re.escape(message)):
        import_xml(xml, "t.xml")


# --- trees/ -----------------------------------------------------------------------------


def test_bundled_trees_are_the_importers_output(nav2_dir: Path) -> None:
    """trees/*.yaml are exactly what the importer makes of Nav2's files (regenerate with
    `python -m btnav.bt.bundled ../shared/nav2/behavior_trees`)."""
    files = nav2_files(nav2_dir)
    nav2_made = sorted(set(bundled_trees()) - set(BTNAV_TREES))
    assert nav2_made == sorted(p.stem for p in files)
    for path in files:
        bundled = trees_dir() / f"{path.stem}.yaml"
        text = bundled.read_text(encoding="utf-8")
        assert text == bundled_yaml(path), f"{bundled} is stale: regenerate it"
        head = text.split("\nmain_tree:")[0]
        assert path.name in head and NAV2_COMMIT in head and "Apache License 2.0" in head


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


def test_bundled_trees_build_the_same_tree_as_nav2s_xml(
    nav2_dir: Path, nav2_stubs: dict[str, Any]
) -> None:
    for path in nav2_files(nav2_dir):
        from_xml = load_tree(path, clock=SimClock())
        from_bundle = load_tree(find_tree(path.stem), clock=SimClock())
        assert tree_text(from_xml) == tree_text(from_bundle), path.name


def test_find_tree_by_path_bare_name_nav2_name_and_alias(tmp_path: Path) -> None:
    bundled = trees_dir() / "navigate_to_pose_w_replanning_and_recovery.yaml"
    assert find_tree("navigate_to_pose_w_replanning_and_recovery") == bundled
    assert find_tree("navigate_to_pose_w_replanning_and_recovery.xml") == bundled
    assert find_tree("navigate_w_replanning_and_recovery") == bundled
    own = tmp_path / "navigate_to_pose_w_replanning_and_recovery.xml"
    own.write_text("<root/>")
    assert find_tree(own) == own  # an existing file wins over the bundled name
    assert find_tree(own.name, base_dir=tmp_path) == own
    with pytest.raises(UnknownNodeError) as info:
        find_tree("navigate_to_pose_w_replaning_and_recovery")
    assert info.value.suggestion == "navigate_to_pose_w_replanning_and_recovery"
    assert "bundled trees: explore, follow_point" in str(info.value)
    with pytest.raises(UnknownNodeError, match=re.escape("no tree file 'missing/t.yaml'")):
        find_tree("missing/t.yaml")


# --- tree import / tree show ------------------------------------------------------------


def test_tree_import_prints_or_writes(nav2_dir: Path, tmp_path: Path) -> None:
    src = nav2_dir / "behavior_trees" / "navigate_w_replanning_time.xml"
    out, err = io.StringIO(), io.StringIO()
    assert tree_import_main(src, out=out, err=err) == 0
    text = out.getvalue()
    assert text.startswith("# Imported from navigate_w_replanning_time.xml by `btnav tree import`.")
    assert_same_trees(load_document(src), from_yaml(text))
    missing = unknown_nodes(src)
    assert ("note: btnav has no node types" in err.getvalue()) == bool(missing)

    dst = tmp_path / "t.yaml"
    out = io.StringIO()
    assert tree_import_main(src, dst, out=out, err=io.StringIO()) == 0
    assert dst.read_text() == text
    assert out.getvalue().startswith(f"wrote {dst}: main tree NavigateWithReplanningTime")

    with pytest.raises(TreeError, match="YAML already"):
        tree_import_main(dst)
    with pytest.raises(TreeError, match="not found"):
        tree_import_main(tmp_path / "missing.xml")


def test_tree_show_with_unregistered_nodes_lists_them(tmp_path: Path) -> None:
    path = tmp_path / "t.yaml"
    path.write_text(
        "main_tree: A\ntrees:\n  A:\n    PipelineSequence:\n      name: Go\n      children:\n"
        "        - RateController: {hz: 1.0, child: NotANode}\n"
        '        - AlsoNotANode: {path: "{path}", label: two words}\n'
        "        - SubTree: {ID: B}\n"
        "  B: AlwaysSuccess\n"
    )
    out = io.StringIO()
    with pytest.raises(UnknownNodeError, match="unknown node type 'NotANode'"):
        tree_show_main(path, out=out)  # shown as written, then the error `btnav run` gives
    assert out.getvalue().splitlines() == [
        f"{path}: main tree A",
        "tree A (main):",
        "    [+] Go <PipelineSequence>",
        "        -^- RateController  hz=1.0",
        "            ??? NotANode*",
        '        ??? AlsoNotANode*  path={path} label="two words"',
        "        >>> SubTree B",
        "",
        "tree B:",
        "    --> AlwaysSuccess",
    ]


def test_tree_show_finds_bundled_trees_by_nav2_name(capsys: pytest.CaptureFixture[str]) -> None:
    assert tree_show_main("navigate_w_replanning_time.xml") == 0
    shown = capsys.readouterr().out
    path = trees_dir() / "navigate_w_replanning_time.yaml"
    assert shown.startswith(f"{path}: main tree NavigateWithReplanningTime\n")
    assert "RateController" in shown and "hz=1.0" in shown
    missing = unknown_nodes(path)
    if missing:  # until btnav has all of Nav2's nodes
        assert shown.rstrip().endswith(", ".join(missing))
    else:
        assert "goal={goal} path={path}" in shown


def test_tree_show_prints_py_trees_display_with_ports(tmp_path: Path) -> None:
    path = tmp_path / "t.yaml"
    path.write_text(
        "main_tree: A\ntrees:\n  A:\n    RecoveryNode:\n      name: Recover\n"
        "      number_of_retries: 2\n      children:\n"
        "        - RateController: {hz: 2.0, child: AlwaysSuccess}\n"
        '        - SubTree: {ID: B, name: b, out: "{x}"}\n'
        '  B:\n    TestWrite: {value: "hello world", out: "{out}"}\n'
    )
    out = io.StringIO()
    assert tree_show_main(path, out=out) == 0
    lines = out.getvalue().splitlines()
    assert lines[0] == f"{path}: main tree A"
    assert lines[1:] == [
        "[o] Recover  <RecoveryNode>  number_of_retries=2",
        "    -^- Recover.RateController  hz=2.0",
        "        --> Recover.AlwaysSuccess",
        '    --> Recover.b.TestWrite  [SubTree B out={x}]  value="hello world" out={out}',
    ]


def test_tree_show_errors_are_user_errors(tmp_path: Path) -> None:
    with pytest.raises(UnknownNodeError):
        tree_show_main("no_such_tree")
    path = tmp_path / "t.yaml"
    path.write_text("RateController:\n  hzz: 1.0\n  child: AlwaysSuccess\n")
    with pytest.raises(TreeError) as info:
        tree_show_main(path)
    assert info.value.line == 2 and info.value.suggestion == "hz"
