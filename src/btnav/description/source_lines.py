"""XML parsed with the line of every element kept, across the files a description spans.

xacro builds its documents with `xml.dom.minidom`, which forgets where an element was
written; after macros and includes are expanded nothing says which line of which file
an element came from. Here each file is parsed twice, once by expat (which reports the
line of every start tag, in document order) and once by minidom (the document xacro
works on), and every element gets a `btnav_src="<file index>:<line>"` attribute. xacro
copies attributes with the elements it clones (macro bodies, blocks), so an element of
the expanded URDF still says where in the user's files it was written.
"""

from __future__ import annotations

import xml.dom.minidom
import xml.etree.ElementTree as ET
import xml.parsers.expat
from dataclasses import dataclass, field
from pathlib import Path

from .errors import DescriptionError

#: The attribute that carries an element's place through xacro's expansion.
LINE_ATTR = "btnav_src"


@dataclass
class SourceFiles:
    """The files one description was read from; an element's place indexes into it."""

    files: list[str] = field(default_factory=list)

    def add(self, path: str | Path) -> int:
        name = str(path)
        if name in self.files:
            return self.files.index(name)
        self.files.append(name)
        return len(self.files) - 1

    def decode(self, value: str | None) -> tuple[str | None, int | None]:
        """`"1:17"` -> (the second file, line 17); anything else -> (None, None)."""
        if not value:
            return None, None
        index, _, line = value.partition(":")
        try:
            return self.files[int(index)], int(line)
        except (ValueError, IndexError):
            return None, None

    def place(self, element: ET.Element | None) -> tuple[str | None, int | None]:
        """(file, line) where `element` (of an expanded document) was written."""
        if element is None:
            return None, None
        return self.decode(element.get(LINE_ATTR))


def element_lines(data: bytes, file: str) -> list[int]:
    """The line of every start tag in `data`, in document order (a syntax error is located)."""
    lines: list[int] = []
    parser = xml.parsers.expat.ParserCreate()
    parser.StartElementHandler = lambda name, attrs: lines.append(parser.CurrentLineNumber)
    try:
        parser.Parse(data, True)
    except xml.parsers.expat.ExpatError as exc:
        message = xml.parsers.expat.ErrorString(exc.code)
        raise DescriptionError(
            f"not well-formed XML: {message}", file=file, line=exc.lineno
        ) from None
    return lines


def parse_with_lines(data: bytes, file: str, index: int) -> xml.dom.minidom.Document:
    """A minidom document of `data` whose every element carries its place (`LINE_ATTR`)."""
    lines = element_lines(data, file)
    try:
        doc = xml.dom.minidom.parseString(data)
    except xml.parsers.expat.ExpatError as exc:  # namespaces: an undeclared prefix
        message = xml.parsers.expat.ErrorString(exc.code)
        raise DescriptionError(
            f"not well-formed XML: {message}", file=file, line=exc.lineno
        ) from None
    elements = doc.getElementsByTagName("*")
    if len(elements) == len(lines):  # always, unless expat and minidom ever disagree
        for element, line in zip(elements, lines, strict=True):
            element.setAttribute(LINE_ATTR, f"{index}:{line}")
    return doc


def to_element_tree(doc: xml.dom.minidom.Document) -> ET.Element:
    """The document as an ElementTree element (namespaced tags read `{uri}name`)."""
    return ET.fromstring(doc.toxml())


def read_source(path: Path) -> bytes:
    """A description file's bytes; a missing or unreadable file is a located error."""
    try:
        return path.read_bytes()
    except FileNotFoundError:
        raise DescriptionError("robot description not found", file=path) from None
    except IsADirectoryError:
        raise DescriptionError(
            "is a folder, not a robot description (a Gazebo model folder needs a model.sdf)",
            file=path,
        ) from None
    except OSError as exc:
        raise DescriptionError(f"cannot read: {exc.strerror or exc}", file=path) from None
