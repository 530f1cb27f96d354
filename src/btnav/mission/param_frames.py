"""The frames a params file names, checked against the robot's frame tree.

A frame a params file names (`global_frame`, `robot_base_frame`, `odom_frame_id`,
`base_frame_id`, `sensor_frame`, ...) must be in the frame tree of the mission's
robot, or the server using it would fail its first transform lookup, as tf2 would.
Frames in sections btnav ignores (docking_server, loopback_simulator, ...) are
listed but not required.
"""

from __future__ import annotations

import re
from collections.abc import Mapping
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
    origin: str | None = None  # the `--set KEY=VALUE` that gave it, if one did

    @property
    def place(self) -> str:
        """Where the value was written: `line 8`, or `--set amcl.base_frame_id=base_foot`."""
        return self.origin or f"line {self.line}"


def frame_params(params: ParamsFile, set_by: Mapping[str, str] | None = None) -> list[FrameParam]:
    """Every non-empty frame id in the file, in file order.

    `set_by` maps keys changed by `--set` (`amcl.base_frame_id`, or a section above one)
    to that option, which then stands for the file line the value was never on.
    """
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
                origin = _set_by(dotted, set_by or {})
                line = None if origin else node.line_of(key)
                found.append(FrameParam(dotted, value, line, not skip, origin))
            walk(value, sub)

    walk(params.raw, [])
    return found


def _set_by(key: str, set_by: Mapping[str, str]) -> str | None:
    for place, origin in set_by.items():
        if key == place or key.startswith(place + "."):
            return origin
    return None


def missing_frames(
    params: ParamsFile, frames: FrameTree, set_by: Mapping[str, str] | None = None
) -> list[FrameParam]:
    return [p for p in frame_params(params, set_by) if p.checked and not frames.has(p.frame)]


def check_frames(
    params: ParamsFile, frames: FrameTree, set_by: Mapping[str, str] | None = None
) -> None:
    """A located `FrameError` for the first frame the params name that `frames` lacks
    (located at the `--set` that gave it, when `set_by` says one did)."""
    missing = missing_frames(params, frames, set_by)
    if missing:
        first = missing[0]
        more = f" ({len(missing) - 1} more)" if len(missing) > 1 else ""
        raise FrameError(
            f"frame '{first.frame}' is not in the robot's frame tree "
            f"({', '.join(frames.frames)}){more}",
            file=first.origin or str(params.path),
            line=first.line,
            key=first.key,
            suggestion=best_match(first.frame, frames.frames),
        )
