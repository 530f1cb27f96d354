"""Safe YAML loading that remembers the line of every key and item.

Every btnav file format (params, worlds, maps, missions, trees) is read through
`load_yaml`, so every later error can name the line a user has to fix. Only plain
data is built: mappings, sequences, strings, numbers, booleans and null. Any other
tag (`!!python/object`, `!!binary`, `!custom`, ...) is refused, never constructed.
"""

from __future__ import annotations

from collections.abc import Sequence
from os import PathLike
from pathlib import Path
from typing import Any

import yaml

from .errors import YamlError
from .files import read_bytes

# The pure-Python parser on purpose: libyaml's C composer recurses without a limit and
# crashes the process on deeply nested input, while Python's raises RecursionError.
_Base = yaml.SafeLoader

#: Anchors/aliases beyond this count are refused: they would let a small file expand
#: into an exponentially large document ("billion laughs") downstream.
MAX_ALIASES = 1000


class YamlMap(dict):
    """A mapping that knows its file, its own line and the line of each key (1-based)."""

    file: str | None
    line: int | None
    key_lines: dict[Any, int]

    def __init__(self, *args: Any, file: str | None = None, line: int | None = None) -> None:
        super().__init__(*args)
        self.file = file
        self.line = line
        self.key_lines = {}

    def line_of(self, key: Any) -> int | None:
        return self.key_lines.get(key, self.line)


class YamlSeq(list):
    """A sequence that knows its file, its own line and the line of each item (1-based)."""

    file: str | None
    line: int | None
    item_lines: list[int]

    def __init__(self, *args: Any, file: str | None = None, line: int | None = None) -> None:
        super().__init__(*args)
        self.file = file
        self.line = line
        self.item_lines = []

    def line_of(self, index: int) -> int | None:
        if 0 <= index < len(self.item_lines):
            return self.item_lines[index]
        return self.line


def _line(node: yaml.Node) -> int:
    return node.start_mark.line + 1


class _LineLoader(_Base):  # type: ignore[misc, valid-type]
    file: str | None = None

    def __init__(self, stream: Any, file: str | None = None) -> None:
        super().__init__(stream)
        self.file = file
        self._aliases = 0

    def compose_node(self, parent: Any, index: Any) -> Any:  # count aliases as they are met
        if self.check_event(yaml.AliasEvent):
            self._aliases += 1
            if self._aliases > MAX_ALIASES:
                event = self.peek_event()
                raise YamlError(
                    f"more than {MAX_ALIASES} aliases; btnav refuses such documents",
                    file=self.file,
                    line=event.start_mark.line + 1,
                )
        return super().compose_node(parent, index)

    def construct_yaml_map_lines(self, node: yaml.MappingNode) -> Any:
        data = YamlMap(file=self.file, line=_line(node))
        yield data
        self.flatten_mapping(node)
        for key_node, value_node in node.value:
            key = self.construct_object(key_node, deep=True)
            try:
                hash(key)
            except TypeError:
                raise YamlError(
                    "a mapping key must be a plain value, not a list or mapping",
                    file=self.file,
                    line=_line(key_node),
                ) from None
            if key in data.key_lines:
                raise YamlError(
                    f"duplicate key '{key}' (first at line {data.key_lines[key]})",
                    file=self.file,
                    line=_line(key_node),
                    key=str(key),
                )
            data[key] = self.construct_object(value_node, deep=True)
            data.key_lines[key] = _line(key_node)

    def construct_yaml_seq_lines(self, node: yaml.SequenceNode) -> Any:
        data = YamlSeq(file=self.file, line=_line(node))
        yield data
        data.extend(self.construct_object(child, deep=True) for child in node.value)
        data.item_lines.extend(_line(child) for child in node.value)

    def construct_plain_str(self, node: yaml.ScalarNode) -> str:
        return str(self.construct_scalar(node))

    def construct_refused(self, node: yaml.Node) -> Any:
        raise YamlError(
            f"the tag '{node.tag}' is not allowed; btnav files hold plain data only "
            "(mappings, lists, strings, numbers, booleans, null)",
            file=self.file,
            line=_line(node),
        )


_LineLoader.add_constructor("tag:yaml.org,2002:map", _LineLoader.construct_yaml_map_lines)
_LineLoader.add_constructor("tag:yaml.org,2002:seq", _LineLoader.construct_yaml_seq_lines)
# A date-like scalar stays a string, as ROS's parameter parser reads it.
_LineLoader.add_constructor("tag:yaml.org,2002:timestamp", _LineLoader.construct_plain_str)
for _tag in ("binary", "omap", "pairs", "set"):
    _LineLoader.add_constructor(f"tag:yaml.org,2002:{_tag}", _LineLoader.construct_refused)
_LineLoader.add_constructor(None, _LineLoader.construct_refused)


#: PyYAML contexts whose mark is where the broken construct starts (an unclosed `[`, `{`
#: or quote, a key without its `:`): the parser only notices the mistake later, often on
#: the next line or at the end of the file, so the start is the line to fix.
_OPENED_HERE = {
    "while parsing a flow sequence": "the '[' opened on this line is not closed",
    "while parsing a flow mapping": "the '{' opened on this line is not closed",
    "while scanning a quoted scalar": "the quote opened on this line is not closed",
    "while scanning a simple key": "the key on this line has no ':'",
}
#: PyYAML's terser problems (by a part of their text) and what usually causes them.
_HINTS = {
    "character '\\t' that cannot start any token": "YAML indents with spaces, not tabs",
    "mapping values are not allowed here": (
        "is this line indented too far, or does it hold an unquoted ': '?"
    ),
    "expected <block end>": "check the indentation of this line",
}


