"""Launch-time placeholders Nav2's launch files fill in before a node reads its params.

- `$(find-pkg-share nav2_bt_navigator)` is where Nav2 installs its trees; btnav's
  bundled trees folder plays that part, so the placeholder (and a following
  `/behavior_trees`, Nav2's folder inside that package) resolves to
  `bundled_dir("trees")`. Other packages' `$(find-pkg-share X)` stay as written.
- nav2_bringup's launch arguments `use_keepout_zones` and `use_speed_zones` are
  written into the file as `KEEPOUT_ZONE_ENABLED` and `SPEED_ZONE_ENABLED` (RewrittenYaml's
  value_rewrites). Inside the sections a costmap's `filters` list names, where Nav2's
  file puts them, a mission rewrites them to its `use_keepout_zones` / `use_speed_zones`
  before loading (`rewrite_launch_tokens`); left in the file, they read as false.
- Other all-caps tokens are left as they are: they are accepted only inside sections
  btnav ignores (`schema` explains the error elsewhere).
"""

from __future__ import annotations

import re
from collections.abc import Callable, Mapping
from typing import Any

from ..core.errors import format_key_path
from ..core.resources import bundled_dir
from .paramsfile import Placeholder
from .tree import line_of

_FIND_PKG_SHARE = re.compile(
    r"\$\(\s*find-pkg-share\s+([A-Za-z0-9_]+)\s*\)(/behavior_trees(?=/|$))?"
)

#: Packages whose share folder btnav provides, and the folder standing in for it.
PACKAGE_SHARES: dict[str, Callable[[], str]] = {
    "nav2_bt_navigator": lambda: str(bundled_dir("trees")),
    "nav2_route": lambda: str(bundled_dir("graphs").parent),  # $(...)/graphs/<name>.geojson
}


#: nav2_bringup's launch tokens (RewrittenYaml value_rewrites) -> the mission key giving each.
LAUNCH_TOKENS: dict[str, str] = {
    "KEEPOUT_ZONE_ENABLED": "use_keepout_zones",
    "SPEED_ZONE_ENABLED": "use_speed_zones",
}


def rewrite_launch_tokens(
    node: Any, values: Mapping[str, bool], path: list[str | int] | None = None
) -> list[Placeholder]:
    """A whole params document's launch tokens, as RewrittenYaml writes a launch's values
    in (`{"KEEPOUT_ZONE_ENABLED": True}`; a token not given is false); in place."""
    found: list[Placeholder] = []
    where: list[str | int] = [] if path is None else path
    if isinstance(node, Mapping):
        _resolve_launch_tokens(node, where, found, values)
        for key, value in node.items():
            found += rewrite_launch_tokens(value, values, [*where, key])
    elif isinstance(node, list):
        for i, value in enumerate(node):
            found += rewrite_launch_tokens(value, values, [*where, i])
    return found


def _resolve_launch_tokens(
    doc: Mapping[Any, Any],
    path: list[str | int],
    found: list[Placeholder],
    values: Mapping[str, bool],
) -> None:
    """The launch tokens of the filter sections a costmap's `filters` list names, resolved."""
    names = doc.get("filters")
    if not isinstance(names, list):
        return
    shown = [p for p in path if p != "ros__parameters"]
    for name in names:
        section = doc.get(name) if isinstance(name, str) else None
        if not isinstance(section, Mapping):
            continue
        for key, value in section.items():
            if not (isinstance(value, str) and value in LAUNCH_TOKENS):
                continue
            resolved = bool(values.get(value, False))
            section[key] = resolved  # type: ignore[index]
            found.append(
                Placeholder(
                    key=format_key_path([*shown, name, key]) or "",
                    line=line_of(section, key),
                    text=value,
                    resolved=f"{str(resolved).lower()} (a mission's {LAUNCH_TOKENS[value]}, "
                    "false by default)",
                )
            )


def resolve_text(text: str) -> str:
    """`$(find-pkg-share nav2_bt_navigator)/behavior_trees/x.xml` -> `<bundled trees>/x.xml`."""

    def sub(match: re.Match[str]) -> str:
        share = PACKAGE_SHARES.get(match.group(1))
        return share() if share else match.group(0)

    return _FIND_PKG_SHARE.sub(sub, text)


def resolve_placeholders(node: Any, path: list[str | int], found: list[Placeholder]) -> Any:
    """Resolve placeholders in a tree btnav owns (in place); note each one in `found`."""
    if isinstance(node, Mapping):
        _resolve_launch_tokens(node, path, found, {})
        for key in list(node):
            node[key] = _resolve_child(node, key, [*path, key], found)  # type: ignore[index]
    elif isinstance(node, list):
        for i in range(len(node)):
            node[i] = _resolve_child(node, i, [*path, i], found)
    return node


def _resolve_child(parent: Any, key: Any, path: list[str | int], found: list[Placeholder]) -> Any:
    value = parent[key]
    if isinstance(value, str) and "$(" in value:
        resolved = resolve_text(value)
        found.append(
            Placeholder(
                key=format_key_path(path) or "",
                line=line_of(parent, key),
                text=value,
                resolved=resolved if resolved != value else "left as written (package not bundled)",
            )
        )
        return resolved
    return resolve_placeholders(value, path, found)
