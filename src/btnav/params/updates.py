"""Changing params after loading: Nav2's dynamic parameters, and `btnav run --set` overrides.

Both write the new values into a copy of the document and validate it exactly as
a file is validated, so a value is never accepted by one path and refused by the
other. An error about a changed value names where the value came from
(`--set`, `set_parameters`) instead of a file line it was never on. A key set this
way that Nav2 does not read is an error, not a warning: the change would do nothing.
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from typing import Any

from ..core.errors import BtnavError, ParamsError
from ..core.suggest import best_match
from ..core.yaml_io import YamlMap, load_yaml_text
from .loader import (
    ROS_PARAMETERS,
    build_server,
    load_params_doc,
    server_name,
    server_spec,
)
from .nav2_known import NAV2_KNOWN_NODES, known_node_reason
from .paramsfile import ParamsFile, ServerParams, SkippedKey
from .servers import SERVERS
from .tree import copy_tree, set_path


def _parts(key: str) -> list[str]:
    parts = key.split(".") if isinstance(key, str) else []
    if not parts or any(not p for p in parts):
        raise ParamsError(f"'{key}' is not a dotted parameter name", key=str(key))
    return parts


def _relocate(err: ParamsError, changed: Sequence[str], origin: str) -> ParamsError:
    """An error about a value we wrote names `origin`, not a line of the file."""
    key = err.key or ""
    if any(key == c or key.startswith((c + ".", c + "[")) for c in changed):
        return ParamsError(
            f"{err.message} (value given by {origin})", key=key, suggestion=err.suggestion
        )
    return err


def validate_update(params: ParamsFile, server: str, changes: Mapping[str, Any]) -> ServerParams:
    """Re-validate `server` with `changes` applied, as Nav2's dynamic parameters; keep it on success.

    `changes` maps ROS parameter names of that server to values: `{"update_frequency": 2.0,
    "inflation_layer.inflation_radius": 0.5}`. The whole change is refused (nothing
    is kept) if any value is wrong. Plugin lists and plugin types cannot change:
    Nav2 reads them only when a server is configured. Returns the server's new
    params: `.model` for its own keys, `.plugins[name].params` for plugin sections.
    """
    spec = server_spec(server)
    current = params.server(spec.name)
    doc = copy_tree(current.doc) if current.doc is not None else YamlMap()
    frozen = {p.key for p in spec.plugin_lists}
    changed: list[str] = []
    for key, value in changes.items():
        parts = _parts(key)
        full = ".".join([*current.path, *parts])
        if parts[0] in frozen or (len(parts) == 2 and parts[1] == "plugin"):
            raise ParamsError(
                "cannot change while running: Nav2 loads plugins only when a server is configured",
                key=full,
            )
        set_path(doc, parts, value, full)
        changed.append(full)
    skipped: list[SkippedKey] = []
    try:
        updated, ignored = build_server(
            spec,
            doc,
            current.path,
            current.line,
            str(params.path),
            [],
            in_file=current.in_file,
            skipped=skipped,
        )
        _refuse_set_skips(skipped, changed)
    except ParamsError as err:
        raise _relocate(err, changed, "set_parameters") from None
    params.servers[spec.name] = updated
    params.ignored = [e for e in params.ignored if not _under(e.key, updated.key)] + ignored
    return updated


def _under(key: str, prefix: str) -> bool:
    return key == prefix or key.startswith((prefix + ".", prefix + "["))


def apply_overrides(params: ParamsFile, overrides: Mapping[str, Any]) -> ParamsFile:
    """A new `ParamsFile` with dotted-key overrides applied (what `btnav run --set` does).

    Keys are the paths errors use: `controller_server.controller_frequency`,
    `local_costmap.local_costmap.inflation_layer.inflation_radius` (for a costmap the
    repeated name is optional, and so is `ros__parameters`). A server the file lacks
    is added. `params` itself is left unchanged.
    """
    raw = copy_tree(params.raw, str(params.path))
    changed: list[str] = []
    for key, value in overrides.items():
        node_path, rest = _override_target(raw, key)
        set_path(raw, [*node_path, ROS_PARAMETERS, *rest], value, key)
        changed.append(".".join([*node_path, *rest]))
    try:
        updated = load_params_doc(raw, params.path)
        _refuse_set_skips(updated.skipped, changed)
    except ParamsError as err:
        raise _relocate(err, changed, "--set") from None
    return updated


def _refuse_set_skips(skipped: Sequence[SkippedKey], changed: Sequence[str]) -> None:
    """A key set by hand that Nav2 does not read is an error: the setting would change nothing.

    (In a file the same key is only a warning: Nav2 runs that file, and so does btnav.)
    """
    for skip in skipped:
        if any(_under(skip.key, c) or _under(c, skip.key) for c in changed):
            name = skip.parts[-1] if skip.parts else skip.key
            known = f" ({skip.message})" if skip.family else ""
            raise ParamsError(
                f"unknown key '{name}', which Nav2 does not read either: setting it "
                f"changes nothing{known}",
                key=skip.key,
            )


def _override_target(raw: YamlMap, key: str) -> tuple[list[str], list[str]]:
    """Where `key` goes in the document: the server's nesting as the file has it, and the name."""
    parts = _parts(key)
    name = server_name(parts[0])
    spec = SERVERS.get(name)
    if spec is None and known_node_reason(name) is None:
        raise ParamsError(
            f"unknown server '{parts[0]}' in '{key}'",
            key=key,
            suggestion=best_match(name, [*SERVERS, *NAV2_KNOWN_NODES]),
        )
    top = next((k for k in raw if isinstance(k, str) and server_name(k) == name), name)
    rest = parts[1:]
    node_path = [top]
    if spec is not None and spec.nested:
        if rest and rest[0] == name:
            rest = rest[1:]
        existing = raw.get(top)
        single = isinstance(existing, Mapping) and ROS_PARAMETERS in existing
        if not single:
            node_path.append(name)
    if rest and rest[0] == ROS_PARAMETERS:
        rest = rest[1:]
    if not rest:
        raise ParamsError(f"'{key}' names a server, not one of its parameters", key=key)
    return node_path, rest


def parse_set_option(text: str) -> tuple[str, Any]:
    """`"KEY=VALUE"` (a `--set` argument) -> (key, value), VALUE read as YAML (`0.5`, `true`, `[1, 2]`)."""
    key, sep, value = text.partition("=")
    key = key.strip()
    if not sep or not key:
        raise ParamsError(f"expected KEY=VALUE, got '{text}'")
    try:
        parsed = load_yaml_text(value) if value.strip() else ""
    except BtnavError as err:
        raise ParamsError(f"cannot read the value: {err.message}", key=key) from None
    return key, parsed
