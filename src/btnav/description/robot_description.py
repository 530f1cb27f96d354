"""What btnav takes from a robot description: frames, footprint, drive and lidars.

All poses are 2D, in the description's base frame (`base_frame`: its `base_footprint`
link, else `base_link`, else its root link), which btnav's `base_footprint` and
`base_link` stand for; heights (`z`) are kept for what a user checks against the file.
Each part names where it was read (`source`, `file`, `line`).
"""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import Any

from ..core import fmath

Pose = tuple[float, float, float]  # x, y, yaw
#: The frames btnav's own REP-105 chain has (`map -> odom -> base_footprint -> base_link`).
OWN_FRAMES = ("map", "odom", "base_footprint", "base_link")


@dataclass(frozen=True)
class LinkFrame:
    """One link of the description, placed in the base frame."""

    name: str
    parent: str | None
    x: float
    y: float
    z: float
    yaw: float


@dataclass(frozen=True)
class FootprintDescription:
    """The base link's collision geometry seen from above: a disc or a convex polygon."""

    radius: float | None
    polygon: tuple[tuple[float, float], ...] | None
    link: str
    source: str  # "box", "cylinder", "box + cylinder", ...
    file: str | None
    line: int | None

    def spec(self) -> dict[str, Any]:
        """As a world file writes it: `{radius: r}` or `{polygon: [[x, y], ...]}`."""
        if self.radius is not None:
            return {"radius": self.radius}
        assert self.polygon is not None
        return {"polygon": [list(p) for p in self.polygon]}


@dataclass(frozen=True)
class DriveDescription:
    """How the base moves: btnav's drive plugin name and the geometry it needs."""

    name: str  # diff_drive | ackermann | omni
    source: str  # the Gazebo plugin's file name, or "joints ..."
    file: str | None
    line: int | None
    wheel_separation: float | None = None
    wheel_radius: float | None = None
    wheelbase: float | None = None
    max_steering_angle: float | None = None
    max_steering_speed: float | None = None
    #: limits the plugin states, by btnav's `limits:` keys (v_max, v_min, w_max, a_max, alpha_max)
    limits: dict[str, float] = field(default_factory=dict)

    def params(self) -> dict[str, float]:
        """Every drive parameter the description gives (a drive plugin takes the ones it has)."""
        keys = ("wheel_separation", "wheel_radius", "wheelbase", "max_steering_angle")
        out = {k: getattr(self, k) for k in (*keys, "max_steering_speed")}
        return {k: float(v) for k, v in out.items() if v is not None}


@dataclass(frozen=True)
class LidarDescription:
    """A 2D lidar from its Gazebo sensor block, mounted where the joint chain puts it."""

    name: str  # the <sensor name="...">
    frame: str  # the frame its scans are stamped with
    link: str  # the link it is attached to
    pose: Pose  # in the base frame
    z: float  # height above the base frame
    beams: int
    angle_min: float
    angle_max: float
    range_min: float
    range_max: float
    rate: float
    noise_std: float
    file: str | None
    line: int | None

    def sensor_params(self) -> dict[str, Any]:
        """btnav's `lidar` sensor parameters, as a world file's `sensors:` entry writes them."""
        return {
            "frame": self.frame,
            "pose": list(self.pose),
            "beams": self.beams,
            "angle_min": self.angle_min,
            "angle_max": self.angle_max,
            "range": [self.range_min, self.range_max],
            "rate": self.rate,
            "noise_std": self.noise_std,
        }


@dataclass(frozen=True)
class RobotDescription:
    """A robot description read: what `btnav robot show` prints and a world's robot uses."""

    name: str
    file: str
    kind: str  # urdf | xacro | sdf
    base_frame: str
    frames: tuple[LinkFrame, ...]
    footprint: FootprintDescription | None
    drive: DriveDescription | None
    lidars: tuple[LidarDescription, ...]

    def frame(self, name: str) -> LinkFrame:
        for f in self.frames:
            if f.name == name:
                return f
        raise KeyError(name)

    def frame_edges(self) -> list[tuple[str, str, Pose]]:
        """(parent, child, pose of the child in the parent) for every link but the base
        frame, in tree order, each pose from the links' base-frame poses so composing
        the edges gives back where each link is (a 2D view of 3D joints)."""
        out = []
        for f in self.frames:
            if f.parent is None:
                continue
            p = self.frame(f.parent)
            s, c = fmath.sincos(p.yaw)
            dx, dy = f.x - p.x, f.y - p.y
            sd, cd = fmath.sincos(f.yaw - p.yaw)
            yaw = float(fmath.arctan2(sd, cd))
            out.append((f.parent, f.name, (c * dx + s * dy, -s * dx + c * dy, yaw)))
        return out

    def tf_edges(self) -> list[tuple[str, str, Pose]]:
        """Static transforms that add the description's links to btnav's frame tree.

        btnav's `base_footprint` and `base_link` coincide and stand for the base frame, so
        a link hanging from the base frame (or from `base_link`) goes under `base_link` at
        its base-frame pose; every other link under its own parent. Composing them gives
        each link's base-frame pose (what `frames` holds). When the base is a nested SDF
        model's (`robot::base_footprint`), that model's `robot::base_link` is btnav's too.
        """
        own = set(OWN_FRAMES) | {self.base_frame}
        scope, _, _ = self.base_frame.rpartition("::")
        if scope:
            own |= {f"{scope}::{name}" for name in OWN_FRAMES}
        out: list[tuple[str, str, Pose]] = []
        for parent, child, pose in self.frame_edges():
            if child in own:
                continue
            if parent in own:
                f = self.frame(child)
                out.append(("base_link", child, (f.x, f.y, f.yaw)))
            else:
                out.append((parent, child, pose))
        return out
