"""Typed views of the Cartographer options btnav acts on (field name = Cartographer key).

`load_cartographer_config` fills these from the options table; a field's Cartographer key
is its name, under the view's place in `VIEWS`, unless the class's `PATHS` says otherwise.
The keys these views read are the ones btnav implements; every other key is accepted and,
when it asks for something btnav does not do, listed in `CartographerConfig.ignored`.
"""

from __future__ import annotations

import typing
import warnings
from dataclasses import dataclass
from pathlib import Path
from typing import Any

from ...core.errors import BtnavWarning

#: A dotted key of the options table, as a tuple of its parts.
Key = tuple[str, ...]
TB2D: Key = ("trajectory_builder", "trajectory_builder_2d")
TB3D: Key = ("trajectory_builder", "trajectory_builder_3d")
PG: Key = ("map_builder", "pose_graph")
#: The globals Cartographer's defaults define, used to spell a key as users write it.
GLOBALS: dict[Key, str] = {
    ("map_builder",): "MAP_BUILDER", ("trajectory_builder",): "TRAJECTORY_BUILDER",
    TB2D: "TRAJECTORY_BUILDER_2D", TB3D: "TRAJECTORY_BUILDER_3D", PG: "POSE_GRAPH",
}  # fmt: skip


def spell(key: Key) -> str:
    """A key as users write it: under the global that holds it (`TRAJECTORY_BUILDER_2D.min_range`)."""
    for n in range(len(key), 0, -1):
        if key[:n] in GLOBALS:
            return ".".join((GLOBALS[key[:n]], *key[n:]))
    return ".".join(key)


@dataclass(frozen=True)
class Frames:
    """The REP-105 frames Cartographer reads and publishes between (map -> odom -> published)."""

    map_frame: str
    tracking_frame: str
    published_frame: str
    odom_frame: str
    provide_odom_frame: bool
    use_odometry: bool


@dataclass(frozen=True)
class RealTimeCorrelativeScanMatcher:
    linear_search_window: float
    angular_search_window: float
    translation_delta_cost_weight: float
    rotation_delta_cost_weight: float


@dataclass(frozen=True)
class CeresScanMatcher:
    PATHS: typing.ClassVar[dict[str, Key]] = {
        "max_num_iterations": ("ceres_solver_options", "max_num_iterations"),
    }
    occupied_space_weight: float
    translation_weight: float
    rotation_weight: float
    max_num_iterations: int


@dataclass(frozen=True)
class AdaptiveVoxelFilter:
    """The coarsest voxel filter (edge at most `max_length`) that keeps `min_num_points`."""

    max_length: float
    min_num_points: int
    max_range: float


@dataclass(frozen=True)
class MotionFilter:
    max_time_seconds: float
    max_distance_meters: float
    max_angle_radians: float


@dataclass(frozen=True)
class Submaps2D:
    """`submaps`, flattened: a probability grid is the only kind btnav builds (`PATHS`: where)."""

    PATHS: typing.ClassVar[dict[str, Key]] = {
        "resolution": ("grid_options_2d", "resolution"),
        "hit_probability": ("range_data_inserter", "probability_grid_range_data_inserter", "hit_probability"),
        "miss_probability": ("range_data_inserter", "probability_grid_range_data_inserter", "miss_probability"),
    }  # fmt: skip
    num_range_data: int
    resolution: float
    hit_probability: float
    miss_probability: float


@dataclass(frozen=True)
class TrajectoryBuilder2D:
    min_range: float
    max_range: float
    missing_data_ray_length: float
    num_accumulated_range_data: int
    voxel_filter_size: float
    adaptive_voxel_filter: AdaptiveVoxelFilter
    loop_closure_adaptive_voxel_filter: AdaptiveVoxelFilter
    use_online_correlative_scan_matching: bool
    real_time_correlative_scan_matcher: RealTimeCorrelativeScanMatcher
    ceres_scan_matcher: CeresScanMatcher
    motion_filter: MotionFilter
    submaps: Submaps2D


@dataclass(frozen=True)
class FastCorrelativeScanMatcher:
    linear_search_window: float
    angular_search_window: float
    branch_and_bound_depth: int


@dataclass(frozen=True)
class ConstraintBuilder:
    sampling_ratio: float
    max_constraint_distance: float
    min_score: float
    #: Cartographer reads it only for a node of one trajectory matched against another's
    #: submaps (global localisation); btnav maps one trajectory, where Cartographer never
    #: reads it either: range-checked, kept, no warning.
    global_localization_min_score: float
    loop_closure_translation_weight: float
    loop_closure_rotation_weight: float
    fast_correlative_scan_matcher: FastCorrelativeScanMatcher
    ceres_scan_matcher: CeresScanMatcher


@dataclass(frozen=True)
class OptimizationProblem:
    PATHS: typing.ClassVar[dict[str, Key]] = {
        "max_num_iterations": ("ceres_solver_options", "max_num_iterations"),
    }
    huber_scale: float
    local_slam_pose_translation_weight: float
    local_slam_pose_rotation_weight: float
    odometry_translation_weight: float
    odometry_rotation_weight: float
    max_num_iterations: int


@dataclass(frozen=True)
class PoseGraph:
    optimize_every_n_nodes: int
    constraint_builder: ConstraintBuilder
    matcher_translation_weight: float
    matcher_rotation_weight: float
    optimization_problem: OptimizationProblem
    max_num_final_iterations: int
    global_sampling_ratio: float


@dataclass(frozen=True)
class CartographerConfig:
    """A loaded configuration: the whole table as Python, btnav's typed view of what it acts
    on, and the keys it accepts but will not act on (the caller warns about them once)."""

    options: dict[str, Any]
    file: Path
    ignored: list[str]
    frames: Frames
    trajectory_builder_2d: TrajectoryBuilder2D
    pose_graph: PoseGraph

    def warn_ignored(self, stacklevel: int = 2) -> None:
        """The one warning that lists `ignored`, so a run never drops an option silently
        (`btnav slam --lua` and the live plugin say it in the same words)."""
        if self.ignored:
            warnings.warn(BtnavWarning(IGNORED_WARNING + ", ".join(self.ignored), file=self.file), stacklevel=stacklevel + 1)  # fmt: skip


#: How the warning about options btnav does not act on starts.
IGNORED_WARNING = "btnav does not implement these Cartographer options and runs without them: "


#: Where each typed view sits in the options table.
VIEWS: dict[str, tuple[type, Key]] = {
    "frames": (Frames, ()), "trajectory_builder_2d": (TrajectoryBuilder2D, TB2D), "pose_graph": (PoseGraph, PG),
}  # fmt: skip
