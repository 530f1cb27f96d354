"""SimpleSmoother: smoother paths, never into lethal cells, Nav2's params and codes."""

from __future__ import annotations

from pathlib import Path as FilePath

import numpy as np
import pytest

from btnav.core.geometry import Pose2D
from btnav.core.messages import Path
from btnav.costmap.costmap_2d import Costmap2D
from btnav.params import load_params
from btnav.planning.exceptions import InvalidPath, SmootherTimedOut, SmoothPathError
from btnav.planning.navfn_planner import NavfnPlanner
from btnav.planning.simple_smoother import SimpleSmoother, directional_segments
from btnav.plugins import lookup

RES = 0.05


def turning(poses: np.ndarray) -> float:
    """Total absolute heading change along a path (a curvature measure)."""
    d = np.diff(poses[:, :2], axis=0)
    d = d[np.hypot(*d.T) > 1e-9]
    h = np.unwrap(np.arctan2(d[:, 1], d[:, 0]))
    return float(np.abs(np.diff(h)).sum())


def staircase(n: int = 40) -> Path:
    pts = [(0.5 + RES * ((i + 1) // 2), 0.5 + RES * (i // 2)) for i in range(n)]
    poses = np.zeros((n, 3))
    poses[:, :2] = pts
    return Path(0.0, poses)


def test_registered_and_nav2_sections_validate(nav2_params_file: FilePath) -> None:
    assert lookup("smoother", "nav2_smoother::SimpleSmoother") is SimpleSmoother
    server = load_params(nav2_params_file).server("smoother_server")
    for name, ref in (("simple_smoother", 2), ("route_smoother", 5)):
        p = server.plugins[name].params
        assert (p.tolerance, p.max_its, p.refinement_num, p.do_refinement) == (
            1e-10,
            1000,
            ref,
            True,
        )


def test_smoothing_reduces_curvature_and_keeps_ends() -> None:
    cm = Costmap2D.empty(80, 80, RES)
    path = staircase()
    out, done = SimpleSmoother("s").smooth(path, cm)
    assert done
    assert turning(out.poses) < 0.3 * turning(path.poses)
    assert out.poses[0, :2] == pytest.approx(path.poses[0, :2])
    assert out.poses[-1, :2] == pytest.approx(path.poses[-1, :2])
    # orientations face along the path
    d = np.diff(out.poses[:, :2], axis=0)
    assert out.poses[:-1, 2] == pytest.approx(np.arctan2(d[:, 1], d[:, 0]))
    assert path.poses[5, 0] == 0.5 + RES * 3  # the input is not modified


def test_never_enters_lethal_cells_around_a_corner() -> None:
    cm = Costmap2D.empty(100, 100, RES)
    cm.costs[:60, 40:60] = 254  # a block whose corner the path wraps tightly
    planner = NavfnPlanner("p", NavfnPlanner.Params())
    path = planner.create_plan(Pose2D(1.0, 0.5), Pose2D(4.0, 0.5), cm)
    out, _ = SimpleSmoother("s", SimpleSmoother.Params(w_smooth=0.45, w_data=0.05)).smooth(path, cm)
    m, inside = cm.world_to_map(out.poses[:, :2])
    assert inside.all() and cm.costs[m[:, 1], m[:, 0]].max() < 253
    assert turning(out.poses) <= turning(path.poses)


def test_collision_reverts_to_the_last_feasible_iteration() -> None:
    cm = Costmap2D.empty(80, 80, RES)
    path = staircase()
    free_out, _ = SimpleSmoother("s").smooth(path, cm)
    # put an obstacle where the free smoothing moved a point to
    before = {tuple(c) for c in cm.world_to_map(path.poses[:, :2])[0]}
    after = [tuple(c) for c in cm.world_to_map(free_out.poses[:, :2])[0]]
    mx, my = next(c for c in after if c not in before)
    blocked = cm.copy()
    blocked.costs[my, mx] = 254
    out, done = SimpleSmoother("s").smooth(path, blocked)
    assert not done
    m, _ = blocked.world_to_map(out.poses[:, :2])
    assert blocked.costs[m[:, 1], m[:, 0]].max() < 253


def test_path_inversion_splits_at_cusps() -> None:
    xy = np.array([[0, 0], [1, 0], [2, 0], [1.5, 0.1], [1, 0.2]], float)
    assert directional_segments(xy) == [(0, 2), (2, 4)]


def test_codes_timeout_and_invalid() -> None:
    with pytest.raises(SmootherTimedOut) as info:
        SimpleSmoother("s").smooth(staircase(), cancel_checker=lambda: True)
    assert info.value.error_code == SmoothPathError.TIMEOUT == 502
    with pytest.raises(InvalidPath) as bad:
        SimpleSmoother("s").smooth(Path(0.0, np.zeros((3, 2))))
    assert bad.value.error_code == 505
    short = Path(0.0, np.zeros((3, 3)))
    assert SimpleSmoother("s").smooth(short).path.poses.tolist() == short.poses.tolist()
