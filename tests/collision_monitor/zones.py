"""Nav2's example zones and sources (nav2_collision_monitor/params/collision_monitor_params.yaml
at the mirror's main), as params models for the tests."""

from __future__ import annotations

from typing import Any

from btnav.params.collision_monitor import CollisionMonitorParams, CollisionPolygon

POLYGON_STOP = {
    "type": "polygon",
    "points": "[[0.3, 0.3], [0.3, -0.3], [0.0, -0.3], [0.0, 0.3]]",
    "action_type": "stop",
    "min_points": 4,
}
POLYGON_SLOW = {
    "type": "polygon",
    "points": "[[0.4, 0.4], [0.4, -0.4], [-0.4, -0.4], [-0.4, 0.4]]",
    "action_type": "slowdown",
    "min_points": 4,
    "slowdown_ratio": 0.3,
}
POLYGON_LIMIT = {
    "type": "polygon",
    "points": "[[0.5, 0.5], [0.5, -0.5], [-0.5, -0.5], [-0.5, 0.5]]",
    "action_type": "limit",
    "min_points": 4,
    "linear_limit": 0.4,
    "angular_limit": 0.5,
}
FOOTPRINT_APPROACH = {
    "type": "polygon",
    "action_type": "approach",
    "footprint_topic": "/local_costmap/published_footprint",
    "time_before_collision": 2.0,
    "simulation_time_step": 0.1,
    "min_points": 6,
}
VELOCITY_POLYGON_STOP = {
    "type": "velocity_polygon",
    "action_type": "stop",
    "min_points": 6,
    "velocity_polygons": ["rotation", "translation_forward", "translation_backward", "stopped"],
    "holonomic": False,
    "rotation": {
        "points": "[[0.3, 0.3], [0.3, -0.3], [-0.3, -0.3], [-0.3, 0.3]]",
        "linear_min": 0.0,
        "linear_max": 0.05,
        "theta_min": -1.0,
        "theta_max": 1.0,
    },
    "translation_forward": {
        "points": "[[0.35, 0.3], [0.35, -0.3], [-0.2, -0.3], [-0.2, 0.3]]",
        "linear_min": 0.0,
        "linear_max": 1.0,
        "theta_min": -1.0,
        "theta_max": 1.0,
    },
    "translation_backward": {
        "points": "[[0.2, 0.3], [0.2, -0.3], [-0.35, -0.3], [-0.35, 0.3]]",
        "linear_min": -1.0,
        "linear_max": 0.0,
        "theta_min": -1.0,
        "theta_max": 1.0,
    },
    "stopped": {
        "points": "[[0.25, 0.25], [0.25, -0.25], [-0.25, -0.25], [-0.25, 0.25]]",
        "linear_min": -1.0,
        "linear_max": 1.0,
        "theta_min": -1.0,
        "theta_max": 1.0,
    },
}


def polygon(section: dict[str, Any], **changes: Any) -> CollisionPolygon:
    return CollisionPolygon.model_validate({**section, **changes})


def monitor_params(
    polygons: dict[str, dict[str, Any]],
    sources: dict[str, dict[str, Any]] | None = None,
    **keys: Any,
) -> CollisionMonitorParams:
    sources = {"scan": {"type": "scan"}} if sources is None else sources
    return CollisionMonitorParams.model_validate(
        {
            "polygons": list(polygons),
            **polygons,
            "observation_sources": list(sources),
            **sources,
            **keys,
        }
    )