def _run_on_start(text: str, line: int) -> int | None:
    """The line of a would-be key (`key:value`, no space) whose plain text ran on to `line`.

    A value that runs on (`b: 1` then a line indented too far) is not one: the line
    indented too far is the mistake there.
    """
    tokens: list[yaml.Token] = []
    try:
        for token in yaml.scan(text, Loader=_Base):
            tokens.append(token)
    except yaml.YAMLError:
        pass
    if not tokens or not isinstance(tokens[-1], yaml.ScalarToken) or not tokens[-1].plain:
        return None
    start = tokens[-1].start_mark.line + 1
    before = tokens[-2] if len(tokens) > 1 else None
    is_value = isinstance(before, yaml.ValueToken) and before.start_mark.line + 1 == start
    return start if start < line and not is_value else None


def syntax_error_place(
    exc: yaml.MarkedYAMLError, text: str | None = None
) -> tuple[int | None, str]:
    """The line a user has to fix for a YAML syntax error (1-based) and what to tell them.

    PyYAML marks where it noticed the problem, which for an unclosed bracket or quote
    is the line after the broken one (or the end of the file); its context mark is
    where the construct began. That start is used for the constructs in `_OPENED_HERE`;
    block contexts mark the enclosing block, not the mistake, so the problem's mark is
    kept for those, except when a plain scalar ran on from an earlier line (`key:value`
    without the space), which `text` (the document) lets us see.
    """
    problem = exc.problem or exc.context or "invalid YAML"
    problem_mark, context_mark = exc.problem_mark, exc.context_mark
    opened = _OPENED_HERE.get(exc.context or "")
    if opened is not None and context_mark is not None:
        line = context_mark.line + 1
        if problem_mark is None or problem_mark.line + 1 == line:
            return line, problem
        at_end = "end of stream" in problem
        where = "" if at_end else f" at line {problem_mark.line + 1}"
        return line, f"{opened} ({problem}{where})"
    mark = problem_mark or context_mark
    line = mark.line + 1 if mark is not None else None
    if text is not None and line is not None and "mapping values are not allowed" in problem:
        start = _run_on_start(text, line)
        if start is not None:  # `key:value` (no space) runs on into the next key's line
            return start, (
                f"the text on this line runs on into line {line} "
                "(a key needs ': ', a colon and a space, before its value)"
            )
    hint = next((h for text, h in _HINTS.items() if text in problem), None)
    return line, f"{problem} ({hint})" if hint else problem


def load_yaml_text(text: str | bytes, file: str | PathLike[str] | None = None) -> Any:
    """Parse one YAML document; any problem becomes a `YamlError` with file and line."""
    name = None if file is None else str(file)
    if isinstance(text, bytes):
        try:
            text = text.decode("utf-8")
        except UnicodeDecodeError as exc:
            raise YamlError(f"not UTF-8 text (byte {exc.start})", file=name) from None
    loader = None
    try:
        loader = _LineLoader(text, name)
        return loader.get_single_data()
    except YamlError:
        raise
    except yaml.MarkedYAMLError as exc:
        line, message = syntax_error_place(exc, text)
        raise YamlError(f"invalid YAML: {message}", file=name, line=line) from None
    except yaml.reader.ReaderError as exc:
        raise YamlError(
            f"invalid YAML: {exc.reason} (character {exc.character!r})", file=name
        ) from None
    except yaml.YAMLError as exc:
        raise YamlError(f"invalid YAML: {exc}", file=name) from None
    except RecursionError:
        raise YamlError("invalid YAML: nested too deeply", file=name) from None
    except ValueError as exc:  # e.g. an integer with more digits than Python converts
        raise YamlError(f"invalid YAML value: {exc}", file=name) from None
    finally:
        if loader is not None:
            loader.dispose()


def load_yaml(path: str | PathLike[str]) -> Any:
    """Read and parse a YAML file; a missing or unreadable file is a `YamlError` too."""
    return load_yaml_text(read_bytes(path, error_cls=YamlError), Path(path))


def line_at(doc: Any, path: Sequence[Any]) -> int | None:
    """The line of the deepest node of `path` that exists in `doc` (for error messages)."""
    line = getattr(doc, "line", None)
    node = doc
    for part in path:
        if (isinstance(node, YamlMap) and part in node) or (
            isinstance(node, YamlSeq) and isinstance(part, int) and 0 <= part < len(node)
        ):
            line = node.line_of(part)
            node = node[part]
        else:
            break
    return line


def file_of(doc: Any) -> str | None:
    return getattr(doc, "file", None)


def to_plain(doc: Any) -> Any:
    """Plain dicts and lists (for dumping, hashing or comparing)."""
    if isinstance(doc, dict):
        return {k: to_plain(v) for k, v in doc.items()}
    if isinstance(doc, list):
        return [to_plain(v) for v in doc]
    return doc
