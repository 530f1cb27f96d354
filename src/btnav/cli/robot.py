"""`btnav robot show FILE [--package NAME=DIR] [--arg NAME=VALUE] [--model-path DIR] [--json]`.

Prints what btnav reads from a URDF, xacro or Gazebo SDF robot description: the drive
(and where it was read), the footprint, the wheel separation and radius or the
wheelbase, each 2D lidar (frame, mounting pose, beams, angles, range, rate, noise) and
the frame tree. With `--json`, the same as one JSON object. A broken description is a
`BtnavError` naming its file and line (the CLI prints it and exits 2).
"""

from __future__ import annotations

import json
import sys
from collections.abc import Iterable
from typing import Any, TextIO

from ..core.errors import BtnavError
from ..description import ModelPaths, PackagePaths, RobotDescription, load_description
from . import EXIT_OK


def parse_assignments(values: Iterable[str], option: str, what: str) -> dict[str, str]:
    """`["a=1", "b=x"]` -> {"a": "1", "b": "x"}; a malformed one names the option as typed."""
    out: dict[str, str] = {}
    for text in values:
        name, sep, value = text.partition("=")
        if not sep or not name.strip():
            raise BtnavError(f"expected {what}", file=f"{option} {text}")
        out[name.strip()] = value
    return out


def package_option(values: Iterable[str]) -> PackagePaths:
    """`--package NAME=DIR` options as package paths, each folder checked."""
    paths = PackagePaths.from_mapping(parse_assignments(values, "--package", "NAME=DIR"))
    try:
        paths.check()
    except BtnavError as err:
        raise err.located(file="--package") from None
    return paths


def _num(v: float | None, unit: str = "") -> str:
    return "-" if v is None else f"{v:g}{unit}"


def description_dict(desc: RobotDescription) -> dict[str, Any]:
    """What `--json` prints: the issue's keys, then the drive's details and the frames."""
    drive = desc.drive
    return {
        "name": desc.name,
        "file": desc.file,
        "drive": drive.name if drive is not None else None,
        "footprint": desc.footprint.spec() if desc.footprint is not None else None,
        "wheel_separation": drive.wheel_separation if drive is not None else None,
        "wheel_radius": drive.wheel_radius if drive is not None else None,
        "wheelbase": drive.wheelbase if drive is not None else None,
        "sensors": [
            {
                "type": "lidar",
                "frame": lidar.frame,
                "pose": list(lidar.pose),
                "height": lidar.z,
                "beams": lidar.beams,
                "angle_min": lidar.angle_min,
                "angle_max": lidar.angle_max,
                "range_min": lidar.range_min,
                "range_max": lidar.range_max,
                "rate": lidar.rate,
                "noise_std": lidar.noise_std,
            }
            for lidar in desc.lidars
        ],
        "drive_params": drive.params() if drive is not None else {},
        "limits": dict(drive.limits) if drive is not None else {},
        "base_frame": desc.base_frame,
        "frames": [
            {"frame": f.name, "parent": f.parent, "xyz": [f.x, f.y, f.z], "yaw": f.yaw}
            for f in desc.frames
        ],
    }


def _where(file: str | None, line: int | None) -> str:
    return f"{file}:{line}" if file and line else file or "?"


def describe(desc: RobotDescription) -> str:
    """The description as a person reads it."""
    lines = [f"robot '{desc.name}' ({desc.kind}: {desc.file})"]
    drive = desc.drive
    if drive is None:
        lines.append("drive: none found (no Gazebo drive plugin, no wheel joints)")
    else:
        lines.append(f"drive: {drive.name}, from {drive.source} ({_where(drive.file, drive.line)})")
        if drive.name == "ackermann":
            lines.append(
                f"  wheelbase {_num(drive.wheelbase, ' m')}, track {_num(drive.wheel_separation, ' m')}, "
                f"wheel radius {_num(drive.wheel_radius, ' m')}, steering limit "
                f"{_num(drive.max_steering_angle, ' rad')}, steering speed "
                f"{_num(drive.max_steering_speed, ' rad/s')}"
            )
        else:
            lines.append(
                f"  wheel separation {_num(drive.wheel_separation, ' m')}, "
                f"wheel radius {_num(drive.wheel_radius, ' m')}"
            )
        if drive.limits:
            lines.append("  limits: " + ", ".join(f"{k} {v:g}" for k, v in drive.limits.items()))
    fp = desc.footprint
    if fp is None:
        lines.append("footprint: none (no box, cylinder or sphere collision on the base link)")
    elif fp.radius is not None:
        lines.append(
            f"footprint: radius {fp.radius:g} m ({fp.link}'s {fp.source}, {_where(fp.file, fp.line)})"
        )
    else:
        assert fp.polygon is not None
        pts = ", ".join(f"[{x:g}, {y:g}]" for x, y in fp.polygon)
        lines.append(
            f"footprint: polygon [{pts}] ({fp.link}'s {fp.source}, {_where(fp.file, fp.line)})"
        )
    if not desc.lidars:
        lines.append("sensors: no 2D lidar")
    else:
        lines.append("sensors:")
    for lidar in desc.lidars:
        x, y, yaw = lidar.pose
        lines.append(
            f"  lidar '{lidar.name}' in frame {lidar.frame} (on {lidar.link}, "
            f"{_where(lidar.file, lidar.line)})"
        )
        lines.append(
            f"    pose [{x:g}, {y:g}, {yaw:g}] in {desc.base_frame}, {lidar.z:g} m up; "
            f"{lidar.beams} beams from {lidar.angle_min:g} to {lidar.angle_max:g} rad; "
            f"range {lidar.range_min:g}-{lidar.range_max:g} m; {lidar.rate:g} Hz; "
            f"noise_std {lidar.noise_std:g} m"
        )
    lines.append(f"frames (from {desc.base_frame}):")
    children: dict[str | None, list[Any]] = {}
    for f in desc.frames:
        children.setdefault(f.parent, []).append(f)

    def walk(parent: str | None, depth: int) -> None:  # each link under its own parent
        for f in children.get(parent, []):
            lines.append(f"  {'  ' * depth}{f.name}  [{f.x:g}, {f.y:g}, {f.z:g}] yaw {f.yaw:g}")
            walk(f.name, depth + 1)

    walk(None, 0)
    return "\n".join(lines)


def robot_main(
    file: str,
    packages: Iterable[str] = (),
    xacro_args: Iterable[str] = (),
    model_paths: Iterable[str] = (),
    *,
    as_json: bool = False,
    out: TextIO | None = None,
) -> int:
    """Read `file` and print what btnav takes from it (as JSON with `as_json`)."""
    out = out or sys.stdout
    paths = package_option(packages)
    args = parse_assignments(xacro_args, "--arg", "NAME=VALUE")
    desc = load_description(file, paths, args, ModelPaths.from_list(list(model_paths)))
    if as_json:
        print(json.dumps(description_dict(desc), indent=2), file=out)
    else:
        print(describe(desc), file=out)
    return EXIT_OK
