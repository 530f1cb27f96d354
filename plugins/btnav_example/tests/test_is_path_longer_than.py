"""IsPathLongerThan in a tree: its ports, its default `{path}`, what it writes."""

from __future__ import annotations

import numpy as np
import pytest
from btnav.bt import load_tree, node_class
from btnav.bt.errors import TreeError
from btnav.core.messages import Path
from py_trees.blackboard import Blackboard
from py_trees.common import Status

from btnav_example.is_path_longer_than import IsPathLongerThan


def straight(length: float) -> Path:
    xs = np.linspace(0.0, length, 51)
    return Path(0.0, np.column_stack([xs, np.zeros_like(xs), np.zeros_like(xs)]), "map")


def tick(tree_yaml: str) -> Status:
    root = load_tree(tree_yaml)
    root.tick_once()
    return root.status


def test_it_is_a_registered_node_type():
    assert node_class("IsPathLongerThan") is IsPathLongerThan


@pytest.mark.parametrize(("length", "status"), [(12.0, Status.SUCCESS), (8.0, Status.FAILURE)])
def test_it_compares_the_path_with_the_length_port(length, status):
    Blackboard.set("/plan", straight(length))
    tree = "IsPathLongerThan: {path: '{plan}', length: 10.0, path_length: '{measured}'}"
    assert tick(tree) is status
    assert Blackboard.get("/measured") == pytest.approx(length)


def test_it_reads_path_from_the_blackboard_by_default():
    Blackboard.set("/path", straight(15.0))
    assert tick("IsPathLongerThan: {}") is Status.SUCCESS  # length defaults to 10 m


def test_no_path_is_failure():
    assert tick("IsPathLongerThan: {length: 1.0}") is Status.FAILURE
    Blackboard.set("/path", Path(0.0, np.zeros((0, 3)), "map"))
    assert tick("IsPathLongerThan: {length: 1.0}") is Status.FAILURE


def test_a_budget_guard_stops_following_a_path_that_is_too_long():
    """The pattern of trees/navigate_w_path_budget.yaml: Inverter over the node."""
    guard = "Inverter: {child: {IsPathLongerThan: {length: 10.0}}}"
    Blackboard.set("/path", straight(5.0))
    assert tick(guard) is Status.SUCCESS
    Blackboard.set("/path", straight(20.0))
    assert tick(guard) is Status.FAILURE


def test_a_misspelt_port_is_a_tree_error_with_the_right_spelling():
    with pytest.raises(TreeError) as info:
        load_tree("IsPathLongerThan: {lenght: 3.0}")
    assert info.value.suggestion == "length"
