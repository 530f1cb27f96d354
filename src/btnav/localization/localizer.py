"""The localiser contract, shared by every localiser and SLAM plugin.

Localisers publish `map -> odom`. A localiser plugin (`@register("localizer", name)`,
or `@register("slam", name)` for one that builds its map) is built as every plugin is,
`cls(name, params)`, then `configure(context)` hands it the runtime, and it is scheduled
at its `rate` in the runtime's LOCALIZATION stage, before costmaps and servers.
`context` is anything shaped like `LocalizerContext` (the `Runtime` is), so a localiser
need not import the runtime. `params` is None for the defaults, a mapping validated by
the plugin's `Params`, or a `Params` instance.
"""

from __future__ import annotations

from collections.abc import Mapping
from typing import Any, Protocol

from ..core.clock import SimClock
from ..core.frames import FrameTree
from ..core.messages import LaserScan, Odometry
from ..core.validation import StrictModel
from ..plugins import Plugin
from ..sim.world import World


class LocalizerContext(Protocol):
    """What a localiser may use: the frame tree, the clock and the latest sensor data.

    Only `ground_truth` may read `world.robot_pose`; a real localiser knows the world
    only through scans, odometry and the map.
    """

    world: World
    frames: FrameTree
    clock: SimClock
    seed: int
    latest_odom: Odometry
    latest_scan: LaserScan | None

    def subscribe(self, topic: str, callback: Any) -> None: ...


class Localizer(Plugin):
    """The base of `localizer` and `slam` plugins: the plugin contract, with the runtime
    (a `LocalizerContext`) as what `configure` hands over, where a planner gets its
    costmap server. Subclasses subscribe to scans and odometry in `configure`."""

    context: LocalizerContext

    def __init__(self, name: str, params: Any = None) -> None:
        super().__init__(name, localizer_params(type(self).Params, params))

    def configure(self, context: LocalizerContext) -> None:  # type: ignore[override]
        """The runtime hands itself over once; subscribe to `scan` and `odom` here.

        Args:
            context: the runtime: world, frame tree, sim clock, seed, the latest odometry
                and scan, and `subscribe(topic, callback)`.
        """
        self.context = context


def localizer_params(cls: type[StrictModel], params: Any) -> Any:
    if params is None:
        return cls()
    if isinstance(params, cls):
        return params
    if isinstance(params, Mapping):
        return cls(**params)
    raise TypeError(f"params for a localiser are a mapping or {cls.__name__}, got {params!r}")
