"""The zones and sources a collision_monitor or collision_detector section describes,
built in the order the file lists them (the order Nav2 checks them in)."""

from __future__ import annotations

from collections.abc import Callable

import numpy as np
from numpy.typing import NDArray

from ..core.errors import ParamsError
from ..core.frames import FrameTree
from ..params.collision_monitor import ZonesAndSourcesParams
from .circle import Circle
from .costmap_source import CostmapReading, CostmapSource
from .exclusion_zone import ExclusionZone
from .polygon import Polygon
from .polygon_source import PolygonSource
from .scan_source import ScanSource
from .source import Source, SourceFrames
from .velocity_polygon import VelocityPolygon

_POLYGONS: dict[str, type[Polygon]] = {
    "polygon": Polygon,
    "circle": Circle,
    "velocity_polygon": VelocityPolygon,
}

#: Nav2's source types that need a sensor btnav's 2D simulation does not have.
_NO_SUCH_SENSOR = {
    "pointcloud": "a depth camera's PointCloud2",
    "range": "a sonar's or IR sensor's Range",
}


def make_polygons(
    model: ZonesAndSourcesParams, footprint: Callable[[], NDArray[np.float64]] | None = None
) -> list[Polygon]:
    """One zone per `polygons` entry; `footprint` is the robot's (for approach polygons)."""
    sources = list(model.observation_sources)
    return [
        _POLYGONS[p.type](name, p, sources, footprint=footprint)
        for name, p in model.polygon_sections.items()
    ]


def make_sources(
    model: ZonesAndSourcesParams,
    tree: FrameTree,
    *,
    costmap: Callable[[], CostmapReading] | None = None,
    where: Callable[[str, str], dict[str, object]] | None = None,
) -> list[Source]:
    """One source per `observation_sources` entry, with its exclusion zones.

    A `pointcloud` or `range` source, or a `costmap` one with no costmap to read, is a
    `ParamsError` at the source's `type` (`where(source, key)` gives file and line).
    """
    frames = SourceFrames(
        tree, model.base_frame_id, model.odom_frame_id, model.base_shift_correction
    )
    out: list[Source] = []
    for name, params in model.source_sections.items():
        place = where(name, "type") if where is not None else {}
        if params.type in _NO_SUCH_SENSOR:
            raise ParamsError(
                f"a '{params.type}' source reads {_NO_SUCH_SENSOR[params.type]}; btnav's 2D "
                "simulation has lidars only: use a 'scan' source (or 'costmap', 'polygon')",
                **place,  # type: ignore[arg-type]
            )
        zones = [
            ExclusionZone(
                zone,
                model.exclusion_zone_sections[zone],
                tree,
                model.base_frame_id,
                model.odom_frame_id,
                model.transform_tolerance,
            )
            for zone in params.exclusion_zones
        ]
        args = (name, params, frames, model.source_timeout, zones)
        if params.type == "scan":
            out.append(ScanSource(*args))
        elif params.type == "polygon":
            out.append(PolygonSource(*args))
        else:
            if costmap is None:
                raise ParamsError(
                    "a 'costmap' source needs a costmap: give the server the local costmap",
                    **place,  # type: ignore[arg-type]
                )
            out.append(CostmapSource(*args, costmap=costmap))
    return out
