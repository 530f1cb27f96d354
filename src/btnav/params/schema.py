"""The vocabulary params models are written in, and the one place they are run.

- `ignored(default, reason)` marks a Nav2 key btnav accepts but does not act on;
  the loader lists every such key a file sets, once, with the reason. Plugin
  authors use the same marker in their `Params`.
- `one_of(...)` is a string choice whose error suggests the closest choice.
- `Points` parses Nav2's footprint/polygon strings (`"[[x, y], ...]"`).
- `FieldProblem` lets a cross-key check (`min_particles <= max_particles`) point
  at the key that is wrong instead of at the whole section.
- `validate_section` runs a model on a YAML section and raises a `ParamsError`
  with file, line, dotted key and did-you-mean; given a `skipped` list, it leaves out
  the keys Nav2 would skip (each recorded once) instead of refusing them.
"""

from __future__ import annotations

import math
import re
from collections.abc import Callable, Mapping, Sequence
from typing import Annotated, Any

import pydantic
from pydantic import AfterValidator, BeforeValidator, ConfigDict, Field, field_validator
from pydantic_core import PydanticUndefined

from ..core.errors import BtnavError, ParamsError, format_key_path
from ..core.suggest import best_match
from ..core.validation import StrictModel, _model_at, field_names, validation_error
from ..core.yaml_io import file_of, line_at, load_yaml_text
from .legacy_keys import legacy_key
from .paramsfile import SkippedKey
from .tree import copy_tree, drop_path

#: json_schema_extra key that marks a field as accepted-but-ignored (value: the reason).
IGNORED = "btnav_ignored"
#: json_schema_extra key of a dict field that holds sub-sections named by a list key.
NAMED_SECTIONS = "btnav_named_sections"

#: An all-caps launch placeholder such as KEEPOUT_ZONE_ENABLED.
PLACEHOLDER_TOKEN = re.compile(r"^[A-Z][A-Z0-9]*(?:_[A-Z0-9]+)+$")


class Why:
    """Reasons shared by many ignored keys (one wording, everywhere)."""

    TOPIC = "a ROS topic name: btnav components exchange messages directly"
    QOS = "a ROS topic QoS setting: btnav components exchange messages directly"
    TF = "a transform timeout: btnav's frame tree is exact and never late"
    ROS = "ROS node plumbing (QoS, lifecycle bonds, introspection): btnav has no ROS graph"
    REALTIME = "thread priority: btnav runs one deterministic loop on simulated time"
    SIM_TIME = "btnav always runs on simulated time"
    GROOT = "Groot monitoring: btnav writes bt_log.jsonl instead"
    VIZ = "visualisation for RViz: use btnav's png/gif outputs instead"
    SERVICE = "a ROS service or action timeout: btnav calls servers in-process"


def ignored(
    default: Any = PydanticUndefined,
    reason: str = Why.ROS,
    **kwargs: Any,
) -> Any:
    """A field Nav2 has and btnav accepts but does not act on; setting it is reported once."""
    return Field(default, json_schema_extra={IGNORED: reason}, **kwargs)


def named_sections(list_key: str, ignored_reason: str | None = None) -> Any:
    """A dict field holding the sub-sections named by `list_key` (filled by `gather_sections`).

    With `ignored_reason`, the sections are accepted unread and each is listed as ignored.
    """
    extra: dict[str, Any] = {NAMED_SECTIONS: list_key}
    if ignored_reason:
        extra[IGNORED] = ignored_reason
    return Field(default_factory=dict, json_schema_extra=extra)


def field_reason(info: pydantic.fields.FieldInfo) -> str | None:
    extra = info.json_schema_extra
    return extra.get(IGNORED) if isinstance(extra, dict) else None  # type: ignore[return-value]


def field_named_list(info: pydantic.fields.FieldInfo) -> str | None:
    extra = info.json_schema_extra
    return extra.get(NAMED_SECTIONS) if isinstance(extra, dict) else None  # type: ignore[return-value]


#: ROS integer parameters are 64-bit.
INT64_MAX = 2**63 - 1


