"""Nav2 / BehaviorTree.CPP XML trees written in btnav's YAML spelling (`btnav tree import`).

```python
from btnav.bt.xml_to_yaml import import_xml
print(import_xml(Path("navigate_to_pose_w_replanning_and_recovery.xml").read_bytes()))
```

The output is the format `yaml_tree` reads: one-key nodes, `children` for controls,
`child` for decorators, ports as keys (`name` first, then the ports in the XML's
order), several trees under `trees:` with `main_tree`. It is made to be read and
edited by people: leaves with their ports fit on one line as a flow mapping,
`"{key}"` blackboard references are double-quoted, `true`/`false` and plain decimal
numbers are YAML booleans and numbers (spelled as in the XML, so `0.30` stays
`0.30`), and the XML comments are kept: the file's leading comment goes to the
header, a comment inside a tree goes above the node it precedes (or shares a line
with).

Whatever is written is read back and compared with the XML's element tree before
it is returned (`equivalence`), so an import never changes a tree silently. What
the YAML has no place for is refused or dropped on purpose: `<include>` is an error
(import the included file on its own), Groot's `<TreeNodesModel>` palette is
dropped, and so are `BTCPP_format` (btnav reads format 4) and attributes of
`<BehaviorTree>` other than `ID`.
"""

from __future__ import annotations

import json
import math
import re
import xml.etree.ElementTree as ET
from collections.abc import Iterable, Mapping
from dataclasses import dataclass, field
from functools import lru_cache
from os import PathLike
from xml.parsers import expat

from ..core.errors import YamlError
from ..core.yaml_io import load_yaml_text
from .document import TreeDocument, parse_xml_text
from .errors import TreeError
from .registry import node_category, node_types
from .validate import NON_TREE_ELEMENTS, SUBTREE_TAGS, is_blackboard_ref
from .yaml_tree import attribute_text, yaml_to_document

#: Lines longer than this are written in block style instead of as one flow line.
WIDTH = 100
INDENT = 2

#: Plain decimal numbers (no exponent, no leading zeros, no `+`): YAML reads them as the
#: same int or float, and BT.CPP reads their attribute text the same way.
_INT = re.compile(r"-?(?:0|[1-9][0-9]*)\Z")
_FLOAT = re.compile(r"-?(?:0|[1-9][0-9]*)\.[0-9]+\Z")
_BOOLS = {"true": True, "false": False}

#: Attributes that are always names (never numbers or booleans), whatever they look like.
_NAME_ATTRS = ("name", "ID")


# --- reading the XML ----------------------------------------------------------------


@dataclass
class _Comments:
    """XML comments: the file's leading ones, and those inside trees by the element they go with."""

    leading: list[str] = field(default_factory=list)
    by_element: dict[ET.Element, list[str]] = field(default_factory=dict)


def _read_comments(text: str | bytes, doc: TreeDocument) -> _Comments:
    """Comments with their lines (a second expat pass), matched to the document's elements.

    A comment before `<root>` is the file's description. A comment inside a tree goes
    with the element that starts on the same line before it, else with the next element.
    """
    found: list[tuple[int, int, str]] = []  # (line, column, text)
    starts: list[tuple[int, int]] = []  # (line, column) of each element start, in order
    parser = expat.ParserCreate()

    def comment(data: str) -> None:
        found.append((parser.CurrentLineNumber, parser.CurrentColumnNumber, data))

    def start(tag: str, attrs: dict[str, str]) -> None:
        starts.append((parser.CurrentLineNumber, parser.CurrentColumnNumber))

    parser.CommentHandler = comment
    parser.StartElementHandler = start
    parser.Parse(text, True)  # the text already parsed once, so it is well-formed

    elements = list(doc.root.iter())  # document order, as expat met them
    if len(elements) == len(starts) + 1:  # a bare <BehaviorTree> file: its <root> was added
        elements = elements[1:]
    out = _Comments()
    if len(elements) != len(starts):  # pragma: no cover - both passes read the same text
        return out
    tree_elements = set()
    for bt in doc.root.findall("BehaviorTree"):
        tree_elements.update(bt.iter())
    root_start = starts[0]
    for line, col, data in found:
        lines = _comment_lines(data)
        if not lines:
            continue
        if (line, col) < root_start:
            if out.leading:
                out.leading.append("")
            out.leading.extend(lines)
            continue
        target = None
        for elem, (eline, ecol) in zip(elements, starts, strict=True):
            if (eline, ecol) > (line, col):
                if target is None:
                    target = elem
                break
            if eline == line:  # a trailing comment on the element's own line
                target = elem
        if target is not None and target in tree_elements:
            out.by_element.setdefault(target, []).extend(lines)
    return out


