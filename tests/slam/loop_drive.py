"""Drive the corridor loop for SLAM tests: pure pursuit on the true pose, SLAM mapping.

The tests judge SLAM, not navigation, so the robot is steered by the world's ground
truth along the corridors' middle (once round and on past the start, to close the loop)
while SLAM sees only odometry and scans, as slam_toolbox does under teleop.
"""

from __future__ import annotations

import itertools
import math
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import numpy as np

from btnav.core.messages import Twist
from btnav.nav.runtime import Runtime
from btnav.sim.world import World

REPO = Path(__file__).resolve().parents[2]
LOOP_WORLD = REPO / "worlds" / "corridor_loop.yaml"
#: Once round the corridors' middle and on past the start to (10, 1.2).
LOOP = [(1.2, 1.2), (26.8, 1.2), (26.8, 14.8), (1.2, 14.8), (1.2, 1.2), (10.0, 1.2)]


@dataclass
class Drive:
    runtime: Runtime
    slam: Any
    truth: np.ndarray  # (T, 4) t, x, y, yaw at every step
    odom: np.ndarray  # (T, 3) odometry placed at the start pose, at every step
    estimate: np.ndarray  # (T, 3) map -> base_footprint at every step

    def truth_at(self, stamps: np.ndarray) -> np.ndarray:
        k = np.clip(np.searchsorted(self.truth[:, 0], np.asarray(stamps) - 1e-9), 0, None)
        return self.truth[np.minimum(k, len(self.truth) - 1), 1:]


def _dense(points: list[tuple[float, float]], step: float = 0.05) -> np.ndarray:
    out = []
    for (ax, ay), (bx, by) in itertools.pairwise(points):
        n = max(1, int(math.hypot(bx - ax, by - ay) / step))
        out += [(ax + (bx - ax) * k / n, ay + (by - ay) * k / n) for k in range(n)]
    return np.array([*out, points[-1]])


def drive_loop(
    world: Path = LOOP_WORLD,
    *,
    seed: int = 0,
    params: Any = None,
    route: list[tuple[float, float]] = LOOP,
    kind: str = "slam",
    name: str = "slam",
    on_start: Any = None,
) -> Drive:
    w = World.from_file(world, seed=seed)
    rt = Runtime(w, seed=seed)
    slam = rt.use_localizer(name, params, kind=kind)
    if on_start is not None:  # e.g. give AMCL its map and initial pose
        on_start(slam)
    path = _dense(route)
    start = rt.frames.lookup("map", "odom")
    i = 0
    truth, odom, est = [], [], []
    while i < len(path) - 2:
        p = w.robot_pose
        near = np.hypot(path[i : i + 60, 0] - p.x, path[i : i + 60, 1] - p.y)
        i += int(np.argmin(near))
        tx, ty = path[min(i + 16, len(path) - 1)]
        a = math.atan2(ty - p.y, tx - p.x) - p.yaw
        a = math.atan2(math.sin(a), math.cos(a))
        rt.set_cmd_vel(
            Twist(linear_x=0.4 if abs(a) < 0.6 else 0.05, angular_z=max(-1.2, min(1.2, 2 * a)))
        )
        for _ in range(5):
            rt.step()
            truth.append((rt.now, *w.robot_pose.as_array()))
            odom.append((start @ rt.frames.lookup("odom", "base_footprint")).as_array())
            est.append(rt.robot_pose().as_array())
    return Drive(rt, slam, np.array(truth), np.array(odom), np.array(est))
