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

import copy
from collections.abc import Callable, Generator, Sequence
from types import UnionType
from typing import Any, ClassVar, Union, get_args, get_origin

import py_trees
from py_trees.behaviour import Behaviour
from py_trees.blackboard import Blackboard
from py_trees.common import Status
from py_trees.ports import NoDataAvailable, PortInformation, PortsMixin
from py_trees.ports_utils import is_instance_of_type

TickGen = Generator[Behaviour, None, Status]

_MISSING = object()
_STATUSES = frozenset(Status)
_INFO = py_trees.logging.Level.INFO
#: Port defaults returned as they are (py_trees deep-copies a default; these need not be).
_IMMUTABLE = frozenset({str, int, float, bool, bytes})

#: Tolerance for comparing sim times (the clock counts integer nanoseconds).
TIME_EPS = 1e-9


#: BT.CPP's NodeStatus, as every node file spells them.
S, F, R = Status.SUCCESS, Status.FAILURE, Status.RUNNING


def input_port(data_type: Any, description: str = "", default: Any = None) -> PortInformation:
    """BT.CPP's `InputPort<T>(name, default, description)` for a node's ports table."""
    return PortInformation(
        data_type, required=False, description=description, default_value=default
    )


def output_port(data_type: Any, description: str = "") -> PortInformation:
    """BT.CPP's `OutputPort<T>(name, description)`."""
    return PortInformation(data_type, required=False, description=description)


def _plain_types(data_type: Any) -> tuple[type, ...] | None:
    """The classes `isinstance` can check a port's type with, or None for other types
    (generics such as `list[Pose2D]`), which py_trees' own check handles."""
    if isinstance(data_type, type) and get_origin(data_type) is None:
        return (data_type,)
    if get_origin(data_type) in (Union, UnionType):
        args = get_args(data_type)
        if all(isinstance(a, type) and get_origin(a) is None for a in args):
            return tuple(args)
    return None


