"""btnav's explicit registry of tree node types: the `bt_node` plugin kind.

A node type is a `py_trees.ports.PortsMixin` behaviour (leaf, decorator or
composite) registered with `btnav.plugins.register("bt_node", "Name")`; the name is
the XML tag (and the YAML key) that creates it. A user's node is a peer of the
built-ins: same decorator, same lookup, and it may take a built-in's name.
"""

from __future__ import annotations

import functools
from collections.abc import Mapping
from typing import Any

import py_trees
from py_trees.ports import PortsMixin

from .. import plugins
from ..core.suggest import close_matches
from .errors import UnknownNodeError

KIND = "bt_node"

#: Tags the XML format itself defines (not node types).
STRUCTURE_TAGS = ("BehaviorTree", "SubTree", "root")


def _load_builtins() -> None:
    """btnav's node types register like a user's: through the `btnav.plugins` entry points."""
    plugins.load_entry_points()


def node_types() -> dict[str, type]:
    """Every registered node type by name (aliases included)."""
    _load_builtins()
    return {name: plugins.lookup(KIND, name) for name in plugins.names(KIND, aliases=True)}


def node_class(name: str) -> type:
    """The class registered as `name`; an unknown name lists the close ones."""
    _load_builtins()
    if plugins.is_registered(KIND, name):
        return plugins.lookup(KIND, name)
    known = plugins.names(KIND, aliases=True)
    near = close_matches(name, known)
    raise UnknownNodeError(
        f"unknown node type '{name}' (btnav has no tree node of that name)",
        suggestion=near[0] if near else None,
    )


def node_category(cls: type) -> str:
    """`control`, `decorator` or `leaf`, as BT.CPP sorts node types."""
    if issubclass(cls, py_trees.composites.Composite):
        return "control"
    if issubclass(cls, py_trees.decorators.Decorator):
        return "decorator"
    return "leaf"


def check_node_class(name: str, cls: Any) -> None:
    """A node type must be a PortsMixin behaviour; say so plainly when it is not."""
    if not (
        isinstance(cls, type)
        and issubclass(cls, PortsMixin)
        and issubclass(cls, py_trees.behaviour.Behaviour)
    ):
        raise TypeError(
            f"bt_node '{name}' is {cls!r}: a tree node must subclass py_trees.ports.PortsMixin "
            "and a py_trees Behaviour (leaf, Decorator or Composite)"
        )


def parser_registry(inject: Mapping[str, Any] | None = None) -> dict[str, Any]:
    """`{tag: class or partial}` for py_trees' XML parser.

    A class lists the dependencies it takes as keyword arguments in `INJECT`
    (e.g. `("clock",)`); they are bound with `functools.partial`, the way py_trees'
    parser documents dependency injection.
    """
    inject = dict(inject or {})
    out: dict[str, Any] = {}
    for name, cls in node_types().items():
        check_node_class(name, cls)
        wanted = {k: inject.get(k) for k in getattr(cls, "INJECT", ())}
        out[name] = functools.partial(cls, **wanted) if wanted else cls
    return out
