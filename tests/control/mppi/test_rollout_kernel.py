"""MPPI's compiled rollouts (rollout_kernel.py) give the numpy path's bits: controls,
velocities, positions and yaws for every motion model, symmetric and asymmetric
acceleration limits, with and without clamp_raw_controls, and whole controller cycles
(the same commands and control sequences)."""

from __future__ import annotations

import zlib

import numpy as np
import pytest

from btnav.control.goal_checkers import SimpleGoalChecker
from btnav.control.mppi import MPPIController, MPPIParams
from btnav.control.mppi.motion_models import (
    AckermannMotionModel,
    ControlConstraints,
    DiffDriveMotionModel,
    MotionModel,
    OmniMotionModel,
    make_motion_model,
)
from btnav.control.mppi.optimizer import Optimizer, OptimizerSettings
from btnav.core.geometry import Pose2D
from btnav.core.messages import Path as PathMsg
from btnav.core.messages import Twist
from btnav.costmap.cost_values import LETHAL_OBSTACLE

from ..unicycle import free_costmap

MODELS = {
    "diff": (DiffDriveMotionModel, None),
    "omni": (OmniMotionModel, None),
    "ackermann": (AckermannMotionModel, AckermannMotionModel.Params(min_turning_r=0.5)),
}
LIMITS = {
    "symmetric": ControlConstraints(),
    "asymmetric": ControlConstraints(ax_max=1.0, ax_min=-2.5, ay_max=0.7, ay_min=-1.3, az_max=2.0),
}


def same_bits(a: np.ndarray, b: np.ndarray) -> bool:
    """float32 arrays equal bit for bit (a NaN matches a NaN)."""
    nan = np.isnan(a)
    return bool(np.array_equal(nan, np.isnan(b))) and bool(
        np.array_equal(a.view(np.uint32)[~nan], b.view(np.uint32)[~nan])
    )


def controls(rng: np.random.Generator, shape: tuple[int, int, int]) -> np.ndarray:
    """Sampled-like controls, many beyond the acceleration limits, with zeros of both
    signs, exact repeats of the previous step, infinities and a NaN."""
    u = rng.normal(0.0, 0.8, shape).astype(np.float32)
    u[:, :, 0] = 0.0
    u[:, :, 1] = -0.0
    u[3:9, :, 2] = u[2, :, 2]  # steps the velocity can reach exactly
    u[5, :, 3] = np.inf
    u[7, :, 4] = -np.inf
    u[10, 0, 5] = np.nan
    return u


def run(opt: Optimizer, method: str, u: np.ndarray, robot, speeds, write_back: bool):
    """One prediction and rollout from `u` by `method`; (u, v, pos, yaw_rows) copies."""
    opt.s.clamp_raw_controls = write_back
    opt.u[...] = u
    for buf in (opt.v, opt._pos, opt._yaw_rows):
        buf[...] = np.float32(123.0)  # stale values every path must overwrite
    if method == "numpy":
        opt.model.predict(opt.u, opt.v, speeds, write_back=write_back)
        opt._rollouts(robot, opt.v)
    else:
        opt._rollouts_compiled(robot, speeds)
    return tuple(a.copy() for a in (opt.u, opt.v, opt._pos, opt._yaw_rows))


@pytest.mark.parametrize("write_back", [False, True])
@pytest.mark.parametrize("limits", sorted(LIMITS))
@pytest.mark.parametrize("model_name", sorted(MODELS))
def test_kernel_rollouts_give_the_numpy_bits(model_name, limits, write_back):
    cls, params = MODELS[model_name]
    model = make_motion_model(cls, LIMITS[limits], 0.05, params)
    settings = OptimizerSettings(batch_size=301, time_steps=40)
    opt = Optimizer(settings, model, [], np.random.default_rng(0))
    rng = np.random.default_rng(zlib.crc32(f"{model_name} {limits} {write_back}".encode()))
    u = controls(rng, opt.u.shape)
    for robot, speed in [
        ((0.5, -1.25, 0.15), (0.3, 0.1, -0.2)),
        ((-3.7, 12.1, 5.9), (-0.2, 0.0, 1.5)),
        ((0.0, 0.0, -3.1), (0.0, -0.4, 0.0)),
    ]:
        chans = [speed[0], speed[2], speed[1]][: model.channels]
        speeds = np.array(chans, np.float32)
        pose = np.array(robot, np.float64)
        want = run(opt, "numpy", u, pose, speeds, write_back)
        got = run(opt, "kernel", u, pose, speeds, write_back)
        for name, a, b in zip(("u", "v", "pos", "yaw_rows"), want, got, strict=True):
            assert same_bits(a, b), (name, robot)
    assert np.isnan(want[1]).any() and not np.isnan(want[1][:, :, 6:]).any()


def test_a_model_with_its_own_predict_takes_the_numpy_path():
    class Custom(DiffDriveMotionModel):
        calls = 0

        def predict(self, u, v, speed, write_back=False):  # type: ignore[no-untyped-def]
            Custom.calls += 1
            MotionModel.predict(self, u, v, speed, write_back)

    c = controller("diff_drive", "kernel")
    c.optimizer.model = make_motion_model(Custom, ControlConstraints(), 0.05)
    step_cycle(c, 0)
    assert Custom.calls == 1


# -- whole controller cycles ------------------------------------------------------------


def curved_path() -> PathMsg:
    t = np.linspace(0.0, np.pi / 2, 120)
    poses = np.stack([2.0 * np.sin(t), 2.0 * (1 - np.cos(t)), t], axis=1)
    return PathMsg(0.0, poses, "odom")


def controller(motion_model: str, method: str, **params: object) -> MPPIController:
    c = MPPIController(
        "FollowPath", MPPIParams(batch_size=500, motion_model=motion_model, **params), seed=5
    )
    c.optimizer.method = method  # type: ignore[assignment]
    for critic in c.optimizer.critics:
        if hasattr(critic, "method"):
            critic.method = method
    c.control_duration = 0.05
    c.set_plan(curved_path())
    return c


def step_cycle(c: MPPIController, k: int) -> Twist:
    cm = free_costmap()
    cm.costs[cm.size_y // 2 + 2, cm.size_x // 2 + 8] = LETHAL_OBSTACLE
    robot = Pose2D(0.05 * k, 0.01 * k, 0.02 * k)
    speed = Twist(linear_x=0.2, linear_y=0.02 * (k % 3), angular_z=0.1)
    return c.compute_velocity_commands(robot, speed, cm, SimpleGoalChecker())


@pytest.mark.parametrize(
    ("motion_model", "params"),
    [
        ("diff_drive", {}),
        ("omni", {"ax_min": -1.5, "ay_min": -0.8}),
        ("ackermann", {"clamp_raw_controls": True}),
    ],
)
def test_controller_cycles_give_the_same_commands_and_sequences(motion_model, params):
    a, b = controller(motion_model, "numpy", **params), controller(motion_model, "kernel", **params)
    for k in range(4):
        ca, cb = step_cycle(a, k), step_cycle(b, k)
        assert (ca.linear_x, ca.linear_y, ca.angular_z) == (cb.linear_x, cb.linear_y, cb.angular_z)
        assert same_bits(a.optimizer.control_sequence, b.optimizer.control_sequence)
        assert same_bits(a.optimizer._pos, b.optimizer._pos)