class ParamsModel(StrictModel):
    """Base of btnav's params models: strict keys, finite numbers, 64-bit integers (as ROS)."""

    model_config = ConfigDict(extra="forbid", validate_assignment=True, allow_inf_nan=False)

    @field_validator("*", mode="after")
    @classmethod
    def _int64(cls, value: Any) -> Any:
        if isinstance(value, int) and not isinstance(value, bool) and abs(value) > INT64_MAX:
            raise ValueError("is beyond a 64-bit integer, the range of a ROS integer parameter")
        return value


class FieldProblem(ValueError):
    """A cross-key check failed; `key` (relative to the model) is where the user must look.

    `unknown` marks a key the model does not have (a sub-section's own validation found
    it): the loader treats it as pydantic's unknown keys, a warning unless it is a near miss.
    """

    def __init__(
        self,
        key: str | Sequence[str | int],
        message: str,
        suggestion: str | None = None,
        *,
        unknown: bool = False,
    ) -> None:
        self.key: tuple[str | int, ...] = (key,) if isinstance(key, str) else tuple(key)
        self.message = message
        self.suggestion = suggestion
        self.unknown = unknown
        super().__init__(message)


class ChoiceError(ValueError):
    """A string that is not one of the allowed values; carries the closest one."""

    def __init__(self, value: str, choices: Sequence[str]) -> None:
        self.suggestion = best_match(value, choices)
        super().__init__("must be one of " + ", ".join(repr(c) for c in choices))


def one_of(*choices: str) -> Any:
    """A `str` type limited to `choices`; a wrong value suggests the closest choice."""

    def check(value: str) -> str:
        if value not in choices:
            raise ChoiceError(value, choices)
        return value

    return Annotated[str, AfterValidator(check)]


def _finite(value: Any, what: str) -> float:
    if isinstance(value, bool) or not isinstance(value, int | float):
        raise ValueError(f"{what} must be a number, got {value!r}")
    try:
        out = float(value)
    except OverflowError:
        raise ValueError(f"{what} is too large") from None
    if not math.isfinite(out):
        raise ValueError(f"{what} must be finite")
    return out


def parse_points(value: Any, min_points: int = 3) -> tuple[tuple[float, float], ...]:
    """Nav2 writes polygons as a string `"[[x, y], ...]"`; a YAML list is accepted too.

    An empty string or `"[]"` means "no polygon" (a costmap then uses robot_radius).
    """
    example = '"[[0.3, 0.25], [0.3, -0.25], [-0.3, -0.25], [-0.3, 0.25]]"'
    if value is None:
        return ()
    if isinstance(value, str):
        text = value.strip()
        if text in ("", "[]"):
            return ()
        try:
            value = load_yaml_text(text)
        except BtnavError:
            raise ValueError(f"must be a list of [x, y] points, e.g. {example}") from None
    if not isinstance(value, list | tuple):
        raise ValueError(f"must be a list of [x, y] points, e.g. {example}")
    points = []
    for point in value:
        if not isinstance(point, list | tuple) or len(point) != 2:
            raise ValueError(f"each point must be [x, y], got {point!r}")
        points.append((_finite(point[0], "x"), _finite(point[1], "y")))
    if 0 < len(points) < min_points:
        raise ValueError(f"a polygon needs at least {min_points} points, got {len(points)}")
    return tuple(points)


def _unique(names: list[str]) -> list[str]:
    seen: set[str] = set()
    for name in names:
        if name in seen:
            raise ValueError(f"'{name}' is listed twice")
        seen.add(name)
    return names


#: A list of section names (`planner_plugins`, `polygons`, ...): each name once.
Names = Annotated[list[str], AfterValidator(_unique)]

#: A frame id; empty is never valid.
Frame = Annotated[str, Field(min_length=1)]

#: A polygon (costmap footprint, collision polygon) written Nav2's way.
Points = Annotated[tuple[tuple[float, float], ...], BeforeValidator(parse_points)]


