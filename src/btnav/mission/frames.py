"""`btnav frames MISSION`: the mission's frame tree, and every frame its params name checked.

A frame a params file names (`global_frame`, `robot_base_frame`, `odom_frame_id`,
`base_frame_id`, `sensor_frame`, ...) must be in the frame tree the mission's robot
has, or the server using it would fail its first transform lookup, as tf2 would.
Frames in sections btnav ignores (docking_server, loopback_simulator, ...) are
listed but not required.
"""

from __future__ import annotations

import re
from dataclasses import dataclass
from typing import Any

from ..core.errors import FrameError
from ..core.frames import FrameTree
from ..core.suggest import best_match
from ..core.yaml_io import YamlMap
from ..params.loader import ROS_PARAMETERS
from ..params.paramsfile import ParamsFile
from .mission import Mission

#: Keys that hold a frame id: `*_frame`, `*_frame_id`, `frame_id`.
FRAME_KEY = re.compile(r"(^|_)frame(_id)?$")


@dataclass(frozen=True)
class FrameParam:
    key: str
    frame: str
    line: int | None
    checked: bool  # False: in a section btnav ignores


def frame_params(params: ParamsFile) -> list[FrameParam]:
    """Every non-empty frame id in the file, in file order."""
    ignored = [e.key for e in params.ignored]
    found: list[FrameParam] = []

    def walk(node: Any, path: list[str]) -> None:
        if not isinstance(node, YamlMap):
            return
        for key, value in node.items():
            sub = path if key == ROS_PARAMETERS else [*path, str(key)]
            if isinstance(value, str) and value and FRAME_KEY.search(str(key)):
                dotted = ".".join(sub)
                skip = any(dotted == k or dotted.startswith(k + ".") for k in ignored)
                found.append(FrameParam(dotted, value, node.line_of(key), not skip))
            walk(value, sub)

    walk(params.raw, [])
    return found


def frames_report(mission: Mission) -> tuple[FrameTree, list[FrameParam], list[FrameParam]]:
    """The robot's frame tree at t = 0, the frame params, and those naming a frame it lacks."""
    frames = mission.navigator().runtime.frames
    found = frame_params(mission.params)
    missing = [p for p in found if p.checked and not frames.has(p.frame)]
    return frames, found, missing


def frames_main(path: str, overrides: dict[str, Any] | None = None) -> int:
    mission = Mission.load(path, overrides=overrides)
    tree, found, missing = frames_report(mission)
    print(tree.describe())
    print()
    print(f"frames named in {mission.params.path}:")
    for p in found:
        state = "MISSING" if p in missing else "ok"
        if not p.checked:
            state = "not checked (section ignored by btnav)"
        print(f"  {p.key} = {p.frame} (line {p.line}): {state}")
    if missing:
        first = missing[0]
        more = f" ({len(missing) - 1} more above)" if len(missing) > 1 else ""
        raise FrameError(
            f"frame '{first.frame}' is not in the robot's frame tree{more}",
            file=str(mission.params.path),
            line=first.line,
            key=first.key,
            suggestion=best_match(first.frame, tree.frames()),
        )
    return 0
