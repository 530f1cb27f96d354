"""BackUp: drive straight backwards (nav2_behaviors::BackUp).

DriveOnHeading with the distance and speed taken as backwards whatever their
signs, as Nav2's BackUp does: `backup_dist: 0.3, backup_speed: 0.05` and
`-0.3, -0.05` mean the same.
"""

from __future__ import annotations

import math
from typing import Any

from ..plugins import register
from .behavior import BehaviorOutcome
from .drive_on_heading import DriveOnHeading, _point


@register("behavior", "nav2_behaviors::BackUp", aliases=["btnav/BackUp"])
class BackUp(DriveOnHeading):
    """Drive backwards by |target.x| at |speed|."""

    action = "BackUp"

    def _command(self, goal: Any) -> tuple[float, float] | BehaviorOutcome:
        x, y, z = _point(goal.target)
        if y != 0.0 or z != 0.0:
            return self.fail("INVALID_INPUT", "BackUp drives along x only; target y, z must be 0")
        if not (math.isfinite(x) and math.isfinite(goal.speed)) or goal.speed == 0.0:
            return self.fail(
                "INVALID_INPUT", f"speed must be finite and non-zero, got {goal.speed}"
            )
        return -abs(x), -abs(float(goal.speed))