def gather_sections(
    cls: type[pydantic.BaseModel], data: Any, list_key: str, into: str, default: Sequence[str] = ()
) -> Any:
    """Move the sub-sections named by `data[list_key]` into `data[into]` (a before-validator step).

    Nav2 names sub-sections by a list (`polygons: [a, b]` then `a:` and `b:` beside
    it); pydantic needs them in one field. A listed name without a section is an
    error on the list key, as Nav2 refuses it too.
    """
    if not isinstance(data, Mapping):
        return data
    if into in data:
        raise FieldProblem(into, f"unknown key '{into}'")
    names = data.get(list_key, list(default))
    out = dict(data)
    sections: dict[Any, Any] = {}
    if isinstance(names, list) and all(isinstance(n, str) for n in names):
        for name in names:
            if name in cls.model_fields:
                raise FieldProblem(list_key, f"'{name}' is a key of this section, not a name")
            if name not in data:
                candidates = [k for k, v in data.items() if isinstance(v, Mapping)]
                raise FieldProblem(
                    list_key,
                    f"'{name}' is listed but has no section '{name}:'",
                    suggestion=best_match(name, [str(c) for c in candidates]),
                )
            sections[name] = out.pop(name)
    out[into] = sections
    return out


def _doc_path(doc: Any, loc: Sequence[Any]) -> list[str | int]:
    """The parts of a pydantic `loc` that exist in the document (skips field-only parts)."""
    path: list[str | int] = []
    node = doc
    for part in loc:
        in_map = isinstance(node, Mapping) and part in node
        in_list = isinstance(node, list) and isinstance(part, int) and 0 <= part < len(node)
        if in_map or in_list:
            node = node[part]
            path.append(part)
    return path


def _first_error(exc: pydantic.ValidationError) -> dict[str, Any]:
    # The same choice core.validation makes: an unknown key first (usually a typo).
    errors = sorted(exc.errors(include_url=False), key=lambda e: e["type"] != "extra_forbidden")
    return dict(errors[0])


def section_problem(
    exc: pydantic.ValidationError,
    model: type[pydantic.BaseModel],
    label: str,
    place: Callable[[tuple[str, ...]], tuple[str | int, ...]],
) -> FieldProblem:
    """The first problem of a sub-section validated apart from its section (a critic's own
    Params), placed in the file by `place(loc)`; an unknown key names the closest valid one."""
    err = _first_error(exc)
    loc = tuple(str(part) for part in err["loc"])
    if err["type"] == "extra_forbidden" and loc:
        return FieldProblem(
            place(loc),
            f"unknown key '{loc[-1]}' for {label}",
            suggestion=best_match(loc[-1], list(model.model_fields)),
            unknown=True,
        )
    return FieldProblem(place(loc), err["msg"])


def validate_section(
    model: type[pydantic.BaseModel],
    doc: Any,
    *,
    key_prefix: Sequence[str | int] = (),
    file: str | None = None,
    skipped: list[SkippedKey] | None = None,
    scope: str = "",
) -> Any:
    """Validate one params section; the first problem becomes a located `ParamsError`.

    With a `skipped` list, a key the model does not have is handled as Nav2 handles it:
    left unread, recorded in `skipped` (one warning each) and validated without. A near
    miss of a real key (did-you-mean finds one) stays the error, unless the catalogue of
    legacy names (`legacy_keys`, looked up in `scope`) knows the key: a catalogue hit
    wins, and a name Nav2 refuses is an error naming what to write instead.
    """
    work = doc if doc is not None else {}
    copied = False
    while True:
        try:
            return model.model_validate(work)
        except pydantic.ValidationError as exc:
            found = None
            if skipped is not None:
                found = _skippable(exc, model, work, key_prefix, file or file_of(doc), scope)
            if skipped is None or not found:
                raise _params_error(exc, model, work, key_prefix, file) from None
            if not copied:  # the caller's document stays as the file wrote it
                work = copy_tree(work, file or file_of(doc))
                copied = True
            for entry, path in found:
                drop_path(work, path)
                skipped.append(entry)


