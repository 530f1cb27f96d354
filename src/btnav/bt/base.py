"""btnav's tick engine: BehaviorTree.CPP's semantics as plain calls, on py_trees' types.

Where py_trees ends and btnav begins:

* **py_trees gives the types and the tools**: every node is a py_trees `Behaviour`
  (a `Composite`, a `Decorator` or a leaf) with py_trees' `Status`, `name`, `children`,
  `parent`, `initialise`/`update`/`terminate` hooks and `stop()`; its ports are
  `PortsMixin` declarations (see `ports`); trees are built by py_trees' XML parser and
  drawn, iterated, visited and snapshotted by py_trees' display, visitors and
  `BehaviourTree`.
* **btnav ticks them**: a node's tick is one plain call, `execute_tick() -> Status`
  (BT.CPP's `executeTick`), with no generators on the way down; `status` is a plain
  attribute; ports are bound to their blackboard keys when the tree is built (the
  nodes of every steady tick of Nav2's trees, the selectors, RecoveryNode and
  FollowPath, read and write those keys themselves where that is exactly what
  py_trees' `get_input`/`_set_output` would do, and call them otherwise).
  `tick_once()` runs `execute_tick()`. The built-in controls and decorators call their
  children through `child_ticks`, the children's `execute_tick`s bound once (a call
  site that meets many classes is never specialised). py_trees' generator `tick()`
  still works (for `py_trees.trees.BehaviourTree` and its visitors): it runs the same
  plain tick, then yields the nodes it ticked in the order py_trees would.

The semantics are BT.CPP's where Nav2's trees rely on them:

* **Halt** is `stop(Status.INVALID)`. As in BT.CPP's `haltChild`, a node's own halt
  logic (`reset_state`, e.g. RecoveryNode's retry count) runs only when it was
  RUNNING; stopping a node that already finished just returns it to idle. So a
  RoundRobin that succeeded keeps its place when its parent resets it.
* A control or decorator **keeps its state across ticks** and resets it only where
  BT.CPP does (on completion or halt), never because the node was not RUNNING.
* **SKIPPED** (BT.CPP v4) has no py_trees status: a node that would return SKIPPED
  returns SUCCESS with `skipped = True`, and btnav's controls pass over such a child.
* **Time** is sim time: nodes that wait read `clock.now` from the clock the loader
  injects (never the wall clock).

A control writes `tick_children() -> Status` and a decorator `tick_decorated() ->
Status`, calling `self.tick_child(...)` (which returns the child's new status); a leaf
writes `update()` as in py_trees.
"""

from __future__ import annotations

import functools
import inspect
from collections.abc import Callable, Iterator, Sequence
from typing import Any, ClassVar

import py_trees
import py_trees.logging as _pt_logging
from py_trees.behaviour import Behaviour
from py_trees.common import Status

from .ports import BoundPortsMixin, PortInformation, input_port, output_port

__all__ = [
    "TIME_EPS",
    "ControlNode",
    "DecoratorNode",
    "F",
    "LeafNode",
    "R",
    "S",
    "halt",
    "input_port",
    "is_skipped",
    "output_port",
]

_STATUSES = frozenset(Status)
_INFO = _pt_logging.Level.INFO
_INVALID = Status.INVALID

#: Tolerance for comparing sim times (the clock counts integer nanoseconds).
TIME_EPS = 1e-9

#: BT.CPP's NodeStatus, as every node file spells them.
S, F, R = Status.SUCCESS, Status.FAILURE, Status.RUNNING


def halt(node: Behaviour) -> None:
    """BT.CPP's haltChild/resetChild: halt a RUNNING node, return any node to idle."""
    if node.status is not _INVALID:
        node.stop(_INVALID)


def is_skipped(node: Behaviour) -> bool:
    """Whether the node's last tick meant BT.CPP's SKIPPED."""
    return node.status is S and bool(getattr(node, "skipped", False))


