"""The plugin registry: every algorithm in btnav, built-in or a user's, is found here.

A plugin is registered under a kind and a name; Nav2's class names are aliases,
so a Nav2 params file names btnav plugins without edits. Both of Nav2's
spellings, `pkg::Class` (C++) and `pkg/Class` (pluginlib), find the same plugin.

Third-party plugins come from the `btnav.plugins` entry-point group or from a
mission's `plugins:` list of modules or `.py` files.
"""

from __future__ import annotations

import importlib
import importlib.util
import sys
from collections.abc import Callable, Iterable
from importlib.metadata import entry_points
from os import PathLike
from pathlib import Path
from typing import Any, ClassVar, TypeVar

from .core.errors import PluginError
from .core.suggest import best_match, close_matches

T = TypeVar("T")

#: The kinds of plugin btnav knows, from the design brief plus the Nav2 sub-plugins
#: (critics, path handlers, navigators, waypoint task executors, motion models), and
#: a run's extra outputs (`output`: pictures and whatever a user wants written).
KINDS: tuple[str, ...] = (
    "planner",
    "controller",
    "smoother",
    "behavior",
    "goal_checker",
    "progress_checker",
    "path_handler",
    "critic",
    "motion_model",
    "costmap_layer",
    "costmap_filter",
    "localizer",
    "slam",
    "sensor",
    "drive",
    "bt_node",
    "navigator",
    "waypoint_task_executor",
    "output",
    "charging_dock",
    "edge_cost_function",
    "route_operation",
    "graph_file_loader",
    "graph_file_saver",
)

ENTRY_POINT_GROUP = "btnav.plugins"

_registry: dict[str, dict[str, Any]] = {kind: {} for kind in KINDS}
_primary: dict[str, dict[str, str]] = {kind: {} for kind in KINDS}  # alias -> primary name
_entry_points_loaded = False


class Plugin:
    """The shape the `cls(name, params)` plugin kinds share, as nav2_core's interfaces do:
    a `Params` model (the schema of the plugin's params section), the name the params
    file gives the instance, and its validated params (the defaults when None); then
    `configure(costmap_ros)` hands over what the plugin works on.

    Controllers, global planners, smoothers, goal and progress checkers, path handlers
    and costmap layers extend it; `register` fills in `plugin_kind` and `plugin_name`.
    """

    Params: ClassVar[type[Any]]
    plugin_kind: ClassVar[str]
    plugin_name: ClassVar[str]

    #: The costmap server the plugin's server hands over in `configure` (footprint, radii,
    #: layers, frames); None when the plugin is used on its own with a bare grid.
    costmap_ros: Any = None

    def __init__(self, name: str, params: Any = None) -> None:
        """Built as pluginlib builds it: by name, before anything is handed over.

        Args:
            name: the instance's name in the params file (`FollowPath`, `GridBased`).
            params: its validated `Params` (the server validates the section); None for
                the defaults.
        """
        self.name = name
        self.params = params if params is not None else type(self).Params()

    def configure(self, costmap_ros: Any) -> None:
        """nav2_core's configure(): the server hands over its costmap server, once, after
        construction, so a footprint-aware planner or controller can see the footprint.

        Args:
            costmap_ros: the plugin's costmap server (`CostmapROS`: the layered costmap,
                footprint, inscribed and circumscribed radii, frames).
        """
        self.costmap_ros = costmap_ros


def canonical(name: str) -> str:
    """Nav2 writes `pkg::Class` in params and `pkg/Class` in pluginlib XML: both mean one thing."""
    return name.strip().replace("::", "/")


def _check_kind(kind: str) -> dict[str, Any]:
    if kind not in _registry:
        raise PluginError(
            f"unknown plugin kind '{kind}'; kinds: {', '.join(KINDS)}",
            suggestion=best_match(kind, KINDS),
        )
    return _registry[kind]


def register(kind: str, name: str, *, aliases: Iterable[str] = ()) -> Callable[[T], T]:
    """Class decorator: make `cls` the plugin `name` of `kind` (and of each alias).

    Registering a second class under a taken name replaces the first, so a user's
    plugin can stand in for a built-in one by taking its name (a built-in imported
    later never takes the name back).
    """
    table = _check_kind(kind)

    def deco(cls: T) -> T:
        primary = canonical(name)
        for spelling in (name, *aliases):
            key = canonical(spelling)
            if _is_builtin(cls) and key in table and not _is_builtin(table[key]):
                continue  # a user's plugin keeps its name whatever the import order
            table[key] = cls
            _primary[kind][key] = primary
        cls.plugin_kind = kind  # type: ignore[attr-defined]
        cls.plugin_name = primary  # type: ignore[attr-defined]
        return cls

    return deco