def _unknown_key(
    err: Any, model: type[pydantic.BaseModel], doc: Any
) -> tuple[list[str | int], str, str | None, str | None] | None:
    """(path in the document, the key, the closest real key, the sub-model's own sentence)
    when `err` is about a key the model does not have; None for any other problem."""
    loc = tuple(err["loc"])
    if err["type"] == "extra_forbidden" and loc:
        path = _doc_path(doc, loc)
        if not path or path[-1] != loc[-1]:
            return None
        candidates = [n for m in _model_at(model, loc[:-1]) for n in field_names(m)]
        return path, str(loc[-1]), best_match(str(loc[-1]), candidates), None
    cause = (err.get("ctx") or {}).get("error")
    if isinstance(cause, FieldProblem) and cause.unknown and cause.key:
        path = _doc_path(doc, [*loc, *cause.key])
        if not path or path[-1] != cause.key[-1]:
            return None
        return path, str(cause.key[-1]), cause.suggestion, cause.message
    return None


def _skippable(
    exc: pydantic.ValidationError,
    model: type[pydantic.BaseModel],
    doc: Any,
    key_prefix: Sequence[str | int],
    file: str | None,
    scope: str,
) -> list[tuple[SkippedKey, list[str | int]]] | None:
    """The unknown keys Nav2 would skip, when the first problem is one of them; else None
    (the first problem is a near miss or a wrong value: the caller raises it). A legacy
    name Nav2 refuses raises here."""
    errors = sorted(exc.errors(include_url=False), key=lambda e: e["type"] != "extra_forbidden")
    out: list[tuple[SkippedKey, list[str | int]]] = []
    for i, err in enumerate(errors):
        unknown = _unknown_key(err, model, doc)
        if unknown is None:
            if i == 0:
                return None
            continue
        path, name, suggestion, sentence = unknown
        key = [*key_prefix, *path]
        line = line_at(doc, path)
        legacy = legacy_key(scope, name)
        if legacy is not None and legacy.refused:
            if i == 0:
                raise ParamsError(legacy.message(scope), file=file, line=line, key=key)
            continue
        if legacy is None and suggestion is not None:  # a near miss: the user's typo
            if i == 0:
                return None
            continue
        if legacy is not None:
            message, family = legacy.message(scope, _value_at(doc, path)), legacy.family.value
        else:
            what = sentence or f"unknown key '{name}' (not a parameter {_reader(scope)} reads)"
            message, family = f"{what}; Nav2 ignores it too", None
        skip = SkippedKey(format_key_path(key) or name, line, message, file, family, tuple(key))
        out.append((skip, path))
    return out


def _value_at(doc: Any, path: Sequence[str | int]) -> Any:
    node = doc
    for part in path:
        node = node[part]
    return node


def _reader(scope: str) -> str:
    """Who reads a scope's keys, for a sentence: `DWBLocalPlanner`, `controller_server`."""
    if not scope:
        return "this section"
    return scope.rsplit("/", 1)[-1] if ":" in scope else scope


def _params_error(
    exc: pydantic.ValidationError,
    model: type[pydantic.BaseModel],
    doc: Any,
    key_prefix: Sequence[str | int],
    file: str | None,
) -> ParamsError:
    first = _first_error(exc)
    cause = (first.get("ctx") or {}).get("error")
    file = file or file_of(doc)
    if isinstance(cause, FieldProblem):
        path = _doc_path(doc, [*first["loc"], *cause.key])
        # A key the file does not have (yet) is still named, at its section's line.
        tail = list(cause.key[-1:]) if cause.key and path[-1:] != list(cause.key[-1:]) else []
        return ParamsError(
            cause.message,
            file=file,
            line=line_at(doc, path),
            key=[*key_prefix, *path, *tail],
            suggestion=cause.suggestion,
        )
    err = validation_error(exc, model, doc, file=file, key_prefix=key_prefix, error_cls=ParamsError)
    assert isinstance(err, ParamsError)
    if isinstance(cause, ChoiceError) and cause.suggestion:
        err.suggestion = cause.suggestion
    got = first.get("input")
    if first["type"].startswith("bool") and isinstance(got, str) and PLACEHOLDER_TOKEN.match(got):
        err.message += (
            f"; '{got}' is a launch-file placeholder, accepted only in sections btnav "
            "ignores: write true or false here"
        )
    err.args = (str(err),)
    return err