def _tick_foreign(node: Behaviour) -> Status:
    """A plain py_trees behaviour (not a btnav node) ticked through its own generator."""
    for _ in node.tick():
        pass
    return node.status


def adopt(child: Behaviour) -> None:
    """Give a plain py_trees child the `execute_tick()` btnav's parents call."""
    if not hasattr(child, "execute_tick"):
        child.execute_tick = functools.partial(_tick_foreign, child)  # type: ignore[attr-defined]


def _recording(tick: Callable[[], Status], node: Behaviour, out: list[Behaviour]) -> Any:
    def record() -> Status:
        status = tick()
        out.append(node)
        return status

    return record


class _BtNode(BoundPortsMixin):
    """What every btnav node shares: the tick protocol, ports, injected dependencies, sim time."""

    INPUT_PORTS: ClassVar[dict[str, PortInformation]] = {}
    OUTPUT_PORTS: ClassVar[dict[str, PortInformation]] = {}
    #: Keyword arguments the loader binds at build time (e.g. "clock").
    INJECT: ClassVar[tuple[str, ...]] = ()
    #: Ports whose unset value is a blackboard entry (BT.CPP's `InputPort("goal", "{goal}")`).
    DEFAULT_KEYS: ClassVar[dict[str, str]] = {}
    #: How many children the node takes: (min, max); max None = unbounded.
    CHILDREN: ClassVar[tuple[int, int | None]] = (0, 0)

    #: Set by py_trees' `Behaviour.__init__`; no class-level default, on purpose: CPython
    #: 3.11 will not specialise an attribute read whose class attribute is an instance of
    #: a mutable class (an Enum member is), and `status` is read at every node of a tick.
    status: Status
    skipped: bool = False
    _INITIALISES: ClassVar[bool] = False
    _TERMINATES: ClassVar[bool] = False
    _OWN_STOP: ClassVar[bool] = False
    #: None of the three above: a tick that changes no status calls nothing but the node's own.
    _HOOKLESS: ClassVar[bool] = True
    clock: Any = None
    #: Called as `status_listener(node, old, new)` on every change of this node's status,
    #: even one undone within the same tick (a tick log sets it; None: nobody listens).
    status_listener: Callable[[Any, Status, Status], None] | None = None

    def __init__(self, *args: Any, **kwargs: Any) -> None:
        # An instance's attribute values are stored in the order they were first set on
        # its class: what a tick reads, set before py_trees' own, shares a cache line
        # (subclasses set their own tick state before calling this).
        self.status = _INVALID
        super().__init__(*args, **kwargs)

    def __init_subclass__(cls, *, register: bool = False, **kwargs: Any) -> None:
        # btnav's registry (the bt_node plugin kind) is the one that names node types;
        # py_trees' global auto-registry is left to the user's own classes.
        super().__init_subclass__(register=register, **kwargs)
        # py_trees' hooks are called only where a class has them (most nodes do not):
        cls._INITIALISES = cls.initialise is not Behaviour.initialise
        cls._TERMINATES = cls.terminate is not Behaviour.terminate
        cls._OWN_STOP = cls.stop is not _BtNode.stop
        cls._HOOKLESS = not (cls._INITIALISES or cls._TERMINATES or cls._OWN_STOP)
        for hook in ("tick_children", "tick_decorated"):
            if inspect.isgeneratorfunction(cls.__dict__.get(hook)):
                raise TypeError(
                    f"{cls.__name__}.{hook} is a generator: btnav ticks with plain calls; "
                    f"return the status instead (`status = self.tick_child(...)`, no yield)"
                )

    # -- the tick ---------------------------------------------------------------------------

    def execute_tick(self) -> Status:
        """BT.CPP's `executeTick`: tick this node once; its new status."""
        raise NotImplementedError

    def set_status(self, new: Status) -> None:
        """Every status change goes through here, so a tick log sees each one."""
        old = self.status
        self.status = new
        if new is not old and self.status_listener is not None:
            self.status_listener(self, old, new)

    def tick_once(self) -> None:
        """py_trees' `tick_once`, without generators."""
        self.execute_tick()

    def tick(self) -> Iterator[Behaviour]:
        """py_trees' generator tick, for `py_trees.trees.BehaviourTree` and its visitors: the
        plain tick runs, then each node it ticked is yielded, after its own tick, in the
        order py_trees yields them (visitors see the statuses the tick ended with)."""
        ticked: list[Behaviour] = []
        nodes = list(self.iterate())
        saved = [node.__dict__.get("execute_tick") for node in nodes]
        for node in nodes:
            node.execute_tick = _recording(node.execute_tick, node, ticked)  # type: ignore[attr-defined]
            unbind_child_ticks(node)
        try:
            self.tick_once()
        finally:
            for node, before in zip(nodes, saved, strict=True):
                if before is None:
                    del node.execute_tick  # type: ignore[attr-defined]
                else:
                    node.execute_tick = before  # type: ignore[attr-defined]
                unbind_child_ticks(node)
        yield from ticked

    def stop(self, new_status: Status = _INVALID) -> None:
        """py_trees' `stop`: `terminate`, then the new status (a halt with INVALID)."""
        if _pt_logging.level < _INFO:
            self.logger.debug(f"{type(self).__name__}.stop({self.status}->{new_status})")
        if self._TERMINATES:
            self.terminate(new_status)
        if new_status is not self.status:
            self.set_status(new_status)

    # -- state and time ---------------------------------------------------------------------

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

    # -- the children's ticks, bound ----------------------------------------------------------

    #: The children's `execute_tick`s, bound on a parent's first tick and unbound when its
    #: children change: a call through `child.execute_tick()` is a generic lookup (the
    #: children's classes differ), a call through this tuple is not.
    child_ticks: tuple[Callable[[], Status], ...] | None

    def bind_child_ticks(self) -> tuple[Callable[[], Status], ...]:
        ticks = self.child_ticks = tuple(child.execute_tick for child in self.children)
        return ticks


