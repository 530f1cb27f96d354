"""`btnav tree import TREE.xml [-o TREE.yaml]`, `btnav tree show TREE` and
`btnav tree palette [-o nodes.xml]`.

Each raises a `BtnavError` for a user's mistake (the CLI prints it and exits 2) and
returns 0 otherwise. `tree show` raises for any tree `btnav run` would refuse, with the
same message, after showing what it can of it.
"""

from __future__ import annotations

import sys
import xml.etree.ElementTree as ET
from collections import Counter
from collections.abc import Iterator, Sequence
from os import PathLike
from pathlib import Path
from typing import TextIO

from py_trees.behaviour import Behaviour

from .. import __version__
from ..bt.bundled import find_tree
from ..bt.display import tree_text
from ..bt.document import TreeDocument
from ..bt.errors import TreeError
from ..bt.loader import build_tree, load_document
from ..bt.palette import palette_models, palette_xml
from ..bt.registry import node_category, node_types
from ..bt.validate import SUBTREE_TAGS, unknown_node_types
from ..bt.xml_to_yaml import element_counts, import_xml
from ..core.clock import SimClock
from ..core.files import read_bytes
from ..plugins import load_plugins
from . import EXIT_OK

# --- tree import ----------------------------------------------------------------------


def tree_import_main(
    xml_path: str | PathLike[str],
    out_path: str | PathLike[str] | None = None,
    *,
    out: TextIO | None = None,
    err: TextIO | None = None,
) -> int:
    """Write `xml_path` (Nav2 / BT.CPP XML) as btnav YAML to `out_path`, or print it.

    Node types btnav does not register are listed on stderr: the file imports, and
    loads once they are registered.
    """
    out = out or sys.stdout
    err = err or sys.stderr
    src = Path(xml_path)
    if src.suffix.lower() in (".yaml", ".yml"):
        raise TreeError("`tree import` reads Nav2 XML; this file is YAML already", file=src)
    text = read_bytes(src, error_cls=TreeError, what="tree file")
    header = [f"Imported from {src.name} by `btnav tree import`."]
    yaml_text = import_xml(text, src, header=header)
    doc = load_document(yaml_text)
    missing = unknown_node_types(doc, node_types())
    if out_path is None:
        out.write(yaml_text)
    else:
        dst = Path(out_path)
        if dst.exists() and dst.resolve() == src.resolve():
            raise TreeError("the output would overwrite the XML it reads", file=dst)
        try:
            dst.write_text(yaml_text, encoding="utf-8")
        except OSError as exc:
            raise TreeError(f"cannot write: {exc.strerror or exc}", file=dst) from None
        counts = element_counts(doc)
        trees = ", ".join(f"{t} ({n} nodes)" for t, n in counts.items())
        out.write(f"wrote {dst}: main tree {doc.main_tree}; trees: {trees}\n")
    if missing:
        err.write(
            f"btnav: note: btnav has no node types {', '.join(missing)} yet; "
            "the tree loads once they are registered\n"
        )
    return EXIT_OK


# --- tree show --------------------------------------------------------------------------


def tree_show_main(
    tree: str | PathLike[str],
    *,
    base_dir: str | PathLike[str] | None = None,
    out: TextIO | None = None,
) -> int:
    """Print the tree `tree` (a path, or the bare name of a bundled tree) with its ports.

    A tree btnav cannot build (a node type it lacks, a misspelt port) is shown as
    written, with `???` at the types btnav lacks, and then raises the error `btnav run`
    gives for it, so both commands say the same and exit 2.
    """
    out = out or sys.stdout
    path = find_tree(tree, base_dir=base_dir)
    doc = load_document(path)
    if unknown_node_types(doc, node_types()):
        out.write(f"{_head(path, doc)}\n{structure_text(doc)}")
        out.flush()
        build_tree(load_document(path), clock=SimClock())  # raises what `btnav run` would
        return EXIT_OK  # not reached while validation refuses unknown node types
    out.write(show_tree(path))
    return EXIT_OK


def _head(path: str | PathLike[str], doc: TreeDocument) -> str:
    return f"{path}: main tree {doc.main_tree}" if doc.main_tree else f"{path}"


def show_tree(path: str | PathLike[str]) -> str:
    """The text `tree show` prints for a tree file.

    When every node type is registered the tree is validated and built, and each line
    of py_trees' display gets the node's ports (`port=value`). Otherwise the file's
    structure is shown with its ports, and the node types btnav lacks are listed.
    """
    doc = load_document(path)
    missing = unknown_node_types(doc, node_types())
    head = _head(path, doc)
    if missing:
        body = structure_text(doc)
        foot = (
            f"\nnot in btnav ({len(missing)}; the tree cannot be built until they are "
            f"registered): {', '.join(missing)}\n"
        )
        return f"{head}\n{body}{foot}"
    return f"{head}\n{built_text(doc)}"


def ports_text(attrib: dict[str, str]) -> str:
    """`port=value ...` (values with spaces quoted), `name` left out."""
    parts = []
    for port, value in attrib.items():
        if port == "name":
            continue
        shown = f'"{value}"' if (not value or any(c.isspace() for c in value)) else value
        parts.append(f"{port}={shown}")
    return " ".join(parts)


def _label(elem: ET.Element, attrib: dict[str, str]) -> str:
    """What a line adds after py_trees' node name: the type when a name hides it, the ports."""
    bits = []
    name = attrib.get("name")
    if name and name != elem.tag:
        bits.append(f"<{elem.tag}>")
    ports = ports_text(attrib)
    if ports:
        bits.append(ports)
    return "  ".join(bits)


