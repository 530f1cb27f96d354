"""Regulated Pure Pursuit's collision check along the carrot arc: the cells near the robot
looked at first (no inscribed cell within the arc's length: no walk) change no answer."""

from __future__ import annotations

import numpy as np
import pytest

from btnav.control import regulated_pure_pursuit as rpp
from btnav.control.regulated_pure_pursuit import RegulatedPurePursuitController as RPP
from btnav.core.geometry import Pose2D
from btnav.costmap.costmap_2d import Costmap2D

from .unicycle import free_costmap


def scattered_obstacles(rng: np.random.Generator, blobs: int) -> Costmap2D:
    """A 3 m costmap with `blobs` squares of 3 x 3 inscribed, lethal, unknown or dear
    cells scattered over it."""
    cm = free_costmap(size_m=3.0, origin=-1.5)
    ny, nx = cm.costs.shape
    for y, x, cost in zip(
        rng.integers(0, ny - 2, blobs),
        rng.integers(0, nx - 2, blobs),
        rng.choice([253, 254, 255, 200], blobs),
        strict=True,
    ):
        cm.costs[y : y + 3, x : x + 3] = cost
    return cm


def collides(ctrl: RPP, pose: Pose2D, linear: float, angular: float, cm: Costmap2D) -> bool:
    return ctrl._collision_imminent(pose, linear, angular, 0.6, 10.0, cm)


@pytest.mark.parametrize("horizon", [1.0, 5.0])  # up to 64 steps a walk, beyond it arrays
def test_the_arc_check_answers_as_the_walk_along_the_whole_arc(monkeypatch, horizon) -> None:
    rng = np.random.default_rng(7)
    ctrl = RPP(params=RPP.Params(max_allowed_time_to_collision_up_to_carrot=horizon))
    scenes = []
    for trial in range(400):
        cm = scattered_obstacles(rng, int(rng.integers(0, 120)))
        pose = Pose2D(*rng.uniform(-1.2, 1.2, 2), rng.uniform(-3.1, 3.1))
        linear = [0.0, 0.005, rng.uniform(-0.5, 0.5), rng.uniform(-0.5, 0.5)][trial % 4]
        scenes.append((pose, linear, rng.uniform(-1.8, 1.8), cm))
    fast = [collides(ctrl, *scene) for scene in scenes]
    monkeypatch.setattr(rpp, "_inscribed_near", lambda *args: True)  # always walk
    walked = [collides(ctrl, *scene) for scene in scenes]
    assert fast == walked
    assert 40 <= sum(walked) <= 360  # both answers are there to be found


def test_an_inscribed_cell_at_the_end_of_the_arc_is_still_found() -> None:
    # 0.5 m/s for 1 s in 5 cm steps: the walk goes 0.45 m; a face of inscribed cells from
    # 0.4 m ahead is on it (just within the square the walk can reach)
    cm = free_costmap(size_m=3.0, origin=-1.5)
    ctrl = RPP()
    mx = int((0.4 + 1.5) / cm.resolution)
    cm.costs[:, mx : mx + 2] = 253
    assert collides(ctrl, Pose2D(), 0.5, 0.0, cm)
    assert not collides(ctrl, Pose2D(0.0, 0.0, 3.14159), 0.5, 0.0, cm)
