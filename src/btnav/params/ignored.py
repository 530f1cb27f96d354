"""Listing the keys a file sets that btnav accepts but does not act on.

The models mark such keys with `schema.ignored(...)`; this walks a validated model
beside the section it came from and lists each marked key the file wrote, once.
Keys left at their default are not listed: the user did not ask for anything.
"""

from __future__ import annotations

from collections.abc import Mapping
from typing import Any

import pydantic

from ..core.errors import format_key_path
from .paramsfile import IgnoredEntry
from .schema import PLACEHOLDER_TOKEN, field_named_list, field_reason
from .tree import line_of, section_keys


def ignored_keys(
    model: pydantic.BaseModel, doc: Any, path: list[str | int], file: str | None
) -> list[IgnoredEntry]:
    """The ignored-marked keys `doc` sets, at any depth of `model`."""
    out: list[IgnoredEntry] = []
    if not isinstance(doc, Mapping):
        return out
    for name, info in type(model).model_fields.items():
        key = info.alias or name
        reason = field_reason(info)
        value = getattr(model, name, None)
        if field_named_list(info) is not None:
            for section, sub in (value or {}).items():
                if section not in doc:
                    continue
                where = [*path, section]
                if reason:
                    out.append(entry(where, line_of(doc, section), reason, file, doc[section]))
                elif isinstance(sub, pydantic.BaseModel):
                    out += ignored_keys(sub, doc[section], where, file)
            continue
        if key not in doc or name not in model.model_fields_set:
            continue
        where = [*path, key]
        if reason:
            out.append(entry(where, line_of(doc, key), reason, file, doc[key]))
        else:
            out += _nested(value, doc[key], where, file)
    return out


def _nested(value: Any, doc: Any, path: list[str | int], file: str | None) -> list[IgnoredEntry]:
    if isinstance(value, pydantic.BaseModel):
        return ignored_keys(value, doc, path, file)
    out: list[IgnoredEntry] = []
    if isinstance(value, list | tuple) and isinstance(doc, list):
        for i, (v, d) in enumerate(zip(value, doc, strict=False)):
            out += _nested(v, d, [*path, i], file)
    elif isinstance(value, Mapping) and isinstance(doc, Mapping):
        for k, v in value.items():
            if k in doc:
                out += _nested(v, doc[k], [*path, k], file)
    return out


def entry(
    path: list[str | int], line: int | None, reason: str, file: str | None, value: Any = None
) -> IgnoredEntry:
    return IgnoredEntry(
        key=format_key_path(path) or "",
        line=line,
        reason=reason,
        file=file,
        keys=section_keys(value),
    )


def placeholder_tokens(
    node: Any, path: list[str | int]
) -> list[tuple[list[str | int], int | None, str]]:
    """All-caps launch tokens (KEEPOUT_ZONE_ENABLED) in a section: (path, line, token) each."""
    found: list[tuple[list[str | int], int | None, str]] = []
    if isinstance(node, Mapping):
        items: Any = node.items()
    elif isinstance(node, list):
        items = enumerate(node)
    else:
        return found
    for key, value in items:
        if isinstance(value, str) and PLACEHOLDER_TOKEN.match(value):
            found.append(([*path, key], line_of(node, key), value))
        else:
            found += placeholder_tokens(value, [*path, key])
    return found
