"""The frames a params file names, checked against the robot's frame tree.

A frame a params file names (`global_frame`, `robot_base_frame`, `odom_frame_id`,
`base_frame_id`, `sensor_frame`, ...) must be in the frame tree of the mission's
robot, or the server using it would fail its first transform lookup, as tf2 would.
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


def missing_frames(params: ParamsFile, frames: FrameTree) -> list[FrameParam]:
    return [p for p in frame_params(params) if p.checked and not frames.has(p.frame)]


def check_frames(params: ParamsFile, frames: FrameTree) -> None:
    """A located `FrameError` for the first frame the params name that `frames` lacks."""
    missing = missing_frames(params, frames)
    if missing:
        first = missing[0]
        more = f" ({len(missing) - 1} more)" if len(missing) > 1 else ""
        raise FrameError(
            f"frame '{first.frame}' is not in the robot's frame tree "
            f"({', '.join(frames.frames)}){more}",
            file=str(params.path),
            line=first.line,
            key=first.key,
            suggestion=best_match(first.frame, frames.frames),
        )
