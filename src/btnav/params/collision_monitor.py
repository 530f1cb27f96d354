"""Keys of Nav2's collision_monitor: zones (polygons) and observation sources, named by lists.

`polygons: [a]` names a section `a:` beside it; `observation_sources: [scan]` a
section `scan:`. A velocity polygon names its sub-polygons the same way
(`velocity_polygons`), and a source its exclusion zones (`exclusion_zones`, sections
at the server level). collision_detector shares the zones and sources
(`ZonesAndSourcesParams`).

Nav2's rules that are load errors here (Nav2 fails to configure): a polygon's
`points` need 4 vertices or more; a `polygon` with no points needs
`polygon_sub_topic` (its shape comes at run time) unless it is an `approach`
polygon (the robot footprint); a `circle` needs `radius` or `polygon_sub_topic`; a
`velocity_polygon` needs `velocity_polygons`; a zone listed in `exclusion_zones`
needs its section.
"""

from __future__ import annotations

import sys
from collections.abc import Mapping
from typing import Any

from pydantic import Field, model_validator

from .node import NodeParams
from .schema import (
    FieldProblem,
    Frame,
    Names,
    ParamsModel,
    Points,
    Why,
    gather_sections,
    ignored,
    named_sections,
    one_of,
)

ActionType = one_of("stop", "slowdown", "limit", "approach", "none")
PolygonType = one_of("polygon", "circle", "velocity_polygon")
SourceType = one_of("scan", "pointcloud", "range", "polygon", "costmap")
ZoneType = one_of("polygon", "circle")

#: Nav2 parses collision polygons with at least this many vertices (polygon_utils.hpp).
MIN_POLYGON_VERTICES = 4


def _enough_vertices(points: tuple[tuple[float, float], ...] | None, key: tuple[str, ...]) -> None:
    if points and len(points) < MIN_POLYGON_VERTICES:
        raise FieldProblem(
            key,
            f"a collision polygon needs at least {MIN_POLYGON_VERTICES} points "
            f"(Nav2's rule), got {len(points)}",
        )


class VelocitySubPolygon(ParamsModel):
    """One sub-polygon of a velocity polygon: used while the velocity is in its range.

    `direction_*_angle` are read only when the velocity polygon is `holonomic`."""

    points: Points
    linear_min: float
    linear_max: float
    theta_min: float
    theta_max: float
    direction_end_angle: float = 3.141592653589793
    direction_start_angle: float = -3.141592653589793

    @model_validator(mode="after")
    def _check(self) -> VelocitySubPolygon:
        _enough_vertices(self.points, ("points",))
        return self


class CollisionPolygon(ParamsModel):
    """A zone around the robot (`polygon`, `circle` or `velocity_polygon`) and its action."""

    type: PolygonType
    action_type: ActionType
    enabled: bool = True
    points: Points | None = None
    radius: float | None = Field(None, gt=0.0)
    min_points: int = Field(4, ge=1)
    max_points: int | None = Field(None, ge=0, description="deprecated by Nav2: min_points - 1")
    trigger_consecutive_points: int = Field(1, ge=1)
    release_consecutive_points: int = Field(1, ge=1)
    slowdown_ratio: float = Field(0.5, ge=0.0, le=1.0)
    linear_limit: float = Field(0.5, ge=0.0)
    angular_limit: float = Field(0.5, ge=0.0)
    time_before_collision: float = Field(2.0, gt=0.0)
    simulation_time_step: float = Field(0.1, gt=0.0)
    sources_names: Names | None = None
    holonomic: bool = False
    velocity_polygons: Names = []
    sub_polygons: dict[str, VelocitySubPolygon] = named_sections("velocity_polygons")
    polygon_sub_topic: str = Field(
        "", description="set: the shape comes at run time (Polygon.set_polygon / set_radius)"
    )
    visualize: bool = ignored(False, Why.VIZ)
    polygon_pub_topic: str = ignored("", Why.TOPIC)
    footprint_topic: str = ignored("local_costmap/published_footprint", Why.TOPIC)
    polygon_subscribe_transient_local: bool = ignored(False, Why.QOS)

    @model_validator(mode="before")
    @classmethod
    def _gather(cls, data: Any) -> Any:
        return gather_sections(cls, data, "velocity_polygons", "sub_polygons")

    @model_validator(mode="after")
    def _shape_given(self) -> CollisionPolygon:
        _enough_vertices(self.points, ("points",))
        dynamic = self.polygon_sub_topic != ""
        footprint = self.action_type == "approach"
        if self.type == "polygon" and not self.points and not dynamic and not footprint:
            raise FieldProblem(
                ("points",),
                "a polygon needs points, or polygon_sub_topic for a shape given at "
                "run time (only an approach polygon takes the robot footprint)",
            )
        if self.type == "circle" and self.radius is None and not dynamic:
            raise FieldProblem(("radius",), "a circle needs radius, or polygon_sub_topic")
        if self.type == "velocity_polygon" and not self.velocity_polygons:
            raise FieldProblem(("velocity_polygons",), "a velocity_polygon lists its sub-polygons")
        return self

    @property
    def required_min_points(self) -> int:
        """min_points, or Nav2's reading of the deprecated max_points (max_points + 1)."""
        return self.min_points if self.max_points is None else self.max_points + 1


