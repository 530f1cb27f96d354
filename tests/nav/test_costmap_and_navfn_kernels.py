"""In the closed loop, the compiled costmap and NavFn passes change nothing: the office
tour's costmaps after every update and its plans are the numpy reference's, byte for byte."""

from __future__ import annotations

import hashlib
from pathlib import Path

import numpy as np
import pytest

from btnav import Navigator
from btnav.costmap import costmap_ros, inflation_layer, obstacle_layer
from btnav.planning import navfn, navfn_planner

REPO = Path(__file__).resolve().parents[2]
WORLD = REPO / "worlds" / "small_office.yaml"
PARAMS = REPO / "params" / "nav2_params.yaml"
MAP = REPO / "maps" / "small_office.yaml"


def tour(monkeypatch: pytest.MonkeyPatch, method: str) -> tuple[list[str], list[str], str]:
    """The office tour to its second waypoint with every layer and NavFn on `method`:
    a digest of each costmap update (its name, origin and cells), of each plan, and of
    the robot's trajectory."""
    for module in (obstacle_layer, inflation_layer, navfn, navfn_planner):
        monkeypatch.setattr(module, "DEFAULT_METHOD", method)
    updates: list[str] = []
    plans: list[str] = []
    update, create_plan = costmap_ros.CostmapROS.update, navfn_planner.NavfnPlanner.create_plan

    def recorded_update(self, *args, **kwargs):  # type: ignore[no-untyped-def]
        done = update(self, *args, **kwargs)
        m = self.costmap
        key = f"{self.name} {m.origin_x!r} {m.origin_y!r}".encode() + m.costs.tobytes()
        updates.append(hashlib.sha1(key).hexdigest())
        return done

    def recorded_plan(self, *args, **kwargs):  # type: ignore[no-untyped-def]
        assert self.method == method
        path = create_plan(self, *args, **kwargs)
        plans.append(hashlib.sha1(path.poses.tobytes() + self.potential.tobytes()).hexdigest())
        return path

    monkeypatch.setattr(costmap_ros.CostmapROS, "update", recorded_update)
    monkeypatch.setattr(navfn_planner.NavfnPlanner, "create_plan", recorded_plan)
    nav = Navigator.from_files(WORLD, PARAMS, MAP, seed=0)
    poses: list[tuple[float, float, float]] = []

    def pose() -> None:
        p = nav.world.robot_pose
        poses.append((p.x, p.y, p.yaw))

    nav.follow_waypoints([(3.0, 2.0, 1.57), (6.0, 3.0, 0.0)])
    result = nav.wait_until_done(60.0, poll=pose)
    assert result is not None and result.succeeded
    monkeypatch.undo()
    return updates, plans, hashlib.sha1(np.array(poses).tobytes()).hexdigest()


@pytest.mark.slow
def test_the_office_tour_is_the_numpy_paths_byte_for_byte(monkeypatch) -> None:
    kernel = tour(monkeypatch, "kernel")
    reference = tour(monkeypatch, "numpy")
    assert len(kernel[0]) > 100 and len(kernel[1]) >= 3  # ~25 s of sim time
    assert kernel == reference
