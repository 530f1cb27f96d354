"""Nav2's route nodes: every one of Nav2's 15 trees is accepted now, ports are Nav2's, and
the leaves that need no server do what Nav2's do."""

from __future__ import annotations

import io
from pathlib import Path

import py_trees
from py_trees.common import Status

from btnav.bt import load_tree, unknown_nodes
from btnav.cli.tree import tree_show_main
from btnav.core.clock import SimClock
from btnav.core.error_codes import ComputeRouteError
from btnav.core.messages import PoseStamped
from btnav.core.nav2_route_msgs import Route, RouteNode
from btnav.plugins import lookup

from .nav2_model import read_model


def nav2_trees(nav2_dir: Path) -> list[Path]:
    return sorted(
        p for p in (nav2_dir / "behavior_trees").glob("*.xml") if p.name != "nav2_tree_nodes.xml"
    )


def test_tree_show_accepts_all_15_of_nav2s_trees(nav2_dir: Path) -> None:
    trees = nav2_trees(nav2_dir)
    assert len(trees) == 15
    for path in trees:
        assert unknown_nodes(path) == [], path.name
        out = io.StringIO()
        assert tree_show_main(str(path), out=out) == 0, path.name
        assert out.getvalue().startswith(f"{path}: main tree ")


def test_the_route_nodes_have_nav2s_ports(nav2_dir: Path) -> None:
    model = read_model(nav2_dir / "behavior_trees" / "nav2_tree_nodes.xml")
    for node_id in (
        "ComputeRoute",
        "ComputeAndTrackRoute",
        "CancelComputeAndTrackRoute",
        "ExtractRouteNodesAsGoals",
        "WouldARouteRecoveryHelp",
    ):
        cls = lookup("bt_node", node_id)
        ours = set(cls.INPUT_PORTS) | set(cls.OUTPUT_PORTS)
        assert set(model[node_id]["ports"]) <= ours, node_id


TREE = """
main_tree: T
trees:
  T:
    Sequence:
      children:
        - ExtractRouteNodesAsGoals: {route: "{route}", goals: "{goals}"}
        - WouldARouteRecoveryHelp: {error_code: "{code}"}
"""


def test_route_nodes_become_goals_and_route_errors_call_for_a_recovery() -> None:
    root = load_tree(TREE, clock=SimClock())
    bb = py_trees.blackboard.Blackboard
    bb.set("/route", Route(3.0, "map", 7.0, (RouteNode(4, 1.0, 2.0), RouteNode(9, 3.0, 2.0))))
    bb.set("/code", int(ComputeRouteError.NO_VALID_ROUTE))
    root.tick_once()
    assert root.status is Status.SUCCESS
    goals = bb.get("/goals")
    assert all(isinstance(g, PoseStamped) and g.frame_id == "map" for g in goals)
    assert [(g.pose.x, g.pose.y) for g in goals] == [(1.0, 2.0), (3.0, 2.0)]
    bb.set("/code", int(ComputeRouteError.TF_ERROR))  # a recovery would not help
    root.tick_once()
    assert root.status is Status.FAILURE
    bb.set("/route", Route())
    root.tick_once()
    assert root.status is Status.FAILURE  # no nodes: nothing to extract
