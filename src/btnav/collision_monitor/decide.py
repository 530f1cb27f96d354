"""One cycle of the monitor (CollisionMonitor::process): the sources' points, then each
enabled zone in turn, keeping the safest command any of them asks for.

A source with a timeout whose data is missing or too old stops the robot ("invalid
source"), whether or not the monitor is enabled, as in Nav2. Then, while the monitor
is enabled, each zone acts: stop (zero command, and no later zone is checked),
slowdown (the command times `slowdown_ratio`), limit (scaled so the speed is at most
`linear_limit` and the turn rate at most `angular_limit`, one ratio for both so the
curvature is kept) and approach (scaled by `collision_time / time_before_collision`);
a zone's command replaces the current one only when it is slower (x^2 + y^2 + w^2).
"""

from __future__ import annotations

from collections.abc import Sequence

import numpy as np
from numpy.typing import NDArray

from ..core import fmath
from ..core.messages import Twist
from .action import Action, ActionType, is_safer, is_zero, scaled
from .polygon import PointsBySource, Polygon
from .source import Source

#: The polygon name Nav2 reports when a source's data is missing or too old.
INVALID_SOURCE = "invalid source"


def collect_points(
    sources: Sequence[Source], now: float, *, stop_at_invalid: bool = True
) -> tuple[dict[str, NDArray[np.float64]], list[str]]:
    """Each source's points (empty when disabled or invalid) and the sources that are
    invalid with a timeout set. The monitor stops collecting at the first of those (it
    stops the robot anyway); the detector only reports them and goes on."""
    points: dict[str, NDArray[np.float64]] = {}
    invalid: list[str] = []
    for source in sources:
        points[source.name] = np.zeros((0, 2))
        if not source.enabled:
            continue
        data = source.get_data(now)
        if data is None:
            if source.source_timeout != 0.0:
                invalid.append(source.name)
                if stop_at_invalid:
                    break
            continue
        points[source.name] = data
    return points, invalid


def stop_slowdown_limit(
    polygon: Polygon, points: PointsBySource, cmd: Twist, action: Action
) -> bool:
    """Nav2's processStopSlowdownLimit: whether `polygon` now sets `action`."""
    if not polygon.is_shape_set():
        return False
    triggered, inside = polygon.is_triggered(points)
    if not triggered:
        return False
    kind = polygon.action_type
    if kind == ActionType.STOP:
        safe = Twist()
    elif kind == ActionType.SLOWDOWN:
        safe = scaled(cmd, polygon.slowdown_ratio)
    else:
        ratio = 1.0
        linear = float(fmath.hypot(cmd.linear_x, cmd.linear_y))
        if linear != 0.0:
            ratio = min(ratio, polygon.linear_limit / linear)
        if cmd.angular_z != 0.0:
            ratio = min(ratio, polygon.angular_limit / abs(cmd.angular_z))
        safe = scaled(cmd, min(max(ratio, 0.0), 1.0))
    if kind != ActionType.STOP and not is_safer(safe, action.req_vel):
        return False
    action.action_type, action.req_vel = kind, safe
    action.polygon_name, action.triggering_points = polygon.name, inside
    return True


def approach(polygon: Polygon, points: PointsBySource, cmd: Twist, action: Action) -> bool:
    """Nav2's processApproach: slow down so the collision stays `time_before_collision` away.

    Under a stop already asked for (a zero command) no slower command exists, so the
    footprint is not simulated: Nav2's answer, without the work."""
    if not polygon.is_shape_set() or is_zero(action.req_vel):
        return False
    time, inside = polygon.collision_time(points, cmd)
    if time < 0.0:
        return False
    safe = scaled(cmd, time / polygon.time_before_collision)
    if not is_safer(safe, action.req_vel):
        return False
    action.action_type, action.req_vel = ActionType.APPROACH, safe
    action.polygon_name, action.triggering_points = polygon.name, inside
    return True


def decide(
    polygons: Sequence[Polygon],
    points: PointsBySource,
    cmd: Twist,
    *,
    enabled: bool = True,
    invalid_sources: Sequence[str] = (),
) -> tuple[Action, Polygon | None]:
    """The action for `cmd` this cycle and the zone that caused it (None: no zone)."""
    if invalid_sources:
        return Action(ActionType.STOP, Twist(), INVALID_SOURCE), None
    action = Action(ActionType.DO_NOTHING, cmd)
    cause: Polygon | None = None
    if not enabled:
        return action, None
    for polygon in polygons:
        if not polygon.enabled:
            continue
        if action.action_type == ActionType.STOP:
            break
        polygon.update_polygon(cmd)
        kind = polygon.action_type
        if kind in (ActionType.STOP, ActionType.SLOWDOWN, ActionType.LIMIT):
            if stop_slowdown_limit(polygon, points, cmd, action):
                cause = polygon
        elif kind == ActionType.APPROACH and approach(polygon, points, cmd, action):
            cause = polygon
    return action, cause
