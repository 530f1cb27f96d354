"""Check a tree document before anything is built or ticked.

Every node type must be registered, every attribute must be a port of its node
(BT.CPP v4 refuses unknown attributes too), every required input port must be
given, constants must read as their port's type, output ports must name a
blackboard entry, and each node must have the number of children its kind takes.
Each error names the file, the line and, for a misspelling, the closest name.
"""

from __future__ import annotations

import xml.etree.ElementTree as ET
from collections.abc import Mapping
from typing import Any

from py_trees.ports_utils import convert_str_to_type

from ..core.suggest import close_matches
from .document import TreeDocument
from .errors import UnknownNodeError
from .registry import node_category

SUBTREE_TAGS = ("SubTree", "SubTreePlus")
SUBTREE_ATTRS = ("ID", "name", "_autoremap")
#: Elements under <root> that are not trees (Groot's palette, imports).
NON_TREE_ELEMENTS = ("TreeNodesModel", "include", "Include", "import", "Import")


def type_name(t: Any) -> str:
    return getattr(t, "__name__", None) or str(t)


def children_range(cls: type) -> tuple[int, int | None]:
    rng = getattr(cls, "CHILDREN", None)
    if rng is not None:
        return rng
    return {"control": (1, None), "decorator": (1, 1), "leaf": (0, 0)}[node_category(cls)]


def is_blackboard_ref(value: str) -> bool:
    return value.startswith("{") and value.endswith("}") and len(value) > 2


def unknown_node_types(doc: TreeDocument, node_types: Mapping[str, type]) -> list[str]:
    """The node types the document uses that are not registered (sorted, each once)."""
    found = set()
    for bt in doc.root.findall("BehaviorTree"):
        for elem in bt.iter():
            if elem is not bt and elem.tag not in SUBTREE_TAGS and elem.tag not in node_types:
                found.add(elem.tag)
    return sorted(found)


def validate(doc: TreeDocument, node_types: Mapping[str, type]) -> None:
    """Raise the first problem (a TreeError with file and line); return when the tree is sound."""
    _Validator(doc, node_types).run()


class _Validator:
    def __init__(self, doc: TreeDocument, node_types: Mapping[str, type]) -> None:
        self.doc = doc
        self.node_types = node_types
        self.trees = doc.trees
        self.unknown = unknown_node_types(doc, node_types)

    def run(self) -> None:
        doc = self.doc
        trees = doc.root.findall("BehaviorTree")
        if not trees:
            raise doc.error("no <BehaviorTree> in the file (is it a node model?)", doc.root)
        for bt in trees:
            if not bt.attrib.get("ID"):
                raise doc.error("a <BehaviorTree> needs an ID", bt)
            if len(bt) != 1:
                raise doc.error(
                    f"tree '{bt.attrib['ID']}' must have exactly one root node, it has {len(bt)}",
                    bt,
                )
        main = doc.main_tree
        if main is None:
            raise doc.error(
                f"several trees ({', '.join(self.trees)}) and no main_tree_to_execute", doc.root
            )
        if main not in self.trees:
            near = close_matches(main, self.trees)
            raise doc.error(
                f"main tree '{main}' is not in the file; trees: {', '.join(self.trees)}",
                doc.root,
                cls=UnknownNodeError,
                suggestion=near[0] if near else None,
            )
        for bt in trees:
            for elem in bt:
                self.node(elem)

    def node(self, elem: ET.Element) -> None:
        if elem.tag in SUBTREE_TAGS:
            self.subtree(elem)
            return
        cls = self.node_types.get(elem.tag)
        if cls is None:
            self.unknown_type(elem)
            return
        lo, hi = children_range(cls)
        n = len(elem)
        if n < lo or (hi is not None and n > hi):
            want = f"exactly {lo}" if lo == hi else (f"{lo} to {hi}" if hi else f"at least {lo}")
            kind = node_category(cls)
            raise self.doc.error(
                f"{elem.tag} ({kind}) takes {want} child{'ren' if hi != 1 else ''}, it has {n}",
                elem,
            )
        self.ports(elem, cls)
        for child in elem:
            self.node(child)

    def unknown_type(self, elem: ET.Element) -> None:
        known = [*self.node_types, *SUBTREE_TAGS[:1]]
        near = close_matches(elem.tag, known)
        others = [t for t in self.unknown if t != elem.tag]
        also = f"; also unknown in this file: {', '.join(others)}" if others else ""
        raise self.doc.error(
            f"unknown node type '{elem.tag}' (btnav has no tree node of that name){also}",
            elem,
            cls=UnknownNodeError,
            suggestion=near[0] if near else None,
        )

    def subtree(self, elem: ET.Element) -> None:
        tree_id = elem.attrib.get("ID")
        if not tree_id:
            raise self.doc.error(f"<{elem.tag}> needs the ID of the tree it includes", elem)
        if tree_id not in self.trees:
            near = close_matches(tree_id, self.trees)
            raise self.doc.error(
                f"SubTree ID '{tree_id}' is not a tree in this file; trees: {', '.join(self.trees)}",
                elem,
                "ID",
                cls=UnknownNodeError,
                suggestion=near[0] if near else None,
            )
        if len(elem):
            raise self.doc.error("a SubTree takes no children (its tree is its content)", elem)
        for attr, value in elem.attrib.items():
            if attr not in SUBTREE_ATTRS:
                self.check_braces(elem, attr, value)

    def check_braces(self, elem: ET.Element, attr: str, value: str) -> None:
        if ("{" in value or "}" in value) and not (
            is_blackboard_ref(value) and value.count("{") == 1 and value.count("}") == 1
        ):
            raise self.doc.error(
                f"'{value}' is not a blackboard reference: write \"{{key}}\" alone", elem, attr
            )

    def ports(self, elem: ET.Element, cls: type) -> None:
        inputs = cls.input_ports()  # type: ignore[attr-defined]
        outputs = cls.output_ports()  # type: ignore[attr-defined]
        for attr, value in elem.attrib.items():
            if attr == "name":
                continue
            if attr not in inputs and attr not in outputs:
                ports = sorted([*inputs, *outputs])
                near = close_matches(attr, ports)
                listed = ", ".join(ports) if ports else "none"
                raise self.doc.error(
                    f"{elem.tag} has no port '{attr}'; its ports: {listed}",
                    elem,
                    attr,
                    cls=UnknownNodeError,
                    suggestion=near[0] if near else None,
                )
            self.check_braces(elem, attr, value)
            if is_blackboard_ref(value):
                continue
            if attr in outputs:
                raise self.doc.error(
                    f"output port '{attr}' of {elem.tag} must name a blackboard entry, "
                    f'like "{{{attr}}}"',
                    elem,
                    attr,
                )
            info = inputs[attr]
            try:
                ok, _ = convert_str_to_type(value, info.data_type)
            except Exception:
                ok = False
            if not ok:
                hint = (
                    ""
                    if info.data_type in (int, float, bool)
                    else f' (give it a blackboard entry, like "{{{attr}}}")'
                )
                raise self.doc.error(
                    f"port '{attr}' of {elem.tag} takes a {type_name(info.data_type)}, "
                    f"not '{value}'{hint}",
                    elem,
                    attr,
                )
        for port, info in inputs.items():
            if info.required and not info.has_default and port not in elem.attrib:
                raise self.doc.error(
                    f"{elem.tag} needs its input port '{port}' ({type_name(info.data_type)})",
                    elem,
                )
