from __future__ import annotations

import math

import numpy as np
import pytest

from btnav.core.geometry import Pose2D, angle_diff, compose_arrays, normalize_angle


def test_normalize_angle_scalar_and_array_agree():
    a = np.linspace(-20, 20, 1001)
    out = normalize_angle(a)
    assert np.all(out > -math.pi) and np.all(out <= math.pi)
    assert np.allclose(np.cos(out), np.cos(a)) and np.allclose(np.sin(out), np.sin(a))
    assert all(
        math.isclose(normalize_angle(float(x)), y, abs_tol=1e-12)
        for x, y in zip(a, out, strict=True)
    )
    assert normalize_angle(-math.pi) == pytest.approx(math.pi)


def test_compose_inverse_and_points():
    rng = np.random.default_rng(1)
    for _ in range(100):
        a = Pose2D(*rng.uniform(-5, 5, 3))
        b = Pose2D(*rng.uniform(-5, 5, 3))
        ident = a @ a.inverse()
        assert abs(ident.x) < 1e-12 and abs(ident.y) < 1e-12 and abs(ident.yaw) < 1e-12
        assert np.allclose((a @ b).as_matrix(), a.as_matrix() @ b.as_matrix())
        pts = rng.uniform(-3, 3, (7, 2))
        assert np.allclose(a.inverse_transform_points(a.transform_points(pts)), pts)
        rel = b.relative_to(a)
        assert np.allclose((a @ rel).as_array(), b.as_array())


def test_compose_arrays_matches_pose_composition():
    rng = np.random.default_rng(2)
    a, b = rng.uniform(-4, 4, (50, 3)), rng.uniform(-4, 4, (50, 3))
    out = compose_arrays(a, b)
    for i in range(50):
        assert np.allclose(out[i], (Pose2D(*a[i]) @ Pose2D(*b[i])).as_array())


def test_angle_diff_is_shortest_rotation():
    assert angle_diff(math.pi - 0.1, -math.pi + 0.1) == pytest.approx(-0.2)