def _comment_lines(data: str) -> list[str]:
    """The comment's text as lines, common indentation removed, outer blank lines dropped."""
    lines = [ln.rstrip() for ln in data.strip("\n").split("\n")]
    while lines and not lines[0].strip():
        lines.pop(0)
    while lines and not lines[-1].strip():
        lines.pop()
    margin = min((len(ln) - len(ln.lstrip()) for ln in lines if ln.strip()), default=0)
    return [ln[margin:] for ln in lines]


# --- values -----------------------------------------------------------------------------


def is_plain_number(text: str) -> bool:
    """`12`, `-1`, `0.30`: a decimal that YAML and BT.CPP both read as that number."""
    return bool(_INT.match(text) or _FLOAT.match(text))


def _canonical(text: str) -> bool:
    """YAML reads `text` as a value whose attribute text is `text` again, character for character."""
    value: object = int(text) if _INT.match(text) else float(text)
    return attribute_text(value) == text


@dataclass(frozen=True)
class _Value:
    text: str  # the YAML spelling
    plain_ok: bool  # may be written unquoted (already checked for the context)


@lru_cache(maxsize=4096)
def _plain_reads_back(text: str, flow: bool, as_key: bool) -> bool:
    """Whether `text` written unquoted (as a value or a key, in block or flow context) loads as that string."""
    if not text or text != text.strip() or any(c in text for c in "\n\r\t\"'#`"):
        return False
    if as_key:
        doc = f"{{{text}: 0}}" if flow else f"{text}: 0"
    else:
        doc = f"{{k: {text}}}" if flow else f"k: {text}"
    try:
        loaded = load_yaml_text(doc)
    except YamlError:
        return False
    if not isinstance(loaded, dict) or len(loaded) != 1:
        return False
    key, value = next(iter(loaded.items()))
    return (key == text and value == 0) if as_key else (key == "k" and value == text)


def _string(text: str, *, flow: bool, as_key: bool = False, force_quotes: bool = False) -> str:
    if not force_quotes and _plain_reads_back(text, flow, as_key):
        return text
    return _double_quoted(text)


#: Characters YAML does not allow raw in a stream, or reads as line breaks: escaped.
_YAML_UNSAFE = re.compile("[\x7f-\x9f\u2028\u2029\ufeff\ufffe\uffff]")


def _double_quoted(text: str) -> str:
    """A YAML double-quoted scalar (a JSON string is one), non-ASCII letters kept readable."""
    quoted = json.dumps(text, ensure_ascii=False)
    return _YAML_UNSAFE.sub(lambda m: f"\\u{ord(m.group()):04x}", quoted)


def _port_value(text: str, *, flow: bool, declared: object, is_name: bool) -> str:
    """One attribute's text as a YAML scalar: a boolean, a number, `"{key}"` or a string.

    A number-like value that YAML would respell (`1.10` reads as 1.1) stays a string
    when the registered node declares the port a string.
    """
    if not is_name:
        if text in _BOOLS:
            return text
        if is_plain_number(text) and (_canonical(text) or declared is not str):
            return text
    return _string(text, flow=flow, force_quotes=is_blackboard_ref(text))


# --- writing the YAML -------------------------------------------------------------------