class ObservationSource(ParamsModel):
    """A sensor the monitor checks zones against (`scan`, `pointcloud`, `range`, ...).

    Nav2's scan source reads only `topic`, `enabled`, `source_timeout` and
    `exclusion_zones`: the height and range keys are pointcloud's, `obstacles_angle`
    range's, `sampling_distance` polygon's, `cost_threshold` and
    `treat_unknown_as_obstacle` costmap's."""

    type: SourceType = "scan"
    enabled: bool = True
    source_timeout: float | None = Field(None, ge=0.0, description="s; default: the server's")
    min_height: float = 0.05
    max_height: float = 0.5
    min_range: float = Field(0.0, ge=0.0)
    use_global_height: bool = False
    obstacles_angle: float = Field(0.017453292519943295, gt=0.0)
    sampling_distance: float = Field(0.1, gt=0.0)
    cost_threshold: int = Field(253, ge=0, le=255)
    treat_unknown_as_obstacle: bool = True
    exclusion_zones: Names = []
    topic: str = ignored("scan", Why.TOPIC)
    transport_type: str = ignored("raw", Why.TOPIC)


class ExclusionZone(ParamsModel):
    """A region whose points a source drops before the zones see them (a dock, a robot part).

    Anchored to `frame_id` (empty: the robot base, so it rides with the robot); a frame
    other than the base is held where it was last seen for `frame_hold_timeout`."""

    type: ZoneType = "polygon"
    enabled: bool = False
    frame_id: str = ""
    frame_hold_timeout: float = Field(0.0, ge=0.0)
    min_height: float = -sys.float_info.max
    max_height: float = sys.float_info.max
    points: Points | None = None
    radius: float | None = None
    visualize: bool = ignored(False, Why.VIZ)

    @model_validator(mode="after")
    def _shape(self) -> ExclusionZone:
        if self.type == "circle" and (self.radius is None or self.radius <= 0.0):
            raise FieldProblem(("radius",), "a circle exclusion zone needs a positive radius")
        if self.type == "polygon" and not self.points:
            raise FieldProblem(("points",), "a polygon exclusion zone needs at least 3 points")
        return self


def _gather_zones(cls: type[ParamsModel], data: Any) -> Any:
    """polygons, observation_sources and the sources' exclusion zones into their fields."""
    data = gather_sections(cls, data, "polygons", "polygon_sections")
    data = gather_sections(cls, data, "observation_sources", "source_sections")
    if not isinstance(data, Mapping):
        return data
    zones: dict[Any, Any] = {}
    for source in data.get("source_sections", {}).values():
        names = source.get("exclusion_zones") if isinstance(source, Mapping) else None
        for name in names if isinstance(names, list) else []:
            if isinstance(name, str) and name in data and name not in cls.model_fields:
                zones[name] = data[name]
    out = {k: v for k, v in data.items() if k not in zones}
    out["exclusion_zone_sections"] = zones
    return out


class ZonesAndSourcesParams(NodeParams):
    """The keys collision_monitor and collision_detector share: frames, sources, zones."""

    base_frame_id: Frame = "base_footprint"
    odom_frame_id: Frame = "odom"
    source_timeout: float = Field(2.0, ge=0.0)
    base_shift_correction: bool = True
    # Nav2 requires both lists; btnav reads their absence as "no zones / no sources".
    polygons: Names = []
    observation_sources: Names = []
    polygon_sections: dict[str, CollisionPolygon] = named_sections("polygons")
    source_sections: dict[str, ObservationSource] = named_sections("observation_sources")
    exclusion_zone_sections: dict[str, ExclusionZone] = named_sections("exclusion_zones")
    transform_tolerance: float = ignored(0.1, Why.TF, ge=0.0)
    collision_points_marker_3d: bool = ignored(False, Why.VIZ)

    @model_validator(mode="before")
    @classmethod
    def _gather(cls, data: Any) -> Any:
        return _gather_zones(cls, data)

    @model_validator(mode="after")
    def _names_exist(self) -> ZonesAndSourcesParams:
        for name, polygon in self.polygon_sections.items():
            for source in polygon.sources_names or []:
                if source not in self.observation_sources:
                    raise FieldProblem(
                        ("polygon_sections", name, "sources_names"),
                        f"'{source}' is not one of observation_sources "
                        f"({', '.join(self.observation_sources) or 'none'})",
                    )
        for name, source in self.source_sections.items():
            for zone in source.exclusion_zones:
                if zone not in self.exclusion_zone_sections:
                    raise FieldProblem(
                        ("source_sections", name, "exclusion_zones"),
                        f"'{zone}' is listed but has no section '{zone}:' beside the sources",
                    )
        return self


class CollisionMonitorParams(ZonesAndSourcesParams):
    """collision_monitor: slows or stops the robot when sensed points enter its zones."""

    enabled: bool = True
    stop_pub_timeout: float = Field(1.0, ge=0.0)
    cmd_vel_in_topic: str = ignored("cmd_vel_smoothed", Why.TOPIC)
    cmd_vel_out_topic: str = ignored("cmd_vel", Why.TOPIC)
    state_topic: str = ignored("", Why.TOPIC)
    use_realtime_priority: bool = ignored(False, Why.REALTIME)
