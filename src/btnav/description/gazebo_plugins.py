"""The drive a description's Gazebo drive plugin (or gz-sim system) block states.

When the block is there it is what Gazebo drives the robot with, so it wins over what
the joints suggest:

- diff drive: Gazebo classic's `libgazebo_ros_diff_drive.so` (ROS 2: `wheel_separation`,
  `wheel_diameter`, `max_wheel_acceleration`; ROS 1: `wheelSeparation`, `wheelDiameter`,
  `wheelAcceleration`) and `libgazebo_ros_skid_steer_drive.so`; gz-sim's `DiffDrive`
  (`wheel_separation`, `wheel_radius`, `max_linear_acceleration`, `max_linear_velocity`,
  `min_linear_velocity`, `max_angular_velocity`, `max_angular_acceleration`);
- Ackermann: gz-sim's `AckermannSteering` (`wheel_base`, `steering_limit`,
  `wheel_separation`, `wheel_radius`, `min_velocity`, `max_velocity`, `max_acceleration`)
  and classic's `libgazebo_ros_ackermann_drive.so` (`max_steer`, `max_speed`; its
  wheelbase comes from the joints);
- omni: classic's `libgazebo_ros_planar_move.so`, gz-sim's `MecanumDrive`.
"""

from __future__ import annotations

from .model import Block, RobotModel
from .robot_description import DriveDescription
from .xml_values import child_number


def _kind(block: Block) -> str | None:
    text = f"{block.element.get('filename', '')} {block.element.get('name', '')}".lower()
    if "ackermann" in text:
        return "ackermann"
    if "diff_drive" in text or "diff-drive" in text or "diffdrive" in text or "skid_steer" in text:
        return "diff_drive"
    if "planar_move" in text or "mecanum" in text:
        return "omni"
    return None


def _first(block: Block, model: RobotModel, *paths: str, positive: bool = True) -> float | None:
    for path in paths:
        value = child_number(block.element, path, model.sources, positive=positive)
        if value is not None:
            return value
    return None


def _limits(block: Block, model: RobotModel, table: dict[str, tuple[str, ...]]) -> dict[str, float]:
    out: dict[str, float] = {}
    for key, paths in table.items():
        value = _first(block, model, *paths, positive=key != "v_min")
        if value is not None:
            out[key] = value
    if "v_min" in out and out["v_min"] > 0.0:  # gz-sim's min_velocity is a signed speed
        out["v_min"] = -out["v_min"]
    return out


def read_drive_plugin(model: RobotModel) -> tuple[DriveDescription, Block] | None:
    """The first drive plugin block's drive, and the block (None when there is none)."""
    for block in model.plugins:
        kind = _kind(block)
        if kind is None:
            continue
        source = block.element.get("filename") or block.element.get("name") or "plugin"
        where = dict(source=source, file=block.file, line=block.line)
        if kind == "diff_drive":
            diameter = _first(block, model, "wheel_diameter", "wheelDiameter")
            radius = _first(block, model, "wheel_radius")
            if radius is None and diameter is not None:
                radius = diameter / 2.0
            limits = _limits(
                block,
                model,
                {
                    "v_max": ("max_linear_velocity", "max_velocity"),
                    "v_min": ("min_linear_velocity", "min_velocity"),
                    "w_max": ("max_angular_velocity",),
                    "a_max": (
                        "max_linear_acceleration",
                        "max_acceleration",
                        "max_wheel_acceleration",
                        "wheelAcceleration",
                    ),
                    "alpha_max": ("max_angular_acceleration",),
                },
            )
            sep = _first(block, model, "wheel_separation", "wheelSeparation")
            return DriveDescription(
                "diff_drive", wheel_separation=sep, wheel_radius=radius, limits=limits, **where
            ), block
        if kind == "ackermann":
            limits = _limits(
                block,
                model,
                {
                    "v_max": ("max_velocity", "max_speed"),
                    "v_min": ("min_velocity",),
                    "a_max": ("max_acceleration",),
                },
            )
            return DriveDescription(
                "ackermann",
                wheel_separation=_first(block, model, "wheel_separation"),
                wheel_radius=_first(block, model, "wheel_radius"),
                wheelbase=_first(block, model, "wheel_base", "wheelbase"),
                max_steering_angle=_first(block, model, "steering_limit", "max_steer"),
                limits=limits,
                **where,
            ), block
        return DriveDescription(
            "omni",
            wheel_separation=_first(block, model, "wheel_separation"),
            wheel_radius=_first(block, model, "wheel_radius"),
            wheelbase=_first(block, model, "wheelbase", "wheel_base"),
            **where,
        ), block
    return None
