"""Keys of Nav2's collision_monitor: zones (polygons) and observation sources, named by lists.

`polygons: [a]` names a section `a:` beside it; `observation_sources: [scan]` a
section `scan:`. A velocity polygon names its sub-polygons the same way
(`velocity_polygons`), and a source its exclusion zones (`exclusion_zones`,
sections at the server level; not implemented, so listed as ignored).
"""

from __future__ import annotations

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


class VelocitySubPolygon(ParamsModel):
    """One sub-polygon of a velocity polygon: used while the velocity is in its range."""

    points: Points
    linear_min: float
    linear_max: float
    theta_min: float
    theta_max: float
    direction_end_angle: float = 3.141592653589793
    direction_start_angle: float = -3.141592653589793


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
    visualize: bool = ignored(False, Why.VIZ)
    polygon_pub_topic: str = ignored("", Why.TOPIC)
    polygon_sub_topic: str = ignored("", Why.TOPIC)
    footprint_topic: str = ignored("local_costmap/published_footprint", Why.TOPIC)
    polygon_subscribe_transient_local: bool = ignored(False, Why.QOS)

    @model_validator(mode="before")
    @classmethod
    def _gather(cls, data: Any) -> Any:
        return gather_sections(cls, data, "velocity_polygons", "sub_polygons")


class ObservationSource(ParamsModel):
    """A sensor the monitor checks zones against (`scan`, `pointcloud`, `range`, ...)."""

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


class CollisionMonitorParams(NodeParams):
    """collision_monitor: slows or stops the robot when sensed points enter its zones."""

    enabled: bool = True
    base_frame_id: Frame = "base_footprint"
    odom_frame_id: Frame = "odom"
    source_timeout: float = Field(2.0, ge=0.0)
    base_shift_correction: bool = True
    stop_pub_timeout: float = Field(1.0, ge=0.0)
    # Nav2 requires both lists; btnav reads their absence as "no zones / no sources".
    polygons: Names = []
    observation_sources: Names = []
    polygon_sections: dict[str, CollisionPolygon] = named_sections("polygons")
    source_sections: dict[str, ObservationSource] = named_sections("observation_sources")
    exclusion_zone_sections: dict[str, Any] = named_sections(
        "exclusion_zones",
        ignored_reason="collision monitor exclusion zones are not implemented yet",
    )
    cmd_vel_in_topic: str = ignored("cmd_vel_smoothed", Why.TOPIC)
    cmd_vel_out_topic: str = ignored("cmd_vel", Why.TOPIC)
    state_topic: str = ignored("", Why.TOPIC)
    transform_tolerance: float = ignored(0.1, Why.TF, ge=0.0)
    collision_points_marker_3d: bool = ignored(False, Why.VIZ)
    use_realtime_priority: bool = ignored(False, Why.REALTIME)

    @model_validator(mode="before")
    @classmethod
    def _gather(cls, data: Any) -> Any:
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

    @model_validator(mode="after")
    def _sources_exist(self) -> CollisionMonitorParams:
        for name, polygon in self.polygon_sections.items():
            for source in polygon.sources_names or []:
                if source not in self.observation_sources:
                    raise FieldProblem(
                        ("polygon_sections", name, "sources_names"),
                        f"'{source}' is not one of observation_sources "
                        f"({', '.join(self.observation_sources) or 'none'})",
                    )
        return self
