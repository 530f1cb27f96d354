"""A tree file as an element tree (Nav2's XML shape) that remembers where each node came from.

Both spellings end here: Nav2 XML is parsed with expat so every element keeps its
line; btnav YAML is translated into the same elements (see `yaml_tree`). Validation
and building then work on this one shape, so XML and YAML cannot behave differently.
"""

from __future__ import annotations

import xml.etree.ElementTree as ET
from dataclasses import dataclass, field
from os import PathLike
from pathlib import Path
from xml.parsers import expat

from ..core.files import read_bytes
from .errors import TreeError


@dataclass
class Origin:
    """Where an element was written: its line, the lines of its attributes, a key path (YAML)."""

    line: int | None = None
    attr_lines: dict[str, int] = field(default_factory=dict)
    key: str | None = None

    def line_of(self, attr: str | None = None) -> int | None:
        if attr is None:
            return self.line
        return self.attr_lines.get(attr, self.line)


@dataclass
class TreeDocument:
    """`<root>` with its `<BehaviorTree ID=...>` children, plus where each element came from."""

    root: ET.Element
    file: str | None = None
    origins: dict[ET.Element, Origin] = field(default_factory=dict)

    @property
    def trees(self) -> dict[str, ET.Element]:
        return {bt.attrib.get("ID", ""): bt for bt in self.root.findall("BehaviorTree")}

    @property
    def main_tree(self) -> str | None:
        """`main_tree_to_execute`, or the only tree when there is one (as BT.CPP picks it)."""
        main = self.root.attrib.get("main_tree_to_execute")
        if main:
            return main
        trees = list(self.trees)
        return trees[0] if len(trees) == 1 else None

    def origin(self, elem: ET.Element) -> Origin:
        return self.origins.get(elem) or Origin()

    def error(
        self, message: str, elem: ET.Element | None = None, attr: str | None = None, **kw: object
    ) -> TreeError:
        """A TreeError located at `elem` (and its attribute `attr`)."""
        cls = kw.pop("cls", TreeError)
        origin = self.origin(elem) if elem is not None else Origin()
        key = origin.key
        if key is not None and attr is not None:
            key = f"{key}.{attr}"
        return cls(message, file=self.file, line=origin.line_of(attr), key=key, **kw)  # type: ignore[operator]

    def to_xml(self) -> str:
        """The document as Nav2 XML text (BTCPP_format 4)."""
        copy = ET.fromstring(ET.tostring(self.root))
        ET.indent(copy, space="  ")
        return ET.tostring(copy, encoding="unicode") + "\n"


def parse_xml_text(text: str | bytes, file: str | PathLike[str] | None = None) -> TreeDocument:
    """Parse BT.CPP / Nav2 XML; every element remembers its line. Errors are TreeErrors."""
    name = None if file is None else str(file)
    builder = ET.TreeBuilder()
    parser = expat.ParserCreate()
    origins: dict[ET.Element, Origin] = {}

    def start(tag: str, attrs: dict[str, str]) -> None:
        elem = builder.start(tag, attrs)
        origins[elem] = Origin(line=parser.CurrentLineNumber)

    parser.StartElementHandler = start
    parser.EndElementHandler = builder.end
    try:
        parser.Parse(text, True)
    except expat.ExpatError as exc:
        raise TreeError(
            f"invalid XML: {expat.ErrorString(exc.code)}", file=name, line=exc.lineno
        ) from None
    root = builder.close()
    if root.tag != "root":
        if root.tag == "BehaviorTree":  # a bare tree: wrap it as BT.CPP's root would
            wrapper = ET.Element("root", {"BTCPP_format": "4"})
            wrapper.append(root)
            root = wrapper
        else:
            raise TreeError(
                f"the top element must be <root>, found <{root.tag}>",
                file=name,
                line=origins.get(root, Origin()).line,
            )
    return TreeDocument(root=root, file=name, origins=origins)


def read_document(path: str | PathLike[str]) -> TreeDocument:
    """A `.xml` or `.yaml`/`.yml` tree file as a TreeDocument."""
    p = Path(path)
    data = read_bytes(p, error_cls=TreeError, what="tree file")
    if p.suffix.lower() == ".xml":
        return parse_xml_text(data, p)
    if p.suffix.lower() in (".yaml", ".yml"):
        from .yaml_tree import parse_yaml_text

        return parse_yaml_text(data, p)
    raise TreeError("a tree file must end in .xml, .yaml or .yml", file=p)