def unbind_child_ticks(node: Behaviour) -> None:
    """Forget the bound ticks of `node`'s children (after any change to them)."""
    if getattr(node, "child_ticks", None) is not None:
        node.child_ticks = None  # type: ignore[attr-defined]


class ControlNode(_BtNode, py_trees.composites.Composite):
    """A composite with BT.CPP semantics; subclasses write `tick_children() -> Status`."""

    CHILDREN: ClassVar[tuple[int, int | None]] = (1, None)
    #: For subclasses that are also py_trees Sequences/Selectors (so py_trees' displays
    #: draw them as such): whether the node resumes a RUNNING child in place.
    MEMORY: ClassVar[bool] = False

    def __init__(self, name: str, children: Sequence[Behaviour] | None = None, **kwargs: Any):
        if isinstance(self, (py_trees.composites.Sequence, py_trees.composites.Selector)):
            kwargs["memory"] = self.MEMORY
        if isinstance(self, py_trees.composites.Parallel):
            kwargs["policy"] = py_trees.common.ParallelPolicy.SuccessOnAll()
        self.child_ticks = None
        self.skipped = False
        self.current_child = None
        super().__init__(name=name, children=children, **kwargs)
        self.reset_state()

    # py_trees changes children through these five (and methods that call them): a plain
    # py_trees child is adopted, and the bound ticks are bound anew on the next tick.
    def add_child(self, child: Behaviour) -> Any:
        adopt(child)
        self.child_ticks = None
        return super().add_child(child)

    def insert_child(self, child: Behaviour, index: int) -> Any:
        adopt(child)
        self.child_ticks = None
        return super().insert_child(child, index)

    def prepend_child(self, child: Behaviour) -> Any:
        adopt(child)
        self.child_ticks = None
        return super().prepend_child(child)

    def remove_child(self, child: Behaviour) -> int:
        self.child_ticks = None
        return super().remove_child(child)

    def remove_all_children(self) -> None:
        self.child_ticks = None
        super().remove_all_children()

    def execute_tick(self) -> Status:
        if self.status is not R and self._INITIALISES:
            self.initialise()
        self.skipped = False
        status = self.tick_children()
        if status is not R:
            self.stop(status)
        elif self.status is not R:
            self.set_status(R)
        return status

    def tick_children(self) -> Status:
        raise NotImplementedError

    def tick_child(self, child: Behaviour) -> Status:
        """Tick one child; its new status."""
        self.current_child = child
        return child.execute_tick()  # type: ignore[attr-defined]

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

    def stop(self, new_status: Status = _INVALID) -> None:
        """py_trees' Composite.stop with BT.CPP's halt: a halt (INVALID) resets a RUNNING
        node's state and returns every child to idle; a result stops RUNNING children."""
        if new_status is _INVALID:
            if self.status is R:
                self.reset_state()
            self.current_child = None
            for child in self.children:
                if child.status is not _INVALID:
                    child.stop(_INVALID)
        else:
            for child in self.children:
                if child.status is R:
                    child.stop(_INVALID)
        if self._TERMINATES:
            self.terminate(new_status)
        if new_status is not self.status:
            self.set_status(new_status)


