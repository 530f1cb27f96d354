"""A 2D scanning lidar: ray casts from its mounting pose against the world's geometry."""

from __future__ import annotations

import math
from typing import TYPE_CHECKING

import numpy as np
from pydantic import Field, model_validator

from ..core import fmath
from ..core.messages import LaserScan
from ..plugins import register
from .raycast import RayCaster
from .sensor import Sensor

if TYPE_CHECKING:
    pass

TWO_PI = 2.0 * math.pi
#: An angular span this close to 2*pi is a full circle (a YAML `6.2832` included).
_FULL_CIRCLE_TOL = 1e-3
#: Scans' worth of range noise drawn at once.
_NOISE_BATCH = 32


def _f32_at_least(x: float) -> np.float32:
    """The smallest float32 >= x, so a clipped float32 reading never falls below x."""
    f = np.float32(x)
    return f if float(f) >= x else np.nextafter(f, np.float32(np.inf))


def _f32_at_most(x: float) -> np.float32:
    """The largest float32 <= x."""
    f = np.float32(x)
    return f if float(f) <= x else np.nextafter(f, np.float32(-np.inf))


#: No intensities (the simulated lidar does not measure them); shared, never written.
_NO_INTENSITIES = np.zeros(0, np.float32)
_NO_INTENSITIES.flags.writeable = False