class _Writer:
    def __init__(self, doc: TreeDocument, comments: _Comments, types: Mapping[str, type]):
        self.doc = doc
        self.comments = comments
        self.types = types

    def declared(self, node_type: str, port: str) -> object:
        """The port's declared type, or None for a node type or port btnav does not know."""
        cls = self.types.get(node_type)
        if cls is None or not hasattr(cls, "input_ports"):
            return None
        info = {**cls.input_ports(), **cls.output_ports()}.get(port)  # type: ignore[attr-defined]
        return None if info is None else info.data_type

    def comment_lines(self, elem: ET.Element, col: int) -> list[str]:
        return [
            (" " * col + "#" + (f" {ln}" if ln else "")).rstrip()
            for ln in self.comments.by_element.get(elem, [])
        ]

    def ports(self, elem: ET.Element) -> list[tuple[str, str]]:
        """`(port, text)` in the order written: ID and name first, then the XML's order."""
        for reserved in ("children", "child"):
            if reserved in elem.attrib:
                raise self.doc.error(
                    f"{elem.tag} has an attribute '{reserved}', which btnav's YAML uses for "
                    "child nodes; rename the port",
                    elem,
                    reserved,
                )
        first = [a for a in ("ID", "name") if a in elem.attrib and elem.tag in SUBTREE_TAGS]
        first = first or (["name"] if "name" in elem.attrib else [])
        rest = [a for a in elem.attrib if a not in first]
        return [(a, elem.attrib[a]) for a in [*first, *rest]]

    def port_items(self, elem: ET.Element, *, flow: bool) -> list[str]:
        return [
            f"{_string(port, flow=flow, as_key=True)}: "
            + _port_value(
                text,
                flow=flow,
                declared=self.declared(elem.tag, port),
                is_name=port in _NAME_ATTRS,
            )
            for port, text in self.ports(elem)
        ]

    def is_bare(self, elem: ET.Element) -> bool:
        return not elem.attrib and not len(elem)

    def flow_line(self, elem: ET.Element) -> str | None:
        """`Type: {port: value, ...}` (a decorator's bare child included), or None if it has more."""
        if len(elem) > 1 or (len(elem) == 1 and not self.is_bare(elem[0])):
            return None
        if len(elem) == 1 and (self.comments.by_element.get(elem[0]) or elem.tag in SUBTREE_TAGS):
            return None
        items = self.port_items(elem, flow=True)
        if len(elem) == 1:
            kind = "children" if self.is_control(elem) else "child"
            child = _string(elem[0].tag, flow=True)
            items.append(f"{kind}: [{child}]" if kind == "children" else f"child: {child}")
        return f"{_string(elem.tag, flow=True, as_key=True)}: {{{', '.join(items)}}}"

    def is_control(self, elem: ET.Element) -> bool:
        """Whether `elem`'s children go under `children` (a control) or `child` (a decorator).

        The registered node type says so; for a type btnav does not know, one child is a
        decorator's, as in every Nav2 tree.
        """
        if len(elem) != 1:
            return True
        cls = self.types.get(elem.tag)
        return cls is not None and node_category(cls) == "control"

    def node(self, elem: ET.Element, col: int) -> list[str]:
        """The node's lines; the first has no indentation (the caller writes its prefix)."""
        tag = _string(elem.tag, flow=False, as_key=True)
        if self.is_bare(elem):
            return [_string(elem.tag, flow=False)]
        line = self.flow_line(elem)
        if line is not None and col + len(line) <= WIDTH:
            return [line]
        pad = " " * (col + INDENT)
        lines = [f"{tag}:"]
        lines += [pad + item for item in self.port_items(elem, flow=False)]
        if not len(elem):
            return lines
        if self.is_control(elem):
            lines.append(pad + "children:")
            item_col = col + 2 * INDENT
            for child in elem:
                lines += self.comment_lines(child, item_col)
                sub = self.node(child, item_col + 2)
                lines.append(" " * item_col + "- " + sub[0])
                lines += sub[1:]
        else:
            child = elem[0]
            sub = self.node(child, col + 2 * INDENT)
            lines += self.comment_lines(child, col + INDENT)
            if len(sub) == 1 and self.is_bare(child):
                lines.append(pad + "child: " + sub[0])
            else:
                lines.append(pad + "child:")
                lines.append(" " * (col + 2 * INDENT) + sub[0])
                lines += sub[1:]
        return lines

    def trees(self) -> list[str]:
        lines: list[str] = []
        main = self.doc.main_tree
        if main is None:
            ids = ", ".join(self.doc.trees)
            raise self.doc.error(
                f"several trees ({ids}) and no main_tree_to_execute: say which one runs",
                self.doc.root,
            )
        lines.append(f"main_tree: {_string(main, flow=False)}")
        lines.append("trees:")
        for i, bt in enumerate(self.doc.root.findall("BehaviorTree")):
            tree_id = bt.attrib.get("ID")
            if not tree_id:
                raise self.doc.error("a <BehaviorTree> needs an ID", bt)
            if len(bt) != 1:
                raise self.doc.error(
                    f"tree '{tree_id}' must have exactly one root node, it has {len(bt)}", bt
                )
            if i:
                lines.append("")
            lines += self.comment_lines(bt, INDENT)
            key = " " * INDENT + _string(tree_id, flow=False, as_key=True) + ":"
            body = self.node(bt[0], 2 * INDENT)
            comments = self.comment_lines(bt[0], 2 * INDENT)
            if len(body) == 1 and self.is_bare(bt[0]) and not comments:
                lines.append(f"{key} {body[0]}")
            else:
                lines.append(key)
                lines += comments
                lines.append(" " * 2 * INDENT + body[0])
                lines += body[1:]
        return lines


def _check_root(doc: TreeDocument) -> None:
    for child in doc.root:
        if child.tag == "BehaviorTree" or child.tag == "TreeNodesModel":
            continue
        if child.tag in NON_TREE_ELEMENTS:
            raise doc.error(
                f"<{child.tag}> pulls in another file, and btnav's YAML has no include: "
                "import that file on its own and copy its trees under `trees:`",
                child,
            )
        raise doc.error(
            f"unexpected <{child.tag}> under <root> (expected <BehaviorTree ID=...>)", child
        )
    if not doc.root.findall("BehaviorTree"):
        raise doc.error("no <BehaviorTree> in the file (is it a node model?)", doc.root)


