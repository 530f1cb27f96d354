"""Fake tree leaves for BT semantics tests: scripted outcomes, halt counting, blackboard flags."""

from __future__ import annotations

from typing import Any, ClassVar

import py_trees
from py_trees.behaviour import Behaviour
from py_trees.common import Status
from py_trees.ports import PortInformation

from btnav.bt import LeafNode, load_tree
from btnav.core.clock import SimClock
from btnav.plugins import register

LETTERS = {"S": Status.SUCCESS, "F": Status.FAILURE, "R": Status.RUNNING}


@register("bt_node", "TestScript")
class Script(LeafNode):
    """Returns the next letter of `script` each tick (S, F, R; the last one repeats).

    Counts ticks, starts (initialise) and halts (stopped while RUNNING).
    """

    INPUT_PORTS: ClassVar = {"script": PortInformation(str, required=False, default_value="S")}

    def __init__(self, name: str, **kwargs: Any) -> None:
        super().__init__(name=name, **kwargs)
        self.ticks = 0
        self.starts = 0
        self.halts = 0

    def initialise(self) -> None:
        self.starts += 1

    def update(self) -> Status:
        script = self.get_input("script").replace(" ", "")
        letter = script[min(self.ticks, len(script) - 1)]
        self.ticks += 1
        return LETTERS[letter]

    def terminate(self, new_status: Status) -> None:
        if new_status == Status.INVALID and self.status == Status.RUNNING:
            self.halts += 1


@register("bt_node", "TestFlag")
class Flag(LeafNode):
    """A condition: SUCCESS while the boolean on `value` is true."""

    INPUT_PORTS: ClassVar = {"value": PortInformation(bool)}

    def __init__(self, name: str, **kwargs: Any) -> None:
        super().__init__(name=name, **kwargs)
        self.ticks = 0

    def update(self) -> Status:
        self.ticks += 1
        return Status.SUCCESS if self.get_input("value") else Status.FAILURE


@register("bt_node", "TestWrite")
class Write(LeafNode):
    """Writes its `value` input to its `out` output port."""

    INPUT_PORTS: ClassVar = {"value": PortInformation(str)}
    OUTPUT_PORTS: ClassVar = {"out": PortInformation(str, required=False)}

    def update(self) -> Status:
        self._set_output("out", self.get_input("value"))
        return Status.SUCCESS


def find(root: Behaviour, name: str) -> Any:
    """The node named `name` (py_trees prefixes names with their named parents)."""
    for node in root.iterate():
        if node.name == name or node.name.endswith("." + name):
            return node
    raise KeyError(f"no node '{name}' in {[n.name for n in root.iterate()]}")


def set_bb(key: str, value: Any) -> None:
    py_trees.blackboard.Blackboard.set("/" + key.strip("/"), value)


class Ticker:
    """A tree on a sim clock: `tick()` ticks once; `tick(dt=0.1)` advances time first."""

    def __init__(self, source: str, **kwargs: Any) -> None:
        self.clock = SimClock()
        self.root = load_tree(source, clock=self.clock, **kwargs)

    def tick(self, dt: float = 0.0) -> Status:
        if dt:
            self.clock.advance(dt)
        self.root.tick_once()
        return self.root.status

    def __getitem__(self, name: str) -> Any:
        return find(self.root, name)
