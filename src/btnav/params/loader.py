"""Loading Nav2 params files as they are: `<server>: ros__parameters:`, nested costmaps, plugins.

Every top-level key is one of four things: a server btnav implements (validated
by its model, its plugin sections resolved), a Nav2 node btnav knows but does not
run (listed once as ignored), a near miss of either (an error with the closest
name), or a node Nav2 does not have (skipped, as Nav2 skips it: one warning).

Inside a server, a key Nav2 does not read is skipped the same way unless it is a
near miss of a real key (`schema.validate_section`); `load_params` warns once per
skipped key, or refuses the first one when strict loading is asked for.
"""

from __future__ import annotations

import warnings
from collections.abc import Mapping, Sequence
from os import PathLike
from pathlib import Path
from typing import Any

from ..core.errors import ParamsError
from ..core.suggest import best_match
from ..core.yaml_io import YamlMap, load_yaml
from .ignored import entry, ignored_keys, placeholder_tokens
from .legacy_keys import legacy_key
from .nav2_known import NAV2_KNOWN_NODES, known_node_reason
from .paramsfile import (
    IgnoredEntry,
    ParamsFile,
    Placeholder,
    PluginSection,
    ServerParams,
    SkippedKey,
)
from .placeholders import resolve_placeholders
from .plugin_sections import resolve_plugin
from .schema import validate_section
from .servers import SERVERS, PluginList, ServerSpec
from .tree import count_nodes, drop_path, expand_dotted, line_of

ROS_PARAMETERS = "ros__parameters"


def load_params(
    path: str | PathLike[str], *, strict: str | None = None, warn: bool = True
) -> ParamsFile:
    """Load and validate a Nav2 params file; any mistake is a located `BtnavError`.

    Each key Nav2 skips is a `BtnavWarning` (`warn=False`: only listed in `.skipped`);
    with `strict` (what asked for it: `--strict`, `strict_params: true`) the first is an
    error instead.
    """
    p = Path(path)
    params = load_params_doc(load_yaml(p), p)
    if strict:
        refuse_skipped(params, strict)
    elif warn:
        for skipped in params.skipped:
            warnings.warn(skipped.warning(), stacklevel=2)
    return params


def refuse_skipped(params: ParamsFile, why: str) -> None:
    """Raise the first key Nav2 skips as a located error; `why` names what made it one."""
    if not params.skipped:
        return
    more = len(params.skipped) - 1
    also = f"; {more} more key{'s' if more > 1 else ''} Nav2 skips" if more else ""
    raise params.skipped[0].error(f"{why} makes a key Nav2 skips an error{also}")


def load_params_doc(doc: Any, path: str | PathLike[str]) -> ParamsFile:
    """Validate an already parsed params document (`path` names it in errors)."""
    file = str(path)
    if doc is None:
        raise ParamsError(
            "the params file is empty; expected Nav2 server sections such as "
            "'controller_server: ros__parameters: ...'",
            file=file,
        )
    if not isinstance(doc, Mapping):
        raise ParamsError(
            "a params file maps server names ('controller_server:', ...) to their "
            f"ros__parameters, not a {type(doc).__name__}",
            file=file,
            line=getattr(doc, "line", None),
        )
    count_nodes(doc, file=file)
    try:
        params = _load(doc, Path(path), file)
    except RecursionError:
        raise ParamsError("the params file is nested too deeply", file=file) from None
    params.skipped.sort(key=lambda s: (s.line or 0, s.key))
    return params


def _load(doc: Mapping[Any, Any], path: Path, file: str) -> ParamsFile:
    raw = doc if isinstance(doc, YamlMap) else YamlMap(doc, file=file)
    params = ParamsFile(path=path, raw=raw, servers={})
    for top, value in doc.items():
        line = line_of(doc, top)
        if not isinstance(top, str):
            raise ParamsError(f"a server name must be a string, got {top!r}", file=file, line=line)
        name = server_name(top)
        spec = SERVERS.get(name)
        if spec is not None:
            if name in params.servers:
                raise ParamsError(
                    f"server '{name}' is configured twice (also at line {params.servers[name].line})",
                    file=file,
                    line=line,
                    key=top,
                )
            section, nesting, section_line = ros_parameters(spec, top, value, line, file)
            server, ignored = build_server(
                spec,
                section,
                nesting,
                section_line,
                file,
                params.placeholders,
                skipped=params.skipped,
            )
            params.servers[name] = server
            params.ignored += ignored
            continue
        reason = known_node_reason(name) or known_node_reason(top)
        if reason is None:
            params.skipped.append(_other_node(top, name, value, line, file))
            continue
        held = value.get(ROS_PARAMETERS, value) if isinstance(value, Mapping) else value
        params.ignored.append(entry([top], line, reason, file, held))
        _note_tokens(held, [top], params.placeholders)
    return params


