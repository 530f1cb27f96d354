"""Groot2's palette of btnav's tree nodes: a `<TreeNodesModel>` built from the live registry.

Groot2 draws a tree only with nodes it has a model for (ID, kind, ports). btnav's
models come from the same place the loader finds node types, the `bt_node` registry,
so the palette holds the built-ins, installed plugins and any plugin loaded before it
is built, each under every name it is registered as (aliases included).

It is spelt as Nav2's own `nav2_tree_nodes.xml` and BT.CPP's model writer spell it:

* kinds are `Action`, `Condition`, `Control`, `Decorator` (a leaf is an `Action` unless
  its class says `NODE_KIND = "Condition"`);
* ports are `input_port`s then `output_port`s, each in the order the class declares
  them (py_trees' ports are one or the other, so BT.CPP's `inout_port` never appears);
* types are C++/ROS names (`double`, `string`, `nav_msgs::msg::Path`, ...). Where the
  Python type cannot say (`int` milliseconds, a bare `list` of goals), the port's Nav2
  name gives Nav2's spelling (`server_timeout` is `chrono::milliseconds`);
* defaults are the text a tree would write (`true`, `0.15`, `inf`, `a;b` for a list);
  a string default is written bare, not in C++ quotes as Nav2's file has them, so a
  port Groot fills from the default reads back as the same value here;
* a port's description is the element's text.

Models are sorted by kind (the order above), then by ID.
"""

from __future__ import annotations

import xml.etree.ElementTree as ET
from collections.abc import Iterable, Mapping
from dataclasses import dataclass
from types import UnionType
from typing import Any, Union, get_args, get_origin

from py_trees.ports import PortInformation

from ..core.errors import PluginError
from ..core.geometry import Pose2D
from ..core.messages import (
    LaserScan,
    Odometry,
    Path,
    PoseStamped,
    PoseWithCovariance,
    TrackingFeedback,
    Twist,
)
from ..core.nav2_route_msgs import Route
from ..core.suggest import best_match
from .registry import check_node_class, node_category, node_types

#: Groot's node kinds, in the palette's order.
KINDS = ("Action", "Condition", "Control", "Decorator", "SubTree")

#: The port elements of a model, by direction (BT.CPP's third, `inout_port`, has no
#: py_trees counterpart: a port cannot be both an input and an output).
PORT_TAGS = {"input": "input_port", "output": "output_port"}

#: BehaviorTree.CPP's own nodes: Groot2 has their models already (`--skip-builtin`).
BTCPP_BUILTINS = frozenset(
    {
        "AlwaysFailure",
        "AlwaysSuccess",
        "Delay",
        "Fallback",
        "ForceFailure",
        "ForceSuccess",
        "IfThenElse",
        "Inverter",
        "KeepRunningUntilFailure",
        "Parallel",
        "ParallelAll",
        "Precondition",
        "ReactiveFallback",
        "ReactiveSequence",
        "Repeat",
        "RetryUntilSuccessful",
        "RunOnce",
        "Script",
        "ScriptCondition",
        "Sequence",
        "SequenceStar",
        "SequenceWithMemory",
        "SetBlackboard",
        "Sleep",
        "SubTree",
        "Switch2",
        "Switch3",
        "Switch4",
        "Switch5",
        "Switch6",
        "Timeout",
        "UnsetBlackboard",
        "WhileDoElse",
    }
)

#: Python types as BT.CPP / ROS 2 spell them.
_TYPE_NAMES: dict[Any, str] = {
    float: "double",
    int: "int",
    bool: "bool",
    str: "string",
    Pose2D: "geometry_msgs::msg::Pose2D",
    PoseStamped: "geometry_msgs::msg::PoseStamped",
    PoseWithCovariance: "geometry_msgs::msg::PoseWithCovariance",
    Twist: "geometry_msgs::msg::Twist",
    Path: "nav_msgs::msg::Path",
    Odometry: "nav_msgs::msg::Odometry",
    LaserScan: "sensor_msgs::msg::LaserScan",
    TrackingFeedback: "nav2_msgs::msg::TrackingFeedback",
    Route: "nav2_msgs::msg::Route",
}

#: A stamped pose absorbs the bare one btnav also accepts (read in the default frame).
_UNION_NAMES = {frozenset({Pose2D, PoseStamped}): "geometry_msgs::msg::PoseStamped"}

_POSES = "vector<geometry_msgs::msg::PoseStamped>"
_STATUSES = "vector<nav2_msgs::msg::WaypointStatus>"
#: Nav2's spelling of ports whose Python type is too loose to say: (name, type) -> C++.
_NAV2_PORT_TYPES: dict[tuple[str, Any], str] = {
    ("server_timeout", int): "chrono::milliseconds",
    ("error_code_id", int): "uint16",
    ("error_code", int): "uint16",
    ("max_cost", int): "unsigned int",
    ("goals", list): "nav_msgs::msg::Goals",
    ("input_goals", list): "nav_msgs::msg::Goals",
    ("output_goals", list): "nav_msgs::msg::Goals",
    ("viapoints", list): _POSES,
    ("collision_poses", list): _POSES,
    ("input_waypoint_statuses", list): _STATUSES,
    ("output_waypoint_statuses", list): _STATUSES,
    ("tracking_feedback", object): "nav2_msgs::msg::TrackingFeedback",
    ("start_id", int): "unsigned int",
    ("goal_id", int): "unsigned int",
    ("last_node_id", int): "uint16",
    ("next_node_id", int): "uint16",
    ("current_edge_id", int): "uint16",
    ("planning_time", float): "builtin_interfaces::msg::Duration",
    ("execution_duration", float): "builtin_interfaces::msg::Duration",
    ("max_staging_time", float): "float",
    ("max_undocking_time", float): "float",
    ("num_retries", int): "uint16",
}


