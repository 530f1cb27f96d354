"""MPPI's optimizer (mppi::Optimizer, as in Nav2 main): sample, roll out, score, softmax,
smooth, constrain, send, shift.

One cycle, all batch-wide numpy on float32:

0. the speed the command will meet: the last command, as far as one controller period
   of acceleration from the measured speed allows (Nav2's prepare); the sequence's
   first step is pinned to it (when shifting) or clamped within reach of it;
1. noise: `batch_size` perturbations of the control sequence (noise.py), kept raw: what
   leaves the velocity box is the ConstraintCritic's to score;
2. the rollouts' velocities follow the controls as far as the acceleration limits
   allow, step by step from that speed (motion_models.py: the only loop, over
   `time_steps`, each step a row of `batch_size` values); `clamp_raw_controls` writes
   them back into the controls;
3. rollouts by running sums: yaw = yaw0 + cumsum(wz dt), then x, y by cumsum of
   v cos/sin(previous yaw) dt;
4. critics add their costs (critics/);
5. the control cost `gamma / std^2 * sum(noise * control)` per rollout, softmax weights
   `exp(-(cost - min) / temperature)` normalised, and the new sequence is the weighted
   mean of the sampled controls; then Savitzky-Golay smoothing with the sent-command
   history (`sgf_order`), and the sequence made feasible: the model's constraints, the
   velocity limits and the acceleration limits from the speed (one controller period
   to the first step, model_dt after), the model's constraints again;
6. repeated `iteration_count` times; the optimal trajectory is checked by the
   validator (a soft reset and a retry, then NoValidControl); the command is the
   second step when the controller runs once per model step (Nav2's shifted sequence,
   whose first step is "now"), the first otherwise, later by the model delay; then
   the sequence is shifted one step for the next cycle.

Storage is (time_steps, batch_size) C-order; critics get (batch_size, time_steps)
views (`.T`), the shape Nav2's critics index.

Steps 2 and 3 run as one compiled pass (rollout_kernel.py, the same bits) unless the
environment says BTNAV_MPPI=numpy or the motion model has its own `predict`.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Any

import numpy as np
from numpy.typing import NDArray

from ...core import fmath
from ...core.kernel_switch import Method
from ...costmap.cost_values import INSCRIBED_INFLATED_OBSTACLE, LETHAL_OBSTACLE
from ...costmap.costmap_2d import Costmap2D
from ...costmap.footprint_cost import footprint_costs
from .critic_data import DEFAULT_METHOD, CriticData, cell_costs
from .critic_function import CriticFunction
from .motion_models import MotionModel
from .noise import NoiseGenerator
from .rollout_kernel import predict_rollouts
from .sequence_limits_kernel import limit_sequence
from .smoothing import HISTORY, savitzky_golay
from .softmax_kernel import softmax_mean

F32 = NDArray[np.float32]


def clamp_by_accel(last: float, value: float, min_delta: float, max_delta: float) -> float:
    """`value` as far as one step from `last` allows: `max_delta` speeds up (away from
    zero, either direction), `min_delta` (negative) slows down; Nav2's
    clampVelocityByAccel."""
    if last >= 0.0:
        return min(last + max_delta, max(value, last + min_delta))
    return min(last - min_delta, max(value, last - max_delta))


@dataclass
class OptimizerSettings:
    batch_size: int = 1000
    time_steps: int = 56
    model_dt: float = 0.05
    iteration_count: int = 1
    temperature: float = 0.3
    gamma: float = 0.015
    vx_std: float = 0.2
    vy_std: float = 0.2
    wz_std: float = 0.2
    retry_attempt_limit: int = 1
    regenerate_noises: bool = False
    model_delay: tuple[float, float, float] = (0.0, 0.0, 0.0)
    collision_lookahead_time: float = 2.0
    validator_consider_footprint: bool = False
    #: 1 / the controller server's controller_frequency.
    controller_period: float = 0.05
    clamp_raw_controls: bool = False
    sgf_order: int = 2

    @property
    def shift_control_sequence(self) -> bool:
        """Nav2 shifts the sequence (and sends its second step) when the controller runs
        once per model step."""
        return abs(self.controller_period - self.model_dt) < 1e-6


class Optimizer:
    def __init__(
        self,
        settings: OptimizerSettings,
        model: MotionModel,
        critics: list[CriticFunction],
        rng: np.random.Generator,
    ) -> None:
        self.s = settings
        self.model = model
        self.critics = critics
        #: The local costmap server (footprint), once the controller is configured.
        self.costmap_ros: Any = None
        self.holonomic = model.holonomic
        #: "kernel" or "numpy" (DEFAULT_METHOD): the sampling, rollouts, softmax and
        #: sequence limits compiled or in numpy; the compiled rollouts only run the base
        #: MotionModel.predict, so a model overriding it always takes the numpy path.
        self.method: Method = DEFAULT_METHOD
        T, B, C = settings.time_steps, settings.batch_size, model.channels
        stds = [settings.vx_std, settings.wz_std, settings.vy_std][:C]
        self.stds = stds
        self.noise = NoiseGenerator(rng, B, T, stds, settings.regenerate_noises)
        self.u = np.zeros((T, C, B), np.float32)  # sampled controls
        self.v = np.zeros((T, C, B), np.float32)  # velocities the rollouts follow
        self._prod = np.empty((T, C, B), np.float32)  # scratch for the softmax mean
        self._pos = np.zeros((T, 2, B), np.float32)  # x, y
        # yaw0 then the rollouts' yaws: the headings the steps move along are rows 0..T-1
        # (one contiguous block, no copy), the yaws rows 1..T
        self._yaw_rows = np.zeros((T + 1, B), np.float32)
        self._yaw = self._yaw_rows[1:]
        self._zeros = np.zeros((B, T), np.float32)
        self.reset()
        #: The last iteration's data (rollouts, costs), for tests and visualisation.
        self.last_data: CriticData | None = None

    # -- state between cycles -------------------------------------------------------

    def reset(self) -> None:
        """Forget the control sequence (Nav2's optimizer reset): a new task or a soft reset."""
        T = self.s.time_steps
        self.control_sequence = np.zeros((T, 3), np.float32)  # vx, vy, wz
        self.control_history = np.zeros((HISTORY, 3), np.float32)
        self.last_command = (0.0, 0.0, 0.0)
        self.noise.reset()

    def shift_control_sequence(self) -> None:
        """Drop the step just executed; hold the last one."""
        cs = self.control_sequence
        cs[:-1] = cs[1:]

    def _sequence_channels(self) -> NDArray[np.float32]:
        """The control sequence as (T, C, 1) in the optimizer's channel order."""
        cs = self.control_sequence
        cols = [0, 2, 1][: self.model.channels]
        return cs[:, cols][:, :, None]

    # -- one cycle --------------------------------------------------------------------

    def eval_control(
        self,
        robot: NDArray[np.float64],
        speed: tuple[float, float, float],
        path: NDArray[np.float32],
        goal: NDArray[np.float64],
        costmap: Costmap2D,
        goal_checker: Any = None,
        open_loop: bool = False,
    ) -> tuple[float, float, float]:
        """The command (vx, vy, wz) for this cycle; raises `NoValidControl` when none is found."""
        from ..exceptions import NoValidControl

        speed = self.last_command if open_loop else self._expected_speed(speed)
        failures = 0
        while True:
            data = None
            for _ in range(self.s.iteration_count):
                data = self._iterate(robot, speed, path, goal, costmap, goal_checker)
            assert data is not None
            self.last_data = data
            fail = data.fail_flag or not self._trajectory_valid(robot, costmap)
            if not fail:
                break
            self.reset()
            failures += 1
            if failures > self.s.retry_attempt_limit:
                raise NoValidControl(
                    "MPPI: no valid control: every rollout or the optimal path collides"
                )
        command = self._command()
        self.last_command = command
        if self.s.shift_control_sequence:
            self.shift_control_sequence()
        return command

    def _command(self) -> tuple[float, float, float]:
        """The step the robot is sent: the second when shifting (the first is now), later
        by the model delay."""
        cs, dt, t = self.control_sequence, self.s.model_dt, self.s.time_steps
        offset = 1 if self.s.shift_control_sequence else 0
        idx = [min(offset + round(d / dt), t - 1) for d in self.s.model_delay]
        vy = float(cs[idx[1], 1]) if self.holonomic else 0.0
        return float(cs[idx[0], 0]), vy, float(cs[idx[2], 2])

    def _expected_speed(self, speed: tuple[float, float, float]) -> tuple[float, float, float]:
        """The speed when this cycle's command takes effect: the last command, as far as
        one controller period of acceleration from the measured speed allows (Nav2's
        prepare)."""
        c, dt = self.model.c, self.s.controller_period
        last = self.last_command
        vx = min(max(last[0], speed[0] + dt * c.ax_min), speed[0] + dt * c.ax_max)
        wz = min(max(last[2], speed[2] - dt * c.az_max), speed[2] + dt * c.az_max)
        vy = speed[1]
        if self.holonomic:
            vy = min(max(last[1], speed[1] + dt * c.ay_min), speed[1] + dt * c.ay_max)
        return vx, vy, wz

    def _iterate(
        self,
        robot: NDArray[np.float64],
        speed: tuple[float, float, float],
        path: NDArray[np.float32],
        goal: NDArray[np.float64],
        costmap: Costmap2D,
        goal_checker: Any,
    ) -> CriticData:
        s, u, v = self.s, self.u, self.v
        self._pin_first_step(speed)
        # Sampled controls: the current sequence plus noise, raw (the ConstraintCritic
        # scores what leaves the velocity box); the rollouts follow them as far as the
        # acceleration limits allow from the robot's speed.
        if self.method == "kernel":
            self.noise.sample_controls(u, np.ascontiguousarray(self._sequence_channels()[:, :, 0]))
        else:
            self.noise.sample(out=u)
            np.add(u, self._sequence_channels(), out=u)
        speeds = np.array([speed[0], speed[2], speed[1]][: self.model.channels], np.float32)
        if self.method == "kernel" and type(self.model).predict is MotionModel.predict:
            self._rollouts_compiled(robot, speeds)
        else:
            self.model.predict(u, v, speeds, write_back=s.clamp_raw_controls)
            self._rollouts(robot, v)
        c = self.model.c
        vy = v[:, 2].T if self.holonomic else self._zeros
        cvy = u[:, 2].T if self.holonomic else self._zeros
        data = CriticData(
            vx=v[:, 0].T,
            vy=vy,
            wz=v[:, 1].T,
            cvx=u[:, 0].T,
            cvy=cvy,
            cwz=u[:, 1].T,
            x=self._pos[:, 0].T,
            y=self._pos[:, 1].T,
            yaws=self._yaw.T,
            path=path,
            goal=goal,
            robot=robot,
            robot_speed=speed,
            costmap=costmap,
            model_dt=s.model_dt,
            costs=np.zeros(s.batch_size, np.float32),
            is_holonomic=self.holonomic,
            goal_checker=goal_checker,
            vx_max=c.vx_max,
            vx_min=c.vx_min,
            vy_max=c.vy_max,
            wz_max=c.wz_max,
            min_turning_r=self.model.min_turning_r,
        )
        for critic in self.critics:
            critic.score(data)
        self._update_control_sequence(data.costs, speed)
        return data

    def _speed_row(self, speed: tuple[float, float, float]) -> tuple[float, float, float]:
        """The speed as a control sequence row (vx, vy, wz): what a shifted step 0 is."""
        return speed[0], speed[1] if self.holonomic else 0.0, speed[2]

    def _pin_first_step(self, speed: tuple[float, float, float]) -> None:
        """Nav2's inter-iteration constraint: the sequence's first step is the speed now
        (when shifting: it is not sent) or within one controller period of it."""
        cs, c, dt = self.control_sequence, self.model.c, self.s.controller_period
        if self.s.shift_control_sequence:
            cs[0] = self._speed_row(speed)
            return
        cs[0, 0] = clamp_by_accel(speed[0], float(cs[0, 0]), c.ax_min * dt, c.ax_max * dt)
        cs[0, 2] = clamp_by_accel(speed[2], float(cs[0, 2]), -c.az_max * dt, c.az_max * dt)
        if self.holonomic:
            cs[0, 1] = clamp_by_accel(speed[1], float(cs[0, 1]), c.ay_min * dt, c.ay_max * dt)

    def _rollouts(self, robot: NDArray[np.float64], v: F32) -> None:
        """Poses from velocities (T, C, B) by running sums; the first pose is the robot's.

        A Python loop over time steps adding contiguous rows is ~10x faster than
        `np.cumsum` along the time axis.
        """
        dt = np.float32(self.s.model_dt)
        x0, y0, yaw0 = (np.float32(a) for a in robot)
        T = v.shape[0]
        yaw, pos = self._yaw, self._pos
        # yaw[i] = yaw0 + dt * sum(wz[0..i]); step i moves along yaw[i - 1] (yaw0 first).
        np.multiply(v[:, 1], dt, out=yaw)
        yaw[0] += yaw0
        for i in range(1, T):
            np.add(yaw[i - 1], yaw[i], out=yaw[i])
        heading = self._yaw_rows[:-1]
        heading[0] = yaw0
        sin, cos = fmath.sincos(heading)  # not np.sin/np.cos: the same bits on every CPU
        vx = v[:, 0]
        np.multiply(vx, cos, out=pos[:, 0])
        np.multiply(vx, sin, out=pos[:, 1])
        if self.holonomic:
            vy = v[:, 2]
            pos[:, 0] -= vy * sin
            pos[:, 1] += vy * cos
        pos *= dt
        pos[0, 0] += x0
        pos[0, 1] += y0
        for i in range(1, T):
            np.add(pos[i - 1], pos[i], out=pos[i])

    def _rollouts_compiled(self, robot: NDArray[np.float64], speeds: F32) -> None:
        """`model.predict` then `_rollouts` as one compiled pass over the batch (u, v,
        positions and yaws with the same bits; rollout_kernel.py)."""
        up, down, symmetric = self.model._accel_steps(self.s.batch_size)
        start = np.array([np.float32(a) for a in robot[:3]], np.float32)
        predict_rollouts(
            self.u,
            self.v,
            speeds,
            up,
            down,
            symmetric,
            self.s.clamp_raw_controls,
            np.float32(self.s.model_dt),
            start,
            self._pos,
            self._yaw_rows,
        )

    def _update_control_sequence(self, costs: F32, speed: tuple[float, float, float]) -> None:
        s, cs = self.s, self.control_sequence
        seq = np.ascontiguousarray(self._sequence_channels()[:, :, 0])  # (T, C)
        if self.method == "kernel":
            mean = self._softmax_compiled(costs, seq)
        else:
            self._control_costs(costs, seq)
            shifted = costs - costs.min()
            weights = fmath.exp(shifted * np.float32(-1.0 / s.temperature))
            weights /= weights.sum()
            mean = np.multiply(self.u, weights, out=self._prod).sum(axis=-1)
        cs[:, 0] = mean[:, 0]
        cs[:, 2] = mean[:, 1]
        if self.holonomic:
            cs[:, 1] = mean[:, 2]
        offset = 1 if s.shift_control_sequence else 0
        savitzky_golay(cs, self.control_history, s.sgf_order, offset)
        self._apply_sequence_constraints(speed)

    def _control_costs(self, costs: F32, seq: F32) -> None:
        """Control cost: gamma / std^2 * sum_t (noise_t * u_t), noise = sampled - current,
        added to `costs`."""
        s, u, prod = self.s, self.u, self._prod
        prod_t = prod.reshape(-1)[: u.shape[0] * u.shape[2]].reshape(u.shape[0], u.shape[2])
        if s.gamma == 0.0:
            return
        for ch, std in enumerate(self.stds):
            if std <= 0.0:
                continue
            uc = seq[:, ch]
            # sum_t (sampled - u) u = u . sampled - u . u, as elementwise products and
            # sums (a BLAS product's summation order depends on the CPU); the same
            # products and sum as fmath.weighted_sum(u[:, ch], uc, axis=0)
            p = np.multiply(u[:, ch], uc[:, None], out=prod_t)
            cost = p.sum(axis=0)
            cost -= np.float32(fmath.weighted_sum(uc, uc))
            costs += np.float32(s.gamma / std**2) * cost

    def _softmax_compiled(self, costs: F32, seq: F32) -> F32:
        """`_control_costs`, the softmax weights and the weighted mean of the samples
        (T, C) in one compiled pass (softmax_kernel.py, the same bits)."""
        s, C = self.s, self.model.channels
        active = np.array([s.gamma != 0.0 and std > 0.0 for std in self.stds], np.bool_)
        gains = np.zeros(C, np.float32)
        self_dot = np.zeros(C, np.float32)
        for ch in np.flatnonzero(active):
            uc = seq[:, ch]
            gains[ch] = np.float32(s.gamma / self.stds[ch] ** 2)
            self_dot[ch] = np.float32(fmath.weighted_sum(uc, uc))
        mean = np.empty((seq.shape[0], C), np.float32)
        neg_inv_t = np.float32(-1.0 / s.temperature)
        softmax_mean(self.u, seq, active, gains, self_dot, costs, neg_inv_t, mean)
        return mean

    def _apply_sequence_constraints(self, speed: tuple[float, float, float]) -> None:
        """Nav2's applyControlSequenceConstraints: the optimal sequence within the
        velocity limits and reachable step by step from the speed now (the first step
        in one controller period, the rest in model_dt each), inside the model's own
        constraints before and after."""
        cs, c, s = self.control_sequence, self.model.c, self.s
        self.model.apply_constraints(cs)
        if s.shift_control_sequence:
            cs[0] = self._speed_row(speed)
        channels = [(0, speed[0], c.vx_min, c.vx_max, c.ax_min, c.ax_max),
                    (2, speed[2], -c.wz_max, c.wz_max, -c.az_max, c.az_max)]  # fmt: skip
        if self.holonomic:
            channels.append((1, speed[1], -c.vy_max, c.vy_max, c.ay_min, c.ay_max))
        for col, last, lo, hi, a_down, a_up in channels:
            if self.method == "kernel":
                limits = (float(v) for v in (last, lo, hi, a_down, a_up))
                limit_sequence(cs[:, col], *limits, s.controller_period, s.model_dt)
                continue
            values = cs[:, col].tolist()
            dt = s.controller_period
            for i, value in enumerate(values):
                value = min(hi, max(value, lo))
                last = float(np.float32(clamp_by_accel(last, value, a_down * dt, a_up * dt)))
                values[i] = last
                dt = s.model_dt
            cs[:, col] = values
        self.model.apply_constraints(cs)

    # -- the optimal trajectory -------------------------------------------------------

    def optimal_trajectory(
        self, robot: NDArray[np.float64], steps: int | None = None
    ) -> NDArray[np.float64]:
        """(T, 3) poses the control sequence leads to (it is feasible from the speed
        already: Nav2 integrates it as it is); only the first `steps` poses if given."""
        cs = self.control_sequence if steps is None else self.control_sequence[:steps]
        dt = self.s.model_dt
        x, y, yaw = float(robot[0]), float(robot[1]), float(robot[2])
        sincos = fmath.sincos
        rows = []
        vy_col = cs[:, 1].tolist() if self.holonomic else [0.0] * len(cs)
        for vx_, vy_, wz_ in zip(cs[:, 0].tolist(), vy_col, cs[:, 2].tolist(), strict=True):
            s_, c = sincos(yaw)
            x += (vx_ * c - vy_ * s_) * dt
            y += (vx_ * s_ + vy_ * c) * dt
            yaw += wz_ * dt
            rows.append((x, y, yaw))
        return np.array(rows, dtype=np.float64).reshape(-1, 3)

    def _trajectory_valid(self, robot: NDArray[np.float64], costmap: Costmap2D) -> bool:
        """DefaultOptimalTrajectoryValidator: within `collision_lookahead_time`, no point
        on a lethal or inscribed cell (points off the grid are skipped), or with
        `consider_footprint` no pose whose footprint touches a lethal cell."""
        n = min(self.s.time_steps, math.ceil(self.s.collision_lookahead_time / self.s.model_dt))
        if n <= 0:
            return True
        traj = self.optimal_trajectory(robot, n)
        if self.s.validator_consider_footprint and self.costmap_ros is not None:
            fp = self.costmap_ros.footprint
            costs = footprint_costs(costmap, fp, traj[:, 0], traj[:, 1], traj[:, 2])
            return not bool((costs == LETHAL_OBSTACLE).any())
        costs = cell_costs(costmap, traj[:, 0], traj[:, 1])
        hit = (costs == LETHAL_OBSTACLE) | (costs == INSCRIBED_INFLATED_OBSTACLE)
        return not bool(hit.any())
