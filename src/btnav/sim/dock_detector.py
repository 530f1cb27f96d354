"""A simulated dock detector: the apriltag-on-a-camera a Nav2 robot finds its dock with.

Mounted on the robot like a lidar (`- dock_detector: {frame: dock_camera, pose: [...]}`
in `robot.sensors`), it looks for the marker in the middle of each dock's front face
(`sim.docks.marker_pose`) and, when one is within `range`, inside the horizontal field
of view `fov` and seen no more than `max_view_angle` off the face's normal, reports the
nearest: its pose in the sensor frame with seeded Gaussian noise (`noise_std`: metres on
x and y, radians on yaw), as a `DockDetection` stamped now. No dock in view: a detection
without a pose (a real detector publishes nothing then). Walls do not hide a marker.

The orientation is the marker's as an apriltag detector gives it: x to the right as the
camera sees the tag, y down, z into the tag. Nav2's `external_detection_rotation_*` of
nav2_params.yaml (roll -1.57, pitch -1.57, yaw 0) turn that frame back into the dock's
yaw; `external_detection_translation_x` is minus the distance from the dock pose to the
face (the footprint's front by default: -0.22 for a 0.22 m radius robot).
"""

from __future__ import annotations

import math

import numpy as np
from pydantic import Field

from ..core import fmath
from ..core.geometry import Pose2D, normalize_angle
from ..core.nav2_docking_msgs import DockDetection, PoseStamped3D
from ..core.quaternion import Quaternion, from_yaw, multiply
from ..plugins import register
from .docks import marker_pose
from .sensor import Sensor

#: An apriltag's axes in the frame of the face it is stuck on (x along the dock's
#: heading): x_tag = -y, y_tag = -z, z_tag = +x.
TAG_AXES: Quaternion = (0.5, -0.5, 0.5, -0.5)


@register("sensor", "dock_detector")
class DockDetector(Sensor):
    class Params(Sensor.Params):
        range: float = Field(3.0, gt=0.0, le=100.0, description="m to the marker, at most")
        fov: float = Field(1.2, gt=0.0, le=2.0 * math.pi, description="horizontal, radians")
        max_view_angle: float = Field(
            1.2, gt=0.0, le=0.5 * math.pi, description="radians off the face's normal"
        )
        noise_std: tuple[float, float] = Field(
            (0.005, 0.01), description="[m on x and y, rad on yaw] of the reported pose"
        )

    params: Params

    def measure(self, now: float) -> DockDetection:
        p = self.params
        camera = self.world.robot_pose @ self.mount
        noise = self.rng.normal(0.0, 1.0, 3)  # drawn every time: the stream never shifts
        best: tuple[float, str, Pose2D] | None = None
        for dock in self.world.spec.docks:
            marker = marker_pose(dock, self.world.spec)
            seen = camera.inverse() @ marker
            distance = fmath.hypot(seen.x, seen.y)
            if distance > p.range or distance == 0.0:
                continue
            if abs(fmath.arctan2(seen.y, seen.x)) > 0.5 * p.fov:
                continue
            # the face's normal points back along the dock's heading, at the camera
            off_normal = normalize_angle(fmath.arctan2(-seen.y, -seen.x) - (seen.yaw + math.pi))
            if abs(off_normal) > p.max_view_angle:
                continue
            if best is None or distance < best[0]:
                best = (distance, dock.name, seen)
        if best is None:
            return DockDetection(now, self.frame_id)
        _, name, seen = best
        sxy, syaw = p.noise_std
        noisy = np.array([seen.x, seen.y, seen.yaw]) + noise * np.array([sxy, sxy, syaw])
        orientation = multiply(from_yaw(float(noisy[2])), TAG_AXES)
        pose = PoseStamped3D(
            now, self.frame_id, (float(noisy[0]), float(noisy[1]), 0.0), orientation
        )
        return DockDetection(now, self.frame_id, pose, name)
