"""Costmaps: Nav2's cost values, Costmap2D, layers, and the layered global/local costmaps."""

from .cost_values import (
    FREE_SPACE,
    INSCRIBED_INFLATED_OBSTACLE,
    LETHAL_OBSTACLE,
    MAX_NON_OBSTACLE,
    NO_INFORMATION,
)
from .costmap_2d import Costmap2D
from .costmap_ros import Costmap2DROS, CostmapROS
from .footprint import footprint_from_radius, min_max_distances, pad_footprint
from .inflation_layer import InflationLayer, inflation_cost
from .layer import Bounds, CostmapLayer, Layer, Window
from .layered_costmap import LayeredCostmap, robot_footprint
from .obstacle_layer import ObservationSource, ObstacleLayer, VoxelLayer
from .static_layer import StaticLayer, interpret_values

__all__ = [
    "FREE_SPACE",
    "INSCRIBED_INFLATED_OBSTACLE",
    "LETHAL_OBSTACLE",
    "MAX_NON_OBSTACLE",
    "NO_INFORMATION",
    "Bounds",
    "Costmap2D",
    "Costmap2DROS",
    "CostmapLayer",
    "CostmapROS",
    "InflationLayer",
    "Layer",
    "LayeredCostmap",
    "ObservationSource",
    "ObstacleLayer",
    "StaticLayer",
    "VoxelLayer",
    "Window",
    "footprint_from_radius",
    "inflation_cost",
    "interpret_values",
    "min_max_distances",
    "pad_footprint",
    "robot_footprint",
]
