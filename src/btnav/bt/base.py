"""Base classes of btnav's tree nodes: py_trees behaviours with BT.CPP's tick and halt.

py_trees and BehaviorTree.CPP differ in a few places that Nav2's trees rely on;
these bases make btnav's nodes behave as BT.CPP's do:

* **Halt** is py_trees' `stop(Status.INVALID)`. As in BT.CPP's `haltChild`, a node's
  own halt logic (`reset_state`, e.g. RecoveryNode's retry count) runs only when it
  was RUNNING; stopping a node that already finished just returns it to idle. So a
  RoundRobin that succeeded keeps its place when its parent resets it.
* A control or decorator **keeps its state across ticks** and resets it only where
  BT.CPP does (on completion or halt), never in `initialise()` merely because the
  node was not RUNNING.
* **SKIPPED** (BT.CPP v4) has no py_trees status: a node that would return SKIPPED
  returns SUCCESS with `skipped = True`, and btnav's controls pass over such a child
  as BT.CPP's do.
* **Time** is sim time: nodes that wait read `clock.now` from the clock the loader
  injects (never the wall clock).
"""

from __future__ import annotations

from collections.abc import Generator, Sequence
from typing import Any, ClassVar

import py_trees
from py_trees.behaviour import Behaviour
from py_trees.common import Status
from py_trees.ports import PortInformation, PortsMixin

TickGen = Generator[Behaviour, None, Status]

#: Tolerance for comparing sim times (the clock counts integer nanoseconds).
TIME_EPS = 1e-9


def halt(node: Behaviour) -> None:
    """BT.CPP's haltChild/resetChild: halt a RUNNING node, return any node to idle."""
    if node.status != Status.INVALID:
        node.stop(Status.INVALID)


def is_skipped(node: Behaviour) -> bool:
    """Whether the node's last tick meant BT.CPP's SKIPPED."""
    return node.status == Status.SUCCESS and bool(getattr(node, "skipped", False))


class _BtNode(PortsMixin):
    """What every btnav node shares: ports, injected dependencies, sim time."""

    INPUT_PORTS: ClassVar[dict[str, PortInformation]] = {}
    OUTPUT_PORTS: ClassVar[dict[str, PortInformation]] = {}
    #: Keyword arguments the loader binds at build time (e.g. "clock").
    INJECT: ClassVar[tuple[str, ...]] = ()
    #: Ports whose unset value is a blackboard entry (BT.CPP's `InputPort("goal", "{goal}")`).
    DEFAULT_KEYS: ClassVar[dict[str, str]] = {}
    #: How many children the node takes: (min, max); max None = unbounded.
    CHILDREN: ClassVar[tuple[int, int | None]] = (0, 0)

    skipped: bool = False
    clock: Any = None

    def __init_subclass__(cls, *, register: bool = False, **kwargs: Any) -> None:
        # btnav's registry (the bt_node plugin kind) is the one that names node types;
        # py_trees' global auto-registry is left to the user's own classes.
        super().__init_subclass__(register=register, **kwargs)

    def port(self, name: str) -> Any:
        """The value of an input port (its declared default when unset)."""
        return self.get_input(name)

    def now(self) -> float:
        """Sim time in seconds, from the clock given to the loader."""
        if self.clock is None:
            raise RuntimeError(
                f"{type(self).__name__} '{self.name}' measures time and has no clock: "
                "load the tree with load_tree(..., clock=sim_clock)"
            )
        return float(self.clock.now)

    def reset_state(self) -> None:
        """BT.CPP's halt(): forget the node's own progress (indices, counters, timers)."""


class ControlNode(_BtNode, py_trees.composites.Composite):
    """A composite with BT.CPP semantics; subclasses write `tick_children()`."""

    CHILDREN: ClassVar[tuple[int, int | None]] = (1, None)
    #: For subclasses that are also py_trees Sequences/Selectors (so py_trees' displays
    #: draw them as such): whether the node resumes a RUNNING child in place.
    MEMORY: ClassVar[bool] = False

    def __init__(self, name: str, children: Sequence[Behaviour] | None = None, **kwargs: Any):
        if isinstance(self, (py_trees.composites.Sequence, py_trees.composites.Selector)):
            kwargs["memory"] = self.MEMORY
        if isinstance(self, py_trees.composites.Parallel):
            kwargs["policy"] = py_trees.common.ParallelPolicy.SuccessOnAll()
        super().__init__(name=name, children=children, **kwargs)
        self.reset_state()

    def tick(self) -> Generator[Behaviour, None, None]:
        if self.status != Status.RUNNING:
            self.initialise()
        self.skipped = False
        status = yield from self.tick_children()
        if status == Status.RUNNING:
            self.status = status
        else:
            self.stop(status)
        yield self

    def tick_children(self) -> TickGen:
        raise NotImplementedError
        yield  # pragma: no cover

    def tick_child(self, child: Behaviour) -> TickGen:
        """Tick one child (yielding what py_trees' visitors expect); its new status."""
        self.current_child = child
        yield from child.tick()
        return child.status

    def halt_child(self, index: int) -> None:
        halt(self.children[index])

    def halt_children(self, start: int = 0) -> None:
        for child in self.children[start:]:
            halt(child)

    def halt_others(self, index: int) -> None:
        """A reactive control's rule: only the child that is RUNNING now may stay so."""
        for i, child in enumerate(self.children):
            if i != index:
                halt(child)

    def halt_self(self) -> None:
        """What BT.CPP's tick calls `halt()` for: children back to idle, own state reset."""
        self.halt_children()
        self.reset_state()

    def stop(self, new_status: Status = Status.INVALID) -> None:
        if new_status == Status.INVALID and self.status == Status.RUNNING:
            self.reset_state()
        if new_status != Status.INVALID:
            for child in self.children:
                if child.status == Status.RUNNING:
                    child.stop(Status.INVALID)
        super().stop(new_status)


class DecoratorNode(_BtNode, py_trees.decorators.Decorator):
    """A decorator with BT.CPP semantics; subclasses write `tick_decorated()`.

    Unlike py_trees' decorators, a btnav decorator decides whether to tick its
    child at all (Delay, RateController and Timeout sometimes do not).
    """

    CHILDREN: ClassVar[tuple[int, int | None]] = (1, 1)

    def __init__(self, name: str, child: Behaviour, **kwargs: Any):
        super().__init__(name=name, child=child, **kwargs)
        self.reset_state()

    def tick(self) -> Generator[Behaviour, None, None]:
        if self.status != Status.RUNNING:
            self.initialise()
        self.skipped = False
        status = yield from self.tick_decorated()
        if status == Status.RUNNING:
            self.status = status
        else:
            self.stop(status)
        yield self

    def tick_decorated(self) -> TickGen:
        raise NotImplementedError
        yield  # pragma: no cover

    def tick_child(self) -> TickGen:
        yield from self.decorated.tick()
        return self.decorated.status

    def update(self) -> Status:  # unused: tick() does the work
        return self.status

    def stop(self, new_status: Status = Status.INVALID) -> None:
        if new_status == Status.INVALID and self.status == Status.RUNNING:
            self.reset_state()
        super().stop(new_status)


class LeafNode(_BtNode, Behaviour):
    """A leaf (action or condition) with ports; subclasses write `update()`."""

    def update(self) -> Status:
        raise NotImplementedError
