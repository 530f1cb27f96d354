"""What every observation source shares (nav2_collision_monitor's Source): whether it is
on, when its data is too old, its exclusion zones, and the transform of its data into
the base frame now.

`base_shift_correction` (Nav2's default) moves the data by the robot's motion since it
was measured: data in frame F stamped t reaches the base frame through the odom frame,
`base(now) <- odom <- F(t)`. The pose of F in odom at t is taken when the data arrives
(`SourceFrames.at_arrival`), which is t in btnav's loop, where odometry is published
before the sensors in each step. Without it the data is put where F is now.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from numpy.typing import NDArray

from ..core.frames import FrameTree
from ..core.geometry import Pose2D
from ..params.collision_monitor import ObservationSource
from .exclusion_zone import ExclusionZone


@dataclass(frozen=True)
class SourceFrames:
    """The frames a source works in: the tree, the base and odom frames, the correction."""

    tree: FrameTree
    base_frame: str = "base_footprint"
    odom_frame: str = "odom"
    base_shift_correction: bool = True

    def at_arrival(self, frame: str) -> Pose2D | None:
        """Frame `frame` in odom as the data arrives (kept for the correction), or None."""
        return self.tree.lookup(self.odom_frame, frame) if self.base_shift_correction else None

    def to_base(self, frame: str, odom_pose_then: Pose2D | None) -> Pose2D:
        """The transform taking data in `frame` into the base frame now."""
        if odom_pose_then is None:
            return self.tree.lookup(self.base_frame, frame)
        return self.tree.lookup(self.base_frame, self.odom_frame) @ odom_pose_then


class Source:
    """Base of the sources: `get_data(now)` is the base-frame points, or None when the
    source is invalid (no data yet, data older than `source_timeout`)."""

    def __init__(
        self,
        name: str,
        params: ObservationSource,
        frames: SourceFrames,
        source_timeout: float,
        zones: list[ExclusionZone] | None = None,
    ) -> None:
        self.name = name
        self.params = params
        self.frames = frames
        self.enabled = params.enabled
        #: 0 disables the timeout (and then missing data is not a reason to stop).
        self.source_timeout = (
            params.source_timeout if params.source_timeout is not None else source_timeout
        )
        self.exclusion_zones = list(zones or [])

    def source_valid(self, stamp: float, now: float) -> bool:
        return self.source_timeout == 0.0 or now - stamp <= self.source_timeout

    def source_data(self, now: float) -> NDArray[np.float64] | None:
        raise NotImplementedError

    def get_data(self, now: float) -> NDArray[np.float64] | None:
        """The points in the base frame, less those in an enabled exclusion zone."""
        points = self.source_data(now)
        if points is None or len(points) == 0:
            return points
        for zone in self.exclusion_zones:
            points = zone.apply(now, points)
        return points

    def __repr__(self) -> str:
        return f"{type(self).__name__}({self.name!r})"