@dataclass(frozen=True)
class PortModel:
    """One port of a node model: `direction` is `input` or `output`."""

    name: str
    direction: str
    type: str | None
    default: str | None
    description: str


@dataclass(frozen=True)
class NodeModel:
    """One node type as Groot2 knows it: its ID (the XML tag), kind and ports."""

    id: str
    kind: str
    ports: tuple[PortModel, ...]


def type_name(data_type: Any) -> str | None:
    """A port type as BT.CPP spells it (`vector<T>` for `list[T]`); None for `object`/`Any`."""
    if data_type is object or data_type is Any:
        return None
    if data_type in _TYPE_NAMES:
        return _TYPE_NAMES[data_type]
    origin = get_origin(data_type)
    if origin in (Union, UnionType):
        members = [a for a in get_args(data_type) if a is not type(None)]
        known = _UNION_NAMES.get(frozenset(members))
        if known:
            return known
        names = [type_name(a) or "any" for a in members]
        return names[0] if len(names) == 1 else " | ".join(names)
    if origin in (list, tuple, set, frozenset):
        args = get_args(data_type)
        inner = type_name(args[0]) if args else None
        return f"vector<{inner}>" if inner else "vector"
    if data_type in (list, tuple, set, frozenset):
        return "vector"
    if data_type is dict or origin is dict:
        return "map"
    if isinstance(data_type, type):
        return f"{data_type.__module__}.{data_type.__qualname__}"
    return str(data_type)


def port_type_name(name: str, data_type: Any) -> str | None:
    """The type of port `name`: Nav2's spelling where its Python type is too loose."""
    try:
        nav2 = _NAV2_PORT_TYPES.get((name, data_type))
    except TypeError:  # an unhashable type annotation
        nav2 = None
    return nav2 or type_name(data_type)


def default_text(value: Any) -> str:
    """A default as a tree would write it: `true`, `0.15`, `inf`, `a;b` (BT.CPP's lists)."""
    if isinstance(value, bool):
        return "true" if value else "false"
    if isinstance(value, float):
        return repr(float(value))  # `inf`, however a float subclass prints itself
    if isinstance(value, (list, tuple)):
        return ";".join(default_text(v) for v in value)
    return str(value)


def node_kind(node_id: str, cls: type) -> str:
    """Groot's kind of a node class: its category, and for a leaf its `NODE_KIND`."""
    category = node_category(cls)
    if category == "control":
        return "Control"
    if category == "decorator":
        return "Decorator"
    kind = getattr(cls, "NODE_KIND", None) or "Action"
    if kind not in ("Action", "Condition"):
        raise PluginError(
            f"bt_node '{node_id}' ({cls.__qualname__}) has NODE_KIND {kind!r}: "
            "a leaf is an 'Action' or a 'Condition'",
            suggestion=best_match(str(kind), ("Action", "Condition")),
        )
    return kind


def _port(name: str, direction: str, info: PortInformation) -> PortModel:
    return PortModel(
        name=name,
        direction=direction,
        type=port_type_name(name, info.data_type),
        default=default_text(info.default_value) if info.has_default else None,
        description=info.description or "",
    )


def node_model(node_id: str, cls: type) -> NodeModel:
    """The model of the class registered as `node_id`."""
    check_node_class(node_id, cls)
    inputs: dict[str, PortInformation] = dict(cls.input_ports())  # type: ignore[attr-defined]
    outputs: dict[str, PortInformation] = dict(cls.output_ports())  # type: ignore[attr-defined]
    ports = [_port(n, "input", p) for n, p in inputs.items()]
    ports += [_port(n, "output", p) for n, p in outputs.items()]
    return NodeModel(id=node_id, kind=node_kind(node_id, cls), ports=tuple(ports))


def palette_models(
    types: Mapping[str, type] | None = None, *, builtin: bool = True
) -> list[NodeModel]:
    """Every registered node type's model (`types`: the live registry by default),
    sorted by kind then ID; `builtin=False` leaves out BT.CPP's own nodes."""
    types = node_types() if types is None else types
    models = [
        node_model(node_id, cls)
        for node_id, cls in types.items()
        if builtin or node_id not in BTCPP_BUILTINS
    ]
    return sorted(models, key=lambda m: (KINDS.index(m.kind), m.id))


def palette_element(models: Iterable[NodeModel]) -> ET.Element:
    """`<root BTCPP_format="4"><TreeNodesModel>...</TreeNodesModel></root>`."""
    root = ET.Element("root", {"BTCPP_format": "4"})
    model = ET.SubElement(root, "TreeNodesModel")
    for node in models:
        elem = ET.SubElement(model, node.kind, {"ID": node.id})
        for port in node.ports:
            attrib = {"name": port.name}
            if port.type:
                attrib["type"] = port.type
            if port.default is not None:
                attrib["default"] = port.default
            ET.SubElement(elem, PORT_TAGS[port.direction], attrib).text = port.description or None
    return root


def palette_xml(models: Iterable[NodeModel] | None = None, *, header: str | None = None) -> str:
    """The palette file's text (the live registry's models by default)."""
    models = palette_models() if models is None else list(models)
    root = palette_element(models)
    ET.indent(root, space="  ")
    comment = f"<!-- {header.replace('--', '-')} -->\n" if header else ""
    return f'<?xml version="1.0"?>\n{comment}{ET.tostring(root, encoding="unicode")}\n'
