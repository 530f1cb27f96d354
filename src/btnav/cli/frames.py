"""`btnav frames MISSION`: the robot's frame tree, and every frame the params name checked.

Every frame is listed with its state before the check raises, so a user sees all the
frames at once and then the one-line error for the first missing one (exit 2).
"""

from __future__ import annotations

from typing import Any

from ..mission.mission import Mission
from ..mission.param_frames import check_frames, frame_params, missing_frames
from . import EXIT_OK


def frames_main(
    path: str, overrides: dict[str, Any] | None = None, origins: dict[str, str] | None = None
) -> int:
    mission = Mission.load(path, overrides=overrides, origins=origins)
    frames = mission.frame_tree()
    print(frames.describe())
    print(f"\nframes named in {mission.params.path}:")
    missing = missing_frames(mission.params, frames, mission.set_by)
    for p in frame_params(mission.params, mission.set_by):
        state = "MISSING" if p in missing else "ok"
        if not p.checked:
            state = "not checked (section ignored by btnav)"
        print(f"  {p.key} = {p.frame} ({p.place}): {state}")
    check_frames(mission.params, frames, mission.set_by)
    return EXIT_OK
