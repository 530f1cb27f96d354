"""What loading a params file gives back: servers, their plugin sections, what was ignored.

Key paths are the ROS parameter paths as the file nests them, without
`ros__parameters`: `controller_server.controller_frequency`,
`local_costmap.local_costmap.inflation_layer.inflation_radius`. Errors, the
ignored and skipped lists and `apply_overrides` all use this one spelling.
"""

from __future__ import annotations

from collections.abc import Iterator
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import pydantic

from ..core.errors import BtnavWarning, ParamsError, format_place
from ..core.yaml_io import YamlMap
from .nav2_known import class_name


@dataclass
class PluginSection:
    """A section named by a `*_plugins` list, resolved to a plugin class or "not implemented yet"."""

    name: str
    kind: str
    type: str
    cls: type | None
    params: pydantic.BaseModel | None
    key: str
    line: int | None
    list_key: str
    #: The type is Nav2's default for this name (no `plugin:` in the file).
    defaulted: bool = False

    @property
    def implemented(self) -> bool:
        return self.cls is not None

    @property
    def status(self) -> str:
        """The class it resolves to, or "not implemented yet" (what `params check` prints)."""
        if self.cls is None:
            return "not implemented yet"
        return f"{self.cls.__module__}.{self.cls.__qualname__}"

    @property
    def short_type(self) -> str:
        return class_name(self.type)


@dataclass
class ServerParams:
    """One server's validated keys and its plugin sections, in list order."""

    name: str
    model: Any
    plugins: dict[str, PluginSection]
    #: The file's nesting without ros__parameters: ("local_costmap", "local_costmap").
    path: tuple[str, ...]
    line: int | None
    #: The ros__parameters mapping as validated (placeholders resolved); None if absent.
    doc: YamlMap | None
    #: False when the file has no section and Nav2's defaults apply.
    in_file: bool = True

    @property
    def key(self) -> str:
        return ".".join(self.path)

    def plugins_of(self, kind: str) -> list[PluginSection]:
        return [p for p in self.plugins.values() if p.kind == kind]

    def plugin(self, name: str) -> PluginSection:
        return self.plugins[name]


@dataclass(frozen=True)
class IgnoredEntry:
    """A key or section btnav accepts and does not act on, listed once with the reason."""

    key: str
    line: int | None
    reason: str
    file: str | None = None
    #: For a whole ignored section: the keys it holds.
    keys: tuple[str, ...] = ()

    def __str__(self) -> str:
        where = f"line {self.line}: " if self.line else ""
        held = f" [{', '.join(self.keys)}]" if self.keys else ""
        return f"{where}{self.key}: {self.reason}{held}"


@dataclass(frozen=True)
class SkippedKey:
    """A key the file sets that Nav2 does not read, so neither does btnav: one warning each.

    Unlike an `IgnoredEntry` (Nav2 reads it, btnav does not act on it), the run with this
    key is the run Nav2 makes with it. `family` is the legacy catalogue's (`ROS 1`,
    `renamed`, `BT port`, `misplaced`), or None for a key no catalogue knows.
    """

    key: str
    line: int | None
    message: str
    file: str | None = None
    family: str | None = None
    #: The key's path as parts (`("controller_server", "FollowPath", "min_rot_vel")`).
    parts: tuple[str | int, ...] = ()

    def __str__(self) -> str:
        return format_place(self.file, self.line, self.key, self.message, None)

    def warning(self) -> BtnavWarning:
        return BtnavWarning(self.message, file=self.file, line=self.line, key=self.key)

    def error(self, why: str) -> ParamsError:
        """The same sentence as an error (`btnav params check --strict`, `strict_params`)."""
        return ParamsError(f"{self.message} ({why})", file=self.file, line=self.line, key=self.key)


@dataclass(frozen=True)
class Placeholder:
    """A launch-time placeholder found in the file, and what btnav made of it."""

    key: str
    line: int | None
    text: str
    resolved: str


@dataclass
class ParamsFile:
    """A loaded Nav2 params file."""

    path: Path
    raw: YamlMap
    servers: dict[str, ServerParams]
    ignored: list[IgnoredEntry] = field(default_factory=list)
    placeholders: list[Placeholder] = field(default_factory=list)
    #: Keys Nav2 skips too, in file order (a warning each; an error with strict loading).
    skipped: list[SkippedKey] = field(default_factory=list)

    def __contains__(self, name: object) -> bool:
        return name in self.servers

    def __getitem__(self, name: str) -> ServerParams:
        return self.server(name)

    def __iter__(self) -> Iterator[ServerParams]:
        return iter(self.servers.values())

    def server(self, name: str) -> ServerParams:
        """The server's params from the file, or Nav2's defaults when the file has none."""
        from .loader import server_params  # loader builds ServerParams; imported late (cycle)

        return server_params(self, name)

    def plugins(self) -> list[PluginSection]:
        return [p for s in self.servers.values() for p in s.plugins.values()]

    def ignored_under(self, key: str) -> list[IgnoredEntry]:
        return [e for e in self.ignored if e.key == key or e.key.startswith(key + ".")]
