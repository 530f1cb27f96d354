"""MPPI's cycle as Nav2 main runs it: the sequence is feasible from the speed now, its
first step is "now" and the second is sent when the controller runs once per model
step, the samples stay raw, and the smoothing history holds what was sent."""

from __future__ import annotations

import numpy as np
import pytest

from btnav.control.goal_checkers import SimpleGoalChecker
from btnav.control.mppi import MPPIController, MPPIParams
from btnav.control.mppi.optimizer import clamp_by_accel
from btnav.control.mppi.smoothing import savitzky_golay
from btnav.core.geometry import Pose2D
from btnav.core.messages import Path as PathMsg
from btnav.core.messages import Twist

from ..unicycle import free_costmap

MODEL_DT = 0.05


def straight(length: float = 3.0, step: float = 0.05) -> PathMsg:
    x = np.arange(0.0, length + 1e-9, step)
    return PathMsg(0.0, np.stack([x, np.zeros_like(x), np.zeros_like(x)], axis=1), "odom")


def controller(period: float = MODEL_DT, **params: object) -> MPPIController:
    c = MPPIController("FollowPath", MPPIParams(batch_size=400, **params), seed=3)
    c.control_duration = period  # the controller server sets 1 / controller_frequency
    c.set_plan(straight())
    return c


def step(c: MPPIController, vx: float = 0.2, wz: float = 0.0) -> Twist:
    return c.compute_velocity_commands(
        Pose2D(), Twist(linear_x=vx, angular_z=wz), free_costmap(), SimpleGoalChecker()
    )


def test_at_the_model_rate_the_second_step_is_sent_and_the_sequence_shifted():
    c = controller()
    opt = c.optimizer
    assert opt.s.shift_control_sequence
    sent_before_shift = []
    original = opt.shift_control_sequence

    def shift() -> None:
        sent_before_shift.append(opt.control_sequence.copy())
        original()

    opt.shift_control_sequence = shift
    opt.last_command = (0.2, 0.0, 0.0)  # the robot runs at what it was sent
    cmd = step(c, vx=0.2)
    (cs,) = sent_before_shift
    assert cs[0, 0] == np.float32(0.2)  # step 0 is the speed now, not a command
    assert cmd.linear_x == float(cs[1, 0])
    assert opt.control_history[-1, 0] == pytest.approx(cs[1, 0], abs=0.05)  # before clamping
    assert np.array_equal(opt.control_sequence[:-1], cs[1:])


def test_slower_than_the_model_rate_the_first_step_is_sent_unshifted():
    c = controller(period=0.1)
    assert not c.optimizer.s.shift_control_sequence
    cmd = step(c, vx=0.2)
    assert cmd.linear_x == float(c.optimizer.control_sequence[0, 0])


def test_the_optimal_sequence_is_reachable_from_the_speed_step_by_step():
    c = controller(ax_max=1.0, ax_min=-2.0, az_max=1.0)
    for _ in range(5):
        step(c, vx=0.1, wz=0.2)
    cs = c.optimizer.control_sequence
    # after the shift the sequence starts one step in: each next step within one
    # model_dt of acceleration (1.0 up, 2.0 down, 1.0 in yaw), velocities in the box
    dvx, dwz = np.diff(cs[:, 0]), np.diff(cs[:, 2])
    assert dvx.max() <= 1.0 * MODEL_DT + 1e-6 and dvx.min() >= -2.0 * MODEL_DT - 1e-6
    assert np.abs(dwz).max() <= 1.0 * MODEL_DT + 1e-6
    assert cs[:, 0].max() <= 0.5 + 1e-6 and np.abs(cs[:, 2]).max() <= 1.9 + 1e-6


def test_the_command_meets_the_speed_the_last_command_leads_to():
    """A robot that lags its commands: the first step is the last command as far as one
    controller period of acceleration from the measured speed reaches (Nav2's prepare)."""
    c = controller(ax_max=1.0)
    step(c, vx=0.0)
    c.optimizer.last_command = (0.4, 0.0, 0.0)
    shifted = []
    c.optimizer.shift_control_sequence = lambda: shifted.append(c.optimizer.control_sequence[0, 0])
    step(c, vx=0.0)
    assert shifted == [np.float32(1.0 * MODEL_DT)]  # 0 + one period at 1 m/s^2, not 0.4


def test_samples_stay_raw_unless_clamp_raw_controls():
    raw = controller()
    step(raw)
    # the rollouts' velocities follow the samples only as far as acceleration allows
    assert not np.array_equal(raw.optimizer.u[:-1], raw.optimizer.v[1:])
    clamped = controller(clamp_raw_controls=True)
    step(clamped)
    assert np.array_equal(clamped.optimizer.u[:-1], clamped.optimizer.v[1:])


def test_clamp_by_accel_speeds_up_by_max_and_slows_by_min_in_either_direction():
    assert clamp_by_accel(0.2, 1.0, -0.3, 0.1) == pytest.approx(0.3)
    assert clamp_by_accel(0.2, -1.0, -0.3, 0.1) == pytest.approx(-0.1)
    assert clamp_by_accel(-0.2, -1.0, -0.3, 0.1) == pytest.approx(-0.3)
    assert clamp_by_accel(-0.2, 1.0, -0.3, 0.1) == pytest.approx(0.1)


def test_the_last_step_is_left_unsmoothed_and_order_one_is_a_moving_average():
    seq = np.zeros((30, 3), np.float32)
    seq[::2, 0] = 1.0
    history = np.zeros((4, 3), np.float32)
    smooth = seq.copy()
    savitzky_golay(smooth, history.copy(), order=1)
    assert smooth[-1, 0] == seq[-1, 0]
    assert smooth[10, 0] == pytest.approx(np.mean(seq[6:15, 0]), abs=1e-6)
    short = np.ones((20, 3), np.float32)
    savitzky_golay(short, history.copy())
    assert (short == 1.0).all()  # under 21 steps: not smoothed, as Nav2
