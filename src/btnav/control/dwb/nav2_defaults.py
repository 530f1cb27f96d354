"""The defaults a DWB section gets: Nav2's own when it is read from a params file, the
documented example (docs.nav2.org's DWB page) when it is built in code.

A params file runs as Nav2 runs it, so a key the section leaves out takes the value
Nav2's code declares: no `critics` list is refused (dwb_core's loadCritics throws "No
critics defined for FollowPath" and the controller_server does not configure), a
critic without `scale` weighs 1.0 (TrajectoryCritic), the align critics' forward point
is 0.325 m ahead, and every velocity and acceleration limit is 0.0
(KinematicsHandler), which leaves DWB no velocity to sample. A section written in code
(`DWBParams()`, `DWBParams(max_vel_x=0.5)`) is the documented FollowPath example
instead, so tests, benchmarks and scripts get a controller that drives without
spelling out twenty keys.
"""

from __future__ import annotations

from collections.abc import Mapping
from typing import Any

from ...params.schema import FieldProblem

#: docs.nav2.org's FollowPath example (params/nav2_params_dwb.yaml): the critics in order,
#: each with the keys the example gives it.
DOCUMENTED_CRITICS: dict[str, dict[str, float]] = {
    "RotateToGoal": {"scale": 32.0, "slowing_factor": 5.0, "lookahead_time": -1.0},
    "Oscillation": {},
    "BaseObstacle": {"scale": 0.02},
    "GoalAlign": {"scale": 24.0, "forward_point_distance": 0.1},
    "PathAlign": {"scale": 32.0, "forward_point_distance": 0.1},
    "PathDist": {"scale": 32.0},
    "GoalDist": {"scale": 24.0},
}

#: Nav2's code defaults for the DWB keys whose documented example value differs (the
#: KinematicsHandler's limits, StandardTrajectoryGenerator's linear_granularity).
NAV2_CODE_DEFAULTS: dict[str, float] = {
    "max_vel_x": 0.0,
    "max_vel_theta": 0.0,
    "max_speed_xy": 0.0,
    "acc_lim_x": 0.0,
    "acc_lim_theta": 0.0,
    "decel_lim_x": 0.0,
    "decel_lim_theta": 0.0,
    "linear_granularity": 0.5,
}

#: Where the documented section is shipped, for a message.
DOCUMENTED_FILE = "params/nav2_params_dwb.yaml"


def documented_critics_yaml(indent: str = "      ") -> str:
    """The documented critics as params-file lines (Nav2's flat `Critic.key: value` form),
    indented as keys of a plugin section, ready to paste under `FollowPath:`."""
    names = ", ".join(f'"{name}"' for name in DOCUMENTED_CRITICS)
    lines = [f"{indent}critics: [{names}]"]
    order = ("BaseObstacle", "PathAlign", "GoalAlign", "PathDist", "GoalDist", "RotateToGoal")
    for name in order:  # the example's own order
        lines += [
            f"{indent}{name}.{key}: {value}" for key, value in DOCUMENTED_CRITICS[name].items()
        ]
    return "\n".join(lines)


def missing_critics(data: Mapping[str, Any]) -> FieldProblem:
    """The located problem of a section read from a file without `critics:`; the message
    ends with the documented list and scales, indented like the section's own keys."""
    name, indent = _section_head(data)
    return FieldProblem(
        "critics",
        "no 'critics:' list; "
        f'Nav2 refuses this section too ("No critics defined for {name}": the '
        "controller_server does not start). Add Nav2's documented critics and scales "
        f"(docs.nav2.org's DWB example, as {DOCUMENTED_FILE} has them):\n"
        + documented_critics_yaml(indent),
    )


def _section_head(data: Mapping[str, Any]) -> tuple[str, str]:
    """The section's name and its keys' indentation, read from its file (the line above
    its first key); `FollowPath` and 6 spaces, Nav2's layout, when the file cannot tell."""
    name, indent = "FollowPath", " " * 6
    file, line = getattr(data, "file", None), getattr(data, "line", None)
    if not (file and line):
        return name, indent
    try:
        with open(file, encoding="utf-8") as f:
            rows = f.read().splitlines()
    except OSError:
        return name, indent
    if not 0 < line <= len(rows) or not rows[line - 1].strip():
        return name, indent
    first = rows[line - 1]
    indent = first[: len(first) - len(first.lstrip())]
    for row in reversed(rows[: line - 1]):
        text = row.strip()
        if not text or text.startswith("#"):
            continue
        head = text.split(":", 1)[0].strip().strip("\"'")
        if text.endswith(":") and len(row) - len(row.lstrip()) < len(indent) and head:
            name = head
        break
    return name, indent


def no_motion_reason(kin: Any, documented: Mapping[str, float]) -> str:
    """Why a cycle's limits (`KinematicParameters`) leave no velocity to sample: the limits
    at 0.0, with their `documented` values. Nav2 defaults every limit a section leaves out
    to 0.0, the usual cause. Empty when no limit is 0.0."""
    keys = ("max_speed_xy", "acc_lim_x", "max_vel_theta", "acc_lim_theta")
    zero = [k for k in keys if getattr(kin, k) == 0.0]
    if kin.max_vel_x == 0.0 and kin.min_vel_x == 0.0:
        zero.insert(0, "max_vel_x")
    if not zero:
        return ""
    verb = "are" if len(zero) > 1 else "is"
    example = ", ".join(f"{k}: {documented[k]}" for k in zero)
    return (
        f": {' and '.join(zero)} {verb} 0.0 (Nav2's default when the section leaves a limit "
        f"out), so no velocity is valid, in Nav2 too; set {'them' if len(zero) > 1 else 'it'} "
        f"(the documented example has {example})"
    )
