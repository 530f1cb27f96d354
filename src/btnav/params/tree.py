"""Copying and reshaping YAML trees without losing the line of any key.

ROS reads `a: {b: 1}` and `a.b: 1` as the same parameter `a.b`; btnav expands the
dotted spelling into the nested one so every later step sees one shape. Overrides
(`--set`, `set_parameters`) are written into a copy the same way.
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from typing import Any

from ..core.errors import ParamsError
from ..core.errors import format_key_path as _fmt
from ..core.yaml_io import YamlMap, YamlSeq

#: A params document expanding (through YAML aliases) beyond this many nodes is refused.
MAX_NODES = 200_000


def count_nodes(node: Any, limit: int = MAX_NODES, file: str | None = None) -> int:
    """Nodes of the tree as a reader sees it (aliases counted each time), refusing huge ones."""
    memo: dict[int, int] = {}

    def size(n: Any) -> int:
        if isinstance(n, Mapping | list):
            if id(n) in memo:
                return memo[id(n)]
            items = n.values() if isinstance(n, Mapping) else n
            total = 1
            for child in items:
                total += size(child)
                if total > limit:
                    break
            memo[id(n)] = total
            return total
        return 1

    total = size(node)
    if total > limit:
        raise ParamsError(
            f"the document expands to more than {limit} values (through YAML aliases); "
            "btnav refuses such params files",
            file=file,
        )
    return total


def copy_tree(node: Any, file: str | None = None) -> Any:
    """A deep copy; plain dicts/lists become YamlMap/YamlSeq (lines kept where known)."""
    if isinstance(node, Mapping):
        out = YamlMap(file=getattr(node, "file", file), line=getattr(node, "line", None))
        lines = getattr(node, "key_lines", {})
        for key, value in node.items():
            out[key] = copy_tree(value, file)
            if key in lines:
                out.key_lines[key] = lines[key]
        return out
    if isinstance(node, list):
        seq = YamlSeq(file=getattr(node, "file", file), line=getattr(node, "line", None))
        seq.extend(copy_tree(v, file) for v in node)
        seq.item_lines.extend(getattr(node, "item_lines", []))
        return seq
    return node


def line_of(node: Any, key: Any) -> int | None:
    if isinstance(node, YamlMap):
        return node.line_of(key)
    if isinstance(node, YamlSeq) and isinstance(key, int):
        return node.line_of(key)
    return getattr(node, "line", None)


def expand_dotted(node: Any, path: Sequence[str | int], file: str | None) -> Any:
    """A copy of a ros__parameters tree with `a.b: v` keys nested as `a: {b: v}`.

    A parameter name must be a string; a dotted key that clashes with a value is an error.
    """
    if isinstance(node, list):
        seq = YamlSeq(file=file, line=getattr(node, "line", None))
        seq.extend(expand_dotted(v, [*path, i], file) for i, v in enumerate(node))
        seq.item_lines.extend(getattr(node, "item_lines", []))
        return seq
    if not isinstance(node, Mapping):
        return node
    out = YamlMap(file=file, line=getattr(node, "line", None))
    for key, value in node.items():
        line = line_of(node, key)
        if not isinstance(key, str) or not key:
            raise ParamsError(
                f"a parameter name must be a non-empty string, got {key!r}",
                file=file,
                line=line,
                key=list(path) or None,
            )
        parts = key.split(".")
        if any(not p for p in parts):
            raise ParamsError(
                f"'{key}' is not a valid parameter name", file=file, line=line, key=[*path, key]
            )
        target = out
        for i, part in enumerate(parts[:-1]):
            existing = target.get(part)
            if existing is None:
                existing = YamlMap(file=file, line=line)
                target[part] = existing
                target.key_lines[part] = line  # type: ignore[assignment]
            elif not isinstance(existing, YamlMap):
                raise ParamsError(
                    f"'{key}' puts a parameter inside '{part}', which is a value",
                    file=file,
                    line=line,
                    key=[*path, *parts[: i + 1]],
                )
            target = existing
        leaf = parts[-1]
        expanded = expand_dotted(value, [*path, *parts], file)
        if leaf in target:
            if isinstance(target[leaf], YamlMap) and isinstance(expanded, YamlMap):
                for k, v in expanded.items():
                    if k in target[leaf]:
                        raise ParamsError(
                            f"'{k}' is set twice (once in dotted form)",
                            file=file,
                            line=expanded.line_of(k),
                            key=[*path, *parts, k],
                        )
                    target[leaf][k] = v
                    target[leaf].key_lines[k] = expanded.line_of(k)
                continue
            raise ParamsError(
                f"'{_fmt([*parts])}' is set twice (once in dotted form)",
                file=file,
                line=line,
                key=[*path, *parts],
            )
        target[leaf] = expanded
        if line is not None:
            target.key_lines[leaf] = line
    return out


def set_path(root: YamlMap, parts: Sequence[str], value: Any, key: str) -> None:
    """Write `value` at `parts` below `root`, creating sections; `key` names it in errors."""
    node = root
    for i, part in enumerate(parts[:-1]):
        child = node.get(part)
        if child is None:
            child = YamlMap(file=root.file)
            node[part] = child
        elif not isinstance(child, YamlMap):
            raise ParamsError(
                f"'{'.'.join(parts[: i + 1])}' is a value, not a section, so '{key}' cannot be set",
                key=key,
            )
        node = child
    node[parts[-1]] = copy_tree(value)


def section_keys(node: Any) -> tuple[str, ...]:
    """The keys of a section (for listing what an ignored section held)."""
    if isinstance(node, Mapping):
        return tuple(str(k) for k in node)
    return ()


def drop_path(root: Any, parts: Sequence[str | int]) -> None:
    """Delete the key at `parts` below `root`, if it is there (a key Nav2 skips, taken out)."""
    node = root
    for part in parts[:-1]:
        in_map = isinstance(node, Mapping) and part in node
        in_list = isinstance(node, list) and isinstance(part, int) and 0 <= part < len(node)
        if not (in_map or in_list):
            return
        node = node[part]
    if parts and isinstance(node, dict) and parts[-1] in node:
        del node[parts[-1]]
