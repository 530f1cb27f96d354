"""behavior_server: Nav2's recovery behaviours, one action server per behaviour name.

`BehaviorServer(runtime, params, local_costmap=...)` builds the behaviours that
`behavior_plugins` lists in the params file's `behavior_server` section (Nav2's
defaults when the file has none), each from its own section (`spin:`,
`backup:`, ...), and registers an action server under the behaviour's name, the
name a BT node's `server_name` uses (`spin`, `backup`, `drive_on_heading`,
`assisted_teleop`, `wait`). A listed behaviour that is not a registered plugin is
skipped and named in `not_implemented`.

The server is one runtime component at `cycle_frequency` (SERVER stage): each
update gives every action server its cycle, so a goal sent between two cycles
starts on the next. Collision checks ahead read `local_costmap` (a `CostmapROS`),
(or the `CostmapServer` holding it), whose frame is normally `local_frame` (odom;
another frame is transformed); without a costmap, behaviours run with
no collision checks. Results carry Nav2's codes: a behaviour names its failure
(TIMEOUT, COLLISION_AHEAD, ...) and the server looks the number up in the action's
table (SpinError, BackUpError, ...).
"""

from __future__ import annotations

from collections.abc import Mapping
from typing import Any

from .. import plugins as registry
from ..behaviors import plugins as _builtin_behaviors  # noqa: F401  (registers them)
from ..behaviors.behavior import Behavior, BehaviorOutcome
from ..behaviors.collision import CollisionChecker
from ..core.error_codes import ERROR_CODES, NavResult, Outcome
from ..params.navigation import BehaviorServerParams
from ..params.paramsfile import ParamsFile, ServerParams
from ..params.schema import validate_section
from .actions import ActionServer, GoalHandle
from .runtime import Stage


class BehaviorServer:
    """Nav2's behavior_server on the runtime schedule."""

    stage = Stage.SERVER

    def __init__(
        self,
        runtime: Any,
        params: ParamsFile | ServerParams | BehaviorServerParams | None = None,
        *,
        local_costmap: Any = None,
        global_costmap: Any = None,
        add: bool = True,
    ) -> None:
        """Build the behaviours and their action servers; `add` schedules the server on
        `runtime` (pass False when a stack builder schedules it itself)."""
        self.runtime = runtime
        self.local_costmap = local_costmap
        self.global_costmap = global_costmap
        server, sections = _server_params(params)
        self.params: BehaviorServerParams = server
        self.rate = float(server.cycle_frequency)
        checker = self._collision_checker(local_costmap)
        self.behaviors: dict[str, Behavior] = {}
        self.servers: dict[str, ActionServer[Any]] = {}
        self.not_implemented: list[str] = []
        for name, cls, plugin_params in sections:
            if cls is None:
                self.not_implemented.append(name)
                continue
            behavior = cls(name, plugin_params)
            behavior.configure(server, runtime, checker)
            self.behaviors[name] = behavior
            action = _ActionServerFor(behavior)
            self.servers[name] = action
            runtime.add_action_server(action)
        if add:
            runtime.add(self, stage=self.stage, rate=self.rate)

    def _collision_checker(self, costmap: Any) -> CollisionChecker | None:
        if costmap is None:
            return None
        costmap = getattr(costmap, "costmap_ros", costmap)  # a CostmapServer: its CostmapROS
        local = self.params.local_frame
        frame = getattr(costmap, "global_frame", local)
        if frame == local:
            return CollisionChecker(costmap)
        return CollisionChecker(costmap, to_costmap=lambda: self.runtime.lookup(frame, local))

    def set_parameters(self, params: ServerParams) -> None:
        """Apply params `validate_update` accepted: server keys and each behaviour's section."""
        self.params = params.model
        for name, behavior in self.behaviors.items():
            behavior.server = params.model
            section = params.plugins.get(name)
            if section is not None and section.params is not None:
                behavior.params = section.params

    def update(self, now: float) -> None:
        for server in self.servers.values():
            server.update(now)

    @property
    def names(self) -> list[str]:
        """The action servers' names (`spin`, `backup`, ...)."""
        return list(self.servers)

    def __repr__(self) -> str:
        return f"BehaviorServer({', '.join(self.servers)})"


class _ActionServerFor(ActionServer[Any]):
    """The action server of one behaviour: hooks call it, outcomes become NavResults."""

    def __init__(self, behavior: Behavior) -> None:
        super().__init__(behavior.action, behavior.name)
        self.behavior = behavior
        self.codes = ERROR_CODES[behavior.action]

    def on_start(self, handle: GoalHandle[Any], now: float) -> NavResult | None:
        return self._result(handle, self.behavior.start(handle.goal, now), now)

    def execute(self, handle: GoalHandle[Any], now: float) -> NavResult | None:
        return self._result(handle, self.behavior.cycle(now), now)

    def on_cancel(self, handle: GoalHandle[Any], now: float) -> NavResult | None:
        return self._result(handle, self.behavior.cancel(now), now)

    def _result(
        self, handle: GoalHandle[Any], outcome: BehaviorOutcome | None, now: float
    ) -> NavResult | None:
        if self.behavior.feedback is not None:
            handle.publish_feedback(self.behavior.feedback, now)
        if outcome is None:
            return None
        if outcome.status == "succeeded":
            return NavResult.success(outcome.result)
        if outcome.status == "canceled":
            return NavResult.cancellation(outcome.result, outcome.message)
        code = self.codes[outcome.error]
        return NavResult(Outcome.FAILED, int(code), outcome.message or code.message, outcome.result)


def _server_params(
    params: ParamsFile | ServerParams | BehaviorServerParams | None,
) -> tuple[BehaviorServerParams, list[tuple[str, type[Behavior] | None, Any]]]:
    """The server's keys and (name, class or None, plugin params) per listed behaviour."""
    if params is None or isinstance(params, BehaviorServerParams):
        model = params if params is not None else BehaviorServerParams()
        out_default: list[tuple[str, type[Behavior] | None, Any]] = []
        for n in model.behavior_plugins:  # no file: Nav2's default types by name
            type_name = _DEFAULT_TYPES.get(n)
            cls = registry.lookup("behavior", type_name) if type_name is not None else None
            out_default.append((n, cls, None))
        return model, out_default
    server = params.server("behavior_server") if isinstance(params, ParamsFile) else params
    out: list[tuple[str, type[Behavior] | None, Any]] = []
    for name, section in server.plugins.items():
        cls, plugin_params = section.cls, section.params
        if cls is None and registry.is_registered("behavior", section.type):
            # The file was loaded before the behaviours were registered: validate now.
            cls = registry.lookup("behavior", section.type)
            body = server.doc.get(name) if server.doc is not None else None
            body = (
                {k: v for k, v in body.items() if k != "plugin"}
                if isinstance(body, Mapping)
                else {}
            )
            plugin_params = validate_section(
                cls.Params,
                body,
                key_prefix=[*server.path, name],
                file=getattr(server.doc, "file", None),
            )
        out.append((name, cls, plugin_params))
    return server.model, out


#: Nav2's default plugin types for its default behaviour names.
_DEFAULT_TYPES: dict[str, str] = {
    "spin": "nav2_behaviors::Spin",
    "backup": "nav2_behaviors::BackUp",
    "drive_on_heading": "nav2_behaviors::DriveOnHeading",
    "wait": "nav2_behaviors::Wait",
}

__all__ = ["BehaviorServer"]
