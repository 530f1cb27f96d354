"""`btnav frames MISSION`: the robot's frame tree, and every frame the params name checked."""

from __future__ import annotations

from typing import Any

from .mission import Mission
from .param_frames import check_frames, frame_params, missing_frames


def frames_main(path: str, overrides: dict[str, Any] | None = None) -> int:
    mission = Mission.load(path, overrides=overrides)
    frames = mission.frame_tree()
    print(frames.describe())
    print(f"\nframes named in {mission.params.path}:")
    missing = missing_frames(mission.params, frames)
    for p in frame_params(mission.params):
        state = "MISSING" if p in missing else "ok"
        if not p.checked:
            state = "not checked (section ignored by btnav)"
        print(f"  {p.key} = {p.frame} (line {p.line}): {state}")
    check_frames(mission.params, frames)
    return 0
