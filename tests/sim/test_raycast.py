"""Ray casting agrees with geometry worked out by hand, at corners and along edges too."""

from __future__ import annotations

import math

import numpy as np
import pytest

from btnav.sim import raycast
from btnav.sim.geometry import Geometry
from btnav.sim.raycast import beam_directions, cast, cast_circles, cast_from_pose, cast_segments

ANGLES = np.linspace(-math.pi, math.pi, 360, endpoint=False)


def square_room(half: float = 2.0) -> Geometry:
    """A zero-thickness square outline centred on the origin."""
    h = half
    return Geometry([np.array([[-h, -h], [h, -h], [h, h], [-h, h]])])


def square_distance(angles: np.ndarray, half: float) -> np.ndarray:
    """From the centre of a square of half-side `half`, the distance to its outline."""
    return half / np.maximum(np.abs(np.cos(angles)), np.abs(np.sin(angles)))


def reference(origin, dirs, segments, circles) -> np.ndarray:
    """One ray and one segment at a time, the textbook way."""
    out = np.full(len(dirs), np.inf)
    for i, (dx, dy) in enumerate(dirs):
        for x1, y1, x2, y2 in segments:
            ex, ey, ax, ay = x2 - x1, y2 - y1, x1 - origin[0], y1 - origin[1]
            den = dx * ey - dy * ex
            if den == 0:
                continue
            t, u = (ax * ey - ay * ex) / den, (ax * dy - ay * dx) / den
            if t >= 0 and -1e-12 <= u <= 1 + 1e-12:
                out[i] = min(out[i], t)
        for cx, cy, r in circles:
            mx, my = cx - origin[0], cy - origin[1]
            b, c2 = dx * mx + dy * my, mx * mx + my * my - r * r
            disc = b * b - c2
            if disc >= 0:
                t = b - math.sqrt(disc) if c2 >= 0 else b + math.sqrt(disc)
                if t >= 0:
                    out[i] = min(out[i], t)
    return out


def random_scene(rng: np.random.Generator, n_polys: int = 25) -> Geometry:
    polys = []
    for _ in range(n_polys):
        c = rng.uniform(0, 10, 2)
        ang = np.sort(rng.uniform(0, 2 * np.pi, rng.integers(3, 7)))
        r = rng.uniform(0.2, 1.0, len(ang))
        polys.append(c + np.c_[r * np.cos(ang), r * np.sin(ang)])
    circles = np.c_[rng.uniform(0, 10, (4, 2)), rng.uniform(0.1, 0.6, 4)]
    return Geometry(polys, circles)


def test_square_room_from_centre_matches_analytic_distance():
    t = cast_from_pose(square_room(2.0), (0.0, 0.0, 0.0), ANGLES)
    np.testing.assert_allclose(t, square_distance(ANGLES, 2.0), rtol=0, atol=1e-9)


def test_rays_through_corners_hit_the_corner():
    # From the centre, the diagonals pass exactly through the shared vertices.
    diag = np.array([1, 3, 5, 7]) * math.pi / 4
    t = cast_from_pose(square_room(2.0), (0.0, 0.0, 0.0), diag)
    np.testing.assert_allclose(t, 2.0 * math.sqrt(2.0), rtol=0, atol=1e-9)


def test_off_centre_pose_and_yaw():
    yaw = 0.7
    pose = (0.5, -0.3, yaw)
    t = cast_from_pose(square_room(2.0), pose, ANGLES)
    a = ANGLES + yaw
    c, s = np.cos(a), np.sin(a)
    with np.errstate(divide="ignore"):
        tx = np.where(c > 0, (2.0 - 0.5) / c, (-2.0 - 0.5) / c)
        ty = np.where(s > 0, (2.0 + 0.3) / s, (-2.0 + 0.3) / s)
    np.testing.assert_allclose(t, np.minimum(np.abs(tx), np.abs(ty)), rtol=0, atol=1e-9)


def test_random_scenes_match_reference_including_misses():
    rng = np.random.default_rng(7)
    for _ in range(3):
        g = random_scene(rng)
        origin = rng.uniform(0, 10, 2)
        dirs = beam_directions(rng.uniform(-np.pi, np.pi, 90))
        got = cast(g, origin, dirs)
        want = reference(origin, dirs, g.segments, g.circles)
        assert np.array_equal(np.isinf(got), np.isinf(want))
        hit = np.isfinite(want)
        np.testing.assert_allclose(got[hit], want[hit], rtol=0, atol=1e-9)


def test_axis_aligned_parallel_rays_give_inf_not_nan():
    # Beams along x next to horizontal edges: d x e is exactly 0 for those pairs.
    g = Geometry([np.array([[0.0, 1.0], [5.0, 1.0], [5.0, 2.0], [0.0, 2.0]])])
    t = cast(g, (-1.0, 0.0), beam_directions([0.0, math.pi]))
    assert np.all(np.isinf(t)) and not np.any(np.isnan(t))