class DecoratorNode(_BtNode, py_trees.decorators.Decorator):
    """A decorator with BT.CPP semantics; subclasses write `tick_decorated() -> Status`.

    Unlike py_trees' decorators, a btnav decorator decides whether to tick its
    child at all (Delay, RateController and Timeout sometimes do not).
    """

    CHILDREN: ClassVar[tuple[int, int | None]] = (1, 1)

    def __init__(self, name: str, child: Behaviour, **kwargs: Any):
        adopt(child)
        self.child_ticks = None
        self.skipped = False
        super().__init__(name=name, child=child, **kwargs)
        self.reset_state()

    def execute_tick(self) -> Status:
        if self.status is not R and self._INITIALISES:
            self.initialise()
        self.skipped = False
        status = self.tick_decorated()
        if status is not R:
            self.stop(status)
        elif self.status is not R:
            self.set_status(R)
        return status

    def tick_decorated(self) -> Status:
        raise NotImplementedError

    def tick_child(self) -> Status:
        """Tick the decorated child; its new status."""
        ticks = self.child_ticks
        if ticks is None:
            ticks = self.bind_child_ticks()
        return ticks[0]()

    def update(self) -> Status:  # unused: execute_tick() does the work
        return self.status

    def stop(self, new_status: Status = _INVALID) -> None:
        """py_trees' Decorator.stop with BT.CPP's halt (a RUNNING node's state is reset)."""
        if new_status is _INVALID and self.status is R:
            self.reset_state()
        if self._TERMINATES:
            self.terminate(new_status)
        child = self.decorated
        if new_status is _INVALID:
            child.stop(_INVALID)
        if child.status is R:
            child.stop(_INVALID)
        if new_status is not self.status:
            self.set_status(new_status)


class LeafNode(_BtNode, Behaviour):
    """A leaf (action or condition) with ports; subclasses write `update()`."""

    def execute_tick(self) -> Status:
        """py_trees' Behaviour.tick, step for step, as one call (its debug message only
        formatted when py_trees logs at DEBUG: leaves are most of a tree's ticks)."""
        if _pt_logging.level < _INFO:
            self.logger.debug(f"{type(self).__name__}.tick()")
        if self.status is not R and self._INITIALISES:
            self.initialise()
        new_status = self.update()
        if new_status is R:
            if self.status is not R:
                self.set_status(R)
            return R
        if new_status is not S and new_status is not F and new_status not in _STATUSES:
            self.logger.error(
                "A behaviour returned an invalid status, setting to INVALID "
                f"[{new_status}][{self.name}]"
            )
            new_status = _INVALID
        self.stop(new_status)
        return new_status

    def update(self) -> Status:
        raise NotImplementedError
