"""opennav_docking's PoseFilter: an exponential filter over successive dock detections.

Each new detection moves the filtered position `filter_coef` of the way towards it and
slerps the orientation by the same fraction. A detection older than `timeout` after the
last one, or in another frame, restarts the filter; `filter_coef <= 0` passes detections
through unfiltered.
"""

from __future__ import annotations

from ..core.nav2_docking_msgs import PoseStamped3D
from ..core.quaternion import slerp


class PoseFilter:
    def __init__(self, coef: float, timeout: float) -> None:
        self.coef = float(coef)
        self.timeout = float(timeout)
        self.pose: PoseStamped3D | None = None

    def update(self, measurement: PoseStamped3D) -> PoseStamped3D:
        """The filtered pose after `measurement` (stamped and framed as it is)."""
        if self.coef <= 0.0:
            return measurement
        last = self.pose
        stamp = last.stamp if last is not None else 0.0
        if (
            last is None
            or measurement.stamp - stamp > self.timeout
            or last.frame_id != measurement.frame_id
        ):
            self.pose = measurement
            return measurement
        k = self.coef
        position = tuple(
            (1.0 - k) * f + k * m for f, m in zip(last.position, measurement.position, strict=True)
        )
        orientation = slerp(last.orientation, measurement.orientation, k)
        self.pose = PoseStamped3D(measurement.stamp, measurement.frame_id, position, orientation)  # type: ignore[arg-type]
        return self.pose
