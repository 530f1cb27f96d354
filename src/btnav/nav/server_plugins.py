"""Building a server's plugins from its params sections, and picking one by id, as Nav2 does;
`PluginServer`, the shape planner_server, controller_server and smoother_server share."""

from __future__ import annotations

import inspect
from typing import Any, ClassVar

from ..core.rng import stream
from ..params.paramsfile import PluginSection, ServerParams
from .actions import ActionServer
from .runtime import Runtime, Stage


def make_plugin(section: PluginSection, *, seed: int | None = None, server: str = "") -> Any:
    """`cls(name, params)` for a resolved section; a plugin that takes `rng` gets its own
    stream of the run's seed (named by server and plugin), so runs repeat bit for bit."""
    if section.cls is None:
        raise ValueError(f"plugin '{section.name}' ({section.type}) is not implemented in btnav")
    kwargs: dict[str, Any] = {}
    if seed is not None:
        try:
            accepted = inspect.signature(section.cls).parameters
        except (TypeError, ValueError):
            accepted = {}
        if "rng" in accepted:
            kwargs["rng"] = stream(seed, server, section.name)
    return section.cls(section.name, section.params, **kwargs)


def make_plugins(params: ServerParams, kind: str, *, seed: int | None = None) -> dict[str, Any]:
    """Every implemented plugin of `kind` in list order, by its name in the file."""
    return {
        s.name: make_plugin(s, seed=seed, server=params.name)
        for s in params.plugins_of(kind)
        if s.cls is not None
    }


def pick(plugins: dict[str, Any], wanted: str) -> Any | None:
    """Nav2's id lookup: an empty id means the only plugin there is; else the named one."""
    if not wanted:
        return next(iter(plugins.values())) if len(plugins) == 1 else None
    return plugins.get(wanted)


class PluginServer:
    """A Nav2 server owning the plugins of one kind (`kind`) on a costmap, and answering
    its actions on the step after a goal comes (no sim time passes during a call; the
    controller server runs at its `controller_frequency` instead). Each plugin is built
    from its name and params, then configured with the server's costmap server, as
    nav2_core's plugins are. The server holds its action servers and registers them
    with the runtime."""

    stage = Stage.SERVER
    kind: ClassVar[str]

    def __init__(
        self, runtime: Runtime, params: ServerParams, costmap: Any, *, seed: int | None = None
    ) -> None:
        self.seed = runtime.seed if seed is None else seed
        self.runtime = runtime
        self.params = params
        self.costmap = costmap
        self.plugins: dict[str, Any] = make_plugins(params, self.kind, seed=self.seed)
        for plugin in self.plugins.values():
            plugin.configure(costmap.costmap_ros)
        self.rate = 1.0 / runtime.physics_dt
        self.actions: list[ActionServer[Any]] = self.action_servers()
        for action in self.actions:
            runtime.add_action_server(action)

    def action_servers(self) -> list[ActionServer[Any]]:
        """The server's actions, built once with the server (their hooks are its methods)."""
        raise NotImplementedError

    def update(self, now: float) -> None:
        for action in self.actions:
            action.update(now)

    def set_parameters(self, params: ServerParams) -> None:
        """Apply params `validate_update` accepted: plugins take their new sections."""
        self.params = params
        for name, section in params.plugins.items():
            plugin = self.plugins.get(name)
            if plugin is not None and section.params is not None:
                plugin.params = section.params
