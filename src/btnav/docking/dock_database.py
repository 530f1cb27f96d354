"""opennav_docking's DockDatabase: the dock plugins by name and the dock instances by id.

Instances come from a `dock_database:` file when the params give one (Nav2's format,
below), else from the params' `docks:` sections; with neither, docking works only by
pose (DockRobot's `use_dock_id: false`). A dock file:

```yaml
docks:
  home_dock:
    type: simple_charging_dock     # a name in dock_plugins
    frame: map                     # optional, default map
    pose: [0.3, 0.0, 0.0]          # x, y, yaw
    id: "c67f50cb-..."             # optional: the detector's id for it
```

A mistake in the file (a misspelt key, a missing `type`, a pose of two numbers, a type
no plugin has) is a `ParamsError` naming the file, line and key, with the closest
valid spelling.
"""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass, field
from os import PathLike
from pathlib import Path
from typing import Any

from ..core.errors import BtnavError, ParamsError
from ..core.geometry import Pose2D
from ..core.messages import PoseStamped
from ..core.suggest import best_match
from ..core.yaml_io import YamlMap, line_at, load_yaml
from ..params.docking import DockInstance
from ..params.schema import validate_section
from .charging_dock import ChargingDock
from .exceptions import DockNotInDB, DockNotValid


@dataclass
class Dock:
    """One dock instance: its pose in `frame`, its plugin type and the plugin itself."""

    pose: Pose2D
    frame: str = "map"
    type: str = ""
    id: str = ""
    plugin: ChargingDock | None = field(default=None, repr=False)

    @property
    def pose_stamped(self) -> PoseStamped:
        return PoseStamped(0.0, self.pose, self.frame)

    def staging_pose(self) -> PoseStamped:
        assert self.plugin is not None
        return self.plugin.get_staging_pose(self.pose, self.frame)


def dock_from(instance: DockInstance) -> Dock:
    return Dock(Pose2D(*instance.pose), instance.frame, instance.type, instance.id)


def load_dock_file(
    path: str | PathLike[str], dock_types: list[str] | None = None
) -> dict[str, Dock]:
    """Nav2's dock file (parseDockFile); `dock_types`, when given, are the plugin names a
    dock's `type` must be one of."""
    file = str(path)
    doc = load_yaml(Path(path))
    if not isinstance(doc, Mapping) or "docks" not in doc:
        keys = [str(k) for k in doc] if isinstance(doc, Mapping) else []
        near = best_match("docks", keys)
        raise ParamsError(
            "a dock database file holds 'docks:', a mapping of dock names to "
            "{type, frame, pose, id}" + (f"; it has '{near}'" if near else ""),
            file=file,
            line=line_at(doc, [near]) if near else getattr(doc, "line", None),
            key=near,
            suggestion="docks" if near else None,
        )
    docks = doc["docks"]
    if not isinstance(docks, Mapping):
        raise ParamsError(
            "'docks' maps each dock's name to {type, frame, pose, id}",
            file=file,
            line=line_at(doc, ["docks"]),
            key="docks",
        )
    out: dict[str, Dock] = {}
    for name, body in docks.items():
        instance = validate_section(
            DockInstance,
            body if body is not None else YamlMap(),
            key_prefix=["docks", str(name)],
            file=file,
        )
        if dock_types is not None and instance.type not in dock_types:
            raise ParamsError(
                f"dock '{name}' has type '{instance.type}', which is not one of the docking "
                f"server's dock_plugins ({', '.join(dock_types) or 'none'})",
                file=file,
                line=line_at(doc, ["docks", name, "type"]),
                key=["docks", str(name), "type"],
                suggestion=best_match(instance.type, dock_types),
            )
        out[str(name)] = dock_from(instance)
    return out


class DockDatabase:
    """The dock plugins (by their `dock_plugins` name) and the dock instances (by id)."""

    def __init__(self, plugins: Mapping[str, ChargingDock], docks: Mapping[str, Dock]) -> None:
        self.plugins = dict(plugins)
        self.docks = dict(docks)

    def find_dock(self, dock_id: str) -> Dock:
        """The instance `dock_id` with its plugin; DockNotInDB / DockNotValid as Nav2."""
        dock = self.docks.get(dock_id)
        if dock is None:
            near = best_match(dock_id, list(self.docks))
            hint = f" (did you mean '{near}'?)" if near else ""
            known = ", ".join(self.docks) or "none: give docks: or dock_database:"
            raise DockNotInDB(
                f"Dock ID requested is not in database: '{dock_id}'{hint}; docks: {known}"
            )
        plugin = self.find_dock_plugin(dock.type)
        if plugin is None:
            raise DockNotValid(f"Dock requested has no valid plugin: type '{dock.type}'")
        dock.plugin = plugin
        return dock

    def find_dock_plugin(self, dock_type: str) -> ChargingDock | None:
        """The plugin `dock_type`; an empty type means the only plugin there is."""
        if not dock_type and len(self.plugins) == 1:
            return next(iter(self.plugins.values()))
        return self.plugins.get(dock_type)

    def reload_database(self, path: str | PathLike[str]) -> bool:
        """Nav2's `reload_database` service: replace the instances from a dock file; False
        (the database unchanged) if the file cannot be read."""
        try:
            self.docks = load_dock_file(path, list(self.plugins))
        except BtnavError:
            return False
        return True


def docks_of(params: Any, base_dir: Path | None = None) -> dict[str, Dock]:
    """The instances a docking_server's params give: its `dock_database` file (relative
    to `base_dir`, the params file's folder) if set, else its `docks:` sections."""
    if params.dock_database:
        path = Path(params.dock_database).expanduser()
        if not path.is_absolute() and base_dir is not None:
            path = base_dir / path
        return load_dock_file(path, list(params.dock_plugins))
    return {name: dock_from(instance) for name, instance in params.dock_sections.items()}
