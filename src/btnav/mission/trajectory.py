"""`trajectory.csv`: one row per control cycle, and the run's path length and localisation error.

Columns: `t, gt_x, gt_y, gt_yaw, est_x, est_y, est_yaw, odom_x, odom_y, odom_yaw, cmd_v,
cmd_w, contact`: the ground-truth pose, the localiser's estimate (the frame tree's
`map -> base_footprint`), the odometry (`odom -> base_footprint`: the wheels', or laser
odometry's with `odometry: {source: laser}`), the command the controller sent, and 1
on the row of the control cycle during which a new contact began (else 0; the
report's `contacts` says what was hit). The recorder runs in the runtime's MONITOR
stage at the controller's rate, so each row sees the command of that control cycle.
Rows stream to the file as they come (a long run keeps no history in memory); the
sums the report needs are kept as it goes, and the poses themselves only with
`keep_track` (for pictures).
"""

from __future__ import annotations

import math
from array import array
from typing import TextIO

import numpy as np

from ..core import fmath
from ..core.geometry import normalize_angle
from ..nav.runtime import Runtime, Stage

COLUMNS = (
    "t",
    "gt_x",
    "gt_y",
    "gt_yaw",
    "est_x",
    "est_y",
    "est_yaw",
    "odom_x",
    "odom_y",
    "odom_yaw",
    "cmd_v",
    "cmd_w",
    "contact",  # after the brief's columns: 1 when a new contact began in this cycle
)


class TrajectoryRecorder:
    """A MONITOR component: a row per control cycle, path length, localisation error."""

    stage = Stage.MONITOR

    def __init__(
        self,
        runtime: Runtime,
        rate: float,
        sink: TextIO | None = None,
        *,
        global_frame: str = "map",
        base_frame: str = "base_footprint",
        keep_track: bool = False,
    ) -> None:
        self.runtime = runtime
        self.rate = rate
        self.sink = sink
        self.global_frame = global_frame
        self.base_frame = base_frame
        self.rows = 0
        self.path_length = 0.0
        self._last_xy: tuple[float, float] | None = None
        self._sum_sq_xy = 0.0
        self._sum_sq_yaw = 0.0
        self.max_xy = 0.0
        self._contacts_seen = len(runtime.world.contacts)
        self._track: array[float] | None = array("d") if keep_track else None
        if sink is not None:
            sink.write(",".join(COLUMNS) + "\n")

    def update(self, now: float) -> None:
        rt = self.runtime
        gt = rt.world.robot_pose
        est = rt.robot_pose(self.global_frame, self.base_frame)
        odom = rt.latest_odom.pose
        cmd = rt.cmd_vel
        if self._last_xy is not None:
            self.path_length += fmath.hypot(gt.x - self._last_xy[0], gt.y - self._last_xy[1])
        self._last_xy = (gt.x, gt.y)
        err_sq = (est.x - gt.x) ** 2 + (est.y - gt.y) ** 2
        self._sum_sq_xy += err_sq
        self._sum_sq_yaw += normalize_angle(est.yaw - gt.yaw) ** 2
        self.max_xy = max(self.max_xy, math.sqrt(err_sq))
        self.rows += 1
        contacts = len(rt.world.contacts)
        contact = 1 if contacts > self._contacts_seen else 0
        self._contacts_seen = contacts
        if self._track is not None:
            self._track.extend((now, gt.x, gt.y, gt.yaw, est.x, est.y, est.yaw))
        if self.sink is not None:
            row = (now, gt.x, gt.y, gt.yaw, est.x, est.y, est.yaw)
            row += (odom.x, odom.y, odom.yaw, cmd.linear_x, cmd.angular_z, contact)
            self.sink.write(",".join(map(repr, row)) + "\n")

    @property
    def track(self) -> np.ndarray:
        """(rows, 7): t, gt_x, gt_y, gt_yaw, est_x, est_y, est_yaw (with `keep_track`)."""
        if self._track is None:
            return np.zeros((0, 7))
        return np.frombuffer(self._track, dtype=float).reshape(-1, 7).copy()

    def localization_error(self) -> dict[str, float]:
        """`rms_xy`, `max_xy` (m) and `rms_yaw` (rad) of the estimate against ground truth."""
        n = max(self.rows, 1)
        return {
            "rms_xy": math.sqrt(self._sum_sq_xy / n),
            "max_xy": self.max_xy,
            "rms_yaw": math.sqrt(self._sum_sq_yaw / n),
        }
