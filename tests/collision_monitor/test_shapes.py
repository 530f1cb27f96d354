"""Inside tests over many points at once: Nav2's ray-crossing rule and the strict circle."""

from __future__ import annotations

import math

import numpy as np
import pytest

from btnav.collision_monitor.shapes import (
    Outline,
    circle_outline,
    points_in_circle,
    points_in_polygon,
)

SQUARE = np.array([[0.3, 0.3], [0.3, -0.3], [0.0, -0.3], [0.0, 0.3]])  # Nav2's PolygonStop


def test_points_inside_and_outside_a_square() -> None:
    pts = np.array([[0.1, 0.0], [0.29, 0.29], [0.31, 0.0], [-0.01, 0.0], [0.1, 0.31], [0.1, -0.5]])
    assert points_in_polygon(pts, SQUARE).tolist() == [True, True, False, False, False, False]
    # on the left edge counts as inside, on the right edge as outside (Nav2's crossing rule)
    assert points_in_polygon(np.array([[0.0, 0.0], [0.3, 0.0]]), SQUARE).tolist() == [True, False]


def test_a_concave_polygon_leaves_its_notch_out() -> None:
    # an L: the square [0, 2]^2 less its top-right quarter
    ell = np.array([[0, 0], [2, 0], [2, 1], [1, 1], [1, 2], [0, 2]], float)
    pts = np.array([[0.5, 0.5], [1.5, 0.5], [0.5, 1.5], [1.5, 1.5], [2.5, 0.5]])
    assert points_in_polygon(pts, ell).tolist() == [True, True, True, False, False]


def test_matches_nav2s_rule_point_by_point_on_random_points() -> None:
    rng = np.random.default_rng(3)
    poly = rng.uniform(-1, 1, (7, 2))
    pts = rng.uniform(-1.2, 1.2, (500, 2))

    def nav2(px: float, py: float) -> bool:  # isPointInsidePolygon, one point at a time
        res, i = False, len(poly) - 1
        for j in range(len(poly)):
            if (py <= poly[i, 1]) == (py > poly[j, 1]):
                x = poly[i, 0] + (py - poly[i, 1]) * (poly[j, 0] - poly[i, 0]) / (
                    poly[j, 1] - poly[i, 1]
                )
                if x > px:
                    res = not res
            i = j
        return res

    assert points_in_polygon(pts, poly).tolist() == [nav2(x, y) for x, y in pts]


def test_batches_of_points_keep_their_shape() -> None:
    pts = np.ones((3, 5, 2))
    pts[1] = [0.1, 0.0]
    out = points_in_polygon(pts, SQUARE)
    assert out.shape == (3, 5)
    assert out[1].all() and not out[0].any()


def test_circle_is_strict_and_its_outline_has_16_vertices() -> None:
    pts = np.array([[0.5, 0.0], [0.49, 0.0], [0.0, -0.51]])
    assert points_in_circle(pts, 0.5).tolist() == [False, True, False]
    outline = circle_outline(0.5)
    assert outline.shape == (16, 2)
    np.testing.assert_allclose(outline[0], [0.5, 0.0])
    np.testing.assert_allclose(np.hypot(outline[:, 0], outline[:, 1]), 0.5)


def nav2_inside(poly: np.ndarray, px: float, py: float) -> bool:
    """nav2_util's isPointInsidePolygon, one point at a time."""
    res, i = False, len(poly) - 1
    for j in range(len(poly)):
        if (py <= poly[i, 1]) == (py > poly[j, 1]):
            x = poly[i, 0] + (py - poly[i, 1]) * (poly[j, 0] - poly[i, 0]) / (
                poly[j, 1] - poly[i, 1]
            )
            if x > px:
                res = not res
        i = j
    return res


def test_points_on_and_next_to_the_bounding_box_fall_as_in_nav2() -> None:
    # the box test leaves out points beyond the polygon's extent before the edges are
    # looked at: on its sides, at the vertices and an ulp either side, nothing changes
    rng = np.random.default_rng(5)
    footprint = circle_outline(0.22)
    polygons = [
        SQUARE,
        np.array([[0, 0], [2, 0], [2, 1], [1, 1], [1, 2], [0, 2]], float),  # an L
        footprint,
        rng.uniform(-1, 1, (6, 2)),
    ]
    for poly in polygons:
        xs = np.unique(np.concatenate([poly[:, 0], np.nextafter(poly[:, 0], np.inf)]))
        xs = np.unique(np.concatenate([xs, np.nextafter(poly[:, 0], -np.inf)]))
        ys = np.unique(np.concatenate([poly[:, 1], np.nextafter(poly[:, 1], np.inf)]))
        ys = np.unique(np.concatenate([ys, np.nextafter(poly[:, 1], -np.inf), [0.0, 0.05]]))
        pts = np.stack(np.meshgrid(xs, ys), axis=-1).reshape(-1, 2)
        got = points_in_polygon(pts, poly).tolist()
        assert got == [nav2_inside(poly, x, y) for x, y in pts.tolist()]
    assert points_in_polygon(np.array([[0.0, 0.0]]), footprint).tolist() == [True]


def test_an_outline_answers_as_the_polygon_does() -> None:
    outline = Outline(SQUARE)
    pts = np.random.default_rng(2).uniform(-0.5, 0.5, (4, 50, 2))
    np.testing.assert_array_equal(outline.contains(pts), points_in_polygon(pts, SQUARE))
    assert outline.reach == pytest.approx(math.hypot(0.3, 0.3))
    assert Outline(np.zeros((0, 2))).contains(pts).shape == (4, 50)