@register("sensor", "lidar")
class Lidar(Sensor):
    """A planar lidar publishing `LaserScan`s in its own frame.

    Beams: `beams` readings from `angle_min` to `angle_max` (sensor frame). When the
    span is a full circle (the default -pi..pi) the last beam is one increment short of
    `angle_max`, as a real 360-degree lidar does, so no direction is measured twice;
    otherwise both ends are measured. The message's `angle_max` is always the angle of
    the last beam, so `angle_min + i * angle_increment` is beam i (ROS convention).

    Ranges follow REP-117: `+inf` when nothing is hit within `range_max`, `-inf` when
    the hit is closer than `range_min` (the sensor cannot measure it but something is
    there, which a costmap may want to know). Gaussian noise (`noise_std`, metres) is
    added to in-range readings only, and the noisy value is clipped back into
    [range_min, range_max]: noise never turns a hit into "nothing there" or "too
    close", so the category of a reading is that of the true distance. The whole scan
    is taken at one instant (`time_increment` 0); noise comes from the generator the
    sensor is given, one normal draw per beam per scan (drawn 32 scans at a time, the
    same numbers as scan by scan), so a seed fixes every scan.

    The lidar sees `world.geometry()` at the time of each measurement: walls, static
    obstacles and moving obstacles where they are now; never the robot's own body.
    """

    class Params(Sensor.Params):
        beams: int = Field(360, ge=1, le=100_000, description="readings per scan")
        angle_min: float = Field(-math.pi, ge=-TWO_PI, le=TWO_PI, description="first beam (rad)")
        angle_max: float = Field(
            math.pi, ge=-TWO_PI, le=TWO_PI, description="end of the span (rad)"
        )
        range: tuple[float, float] = Field(
            (0.12, 8.0), description="[range_min, range_max] in metres"
        )
        noise_std: float = Field(0.0, ge=0.0, le=10.0, description="std dev of range noise (m)")

        @model_validator(mode="after")
        def _check(self) -> Lidar.Params:
            lo, hi = self.range
            if not (0.0 <= lo < hi) or not math.isfinite(hi):
                raise ValueError(
                    f"range must be [range_min, range_max] with 0 <= range_min < range_max,"
                    f" got [{lo}, {hi}]"
                )
            span = self.angle_max - self.angle_min
            if span < 0 or (span == 0 and self.beams > 1):
                raise ValueError(
                    f"angle_max ({self.angle_max}) must be greater than angle_min ({self.angle_min})"
                )
            if span > TWO_PI + _FULL_CIRCLE_TOL:
                raise ValueError(f"the angular span {span:.4f} rad is more than a full circle")
            return self

    params: Params

    def __init__(self, name: str, params: Params) -> None:
        super().__init__(name, params)
        p = params
        self.range_min, self.range_max = float(p.range[0]), float(p.range[1])
        span = p.angle_max - p.angle_min
        if p.beams == 1:
            inc = 0.0
        elif span >= TWO_PI - _FULL_CIRCLE_TOL:
            inc = span / p.beams  # full circle: the last beam does not repeat the first
        else:
            inc = span / (p.beams - 1)
        self.angle_min = float(p.angle_min)
        self.angle_increment = float(inc)
        self.angle_max = self.angle_min + inc * (p.beams - 1)
        self.angles = self.angle_min + inc * np.arange(p.beams)
        self.noise_std = float(p.noise_std)
        self._lo32 = _f32_at_least(self.range_min)
        self._hi32 = _f32_at_most(self.range_max)
        sin, cos = fmath.sincos(self.angles)
        self._local = np.stack([cos, sin])  # (2, B), sensor frame
        self._dirs_t = np.empty((2, p.beams))  # the same in the world, rewritten every scan
        self._rot = np.empty((2, 2))
        # Noise is drawn for _NOISE_BATCH scans at a time (one numpy call instead of one
        # per scan); the values are the same as drawing scan by scan from the stream.
        self._noise = np.empty((0, p.beams))
        self._noise_next = 0
        self._caster = RayCaster()

    def sensor_pose(self) -> tuple[float, float, float]:
        """The sensor's pose in the world (ground truth): robot pose composed with the mount."""
        r = self.world.robot_pose
        m = self.mount
        s, c = fmath.sincos(r.yaw)
        return (r.x + c * m.x - s * m.y, r.y + s * m.x + c * m.y, r.yaw + m.yaw)

    def true_ranges(self) -> np.ndarray:
        """Noise-free distances (float64) per beam from where the sensor is now; `inf` = no hit."""
        x, y, yaw = self.sensor_pose()
        # Rotate the cached beam directions instead of calling cos/sin per beam.
        rot = self._rot
        s, c = fmath.sincos(yaw)
        rot[0, 0] = rot[1, 1] = c
        rot[1, 0] = s
        rot[0, 1] = -s
        fmath.matmul_k(rot, self._local, out=self._dirs_t)  # not BLAS: CPU-independent bits
        return self._caster.cast(self.world.geometry(), (x, y), self._dirs_t.T, self.range_max)

    def _next_noise(self) -> np.ndarray:
        """Range noise for one scan (metres), one normal draw per beam."""
        if self._noise_next >= len(self._noise):
            self._noise = self.rng.standard_normal((_NOISE_BATCH, len(self.angles)))
            self._noise *= self.noise_std
            self._noise_next = 0
        self._noise_next += 1
        return self._noise[self._noise_next - 1]

    def measure(self, now: float) -> LaserScan:
        """One scan of the world as it is now, stamped `now`, in the sensor's frame."""
        t = self.true_ranges()  # inf: nothing within range_max
        ranges = np.empty(len(t), np.float32)
        if self.noise_std > 0:
            np.add(t, self._next_noise(), out=ranges, casting="same_kind")
        else:
            ranges[:] = t
        # Clip in float32 to bounds that are themselves inside [range_min, range_max];
        # a beam with no return stays +inf, one closer than range_min becomes -inf.
        np.clip(ranges, self._lo32, self._hi32, out=ranges, where=t < np.inf)
        if t.min() < self.range_min:
            ranges[t < self.range_min] = -np.inf
        return LaserScan(
            stamp=now,
            frame_id=self.frame_id,
            angle_min=self.angle_min,
            angle_max=self.angle_max,
            angle_increment=self.angle_increment,
            range_min=self.range_min,
            range_max=self.range_max,
            ranges=ranges,
            scan_time=1.0 / self.rate,
            time_increment=0.0,
            intensities=_NO_INTENSITIES,
        )
