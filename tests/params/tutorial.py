"""A Jazzy tutorial's sections (issue 34), pasted into Nav2's own params file.

The tutorial prints controller_server, planner_server and behavior_server as below;
Nav2's nav2_params.yaml supplies every other section. Nav2 reads none of the keys in
`SKIPPED` and runs the file.
"""

from __future__ import annotations

import re
from pathlib import Path

TUTORIAL = """\
controller_server:
  ros__parameters:
    controller_frequency: 20.0
    min_x_velocity_threshold: 0.001
    min_y_velocity_threshold: 0.001
    min_theta_velocity_threshold: 0.001
    progress_checker_plugin: progress_checker
    goal_checker_plugin: goal_checker
    controller_plugins: [FollowPath]
    FollowPath:
      plugin: dwb_core::DWBLocalPlanner
      min_vel_x: -0.3
      max_vel_x: 0.3
      min_vel_y: 0.0
      max_vel_y: 0.0
      min_rot_vel: -0.5
      max_rot_vel: 0.5
      acc_lim_x: 0.5
      acc_lim_y: 0.0
      acc_lim_theta: 0.5
      decel_lim_x: -0.5
      decel_lim_y: 0.0
      decel_lim_theta: -0.5
      vx_samples: 20
      vy_samples: 0
      vtheta_samples: 40
      sim_time: 1.7
      scaling_xy: 0.5
      scaling_theta: 0.25
planner_server:
  ros__parameters:
    planner_plugins: [GridBased]
    GridBased:
      plugin: nav2_navfn_planner/NavfnPlanner
      tolerance: 0.5
      use_astar: false
      allow_unknown: true
behavior_server:
  ros__parameters:
    behavior_plugins: [Spin, BackUp, Wait]
    Spin:
      plugin: nav2_behaviors/Spin
      spin_dist: 1.57
      time_allowance: 10.0
    BackUp:
      plugin: nav2_behaviors/BackUp
      backup_dist: 0.15
      backup_speed: 0.025
      time_allowance: 10.0
    Wait:
      plugin: nav2_behaviors/Wait
      wait_duration: 5
      time_allowance: 10.0
"""

#: The keys Nav2 skips, in file order, and the catalogue family each belongs to.
SKIPPED: list[tuple[str, str]] = [
    ("controller_server.progress_checker_plugin", "renamed"),
    ("controller_server.goal_checker_plugin", "renamed"),
    ("controller_server.FollowPath.min_rot_vel", "ROS 1"),
    ("controller_server.FollowPath.max_rot_vel", "ROS 1"),
    ("controller_server.FollowPath.scaling_xy", "ROS 1"),
    ("controller_server.FollowPath.scaling_theta", "ROS 1"),
    ("behavior_server.Spin.spin_dist", "BT port"),
    ("behavior_server.Spin.time_allowance", "BT port"),
    ("behavior_server.BackUp.backup_dist", "BT port"),
    ("behavior_server.BackUp.backup_speed", "BT port"),
    ("behavior_server.BackUp.time_allowance", "BT port"),
    ("behavior_server.Wait.wait_duration", "BT port"),
    ("behavior_server.Wait.time_allowance", "BT port"),
]


def _blocks(text: str) -> dict[str, str]:
    """The file's top-level sections, each with its text, in order."""
    out: dict[str, str] = {}
    name = None
    for line in text.splitlines(keepends=True):
        head = re.match(r"^([A-Za-z_/][^:\s]*):", line)
        if head:
            name = head.group(1)
            out[name] = ""
        if name is not None:
            out[name] += line
    return out


def with_tutorial_sections(nav2_file: Path, out: Path, *, critics: str = "") -> Path:
    """Nav2's file with its three sections replaced by the tutorial's (written to `out`);
    `critics` (params-file lines, e.g. `DOCUMENTED_CRITICS`) is added at FollowPath's end."""
    return _paste(nav2_file, out, with_critics(TUTORIAL, critics))


def _paste(nav2_file: Path, out: Path, sections: str) -> Path:
    nav2, tutorial = _blocks(nav2_file.read_text()), _blocks(sections)
    assert set(tutorial) <= set(nav2)
    out.write_text("".join(tutorial.get(name, text) for name, text in nav2.items()))
    return out


def line_of(path: Path, key: str) -> int:
    """The line (1-based) of a dotted key's last part, searched below its parents."""
    lines = path.read_text().splitlines()
    n = 0
    for part in key.split("."):
        n = next(i for i in range(n, len(lines)) if lines[i].strip().startswith(f"{part}:"))
    return n + 1


#: What the missing-critics error tells a user to add to the tutorial's FollowPath: Nav2's
#: documented critics and scales (docs.nav2.org's DWB example, params/nav2_params_dwb.yaml).
DOCUMENTED_CRITICS = """\
      critics: ["RotateToGoal", "Oscillation", "BaseObstacle", "GoalAlign", "PathAlign", "PathDist", "GoalDist"]
      BaseObstacle.scale: 0.02
      PathAlign.scale: 32.0
      PathAlign.forward_point_distance: 0.1
      GoalAlign.scale: 24.0
      GoalAlign.forward_point_distance: 0.1
      PathDist.scale: 32.0
      GoalDist.scale: 24.0
      RotateToGoal.scale: 32.0
      RotateToGoal.slowing_factor: 5.0
      RotateToGoal.lookahead_time: -1.0
"""


#: The tutorial's FollowPath ends with this line; what a user adds goes after it.
FOLLOW_PATH_END = "      scaling_theta: 0.25\n"


def with_critics(sections: str, critics: str) -> str:
    """`sections` with `critics` (params-file lines) added at the end of FollowPath."""
    if critics and not critics.endswith("\n"):
        critics += "\n"
    assert sections.count(FOLLOW_PATH_END) == 1
    return sections.replace(FOLLOW_PATH_END, FOLLOW_PATH_END + critics)


def completed(critics: str = DOCUMENTED_CRITICS, extra: str = "") -> str:
    """The tutorial's sections as its two errors tell a user to fix them: `critics` (the
    documented list, or what the error printed) added at the end of FollowPath, and the
    behavior_plugins (and their sections) named as the default tree's nodes call them.
    `extra` (params-file lines) is added to FollowPath after the critics."""
    added = "".join(s + ("" if s.endswith("\n") else "\n") for s in (critics, extra) if s)
    text = with_critics(TUTORIAL, added)
    text = text.replace(
        "behavior_plugins: [Spin, BackUp, Wait]", "behavior_plugins: [spin, backup, wait]"
    )
    for old, new in (("Spin", "spin"), ("BackUp", "backup"), ("Wait", "wait")):
        text = text.replace(f"    {old}:\n", f"    {new}:\n")
    assert "    spin:\n" in text and "    Spin:\n" not in text
    return text


def with_completed_sections(
    nav2_file: Path, out: Path, critics: str = DOCUMENTED_CRITICS, extra: str = ""
) -> Path:
    """Nav2's file with the tutorial's sections, completed as `completed` says (to `out`)."""
    return _paste(nav2_file, out, completed(critics, extra))