def _other_node(top: str, name: str, value: Any, line: int | None, file: str) -> SkippedKey:
    """A top-level name that is no Nav2 node: skipped (Nav2's servers never read it), unless
    it is a near miss of one (an error), an old node name Nav2 refuses, or not a node's
    parameters at all (`ros__parameters:` at the top, a plain value)."""
    legacy = legacy_key("/", name)
    if legacy is None:
        near = best_match(name, [*SERVERS, *NAV2_KNOWN_NODES])
        if near is not None or name == ROS_PARAMETERS or not isinstance(value, Mapping):
            raise ParamsError(
                f"unknown server '{top}'; btnav implements {', '.join(SERVERS)}",
                file=file,
                line=line,
                key=top,
                suggestion=near,
            )
        message = (
            f"'{top}' is not a Nav2 node, so no Nav2 server reads its parameters; "
            "Nav2 ignores them too"
        )
        return SkippedKey(top, line, message, file, None, (top,))
    if legacy.refused:
        raise ParamsError(legacy.message(), file=file, line=line, key=top)
    return SkippedKey(top, line, legacy.message(), file, legacy.family.value, (top,))


def server_name(top: str) -> str:
    """`/controller_server` (an absolute node name) is `controller_server`."""
    return top if top == "/**" else top.lstrip("/")


def ros_parameters(
    spec: ServerSpec, top: str, value: Any, line: int | None, file: str
) -> tuple[YamlMap, tuple[str, ...], int | None]:
    """The server's ros__parameters mapping, the file's nesting of it, and its line."""
    nesting: tuple[str, ...] = (top,)
    node = value
    if (
        spec.nested
        and isinstance(node, Mapping)
        and spec.name in node
        and ROS_PARAMETERS not in node
    ):
        others = [k for k in node if k != spec.name]
        if others:
            raise ParamsError(
                f"unknown key '{others[0]}' in the '{top}' namespace; it holds the node "
                f"'{spec.name}:' only",
                file=file,
                line=line_of(node, others[0]),
                key=[top, str(others[0])],
            )
        line = line_of(node, spec.name)
        node = node[spec.name]
        nesting = (top, spec.name)
    if not isinstance(node, Mapping) or ROS_PARAMETERS not in node:
        keys = [str(k) for k in node] if isinstance(node, Mapping) else []
        hint = best_match(ROS_PARAMETERS, keys) if keys else None
        expected = (
            f"'{spec.name}: {spec.name}: {ROS_PARAMETERS}:'"
            if spec.nested
            else (f"'{spec.name}: {ROS_PARAMETERS}:'")
        )
        if hint is not None:
            raise ParamsError(
                f"unknown key '{hint}'; Nav2 reads a node's parameters from {expected}",
                file=file,
                line=line_of(node, hint),
                key=[*nesting, hint],
                suggestion=ROS_PARAMETERS,
            )
        if spec.nested and keys:
            near = best_match(spec.name, keys)
            if near is not None:
                raise ParamsError(
                    f"unknown node '{near}' in the '{top}' namespace; expected {expected}",
                    file=file,
                    line=line_of(node, near),
                    key=[*nesting, near],
                    suggestion=spec.name,
                )
        raise ParamsError(
            f"expected {expected} (a node's parameters sit under '{ROS_PARAMETERS}:')",
            file=file,
            line=line,
            key=list(nesting),
        )
    others = [k for k in node if k != ROS_PARAMETERS]
    if others:
        raise ParamsError(
            f"unknown key '{others[0]}' beside '{ROS_PARAMETERS}:'; parameters go inside it",
            file=file,
            line=line_of(node, others[0]),
            key=[*nesting, str(others[0])],
        )
    section = node[ROS_PARAMETERS]
    section_line = line_of(node, ROS_PARAMETERS)
    if section is None:
        section = YamlMap(file=file, line=section_line)
    if not isinstance(section, Mapping):
        raise ParamsError(
            f"'{ROS_PARAMETERS}' must map parameter names to values, not a {type(section).__name__}",
            file=file,
            line=section_line,
            key=list(nesting),
        )
    return section, nesting, line


def plugin_names(
    spec: ServerSpec, plist: PluginList, doc: Mapping[str, Any]
) -> tuple[list[str], bool]:
    """The names a plugin list holds (Nav2's defaults when absent) and whether default types apply.

    A malformed list yields no names: the server model reports it with its line.
    """
    defaults = spec.default_names(plist)
    raw: Any = doc.get(plist.key)
    if raw is None:
        return defaults, True
    if plist.single:
        names = [raw] if isinstance(raw, str) else []
    elif isinstance(raw, list) and all(isinstance(n, str) for n in raw):
        names = list(raw)
    else:
        names = []
    return names, plist.always_default_types or names == defaults


