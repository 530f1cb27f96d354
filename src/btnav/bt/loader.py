"""Load a tree file (Nav2 XML or btnav YAML) into a py_trees tree, checked before it ticks.

The build is py_trees' own XML parser path (`py_trees.parsers.behaviour_tree_xml`:
`build_subtree_remapping` + `build_tree_from_xml`, with its blackboard remapping
and SubTree namespaces) fed with btnav's node registry. btnav adds what users need
around it: the file is read with lines kept (expat for XML, `core.yaml_io` for
YAML), validated first (`validate`), and every error names file, line and the
close spellings. A YAML tree is translated to the same elements as its XML, so the
two spellings build the same tree.
"""

from __future__ import annotations

import os
import xml.etree.ElementTree as ET
from collections.abc import Mapping
from os import PathLike
from typing import Any

from py_trees.behaviour import Behaviour
from py_trees.parsers import behaviour_tree_xml as bt_xml
from py_trees.ports_utils import NOOP_LOGGER, strip_trailing_uuid4

from ..core.errors import BtnavError
from .document import TreeDocument, parse_xml_text, read_document
from .errors import TreeError
from .registry import node_types, parser_registry
from .validate import SUBTREE_TAGS, unknown_node_types, validate
from .yaml_tree import parse_yaml_text

TreeSource = str | PathLike[str] | TreeDocument

_TREE_SUFFIXES = (".xml", ".yaml", ".yml")


def _looks_like_text(source: str) -> bool:
    s = source.strip()
    if "\n" in s or s.startswith("<"):
        return True
    return not s.lower().endswith(_TREE_SUFFIXES) and (":" in s or "{" in s)


def load_document(source: TreeSource, *, file: str | PathLike[str] | None = None) -> TreeDocument:
    """A path (`.xml`, `.yaml`), XML or YAML text, or a TreeDocument -> TreeDocument (unbuilt)."""
    if isinstance(source, TreeDocument):
        return source
    if isinstance(source, str) and _looks_like_text(source):
        if source.lstrip().startswith("<"):
            return parse_xml_text(source, file)
        return parse_yaml_text(source, file)
    return read_document(source)


def load_tree(
    source: TreeSource,
    *,
    main_tree: str | None = None,
    clock: Any = None,
    context: Mapping[str, Any] | None = None,
    search_paths: list[str] | None = None,
) -> Behaviour:
    """Build the tree's root behaviour, validated before its first tick.

    `clock` (a `core.clock.SimClock` or anything with `.now` in seconds) times
    Delay, Timeout and RateController; `context` holds further dependencies that
    node types ask for by name in their `INJECT` (servers, for action nodes).
    """
    return build_tree(
        load_document(source),
        main_tree=main_tree,
        clock=clock,
        context=context,
        search_paths=search_paths,
    )


def prepare(doc: TreeDocument, types: Mapping[str, type]) -> None:
    """Fill what BT.CPP fills implicitly: ports' default blackboard entries, SubTree names."""
    for bt in doc.root.findall("BehaviorTree"):
        used: dict[str, int] = {}
        for elem in bt.iter():
            if elem.tag in SUBTREE_TAGS:
                if "name" not in elem.attrib and "ID" in elem.attrib:
                    # A stable instance name (py_trees would draw a random uuid): it is
                    # the SubTree's blackboard namespace.
                    count = used[elem.attrib["ID"]] = used.get(elem.attrib["ID"], 0) + 1
                    suffix = "" if count == 1 else f"_{count}"
                    elem.set("name", elem.attrib["ID"] + suffix)
                continue
            cls = types.get(elem.tag)
            for port, entry in getattr(cls, "DEFAULT_KEYS", {}).items():
                if port not in elem.attrib:
                    elem.set(port, entry)


def _check_subtree_cycles(doc: TreeDocument, main: str) -> None:
    trees = doc.trees

    def visit(tree_id: str, stack: list[str]) -> None:
        for elem in trees[tree_id].iter():
            if elem.tag in SUBTREE_TAGS and elem.attrib.get("ID") in trees:
                target = elem.attrib["ID"]
                if target in stack:
                    chain = " -> ".join([*stack[stack.index(target) :], target])
                    raise doc.error(f"SubTree cycle: {chain}", elem, "ID")
                visit(target, [*stack, target])

    visit(main, [main])


def _inline_imports(doc: TreeDocument, search_paths: list[str] | None) -> None:
    if not any(child.tag.lower() in ("import", "include") for child in doc.root):
        return
    current = doc.file or os.path.join(os.getcwd(), "<text>")
    try:
        bt_xml._inline_imports_into_root(doc.root, current, NOOP_LOGGER, search_paths)
    except (OSError, ValueError, ET.ParseError) as exc:
        raise TreeError(f"cannot import a tree file: {exc}", file=doc.file) from None


def build_tree(
    doc: TreeDocument,
    *,
    main_tree: str | None = None,
    clock: Any = None,
    context: Mapping[str, Any] | None = None,
    search_paths: list[str] | None = None,
) -> Behaviour:
    """Validate `doc` and build it through py_trees' XML parser with btnav's registry."""
    types = node_types()
    _inline_imports(doc, search_paths)
    prepare(doc, types)
    validate(doc, types)
    main = main_tree or doc.main_tree
    trees = doc.trees
    if main not in trees:
        raise TreeError(f"no tree '{main}' in the file; trees: {', '.join(trees)}", file=doc.file)
    _check_subtree_cycles(doc, main)
    registry = parser_registry({"clock": clock, **(context or {})})
    bt_index = bt_xml.build_bt_index(doc.root)
    bt_elem = bt_index[main]
    try:
        remapping = bt_xml.build_subtree_remapping(bt_elem, bt_index, {}, "/", NOOP_LOGGER)
        root = bt_xml.build_tree_from_xml(
            bt_elem,
            remapping_table=remapping,
            node_registry=registry,
            bt_index=bt_index,
            logger=NOOP_LOGGER,
            subtree_namespace="/",
            parent_names_str="",
        )
    except BtnavError as exc:
        raise exc.located(file=doc.file) from None
    except (bt_xml.XMLParserError, ValueError, KeyError, TypeError, RuntimeError) as exc:
        raise TreeError(f"cannot build tree '{main}': {exc}", file=doc.file) from exc
    for node in root.iterate():
        # py_trees names an unnamed node `Type_<uuid4>`; BT.CPP names it `Type`.
        node.name = strip_trailing_uuid4(node.name)
    return root


def unknown_nodes(source: TreeSource) -> list[str]:
    """The node types a tree file uses that btnav does not register (for reports and tests)."""
    return unknown_node_types(load_document(source), node_types())