def _expanded(
    elem: ET.Element, trees: dict[str, ET.Element], subtree: ET.Element | None = None
) -> Iterator[tuple[ET.Element, ET.Element | None]]:
    """Elements in the order py_trees builds behaviours: a SubTree is replaced by its tree's root.

    Each comes with the SubTree element it stands for (its root only), else None.
    """
    if elem.tag in SUBTREE_TAGS:
        target = trees[elem.attrib["ID"]]
        yield from _expanded(target[0], trees, elem)
        return
    yield elem, subtree
    for child in elem:
        yield from _expanded(child, trees)


def _walk(root: Behaviour) -> Iterator[Behaviour]:
    yield root
    for child in root.children:
        yield from _walk(child)


def built_text(doc: TreeDocument) -> str:
    """py_trees' display of the built tree, each line followed by the node's ports."""
    trees = doc.trees
    main = doc.main_tree
    written = {elem: dict(elem.attrib) for elem in doc.root.iter()}  # before build fills defaults
    root = build_tree(doc, clock=SimClock())
    lines = tree_text(root).rstrip("\n").split("\n")
    elems = list(_expanded(trees[main][0], trees)) if main in trees else []
    behaviours = list(_walk(root))
    if len(lines) != len(behaviours) or len(elems) != len(behaviours):  # pragma: no cover
        return tree_text(root) + structure_text(doc)  # the display changed shape: show both
    out = []
    for line, (elem, subtree) in zip(lines, elems, strict=True):
        label = _label(elem, written.get(elem, dict(elem.attrib)))
        if subtree is not None:
            sub = written.get(subtree, dict(subtree.attrib))
            ports = ports_text({k: v for k, v in sub.items() if k != "ID"})
            label = f"[SubTree {sub.get('ID')}{' ' + ports if ports else ''}]  {label}".rstrip()
        out.append(f"{line}  {label}" if label else line)
    unused = [t for t in trees if t != main and not _reached(t, trees, main)]
    if unused:
        out.append(f"(trees not used by {main}: {', '.join(unused)})")
    return "\n".join(out) + "\n"


def _reached(tree_id: str, trees: dict[str, ET.Element], main: str | None) -> bool:
    seen: set[str] = set()
    todo = [main] if main in trees else []
    while todo:
        current = todo.pop()
        if current in seen:
            continue
        seen.add(current)
        for elem in trees[current].iter():
            if elem.tag in SUBTREE_TAGS and elem.attrib.get("ID") in trees:
                todo.append(elem.attrib["ID"])
    return tree_id in seen


def structure_text(doc: TreeDocument) -> str:
    """Each tree of the file as written (main tree first), with ports; nothing is built.

    Markers: `[+]` control, `-^-` decorator, `-->` leaf, `???` a type btnav lacks (`*`
    after its name), `>>>` a SubTree.
    """
    types = node_types()
    trees = doc.trees
    order = sorted(trees, key=lambda t: t != doc.main_tree)
    out: list[str] = []

    def node(elem: ET.Element, depth: int) -> None:
        pad = "    " * depth
        attrib = dict(elem.attrib)
        if elem.tag in SUBTREE_TAGS:
            ports = ports_text({k: v for k, v in attrib.items() if k != "ID"})
            out.append(f"{pad}>>> SubTree {attrib.get('ID')}  {ports}".rstrip())
            return
        cls = types.get(elem.tag)
        if cls is None:
            marker, tag = "???", f"{elem.tag}*"
        else:
            category = node_category(cls)
            marker = {"control": "[+]", "decorator": "-^-"}.get(category, "-->")
            tag = elem.tag
        name = attrib.get("name")
        title = f"{name} <{tag}>" if name and name != elem.tag else tag
        ports = ports_text(attrib)
        out.append(f"{pad}{marker} {title}  {ports}".rstrip())
        for child in elem:
            node(child, depth + 1)

    for i, tree_id in enumerate(order):
        if i:
            out.append("")
        out.append(f"tree {tree_id}{' (main)' if tree_id == doc.main_tree else ''}:")
        for elem in trees[tree_id]:
            node(elem, 1)
    return "\n".join(out) + "\n"


# --- tree palette -----------------------------------------------------------------------


def tree_palette_main(
    out_path: str | PathLike[str] | None = None,
    *,
    plugins: Sequence[str] = (),
    builtin: bool = True,
    out: TextIO | None = None,
) -> int:
    """Write Groot2's palette (`<TreeNodesModel>`) of every registered node type to
    `out_path`, or print it.

    `plugins` (modules or `.py` files, as a mission's `plugins:` list) are loaded first,
    so their nodes are in it; `builtin=False` leaves out BT.CPP's own nodes.
    """
    out = out or sys.stdout
    load_plugins(plugins, Path.cwd())
    models = palette_models(builtin=builtin)
    header = f"Groot2 palette of btnav {__version__}'s tree nodes, written by `btnav tree palette`"
    text = palette_xml(models, header=header)
    if out_path is None:
        out.write(text)
        return EXIT_OK
    dst = Path(out_path)
    try:
        dst.write_text(text, encoding="utf-8")
    except OSError as exc:
        raise TreeError(f"cannot write: {exc.strerror or exc}", file=dst) from None
    kinds = Counter(m.kind for m in models)
    counts = ", ".join(f"{n} {kind}" for kind, n in kinds.items())
    out.write(f"wrote {dst}: {len(models)} node types ({counts})\n")
    return EXIT_OK
