"""Launch-time placeholders Nav2's launch files fill in before a node reads its params.

- `$(find-pkg-share nav2_bt_navigator)` is where Nav2 installs its trees; btnav's
  bundled trees folder plays that part, so the placeholder (and a following
  `/behavior_trees`, Nav2's folder inside that package) resolves to
  `bundled_dir("trees")`. Other packages' `$(find-pkg-share X)` stay as written.
- All-caps tokens such as `KEEPOUT_ZONE_ENABLED` are left as they are: they are
  accepted only inside sections btnav ignores (`schema` explains the error elsewhere).
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
}


def resolve_text(text: str) -> str:
    """`$(find-pkg-share nav2_bt_navigator)/behavior_trees/x.xml` -> `<bundled trees>/x.xml`."""

    def sub(match: re.Match[str]) -> str:
        share = PACKAGE_SHARES.get(match.group(1))
        return share() if share else match.group(0)

    return _FIND_PKG_SHARE.sub(sub, text)


def resolve_placeholders(node: Any, path: list[str | int], found: list[Placeholder]) -> Any:
    """Resolve placeholders in a tree btnav owns (in place); note each one in `found`."""
    if isinstance(node, Mapping):
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