def document_to_yaml(
    doc: TreeDocument,
    *,
    header: Iterable[str] = (),
    types: Mapping[str, type] | None = None,
    _comments: _Comments | None = None,
) -> str:
    """A parsed XML tree document as btnav YAML text, checked to read back as the same trees.

    `header` lines become `#` comments at the top. `types` (default: btnav's node
    registry) only refines the style: a registered control with one child lists it
    under `children`, and a number-like value of a string port stays a string when
    YAML would respell it (`1.10`). The trees written are the same either way.
    """
    _check_root(doc)
    comments = _comments or _Comments()
    if types is None:
        types = node_types()
    lines = [("# " + h).rstrip() for h in header]
    if lines:
        lines.append("")
    lines += _Writer(doc, comments, types).trees()
    text = "\n".join(lines) + "\n"
    try:
        back = yaml_to_document(load_yaml_text(text))
    except (TreeError, YamlError) as exc:  # pragma: no cover - a bug in this writer
        raise RuntimeError(f"the YAML written for {doc.file} does not load: {exc}") from exc
    problem = equivalence(doc, back)
    if problem:  # pragma: no cover - a bug in this writer
        raise RuntimeError(f"the YAML written for {doc.file} differs from the XML: {problem}")
    return text


def import_xml(
    text: str | bytes,
    file: str | PathLike[str] | None = None,
    *,
    header: Iterable[str] = (),
    types: Mapping[str, type] | None = None,
    keep_comments: bool = True,
) -> str:
    """Nav2 / BT.CPP XML text -> btnav YAML text (XML comments kept as `#` comments).

    The header is `header`, then the XML file's leading comment. Problems are
    TreeErrors with the file and line.
    """
    doc = parse_xml_text(text, file)
    comments = _read_comments(text, doc) if keep_comments else _Comments()
    head = list(header)
    if comments.leading:
        if head:
            head.append("")
        head += comments.leading
    return document_to_yaml(doc, header=head, types=types, _comments=comments)


# --- comparing ----------------------------------------------------------------------------


def same_value(a: str, b: str) -> bool:
    """Two attribute texts mean the same: equal, or the same number (`0.30` and `0.3`)."""
    if a == b:
        return True
    if is_plain_number(a) and is_plain_number(b):
        fa, fb = float(a), float(b)
        return fa == fb or (math.isnan(fa) and math.isnan(fb))
    return False


def _same_node(a: ET.Element, b: ET.Element, where: str) -> str | None:
    if a.tag != b.tag:
        return f"{where}: <{a.tag}> became <{b.tag}>"
    here = f"{where}/{a.tag}"
    if set(a.attrib) != set(b.attrib):
        return f"{here}: attributes {sorted(a.attrib)} became {sorted(b.attrib)}"
    for attr, value in a.attrib.items():
        if not same_value(value, b.attrib[attr]):
            return f"{here}: {attr}={value!r} became {b.attrib[attr]!r}"
    if len(a) != len(b):
        return f"{here}: {len(a)} children became {len(b)}"
    for i, (ca, cb) in enumerate(zip(a, b, strict=True)):
        problem = _same_node(ca, cb, f"{here}[{i}]")
        if problem:
            return problem
    return None


def equivalence(a: TreeDocument, b: TreeDocument) -> str | None:
    """None when both documents hold the same trees and main tree; else the first difference.

    Trees are compared by ID; nodes by tag, attributes (values as text, numbers by
    value) and children in order. Groot's palette and `BTCPP_format` are not trees.
    """
    if a.main_tree != b.main_tree:
        return f"main tree {a.main_tree!r} became {b.main_tree!r}"
    ta, tb = a.trees, b.trees
    if list(ta) != list(tb):
        return f"trees {list(ta)} became {list(tb)}"
    for tree_id, bt in ta.items():
        other = tb[tree_id]
        if len(bt) != len(other):
            return f"{tree_id}: {len(bt)} root nodes became {len(other)}"
        for na, nb in zip(bt, other, strict=True):
            problem = _same_node(na, nb, tree_id)
            if problem:
                return problem
    return None


def element_counts(doc: TreeDocument) -> Mapping[str, int]:
    """Nodes per tree ID (for `tree import`'s summary)."""
    return {tree_id: sum(1 for _ in bt.iter()) - 1 for tree_id, bt in doc.trees.items()}
