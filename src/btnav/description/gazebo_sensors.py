"""Every 2D lidar of a description, from its Gazebo sensor block, mounted along the joints.

Gazebo classic writes a lidar as `<sensor type="ray">` (or `gpu_ray`) with a `<ray>`;
gz-sim as `type="gpu_lidar"` (or `lidar`) with a `<lidar>` (or `<ray>`). Both hold
`scan/horizontal/{samples, resolution, min_angle, max_angle}`, `range/{min, max}` and a
`noise` (gaussian `stddev`); the sensor has an `update_rate` and a `<pose>` in its link.
The scans' frame is the plugin's `frame_name` (ROS 2), `frameName` (ROS 1) or the
sensor's `gz_frame_id` (gz-sim), else the link's name. A lidar with more than one
vertical sample (a 3D lidar) is not a 2D scanner and is skipped with a warning.
"""

from __future__ import annotations

import math
import warnings
import xml.etree.ElementTree as ET

from ..core.errors import BtnavWarning
from .model import Block, RobotModel
from .robot_description import LidarDescription
from .source_lines import SourceFiles
from .transforms import IDENTITY, Transform, compose, from_xyz_rpy, up_of, yaw_of
from .xml_values import child_number, child_text, error, floats

LIDAR_TYPES = ("ray", "gpu_ray", "lidar", "gpu_lidar")
#: The frames btnav's own frame chain owns: a scan cannot be stamped with one of these.
BASE_FRAMES = ("base_footprint", "base_link")
#: Rounding of mounting poses (metres, radians): a nanometre, so chains of rotations
#: give the 0.0 the file means and not 1e-17.
DECIMALS = 9
DEFAULT_RATE = 10.0
#: A span this much over 2*pi is a full circle written with rounded digits (6.28319).
FULL_CIRCLE_TOL = 1e-3


def sdf_pose(element: ET.Element | None, sources: SourceFiles) -> Transform:
    """An SDF `<pose>x y z roll pitch yaw</pose>` (radians, or degrees="true")."""
    if element is None or not (element.text or "").strip():
        return IDENTITY
    v = floats(element.text, 6, "<pose>", element, sources)
    if (element.get("degrees") or "").strip().lower() in ("true", "1"):
        v = (*v[:3], *(math.radians(a) for a in v[3:]))
    return from_xyz_rpy(v[:3], v[3:])


def _frame_name(sensor: ET.Element, link: str) -> str:
    for path in ("gz_frame_id", "frame_id", "plugin/frame_name", "plugin/frameName"):
        text = child_text(sensor, path)
        if text:
            return text
    return link


def _lidar(block: Block, poses: dict[str, Transform], model: RobotModel) -> LidarDescription | None:
    s, sources = block.element, model.sources
    name = s.get("name") or "lidar"
    ray = s.find("lidar")
    if ray is None:
        ray = s.find("ray")
    if ray is None:
        raise error(f"lidar '{name}' has no <ray> (or <lidar>) element", s, sources)
    horizontal = ray.find("scan/horizontal")
    if horizontal is None:
        raise error(f"lidar '{name}' has no <scan><horizontal> element", ray, sources)
    vertical = child_number(ray, "scan/vertical/samples", sources, 1.0)
    if vertical is not None and vertical > 1:
        warnings.warn(
            BtnavWarning(
                f"lidar '{name}' has {vertical:g} vertical samples (a 3D lidar); btnav "
                "simulates 2D lidars only, so it is left out",
                file=block.file,
                line=block.line,
            ),
            stacklevel=4,
        )
        return None
    samples = child_number(horizontal, "samples", sources, positive=True)
    if samples is None:
        raise error(f"lidar '{name}' needs <samples>", horizontal, sources)
    resolution = child_number(horizontal, "resolution", sources, 1.0, positive=True)
    assert resolution is not None
    beams = round(samples * resolution)  # Gazebo: resolution multiplies the samples
    a_min = child_number(horizontal, "min_angle", sources, 0.0)
    a_max = child_number(horizontal, "max_angle", sources, 0.0)
    assert a_min is not None and a_max is not None
    if a_max < a_min or (a_max == a_min and beams > 1):
        raise error(
            f"lidar '{name}': max_angle ({a_max:g}) must be above min_angle ({a_min:g})",
            horizontal,
            sources,
        )
    if a_max - a_min > 2.0 * math.pi + FULL_CIRCLE_TOL:
        raise error(f"lidar '{name}' spans more than a full circle", horizontal, sources)
    if a_max - a_min > 2.0 * math.pi:  # 0 to 6.28319, as ROBOTIS writes a full turn
        a_max = a_min + 2.0 * math.pi
    r_min = child_number(ray, "range/min", sources, 0.0)
    r_max = child_number(ray, "range/max", sources)
    assert r_min is not None
    if r_max is None:
        raise error(f"lidar '{name}' needs <range><max>", ray, sources)
    if not 0.0 <= r_min < r_max:
        raise error(
            f"lidar '{name}': range min ({r_min:g}) must be below max ({r_max:g}) and not negative",
            ray.find("range"),
            sources,
        )
    noise = ray.find("noise")
    std = 0.0
    if noise is not None and (child_text(noise, "type") or "gaussian").lower().startswith(
        "gaussian"
    ):
        std = child_number(noise, "stddev", sources, 0.0) or 0.0
    rate = child_number(s, "update_rate", sources, 0.0) or 0.0
    if rate <= 0.0:
        warnings.warn(
            BtnavWarning(
                f"lidar '{name}' has no update_rate (Gazebo: as fast as it can); btnav "
                f"runs it at {DEFAULT_RATE:g} Hz",
                file=block.file,
                line=block.line,
            ),
            stacklevel=4,
        )
        rate = DEFAULT_RATE
    assert block.link is not None
    local = block.pose if block.pose is not None else sdf_pose(s.find("pose"), sources)
    mount = compose(poses[block.link], local)
    if up_of(mount) < 1.0 - 1e-6:
        warnings.warn(
            BtnavWarning(
                f"lidar '{name}' is not mounted level (its z axis is tilted or upside down); "
                "btnav takes its scan plane as horizontal",
                file=block.file,
                line=block.line,
            ),
            stacklevel=4,
        )
    frame = _frame_name(s, block.link)
    if frame in BASE_FRAMES:
        frame = name  # btnav's base frames are its own; the scan gets the sensor's name
    x, y, z = (round(v, DECIMALS) + 0.0 for v in mount[1])
    yaw = round(yaw_of(mount), DECIMALS) + 0.0
    return LidarDescription(
        name=name,
        frame=frame,
        link=block.link,
        pose=(x, y, yaw),
        z=z,
        beams=beams,
        angle_min=a_min,
        angle_max=a_max,
        range_min=r_min,
        range_max=r_max,
        rate=rate,
        noise_std=std,
        file=block.file,
        line=block.line,
    )


def read_lidars(model: RobotModel, poses: dict[str, Transform]) -> tuple[LidarDescription, ...]:
    """The description's 2D lidars, in the order they are written."""
    out = []
    frames: dict[str, int | None] = {}
    for block in model.sensors:
        if (block.element.get("type") or "").strip() not in LIDAR_TYPES:
            continue
        lidar = _lidar(block, poses, model)
        if lidar is None:
            continue
        if lidar.frame in frames:
            raise error(
                f"two lidars publish in frame '{lidar.frame}' (the other at line "
                f"{frames[lidar.frame]}); give each its own frame",
                block.element,
                model.sources,
            )
        frames[lidar.frame] = lidar.line
        out.append(lidar)
    return tuple(out)
