"""btnav's tick engine: plain calls on py_trees' types, still usable with py_trees' own tools."""

from __future__ import annotations

from typing import Any

import py_trees
import pytest
from py_trees.common import Status
from py_trees.ports import NoDataAvailable

from btnav.bt import ControlNode, DecoratorNode, LeafNode
from btnav.bt.controls import Sequence

from .fakes import Ticker, find, set_bb

S, F, R, IDLE = Status.SUCCESS, Status.FAILURE, Status.RUNNING, Status.INVALID


def listen(root: Any) -> list[tuple[str, str, str]]:
    """Every status change of every node, as the tick log sees them: (node, old, new)."""
    changes: list[tuple[str, str, str]] = []
    for node in root.iterate():
        node.status_listener = lambda n, old, new: changes.append((n.name, old.name, new.name))
    return changes


def test_tick_once_is_one_plain_call_returning_nothing_and_status_is_an_attribute():
    t = Ticker("Sequence:\n  children:\n    - TestScript: {name: a, script: R S}\n")
    assert t.root.tick_once() is None and t.root.status is R
    assert t.root.execute_tick() is S and t.root.status is S
    assert "status" in vars(t.root)  # a plain attribute, not a property


def test_a_listener_sees_every_change_in_order_even_one_undone_within_the_tick():
    t = Ticker(
        "ReactiveFallback:\n  children:\n"
        "    - TestFlag: {name: c, value: '{done}'}\n"
        "    - TestScript: {name: work, script: R}\n"
    )
    set_bb("done", False)
    changes = listen(t.root)
    t.tick()
    assert changes == [
        ("c", "INVALID", "FAILURE"),
        ("work", "INVALID", "RUNNING"),
        ("c", "FAILURE", "INVALID"),  # only the RUNNING child stays non-idle
        ("ReactiveFallback", "INVALID", "RUNNING"),
    ]
    changes.clear()
    set_bb("done", True)
    t.tick()
    assert changes == [
        ("c", "INVALID", "SUCCESS"),
        ("c", "SUCCESS", "INVALID"),  # the fallback's halt returns its children to idle...
        ("work", "RUNNING", "INVALID"),  # ...and halts the one that ran
        ("ReactiveFallback", "RUNNING", "SUCCESS"),
    ]
    assert find(t.root, "work").halts == 1


def test_a_parallel_halt_stops_its_running_children_before_the_finished_ones():
    t = Ticker(
        "Parallel:\n  children:\n"
        "    - TestScript: {name: done, script: S}\n"
        "    - TestScript: {name: busy, script: R}\n"
    )
    assert t.tick() == R
    changes = listen(t.root)
    t.root.stop(IDLE)
    assert [c[0] for c in changes] == ["busy", "done", "Parallel"]


def test_py_trees_runner_and_visitors_see_the_nodes_the_tick_reached():
    t = Ticker(
        "Sequence:\n  children:\n"
        "    - TestScript: {name: a}\n"
        "    - TestScript: {name: b, script: R}\n"
        "    - TestScript: {name: c}\n"
    )
    tree = py_trees.trees.BehaviourTree(t.root)
    snapshot = py_trees.visitors.SnapshotVisitor()
    tree.visitors.append(snapshot)
    tree.tick()
    visited = {find(t.root, n).id: s for n, s in (("a", S), ("b", R), ("Sequence", R))}
    assert snapshot.visited == visited  # c was not reached
    assert [n.name for n in t.root.tick()] == ["b", "Sequence"]  # a is done: resumed at b
    assert "execute_tick" not in vars(find(t.root, "b"))  # the engine is as it was


def test_a_plain_py_trees_behaviour_can_be_a_child():
    seq = Sequence(
        "seq", children=[py_trees.behaviours.Success("ok"), py_trees.behaviours.Running("go")]
    )
    seq.tick_once()
    assert [c.status for c in seq.children] == [S, R] and seq.status is R
    seq.add_child(py_trees.behaviours.Failure("no"))
    assert seq.execute_tick() is R  # resumed at the running child


def test_children_changed_after_a_tick_are_the_ones_the_next_tick_reaches():
    # (a control ticks its children through their bound execute_tick, bound anew whenever
    # py_trees' methods change the children)
    seq = Sequence("seq", children=[py_trees.behaviours.Success("a")])
    assert seq.execute_tick() is S
    seq.add_child(py_trees.behaviours.Running("b"))
    assert seq.execute_tick() is R
    seq.replace_child(seq.children[1], py_trees.behaviours.Failure("c"))
    assert seq.execute_tick() is F
    seq.remove_child(seq.children[1])
    seq.insert_child(py_trees.behaviours.Running("d"), 0)
    assert seq.execute_tick() is R and seq.current_child.name == "d"
    seq.remove_all_children()
    seq.prepend_child(py_trees.behaviours.Success("e"))
    assert seq.execute_tick() is S and [c.name for c in seq.children] == ["e"]


def test_a_control_written_with_yield_is_refused_with_the_fix():
    with pytest.raises(TypeError, match="return the status instead"):

        class Old(ControlNode):  # the engine before issue 16
            def tick_children(self) -> Any:
                status = yield from self.tick_child(self.children[0])
                return status

    with pytest.raises(TypeError, match="tick_decorated is a generator"):

        class OldDecorator(DecoratorNode):
            def tick_decorated(self) -> Any:
                return (yield from self.tick_child())


def test_ports_are_bound_to_their_keys_so_a_new_value_is_read_on_the_next_tick():
    t = Ticker("TestWrite: {value: '{in}', out: '{out}'}\n")
    for value in ("a", "b"):
        set_bb("in", value)
        t.tick()
        assert py_trees.blackboard.Blackboard.get("/out") == value


def test_an_unset_port_is_none_through_optional_and_an_error_through_get_input():
    t = Ticker("TestFlag: {value: '{unset}'}\n")
    node = t.root
    assert node.optional("value") is None
    with pytest.raises(NoDataAvailable, match="unset"):
        node.get_input("value")
    set_bb("unset", "yes")  # the wrong type: py_trees' own check says so
    with pytest.raises(TypeError):
        node.get_input("value")


def test_with_the_activity_stream_on_py_trees_records_every_read_and_write():
    t = Ticker("TestWrite: {value: '{in}', out: '{out}'}\n")
    set_bb("in", "x")
    t.tick()  # a tick before the stream is switched on does not keep it off
    py_trees.blackboard.Blackboard.enable_activity_stream()
    try:
        t.tick()
        kinds = {
            (a.key, a.activity_type) for a in py_trees.blackboard.Blackboard.activity_stream.data
        }
    finally:
        py_trees.blackboard.Blackboard.disable_activity_stream()
    assert ("/in", "READ") in kinds and ("/out", "WRITE") in kinds


class _Greeter(LeafNode):
    INPUT_PORTS: dict = {}
    OUTPUT_PORTS: dict = {}

    def __init__(self, name: str) -> None:
        super().__init__(name=name)
        self.starts = 0
        self.ends: list[Status] = []

    def initialise(self) -> None:
        self.starts += 1

    def update(self) -> Status:
        return S

    def terminate(self, new_status: Status) -> None:
        self.ends.append(new_status)


def test_a_leafs_own_initialise_and_terminate_run_as_py_trees_runs_them():
    leaf = _Greeter("g")
    leaf.tick_once()
    leaf.tick_once()
    leaf.stop(IDLE)
    assert leaf.starts == 2 and leaf.ends == [S, S, IDLE]
