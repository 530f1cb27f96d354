"""BT.CPP's ports on py_trees' `PortsMixin`, bound once when the tree is built.

py_trees declares a node's ports (`INPUT_PORTS`/`OUTPUT_PORTS` of `PortInformation`),
registers them on a blackboard client and resolves remappings, SubTree namespaces
and constant values: btnav uses all of that as it is. What py_trees then does on
every read and write (find the port, ask the client whether it is registered,
resolve its key, check its type generically) is done here once, at build time:
`setup_ports` binds each port to its storage key and its type check, and a read is
a dict lookup (`blackboard.read`). Whatever the bound path cannot answer exactly (an
unset port without a default raising, a value of the wrong type, a port used before
`setup_ports`, the blackboard's activity stream switched on) goes through py_trees'
own code, so the results, errors and recorded activity are py_trees'.

A node reads a port one of two ways, as BT.CPP's `getInput` is used: `get_input`
raises `NoDataAvailable` for an unset port without a default; `optional` returns None.
"""

from __future__ import annotations

import copy
from types import UnionType
from typing import Any, Union, get_args, get_origin

from py_trees.blackboard import Blackboard
from py_trees.ports import NoDataAvailable, PortInformation, PortsMixin
from py_trees.ports_utils import is_instance_of_type

from .blackboard import read, recording, write

_MISSING = object()
#: Port defaults returned as they are (py_trees deep-copies a default; these need not be).
_IMMUTABLE = frozenset({str, int, float, bool, bytes})


def input_port(data_type: Any, description: str = "", default: Any = None) -> PortInformation:
    """BT.CPP's `InputPort<T>(name, default, description)` for a node's ports table."""
    return PortInformation(
        data_type, required=False, description=description, default_value=default
    )


def output_port(data_type: Any, description: str = "") -> PortInformation:
    """BT.CPP's `OutputPort<T>(name, description)`."""
    return PortInformation(data_type, required=False, description=description)


class _PortTypeCheck(type):
    """`isinstance` against a port type `isinstance` cannot take (a generic such as
    `list[Pose2D]`), by py_trees' own check."""

    def __instancecheck__(cls, value: Any) -> bool:
        return is_instance_of_type(value, cls.data_type)


def port_types(data_type: Any) -> tuple[type, ...]:
    """What `isinstance` checks a port's values against: the classes of the port's type
    (a class, or a union of classes), else a class running py_trees' check."""
    if isinstance(data_type, type) and get_origin(data_type) is None:
        return (data_type,)
    if get_origin(data_type) in (Union, UnionType):
        args = get_args(data_type)
        if all(isinstance(a, type) and get_origin(a) is None for a in args):
            return tuple(args)
    return (_PortTypeCheck("PortType", (), {"data_type": data_type}),)


class BoundPort:
    """One port of one node, resolved at build time: its storage key, type check, default."""

    __slots__ = ("copy_default", "default", "info", "key", "types")

    def __init__(self, key: str, info: PortInformation) -> None:
        self.key = key
        self.info = info
        self.types = port_types(info.data_type)
        self.default = info.default_value if info.has_default else _MISSING
        self.copy_default = info.has_default and type(info.default_value) not in _IMMUTABLE

    def declared_default(self) -> Any:
        """The port's declared default (a private copy when it is mutable), or _MISSING."""
        dv = self.default
        return copy.deepcopy(dv) if self.copy_default else dv


def _bind(node: PortsMixin, ports: dict[str, PortInformation], write: bool) -> dict[str, BoundPort]:
    """The ports of `node` its blackboard client can read (or write) by key directly."""
    client = node._blackboard_client
    bound: dict[str, BoundPort] = {}
    if client is None:
        return bound
    access = client.write | client.exclusive if write else None
    for name, info in ports.items():
        if "." in name:  # a nested name: py_trees' path
            continue
        absolute = Blackboard.absolute_name(client.namespace, name)
        registered = absolute in access if access is not None else client.is_registered(name)
        key = client.remappings.get(absolute) if registered else None
        if key is not None:
            bound[name] = BoundPort(key, info)
    return bound


class BoundPortsMixin(PortsMixin):
    """`PortsMixin` whose ports are bound to their blackboard keys by `setup_ports`."""

    #: Bound by `setup_ports` (a new blackboard client binds anew); empty until then.
    bound_inputs: dict[str, BoundPort] = {}  # replaced, never mutated
    bound_outputs: dict[str, BoundPort] = {}

    def setup_ports(self, *args: Any, **kwargs: Any) -> None:
        self.bound_inputs = {}  # py_trees may seed output defaults before the binding
        self.bound_outputs = {}
        super().setup_ports(*args, **kwargs)
        self.bound_inputs = _bind(self, self.input_ports(), write=False)
        self.bound_outputs = _bind(self, self.output_ports(), write=True)

    def get_input(self, port_name: str, default: Any = None) -> Any:
        """py_trees' `get_input`: the port's value, else `default`, else its declared
        default, else `NoDataAvailable`."""
        slot = self.bound_inputs.get(port_name)
        if slot is not None and not recording():
            value = read(slot.key, _MISSING)
            if value is _MISSING:
                if default is not None:
                    return default
                if slot.default is not _MISSING:
                    return slot.declared_default()
            elif value is not None and isinstance(value, slot.types):
                return value
        # Unset without a default, None or the wrong type: py_trees' path (its errors).
        return super().get_input(port_name, default)

    def optional(self, port_name: str) -> Any:
        """The input port's value, or None when it has no data and no default (BT.CPP's
        `getInput` returning false)."""
        slot = self.bound_inputs.get(port_name)
        if slot is not None and not recording():
            value = read(slot.key, _MISSING)
            if value is _MISSING:
                return None if slot.default is _MISSING else slot.declared_default()
            if value is not None and isinstance(value, slot.types):
                return value
        try:
            return super().get_input(port_name)
        except NoDataAvailable:
            return None

    def _set_output(self, port_name: str, value: Any) -> None:
        slot = self.bound_outputs.get(port_name)
        if slot is not None and not recording() and isinstance(value, slot.types):
            write(slot.key, value)
            return
        super()._set_output(port_name, value)