def build_server(
    spec: ServerSpec,
    section: Mapping[Any, Any],
    path: Sequence[str],
    line: int | None,
    file: str | None,
    placeholders: list[Placeholder],
    *,
    in_file: bool = True,
    skipped: list[SkippedKey] | None = None,
) -> tuple[ServerParams, list[IgnoredEntry]]:
    """Validate one server's parameters and resolve its plugin sections.

    The keys Nav2 would skip go to `skipped` and are taken out of the server's `doc`, so
    re-validating it (`set_parameters`) sees the section as Nav2 reads it.
    """
    found: list[SkippedKey] = []
    doc = expand_dotted(section, list(path), file)
    resolve_placeholders(doc, list(path), placeholders)
    lists: list[tuple[PluginList, list[str], bool]] = []
    listed: dict[str, str] = {}
    for plist in spec.plugin_lists:
        names, defaults_apply = plugin_names(spec, plist, doc)
        lists.append((plist, names, defaults_apply))
        for name in names:
            if name in listed and listed[name] != plist.key:
                raise ParamsError(
                    f"'{name}' is named by both {listed[name]} and {plist.key}",
                    file=file,
                    line=line_of(doc, plist.key),
                    key=[*path, plist.key],
                )
            listed[name] = plist.key
    server_doc, ignored = _server_keys(spec, doc, lists, listed, path, file)
    model = validate_section(
        spec.model, server_doc, key_prefix=list(path), file=file, skipped=found, scope=spec.name
    )
    ignored += ignored_keys(model, server_doc, list(path), file)
    plugins: dict[str, PluginSection] = {}
    for plist, names, defaults_apply in lists:
        for name in names:
            plugin, plugin_ignored = resolve_plugin(
                plist, name, doc, defaults_apply, path, file, found
            )
            plugins[name] = plugin
            ignored += plugin_ignored
            if plugin.cls is None and name in doc:
                _note_tokens(doc[name], [*path, name], placeholders)
    for skip in found:
        drop_path(doc, skip.parts[len(path) :])
    if skipped is not None:
        skipped += found
    server = ServerParams(
        name=spec.name,
        model=model,
        plugins=plugins,
        path=tuple(path),
        line=line,
        doc=doc,
        in_file=in_file,
    )
    return server, ignored


def _server_keys(
    spec: ServerSpec,
    doc: YamlMap,
    lists: list[tuple[PluginList, list[str], bool]],
    listed: dict[str, str],
    path: Sequence[str],
    file: str | None,
) -> tuple[YamlMap, list[IgnoredEntry]]:
    """The server's own keys (plugin sections taken out), and unlisted plugin sections ignored.

    Nav2 skips a section with `plugin:` that no list names (nav2_params.yaml has one:
    local_costmap's static_layer); btnav lists it as ignored. But when its name is
    a near miss of a listed name that has no section and runs on Nav2's default
    type, it is a typo that would leave the user's settings unread: an error.
    """
    fields = spec.model.model_fields
    defaulted = [
        n
        for plist, names, apply in lists
        for n in names
        if apply and n in plist.default_types and n not in doc
    ]
    where = " or ".join(p.key for p in spec.plugin_lists)
    ignored: list[IgnoredEntry] = []
    server_doc = YamlMap(file=file, line=doc.line)
    for key, value in doc.items():
        if key in fields:
            pass
        elif key in listed:
            continue
        elif spec.plugin_lists and isinstance(value, Mapping) and "plugin" in value:
            near = best_match(str(key), defaulted)
            if near is not None:
                raise ParamsError(
                    f"section '{key}' is not listed in {listed[near]}, so it would be ignored "
                    f"while '{near}' (listed, no section) runs with Nav2's default type",
                    file=file,
                    line=line_of(doc, key),
                    key=[*path, key],
                    suggestion=near,
                )
            reason = f"not listed in {where}, so Nav2 does not load it"
            ignored.append(entry([*path, key], line_of(doc, key), reason, file, value))
            continue
        server_doc[key] = value
        server_doc.key_lines[key] = line_of(doc, key)  # type: ignore[assignment]
    return server_doc, ignored


def _note_tokens(node: Any, path: list[str | int], placeholders: list[Placeholder]) -> None:
    """Launch tokens (KEEPOUT_ZONE_ENABLED) inside an ignored section: accepted, and said so."""
    from ..core.errors import format_key_path

    for where, line, token in placeholder_tokens(node, path):
        placeholders.append(
            Placeholder(
                key=format_key_path(where) or "",
                line=line,
                text=token,
                resolved="accepted as written: the section is ignored",
            )
        )


def server_spec(name: str) -> ServerSpec:
    """The spec of an implemented server (`local_costmap.local_costmap` works too)."""
    parts = name.split(".")
    base = server_name(parts[0])
    spec = SERVERS.get(base)
    if spec is None or len(parts) > 2 or (len(parts) == 2 and parts[1] != base):
        raise ParamsError(
            f"unknown server '{name}'; btnav implements {', '.join(SERVERS)}",
            key=name,
            suggestion=best_match(base, list(SERVERS)),
        )
    return spec


def server_params(params: ParamsFile, name: str) -> ServerParams:
    """The server from the file, or one built from Nav2's defaults when the file has none."""
    spec = server_spec(name)
    if spec.name in params.servers:
        return params.servers[spec.name]
    path = (spec.name, spec.name) if spec.nested else (spec.name,)
    server, _ = build_server(spec, YamlMap(), path, None, str(params.path), [], in_file=False)
    return server
