"""The drive a description's joints imply when no Gazebo drive plugin says it.

A wheel is a continuous (or unlimited revolute) joint turning about a horizontal axis,
with a cylinder on its link (its radius is the wheel's); a steering hinge is a
revolute or continuous joint turning about a vertical axis with a wheel below it.
Steering hinges make an Ackermann base: the wheelbase is the distance along x from
the rear (unsteered) wheels to the hinges, the track the rear wheels' y spread, the
steering limit the hinges' joint limit. Wheels on both sides and no hinge make a
differential base: the separation is the left wheels' y minus the right wheels', the
radius theirs. Casters (a link or joint named `caster`) are no drive wheels.
"""

from __future__ import annotations

from dataclasses import dataclass
from statistics import fmean  # fsum / n: not sum(), compensated from CPython 3.12 (0092)

from .model import Joint, RobotModel
from .robot_description import DriveDescription
from .transforms import Transform, compose, rotate

#: |z| of a unit axis above this is vertical, below `HORIZONTAL` horizontal.
VERTICAL, HORIZONTAL = 0.9, 0.1
#: Lengths are rounded to a nanometre (0.08 - -0.08 is the 0.16 the file means).
DECIMALS = 9


def _r(v: float | None) -> float | None:
    return None if v is None else round(v, DECIMALS) + 0.0


@dataclass(frozen=True)
class _Wheel:
    joint: Joint
    x: float
    y: float
    radius: float | None


def _axis_in_base(joint: Joint, poses: dict[str, Transform]) -> tuple[float, float, float]:
    frame = compose(poses[joint.child], joint.frame)
    x, y, z = rotate(frame[0], joint.axis)
    n = (x * x + y * y + z * z) ** 0.5 or 1.0
    return x / n, y / n, z / n


def _radius(model: RobotModel, link: str) -> float | None:
    shapes = model.links[link].collisions + model.links[link].visuals
    radii = [g.size[0] for g in shapes if g.kind == "cylinder"]
    return radii[0] if radii else None


def _turns(joint: Joint) -> bool:
    if joint.kind == "continuous":
        return True
    return joint.kind == "revolute" and (
        joint.lower is None or joint.upper is None or joint.upper - joint.lower > 6.0
    )


def _is_caster(joint: Joint) -> bool:
    return "caster" in joint.name.lower() or "caster" in joint.child.lower()


def read_drive_joints(model: RobotModel, poses: dict[str, Transform]) -> DriveDescription | None:
    """The drive the wheel and steering joints make, or None (no wheels found)."""
    wheels: list[_Wheel] = []
    hinges: list[Joint] = []
    for joint in model.joints:
        if joint.kind not in ("continuous", "revolute") or _is_caster(joint):
            continue
        axis_z = abs(_axis_in_base(joint, poses)[2])
        at = compose(poses[joint.child], joint.frame)[1]
        if axis_z < HORIZONTAL and _turns(joint):
            radius = _radius(model, joint.child)
            if radius is not None or "wheel" in joint.name.lower():
                wheels.append(_Wheel(joint, at[0], at[1], radius))
        elif axis_z > VERTICAL:
            hinges.append(joint)
    steered = set()
    hinges = [h for h in hinges if any(w.joint.child in model.subtree(h.child) for w in wheels)]
    for h in hinges:
        steered |= set(model.subtree(h.child))
    rear = [w for w in wheels if w.joint.child not in steered]
    radii = [w.radius for w in rear if w.radius is not None]
    radius = fmean(radii) if radii else None
    left, right = [w for w in rear if w.y > 0.0], [w for w in rear if w.y < 0.0]
    separation = None
    if left and right:
        separation = fmean(w.y for w in left) - fmean(w.y for w in right)
    names = ", ".join(w.joint.name for w in rear)
    if hinges and rear:
        hinge_x = [compose(poses[h.child], h.frame)[1][0] for h in hinges]
        wheelbase = abs(fmean(hinge_x) - fmean(w.x for w in rear))
        limits = [
            min(abs(h.lower), abs(h.upper))
            for h in hinges
            if h.lower is not None and h.upper is not None
        ]
        speeds = [h.velocity for h in hinges if h.velocity is not None and h.velocity > 0.0]
        first = hinges[0]
        return DriveDescription(
            "ackermann",
            source=f"joints {', '.join(h.name for h in hinges)} (steering), {names} (rear wheels)",
            file=first.file,
            line=first.line,
            wheel_separation=_r(separation),
            wheel_radius=_r(radius),
            wheelbase=_r(wheelbase) or None,
            max_steering_angle=min(limits) if limits and min(limits) > 0.0 else None,
            max_steering_speed=min(speeds) if speeds else None,
        )
    if separation is not None and separation > 0.0:
        first = rear[0].joint
        return DriveDescription(
            "diff_drive",
            source=f"joints {names}",
            file=first.file,
            line=first.line,
            wheel_separation=_r(separation),
            wheel_radius=_r(radius),
        )
    return None
