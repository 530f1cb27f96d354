"""The dense path of a route: a pose every `path_density` metres along the edges, and
corners rounded into arcs of `smoothing_radius` with `smooth_corners`."""

from __future__ import annotations

import math

import numpy as np
import pytest

from btnav.route.corner_smoothing import CornerArc
from btnav.route.graph import Route
from btnav.route.path_converter import PathConverter

from .graphs import graph


def l_route() -> Route:
    g = graph({0: (0.0, 0.0), 1: (4.0, 0.0), 2: (4.0, 3.0)}, [(0, 1), (1, 2)])
    return Route(g.node(0), [g.node(0).neighbors[0], g.node(1).neighbors[1]])


def test_poses_are_at_most_path_density_apart_and_face_the_next() -> None:
    path = PathConverter(path_density=0.05).densify(l_route())
    xy = path.poses[:, :2]
    steps = np.hypot(*np.diff(xy, axis=0).T)
    assert steps.max() <= 0.05 + 1e-9 and len(path) == 141  # 4 m + 3 m at 5 cm, and the end
    assert tuple(xy[0]) == (0.0, 0.0) and tuple(xy[-1]) == (4.0, 3.0)
    assert (4.0, 0.0) in {tuple(p) for p in xy}  # without smoothing it turns at the node
    assert path.poses[0, 2] == 0.0 and path.poses[-1, 2] == pytest.approx(math.pi / 2)


def test_smoothed_corners_are_an_arc_of_the_radius_tangent_to_both_edges() -> None:
    path = PathConverter(0.05, smooth_corners=True, smoothing_radius=1.0).densify(l_route())
    xy = path.poses[:, :2]
    # a right angle: the arc runs from (3, 0) to (4, 1) round the centre (3, 1)
    on_arc = (xy[:, 0] > 3.0 + 1e-9) & (xy[:, 1] < 1.0 - 1e-9)
    assert on_arc.sum() > 10
    assert np.hypot(xy[on_arc, 0] - 3.0, xy[on_arc, 1] - 1.0) == pytest.approx(1.0)
    assert np.hypot(*np.diff(xy, axis=0).T).max() <= 0.05 + 1e-9
    # the node's corner is cut: the arc passes sqrt(2) - 1 from it
    assert np.hypot(xy[:, 0] - 4.0, xy[:, 1]).min() == pytest.approx(math.sqrt(2) - 1, abs=1e-3)


def test_no_arc_for_a_straight_on_corner_or_one_that_does_not_fit() -> None:
    assert not CornerArc((0, 0), (1, 0), (2, 0.01), 1.0, 2.9).valid  # nearly straight
    assert not CornerArc((0, 0), (0.5, 0), (0.5, 0.5), 1.0, 2.9).valid  # edges too short
    assert CornerArc((0, 0), (2, 0), (2, 2), 1.0, 2.9).valid


def test_a_route_of_one_node_is_one_pose() -> None:
    g = graph({0: (1.0, 2.0), 1: (3.0, 2.0)}, [(0, 1)])
    path = PathConverter().densify(Route(g.node(0)))
    assert path.poses.tolist() == [[1.0, 2.0, 0.0]]
