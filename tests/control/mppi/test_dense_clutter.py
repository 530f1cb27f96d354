"""MPPI with Nav2's defaults crosses a dense cylinder forest, as a user would run it.

The forests are bench/dense_clutter.py's (one generator for the bench and this test):
0.075 m cylinders on a jittered 0.6 m lattice across a 10 x 10 m square, no gap of a
width the map's and the local costmap's cells could judge differently, a 0.42 x 0.33 m
robot, Nav2's params/nav2_params.yaml unchanged and ground-truth localisation. What a
user notices: the robot gets to the goal, touches nothing, within the 100 s limit.
"""

from __future__ import annotations

import importlib.util
import math
import sys
from pathlib import Path
from types import ModuleType

import pytest

BENCH = Path(__file__).resolve().parents[3] / "bench" / "dense_clutter.py"
DENSITY_SPACING = 0.6


def dense_clutter() -> ModuleType:
    """bench/dense_clutter.py as a module (bench/ is not a package)."""
    name = "btnav_bench_dense_clutter"
    if name in sys.modules:
        return sys.modules[name]
    spec = importlib.util.spec_from_file_location(name, BENCH)
    assert spec is not None and spec.loader is not None, BENCH
    module = importlib.util.module_from_spec(spec)
    sys.modules[name] = module
    spec.loader.exec_module(module)
    return module


def test_forests_are_dense_and_passable() -> None:
    """The worlds are the clutter they claim: 60 or more cylinders in the middle 8 m, and the
    widest route's narrowest gap well under a metre yet above the robot's 0.44 m."""
    dc = dense_clutter()
    density = dc.Density(spacing=DENSITY_SPACING)
    for seed in (0, 8):
        cylinders, half_gap, _ = dc.forest(seed, density)
        assert len(cylinders) >= 60
        assert 2 * dc.NAV2_ROBOT_RADIUS < 2 * half_gap < 1.0
        again, _, _ = dc.forest(seed, density)
        assert (again == cylinders).all()  # same seed, same forest


@pytest.mark.slow
@pytest.mark.parametrize("seed", [0, 8])
def test_mppi_crosses_the_forest_without_contact_within_the_limit(seed: int) -> None:
    dc = dense_clutter()
    r = dc.run_world(seed, dc.Density(spacing=DENSITY_SPACING))
    assert r.status == "succeeded", r
    assert r.collisions == 0, r
    # without stalling: Nav2 Jazzy's optimizer (btnav's before) stood still in front of
    # world 8's gaps until the 100 s limit, 8 recoveries, and took 82 s on world 0
    assert r.sim_time < 60.0 and r.recoveries == 0, r
    # no long detour or dithering: under 1.5 times the straight line
    assert r.path_length < 1.5 * math.dist(dc.START[:2], dc.GOAL[:2]), r