def test_ray_along_a_lone_segment_hits_its_near_end():
    # A two-point polygon is one segment, there and back: a ray along its line.
    g = Geometry([np.array([[2.0, 0.0], [4.0, 0.0]])])
    t = cast(g, (0.0, 0.0), beam_directions([0.0, math.pi, math.pi / 2]))
    assert t[0] == pytest.approx(2.0, abs=1e-12)
    assert math.isinf(t[1]) and math.isinf(t[2])


def test_origin_on_a_segment_reads_zero():
    g = Geometry([np.array([[2.0, 0.0], [4.0, 0.0], [4.0, -1.0], [2.0, -1.0]])])
    t = cast(g, (3.0, 0.0), beam_directions(ANGLES))
    assert np.all(t == 0.0)


def test_ray_along_polygon_edge_hits_the_vertex():
    # The origin is on the line of the box's top edge, left of the box.
    g = Geometry([np.array([[2.0, 0.0], [4.0, 0.0], [4.0, 1.0], [2.0, 1.0]])])
    t = cast(g, (0.0, 1.0), beam_directions([0.0]))
    assert t[0] == pytest.approx(2.0, abs=1e-12)


def test_circle_from_outside_and_inside():
    circles = np.array([[5.0, 0.0, 1.0]])
    dirs = beam_directions([0.0, math.asin(0.6), math.pi, math.asin(1.0 / 5.0) + 1e-6])
    t = cast_circles((0.0, 0.0), dirs, circles)
    assert t[0] == pytest.approx(4.0, abs=1e-12)
    # At asin(0.6) the ray passes 3 m from the centre; just past the tangent it misses.
    assert math.isinf(t[1]) and math.isinf(t[2]) and math.isinf(t[3])
    circles = np.array([[5.0, 0.0, 4.0]])
    t = cast_circles((0.0, 0.0), beam_directions([0.0, math.asin(0.6), math.pi / 2]), circles)
    assert t[0] == pytest.approx(1.0, abs=1e-12)
    # The ray passes 3 m from the centre, 4 m along it: it enters sqrt(4^2 - 3^2) earlier.
    assert t[1] == pytest.approx(4.0 - math.sqrt(7.0), abs=1e-12)
    assert math.isinf(t[2])
    # Inside a circle every ray meets its boundary on the way out.
    t = cast_circles((5.0, 0.0), beam_directions(ANGLES), circles)
    np.testing.assert_allclose(t, 4.0, atol=1e-12)


def test_max_range_turns_far_hits_into_inf():
    t = cast_from_pose(square_room(2.0), (0.0, 0.0, 0.0), ANGLES, max_range=2.5)
    want = square_distance(ANGLES, 2.0)
    assert np.array_equal(np.isinf(t), want > 2.5)


def test_pruning_and_chunking_do_not_change_results(monkeypatch):
    rng = np.random.default_rng(3)
    g = random_scene(rng, n_polys=40)
    origin = np.array([1.0, 1.0])
    dirs = beam_directions(ANGLES)
    base = cast_segments(origin, dirs, g.segments, 4.0, prune=False)
    pruned = cast_segments(origin, dirs, g.segments, 4.0, prune=True)
    near = base <= 4.0
    np.testing.assert_allclose(pruned[near], base[near], rtol=0, atol=1e-12)
    assert np.all(pruned[~near] > 4.0)
    whole = cast(g, origin, dirs)
    monkeypatch.setattr(raycast, "CHUNK_PAIRS", 50)  # 1 ray per block for the segments
    # BLAS may round a product differently for another block shape: equal to 1e-12.
    np.testing.assert_allclose(cast(g, origin, dirs), whole, rtol=0, atol=1e-12)


def test_empty_geometry_sees_nothing():
    t = cast(Geometry(), (0.0, 0.0), beam_directions(ANGLES), 10.0)
    assert t.shape == (360,) and np.all(np.isinf(t))


def test_circles_alone_and_many_circles_pruned_by_range():
    rng = np.random.default_rng(5)
    circles = np.c_[rng.uniform(-10, 10, (60, 2)), rng.uniform(0.1, 0.4, 60)]
    circles = circles[np.hypot(circles[:, 0], circles[:, 1]) > 1.0]  # none around the origin
    g = Geometry([], circles)
    dirs = beam_directions(ANGLES)
    full = cast(g, (0.0, 0.0), dirs)
    want = reference((0.0, 0.0), dirs, np.zeros((0, 4)), circles)
    assert np.array_equal(np.isinf(full), np.isinf(want)) and not np.isnan(full).any()
    np.testing.assert_allclose(full[np.isfinite(want)], want[np.isfinite(want)], atol=1e-9)
    near = cast(g, (0.0, 0.0), dirs, max_range=4.0, prune=True)
    np.testing.assert_array_equal(near, np.where(full <= 4.0, full, np.inf))


def test_sensor_inside_a_pillar_next_to_walls():
    g = Geometry(square_room(2.0).polygons, np.array([[0.0, 0.0, 0.5]]))
    t = cast(g, (0.1, 0.0), beam_directions([0.0, math.pi]))
    np.testing.assert_allclose(t, [0.4, 0.6], atol=1e-12)
