"""The MPPI hot paths' shortcuts give the very floats of their plain versions.

Each shortcut (an appended off-map cell in cell_costs, the acceleration limits as full
rows, the optimal trajectory cut at the validator's lookahead, ConstraintCritic's
all-within-limits skip) is checked bit for bit against the straightforward computation
it replaces.
"""

from __future__ import annotations

import numpy as np

from btnav.control.mppi.critic_data import cell_costs
from btnav.control.mppi.critics import ConstraintCritic
from btnav.control.mppi.motion_models import (
    ControlConstraints,
    DiffDriveMotionModel,
    OmniMotionModel,
    make_motion_model,
)
from btnav.costmap.cost_values import NO_INFORMATION

from .batch import costmap, make_data

RNG = np.random.default_rng(7)


def _cell_costs_masked(cm, x, y):
    """cell_costs as a gather at index 0 for off-map points, then masked."""
    res = np.float32(1.0 / cm.resolution)
    mx = np.floor((x - np.float32(cm.origin_x)) * res).astype(np.int32)
    my = np.floor((y - np.float32(cm.origin_y)) * res).astype(np.int32)
    w, h = cm.size_x, cm.size_y
    inside = (mx >= 0) & (mx < w) & (my >= 0) & (my < h)
    out = cm.costs.reshape(-1)[np.where(inside, my * w + mx, 0)]
    out[~inside] = NO_INFORMATION
    return out


def test_cell_costs_off_the_map_read_no_information_as_masking_does():
    cm = costmap()
    cm.costs[...] = RNG.integers(0, 256, cm.costs.shape, dtype=np.uint8)
    # a (T, B) buffer seen as (B, T), as the critics see rollouts; many points off the map
    pts = RNG.uniform(-3.0, 6.0, (2, 28, 500)).astype(np.float32)
    x, y = pts[0].T, pts[1].T
    got, want = cell_costs(cm, x, y), _cell_costs_masked(cm, x, y)
    assert got.dtype == want.dtype and got.strides == want.strides
    assert np.array_equal(got, want)
    assert (got == NO_INFORMATION).any()
    path = RNG.uniform(-1.0, 4.0, (40, 3)).astype(np.float32)
    assert np.array_equal(
        cell_costs(cm, path[:, 0], path[:, 1]), _cell_costs_masked(cm, path[:, 0], path[:, 1])
    )


def _predict_broadcast(model, u, v, speed):
    """MotionModel.predict with (C, 1) limit columns (the limits as written)."""
    c, dt, ch = model.c, np.float32(model.dt), model.channels
    up = np.array([c.ax_max, c.az_max, c.ay_max][:ch], np.float32)[:, None] * dt
    down = np.array([c.ax_min, -c.az_max, c.ay_min][:ch], np.float32)[:, None] * dt
    v[0] = speed[:, None]
    for i in range(1, u.shape[0]):
        prev = v[i - 1]
        if np.allclose(up, -down):
            v[i] = prev + np.maximum(np.minimum(u[i - 1] - prev, up), -up)
        else:
            pos = prev > 0
            lo = prev + np.where(pos, down, -up)
            hi = prev + np.where(pos, up, -down)
            v[i] = np.clip(u[i - 1], lo, hi)
    u[:-1] = v[1:]


def test_predict_and_constraints_match_the_broadcast_limits():
    for model in (
        make_motion_model(DiffDriveMotionModel, ControlConstraints(), 0.05),
        make_motion_model(OmniMotionModel, ControlConstraints(ax_min=-2.0, ay_min=-1.0), 0.05),
    ):
        C = model.channels
        u = RNG.normal(0.0, 0.6, (56, C, 300)).astype(np.float32)
        speed = np.array([0.3, -0.2, 0.1][:C], np.float32)
        u2, v, v2 = u.copy(), np.empty_like(u), np.empty_like(u)
        for _ in range(2):  # the second call reads the cached limit rows
            u1 = u.copy()
            model.predict(u1, v, speed, write_back=True)
        _predict_broadcast(model, u2, v2, speed)
        assert np.array_equal(v.view(np.uint32), v2.view(np.uint32))
        assert np.array_equal(u1.view(np.uint32), u2.view(np.uint32))


def test_constraint_critic_skip_leaves_the_costs_as_adding_its_zeros_does():
    vx = np.full((4, 10), 0.5, np.float32)
    vx[1] = np.float32(-0.35)  # on the limits: terms exactly zero
    data = make_data(batch=4, steps=10, vx=vx)
    data.vx = vx.copy()
    data.costs[:] = np.array([0.0, 1.5, 3.0, 1e6], np.float32)
    before = data.costs.copy()
    ConstraintCritic("ConstraintCritic").score(data)
    assert np.array_equal(data.costs.view(np.uint32), before.view(np.uint32))
    data.vx[2, 3] = np.float32(0.6)  # beyond: scored
    ConstraintCritic("ConstraintCritic").score(data)
    assert data.costs[2] > before[2] and data.costs[0] == before[0]
