"""What the route server hands its plugins (scorers, operations) in `configure`.

Nav2's plugins get the server's node, tf buffer and a costmap subscriber; btnav's get a
`RouteContext`: the costmaps by Nav2's topic name (`global_costmap/costmap_raw`), each
with the transform that takes route-frame points into the costmap's frame, sim time,
the services a TriggerEvent may call, and the controller's speed-limit input.
"""

from __future__ import annotations

from collections.abc import Callable, Mapping
from dataclasses import dataclass, field
from typing import Any

import numpy as np
from numpy.typing import ArrayLike, NDArray

from ..core.geometry import Pose2D
from ..costmap.costmap_2d import Costmap2D


@dataclass(frozen=True)
class CostmapView:
    """A costmap and the transform from the route's frame into the costmap's frame."""

    costmap: Costmap2D
    route_to_costmap: Pose2D = field(default_factory=Pose2D)

    def cells(self, xy: ArrayLike) -> tuple[NDArray[np.int64], NDArray[np.bool_]]:
        """Route-frame points -> costmap cells (mx, my) and whether each is on the map."""
        pts = np.asarray(xy, dtype=float).reshape(-1, 2)
        if self.route_to_costmap != Pose2D():
            pts = self.route_to_costmap.transform_points(pts)
        return self.costmap.world_to_map(pts)


CostmapSource = Callable[[str], CostmapView | None]


def _no_costmap(topic: str) -> CostmapView | None:
    return None


@dataclass
class RouteContext:
    route_frame: str = "map"
    base_frame: str = "base_link"
    #: The server's `costmap_topic`: a plugin whose own topic is this one shares it.
    costmap_topic: str = "global_costmap/costmap_raw"
    costmaps: CostmapSource = _no_costmap
    now: Callable[[], float] = lambda: 0.0
    #: Services by name (a std_srvs/Trigger is a callable of no arguments).
    services: Mapping[str, Callable[..., Any]] = field(default_factory=dict)
    #: ControllerServer.set_speed_limit(speed_limit, percentage), when there is one.
    set_speed_limit: Callable[[float, bool], None] | None = None

    @classmethod
    def with_costmaps(cls, costmaps: Mapping[str, Costmap2D], **kwargs: Any) -> RouteContext:
        """A context over fixed costmaps in the route's frame (for tests and scripts)."""
        views = {topic: CostmapView(cm) for topic, cm in costmaps.items()}
        return cls(costmaps=views.get, **kwargs)

    def costmap(self, topic: str = "") -> CostmapView | None:
        return self.costmaps(topic or self.costmap_topic)
