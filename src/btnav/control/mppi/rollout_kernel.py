"""MPPI's rollouts compiled: the motion model's acceleration limits and the pose running
sums in one pass over the batch, with the numpy path's float32 bits.

The numpy path (`MotionModel.predict`, then `Optimizer._rollouts`) walks the time steps
twice in Python and calls fmath.sincos on the (T, B) headings: about 1.6 ms of a 4.3 ms
cycle at 2000 x 56. Here each time step limits the velocities (a loop over the batch
per channel), writes them back into the controls if asked (`clamp_raw_controls`), then
adds the yaw step and moves the positions along the previous headings (one loop over
the batch). Row loops without branches inside vectorise (0.22 ms in all; one loop
over everything with its branches did not: 0.98 ms).

Same bits as numpy: every value numpy keeps in float32 is float32 here (the inputs are
float32 arrays and scalars, no float64 literal meets them), each + - * is the one numpy
does, in its order, and the running sums add step i to step i - 1 as numpy's rows do:

- symmetric limits: v[i] = v[i-1] + max(min(u[i-1] - v[i-1], up), -up);
- asymmetric ones: clip(u[i-1], v[i-1] + (down or -up), v[i-1] + (up or -down)), the
  choice by v[i-1] > 0; np.minimum, np.maximum and np.clip's NaN and signed-zero rules
  (`np_minimum`, `np_maximum`: a NaN wins, a tie gives the second operand);
- yaw[i+1] = yaw[i] + wz[i] dt; (sin, cos) of yaw[i] by `fmath_kernels.sincos_f32`
  (fmath.sincos's float32 path); x[i] = x[i-1] + (vx cos [- vy sin]) dt, y likewise.

Determinism (issue 37): no libm call, no fastmath (no FMA contraction), no parallel
loop; compiled once per install and cached (`cache=True`).
"""

from __future__ import annotations

import numba as nb
import numpy as np
from numpy.typing import NDArray

from ...core.fmath_kernels import JIT, sincos_f32

F32 = NDArray[np.float32]


@nb.njit(**JIT)
def np_minimum(a: np.float32, b: np.float32) -> np.float32:
    """np.minimum on two floats: a NaN propagates, a tie (-0 and +0) gives `b`."""
    return a if (a < b or a != a) else b


@nb.njit(**JIT)
def np_maximum(a: np.float32, b: np.float32) -> np.float32:
    """np.maximum on two floats: a NaN propagates, a tie gives `b`."""
    return a if (a > b or a != a) else b


@nb.njit(**JIT)
def _limit_row(
    u: F32, prev: F32, out: F32, up: np.float32, down: np.float32, symmetric: bool
) -> None:
    """One channel's velocities at one step from the previous step's, as
    `MotionModel.predict` limits them (up > 0, down < 0: the speed changes per step).
    A row per call, no branch left inside the loop: LLVM vectorises it."""
    if symmetric:
        for b in range(out.shape[0]):
            p = prev[b]
            out[b] = p + np_maximum(np_minimum(u[b] - p, up), down)
    else:
        neg_up, neg_down = -up, -down
        for b in range(out.shape[0]):
            p = prev[b]
            ahead = p > 0
            lo = p + (down if ahead else neg_up)
            hi = p + (up if ahead else neg_down)
            out[b] = np_minimum(np_maximum(u[b], lo), hi)


@nb.njit(**JIT)
def _pose_row(
    v: F32,
    heading: F32,
    yaw_next: F32,
    pos: F32,
    pos_prev: F32,
    x0: np.float32,
    y0: np.float32,
    first: bool,
    dt: np.float32,
) -> None:
    """One step of every rollout: the next yaw, and the position moved along `heading`
    from `pos_prev` (from x0, y0 at the first step). v: (C, B) velocities at this step."""
    holonomic = v.shape[0] == 3
    for b in range(heading.shape[0]):
        h = heading[b]
        yaw_next[b] = h + v[1, b] * dt
        s, c = sincos_f32(h)
        vx = v[0, b]
        dx = vx * c
        dy = vx * s
        if holonomic:
            vy = v[2, b]
            dx = dx - vy * s
            dy = dy + vy * c
        dx = dx * dt
        dy = dy * dt
        if first:
            pos[0, b] = dx + x0
            pos[1, b] = dy + y0
        else:
            pos[0, b] = pos_prev[0, b] + dx
            pos[1, b] = pos_prev[1, b] + dy


@nb.njit(**JIT)
def predict_rollouts(
    u: F32,
    v: F32,
    speed: F32,
    up: F32,
    down: F32,
    symmetric: bool,
    write_back: bool,
    dt: np.float32,
    start: F32,
    pos: F32,
    yaw_rows: F32,
) -> None:
    """`MotionModel.predict(u, v, speed, write_back)` then `Optimizer._rollouts`, in place,
    one time step at a time (each step's rows are still in cache for the poses).

    u, v: (T, C, B) controls and velocities (channels vx, wz[, vy]); speed: (C,);
    up, down: the model's (C, B) speed changes per step (`_accel_steps`; column 0 is
    read: every column is the same); start: x0, y0, yaw0 as float32; pos: (T, 2, B);
    yaw_rows: (T + 1, B), the headings yaw0, yaw[0..T-1] and the last yaw.
    """
    T, C = v.shape[0], v.shape[1]
    for ch in range(C):
        v[0, ch, :] = speed[ch]
    yaw_rows[0, :] = start[2]
    for i in range(T):
        if i > 0:
            for ch in range(C):
                _limit_row(u[i - 1, ch], v[i - 1, ch], v[i, ch], up[ch, 0], down[ch, 0], symmetric)
                if write_back:
                    u[i - 1, ch, :] = v[i, ch, :]
        prev = pos[i - 1] if i > 0 else pos[0]
        _pose_row(v[i], yaw_rows[i], yaw_rows[i + 1], pos[i], prev, start[0], start[1], i == 0, dt)