def _is_builtin(cls: Any) -> bool:
    return getattr(cls, "__module__", "").split(".")[0] == "btnav"


def unregister(kind: str, name: str) -> None:
    """Drop a name (and, for a primary name, its aliases): for tests that register temporaries."""
    table = _check_kind(kind)
    key = canonical(name)
    primary = _primary[kind].get(key, key)
    for alias, p in list(_primary[kind].items()):
        if p == primary or alias == key:
            table.pop(alias, None)
            _primary[kind].pop(alias, None)


def load_entry_points() -> None:
    """Import every module advertised under the `btnav.plugins` entry-point group, once."""
    global _entry_points_loaded
    if _entry_points_loaded:
        return
    _entry_points_loaded = True
    for ep in entry_points(group=ENTRY_POINT_GROUP):
        try:
            ep.load()
        except Exception as exc:  # a broken third-party package must say which one
            raise PluginError(
                f"entry point '{ep.name} = {ep.value}' failed to load: {exc}",
                key=f"{ENTRY_POINT_GROUP}.{ep.name}",
            ) from exc


def lookup(kind: str, name: str) -> Any:
    """The plugin class registered as `name`; an unknown name lists the close ones."""
    table = _check_kind(kind)
    key = canonical(name)
    if key not in table:
        load_entry_points()
    if key in table:
        return table[key]
    near = close_matches(key, table)
    known = ", ".join(sorted({_primary[kind][k] for k in table})) or "none registered"
    raise PluginError(
        f"unknown {kind} plugin '{name}'; known: {known}",
        suggestion=near[0] if near else None,
    )


def is_registered(kind: str, name: str) -> bool:
    table = _check_kind(kind)
    load_entry_points()
    return canonical(name) in table


def primary_name(kind: str, name: str) -> str | None:
    """The name `name` was registered under (itself, or the plugin an alias points at);
    None when nothing of `kind` is registered as `name`."""
    _check_kind(kind)
    load_entry_points()
    return _primary[kind].get(canonical(name))


def names(kind: str, *, aliases: bool = False) -> list[str]:
    """Registered names of a kind (primary names only, unless `aliases`)."""
    table = _check_kind(kind)
    load_entry_points()
    if aliases:
        return sorted(table)
    return sorted(set(_primary[kind].values()))


def load_plugins(
    specs: Iterable[str], base_dir: str | PathLike[str] | None = None, *, file: str | None = None
) -> list[Any]:
    """Import a mission's `plugins:` list: dotted module names or `.py` files (relative to `base_dir`)."""
    modules = []
    for spec in specs:
        if spec.endswith(".py") or "/" in spec or "\\" in spec:
            path = Path(spec)
            if not path.is_absolute() and base_dir is not None:
                path = Path(base_dir) / path
            if not path.is_file():
                raise PluginError(f"plugin file not found: {path}", file=file, key="plugins")
            mod_name = f"btnav_user_plugin_{path.stem}_{abs(hash(str(path.resolve()))):x}"
            if mod_name in sys.modules:
                modules.append(sys.modules[mod_name])
                continue
            module_spec = importlib.util.spec_from_file_location(mod_name, path)
            assert module_spec is not None and module_spec.loader is not None
            module = importlib.util.module_from_spec(module_spec)
            sys.modules[mod_name] = module
            try:
                module_spec.loader.exec_module(module)
            except SyntaxError as exc:
                del sys.modules[mod_name]
                raise PluginError(
                    f"syntax error in plugin: {exc.msg}", file=path, line=exc.lineno
                ) from None
            except BaseException:
                del sys.modules[mod_name]
                raise
            modules.append(module)
        else:
            try:
                modules.append(importlib.import_module(spec))
            except ModuleNotFoundError as exc:
                if exc.name and spec.startswith(exc.name):
                    raise PluginError(
                        f"plugin module '{spec}' not found (is it installed, or is it a file path?)",
                        file=file,
                        key="plugins",
                    ) from None
                raise
    return modules
