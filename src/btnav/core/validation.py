"""Pydantic validation of YAML documents, with errors that point into the file.

Every schema in btnav (params sections, worlds, missions, map metadata) is a
pydantic model; `validate` runs it on a document from `yaml_io` and turns the first
problem into a `ConfigError` with file, line, key path and, for an unknown key,
the closest valid spelling.
"""

from __future__ import annotations

import types
import typing
from collections.abc import Sequence
from typing import Any, TypeVar

import pydantic

from .errors import ConfigError
from .suggest import best_match
from .yaml_io import YamlMap, YamlSeq, file_of

M = TypeVar("M", bound=pydantic.BaseModel)


class StrictModel(pydantic.BaseModel):
    """Base for btnav schemas: unknown keys are errors, assignments are validated."""

    model_config = pydantic.ConfigDict(extra="forbid", validate_assignment=True)


def field_names(model: type[pydantic.BaseModel]) -> list[str]:
    """The spellings a user may write for a model's fields (names and aliases)."""
    names: list[str] = []
    for name, info in model.model_fields.items():
        names.append(info.alias or name)
    return names


def _models_in(annotation: Any) -> list[type[pydantic.BaseModel]]:
    """The pydantic models a field's annotation can hold (through Optional, list, dict, Union)."""
    if isinstance(annotation, type) and issubclass(annotation, pydantic.BaseModel):
        return [annotation]
    origin = typing.get_origin(annotation)
    if origin is typing.Annotated:
        return _models_in(typing.get_args(annotation)[0])
    if origin in (typing.Union, types.UnionType, list, tuple, dict, Sequence):
        out: list[type[pydantic.BaseModel]] = []
        for arg in typing.get_args(annotation):
            out += _models_in(arg)
        return out
    return []


def _model_at(
    model: type[pydantic.BaseModel], loc: Sequence[Any]
) -> list[type[pydantic.BaseModel]]:
    """The models that may sit at `loc` below `model` (to suggest a key's spelling)."""
    current = [model]
    for part in loc:
        if not isinstance(part, str):
            continue
        nxt: list[type[pydantic.BaseModel]] = []
        for m in current:
            for name, info in m.model_fields.items():
                if part in (name, info.alias):
                    nxt += _models_in(info.annotation)
            if m.__name__ == part:  # a union member's tag in the loc
                nxt.append(m)
        current = nxt or current
    return current


def _data_path(doc: Any, loc: Sequence[Any]) -> tuple[list[str | int], int | None]:
    """Walk `loc` through the document, skipping pydantic's union tags; return path and line."""
    path: list[str | int] = []
    node = doc
    line = getattr(doc, "line", None)
    for i, part in enumerate(loc):
        if isinstance(node, dict) and part in node:
            line = node.line_of(part) if isinstance(node, YamlMap) else line
            node = node[part]
            path.append(part)
        elif isinstance(node, list) and isinstance(part, int) and 0 <= part < len(node):
            line = node.line_of(part) if isinstance(node, YamlSeq) else line
            node = node[part]
            path.append(part)
        elif i == len(loc) - 1 and isinstance(part, str) and not part[:1].isupper():
            path.append(part)  # a missing key: name it, keep the line of its parent
    return path, line


def validation_error(
    exc: pydantic.ValidationError,
    model: type[pydantic.BaseModel],
    doc: Any,
    *,
    file: str | None = None,
    key_prefix: Sequence[str | int] = (),
    error_cls: type[ConfigError] = ConfigError,
) -> ConfigError:
    """Turn the first pydantic error into a located btnav error."""
    errors = exc.errors(include_url=False)
    # An unknown key is the most useful thing to report: it is usually a typo.
    errors.sort(key=lambda e: e["type"] != "extra_forbidden")
    err = errors[0]
    loc = list(err["loc"])
    path, line = _data_path(doc, loc)
    suggestion = None
    if err["type"] == "extra_forbidden":
        candidates = [n for m in _model_at(model, loc[:-1]) for n in field_names(m)]
        suggestion = best_match(str(loc[-1]), candidates)
        msg = f"unknown key '{loc[-1]}'"
        if suggestion is None and candidates:
            msg += f"; valid keys: {', '.join(sorted(set(candidates)))}"
    elif err["type"] == "missing":
        msg = "missing required key"
    else:
        got = err.get("input")
        if isinstance(got, dict):
            shown = "a mapping"
        elif isinstance(got, list):
            shown = "a list"
        else:
            shown = repr(got)
        if len(shown) > 60:
            shown = shown[:57] + "..."
        msg = f"{err['msg']} (got {shown})"
        if err["type"] == "value_error":  # our validators' own sentence, without pydantic's prefix
            msg = str(err.get("ctx", {}).get("error", err["msg"]))
            if not isinstance(got, dict | list):
                msg += f" (got {shown})"
    if len(errors) > 1:
        msg += f" [and {len(errors) - 1} more problem{'s' if len(errors) > 2 else ''}]"
    return error_cls(
        msg,
        file=file or file_of(doc),
        line=line,
        key=[*key_prefix, *path],
        suggestion=suggestion,
    )


def validate(
    model: type[M],
    doc: Any,
    *,
    file: str | None = None,
    key_prefix: Sequence[str | int] = (),
    error_cls: type[ConfigError] = ConfigError,
) -> M:
    """Validate a YAML document against a model; raise a located `ConfigError` on failure."""
    if doc is None:
        doc = YamlMap()
    try:
        return model.model_validate(doc)
    except pydantic.ValidationError as exc:
        raise validation_error(
            exc, model, doc, file=file, key_prefix=key_prefix, error_cls=error_cls
        ) from None