class _PortSlot:
    """One port of one node, resolved once: its blackboard storage key and type check."""

    __slots__ = ("info", "key", "types")

    def __init__(self, key: str, info: PortInformation) -> None:
        self.key = key
        self.info = info
        self.types = _plain_types(info.data_type)

    def type_ok(self, value: Any) -> bool:
        types = self.types
        if types is not None:
            return isinstance(value, types)
        return is_instance_of_type(value, self.info.data_type)


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
    #: Called as `status_listener(node, old, new)` on every change of this node's status,
    #: even one undone within the same tick (a tick log sets it; None: nobody listens).
    status_listener: Callable[[Any, Status, Status], None] | None = None

    @property
    def status(self) -> Status:
        return self.__dict__.get("_status", Status.INVALID)

    @status.setter
    def status(self, new: Status) -> None:
        d = self.__dict__
        old = d.get("_status", Status.INVALID)
        d["_status"] = new
        if new is not old and self.status_listener is not None:
            self.status_listener(self, old, new)

    def __init_subclass__(cls, *, register: bool = False, **kwargs: Any) -> None:
        # btnav's registry (the bt_node plugin kind) is the one that names node types;
        # py_trees' global auto-registry is left to the user's own classes.
        super().__init_subclass__(register=register, **kwargs)

    def optional(self, name: str) -> Any:
        """An input port's value, or None when it has no data and no default (BT.CPP's
        `getInput` returning false); `get_input` raises instead."""
        try:
            return self.get_input(name)
        except NoDataAvailable:
            return None

    # -- ports: py_trees' get_input/_set_output, with the key resolved once -----------------
    #
    # py_trees resolves a port's blackboard key (namespace, registration, remapping) and
    # checks its type generically on every read and write; a tree ticking at 100 Hz does
    # that tens of thousands of times a minute. A node resolves each port once per
    # blackboard client (setup_ports makes a new one) and reads the storage directly;
    # the results, errors and type checks are py_trees' own. With the blackboard's
    # activity stream on, py_trees' path runs so every access is still recorded.

    def setup_ports(self, *args: Any, **kwargs: Any) -> None:
        super().setup_ports(*args, **kwargs)
        # a new blackboard client: its ports are resolved anew
        self.__dict__["_btnav_ports"] = ({}, {})

    def _slot(self, port_name: str, outputs: bool) -> _PortSlot | None:
        """The port's slot, or None when py_trees' path must run (undeclared, unregistered,
        a nested name, or an output the client may not write)."""
        cache = self.__dict__.get("_btnav_ports")
        if cache is None:
            cache = self.__dict__["_btnav_ports"] = ({}, {})
        slots = cache[outputs]
        slot = slots.get(port_name, _MISSING)
        if slot is not _MISSING:
            return slot
        slot = None
        ports = self.output_ports() if outputs else self.input_ports()
        client = self._blackboard_client
        if port_name in ports and client is not None and "." not in port_name:
            absolute = Blackboard.absolute_name(client.namespace, port_name)
            access = client.write | client.exclusive if outputs else None
            registered = (
                absolute in access if access is not None else client.is_registered(port_name)
            )
            key = client.remappings.get(absolute) if registered else None
            if key is not None:
                slot = _PortSlot(key, ports[port_name])
        if client is not None:  # before setup_ports, nothing is cached
            slots[port_name] = slot
        return slot

    def get_input(self, port_name: str, default: Any = None) -> Any:
        if Blackboard.activity_stream is None:
            slot = self._slot(port_name, False)
            if slot is not None:
                value = Blackboard.storage.get(slot.key, _MISSING)
                if value is _MISSING:
                    if default is not None:
                        return default
                    info = slot.info
                    if info.has_default:
                        dv = info.default_value
                        return dv if type(dv) in _IMMUTABLE else copy.deepcopy(dv)
                    raise NoDataAvailable(
                        f"{self.name}: Input port '{port_name}' (mapped to "
                        f"'{slot.key}') has no data available."
                    )
                if value is not None and slot.type_ok(value):
                    return value
        # Unset, None or the wrong type: py_trees' path (defaults, errors).
        return super().get_input(port_name, default)

    def _set_output(self, port_name: str, value: Any) -> None:
        if Blackboard.activity_stream is None:
            slot = self._slot(port_name, True)
            if slot is not None and slot.type_ok(value):
                Blackboard.storage[slot.key] = value
                return
        super()._set_output(port_name, value)

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
        if type(child).tick is LeafNode.tick:  # a leaf: ticked here, yielded as it yields
            child.tick_now()  # type: ignore[attr-defined]
            yield child
        else:
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
        child = self.decorated
        if type(child).tick is LeafNode.tick:  # as ControlNode.tick_child
            child.tick_now()  # type: ignore[attr-defined]
            yield child
        else:
            yield from child.tick()
        return child.status

    def update(self) -> Status:  # unused: tick() does the work
        return self.status

    def stop(self, new_status: Status = Status.INVALID) -> None:
        if new_status == Status.INVALID and self.status == Status.RUNNING:
            self.reset_state()
        super().stop(new_status)


class LeafNode(_BtNode, Behaviour):
    """A leaf (action or condition) with ports; subclasses write `update()`."""

    # py_trees' Behaviour.tick and stop, step for step, except that their debug messages
    # are only formatted when py_trees logs at DEBUG (leaves are most of a tree's ticks).

    def tick(self) -> Generator[Behaviour, None, None]:
        self.tick_now()
        yield self

    def tick_now(self) -> None:
        """What `tick()` does before it yields: a parent ticking a leaf calls this and
        yields the leaf itself (one generator less per leaf and tick)."""
        if py_trees.logging.level < _INFO:
            self.logger.debug(f"{self.__class__.__name__}.tick()")
        if self.status != Status.RUNNING:
            self.initialise()
        new_status = self.update()
        if new_status not in _STATUSES:
            self.logger.error(
                "A behaviour returned an invalid status, setting to INVALID "
                f"[{new_status}][{self.name}]"
            )
            new_status = Status.INVALID
        if new_status != Status.RUNNING:
            self.stop(new_status)
        self.status = new_status

    def stop(self, new_status: Status) -> None:
        if py_trees.logging.level < _INFO:
            change = f"{self.status}->{new_status}" if self.status != new_status else new_status
            self.logger.debug(f"{self.__class__.__name__}.stop({change})")
        self.terminate(new_status)
        self.status = new_status
        self.iterator = self.tick()

    def update(self) -> Status:
        raise NotImplementedError
