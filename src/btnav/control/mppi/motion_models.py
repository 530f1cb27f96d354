"""MPPI's motion models: which controls exist and how acceleration limits shape the rollouts.

Controls and velocities are (time_steps, channels, batch_size) float32, channels
`vx, wz` (and `vy` for a holonomic model), so one time step of every channel is a
contiguous block and the step-by-step acceleration loop costs one ufunc call per
operation for all channels at once. The optimizer hands critics (batch_size,
time_steps) views.

Limits are applied where Nav2 applies them: the sampled controls stay raw (the
ConstraintCritic penalises what leaves the velocity box), the rollouts follow them as
far as the acceleration limits allow (`predict`), and the optimizer clamps the
optimal sequence to the velocity and acceleration limits. Besides:

- `apply_constraints` is Nav2's `MotionModel::applyConstraints`: the model's own hard
  limit, applied to the optimal control sequence only (after the softmax, and again
  as the last step before the command is read). A diff-drive or omni robot has none;
  an Ackermann one bounds |wz| by |vx| / min_turning_r. Applying that to every sample
  instead would be wrong: with wz_std (0.4) above the bound (0.3 rad/s at 0.3 m/s and
  1 m), nearly every sample's wz is clipped to +-|vx| / r, its sign drawn afresh at
  each step, so no sample turns steadily and their weighted mean hardly turns (the
  racecar was commanded |wz| <= 0.09 rad/s on a 1.2 m arc that needs 0.25, measured).
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any

import numpy as np
from numpy.typing import NDArray
from pydantic import Field

from ...params.schema import ParamsModel
from ...plugins import Plugin, register

F32 = NDArray[np.float32]

VX, WZ, VY = 0, 1, 2  # channel order of sampled controls and velocities (T, C, B)
SEQ_VX, SEQ_VY, SEQ_WZ = 0, 1, 2  # column order of the control sequence (T, 3), as a Twist


@dataclass
class ControlConstraints:
    vx_max: float = 0.5
    vx_min: float = -0.35
    vy_max: float = 0.5
    wz_max: float = 1.9
    ax_max: float = 3.0
    ax_min: float = -3.0
    ay_max: float = 3.0
    ay_min: float = -3.0
    az_max: float = 3.5


class MotionModel(Plugin):
    """Differential drive by default: vx and wz, no lateral speed."""

    class Params(ParamsModel):
        pass

    holonomic = False
    min_turning_r: float | None = None
    c: ControlConstraints
    dt: float

    def configure(self, constraints: ControlConstraints, model_dt: float) -> None:  # type: ignore[override]
        """The controller's velocity and acceleration limits and its rollouts' time step."""
        self.c = constraints
        self.dt = model_dt
        self._accel_cache: tuple[Any, tuple[F32, F32], bool] | None = None

    @property
    def channels(self) -> int:
        return 3 if self.holonomic else 2

    def apply_constraints(self, control_sequence: NDArray[np.float32]) -> None:
        """The model's hard limits on the optimal control sequence (T, 3: vx, vy, wz), in
        place; Nav2's `applyConstraints`. None for a diff-drive or omni robot."""

    def _accel_steps(self, batch: int) -> tuple[F32, F32, bool]:
        """The largest speed change per step up and down as (C, batch) rows, and whether
        they are symmetric; remembered while the limits, dt and the batch size stay
        (full rows: a ufunc on contiguous operands is ~3x faster than one broadcasting a
        (C, 1) column, with the same results)."""
        c = self.c
        key = (c.ax_max, c.az_max, c.ay_max, c.ax_min, c.ay_min, self.dt, self.channels, batch)
        cached = self._accel_cache
        if cached is None or cached[0] != key:
            dt, ch = np.float32(self.dt), self.channels
            up = np.array([c.ax_max, c.az_max, c.ay_max][:ch], np.float32)[:, None] * dt
            down = np.array([c.ax_min, -c.az_max, c.ay_min][:ch], np.float32)[:, None] * dt
            symmetric = bool(np.allclose(up, -down))
            if symmetric:
                down = -up
            rows = (np.repeat(up, batch, axis=1), np.repeat(down, batch, axis=1))
            cached = self._accel_cache = (key, rows, symmetric)
        return cached[1][0], cached[1][1], cached[2]

    def predict(self, u: F32, v: F32, speed: F32, write_back: bool = False) -> None:
        """Velocities the rollouts follow, in place in `v` (T, C, B).

        v[0] is the robot's current `speed` (per channel); v[i] is control u[i-1] as far
        as the acceleration limits allow from v[i-1]: speeding up away from zero is
        limited by ax_max, slowing towards zero by ax_min, in either direction (az_max
        both ways for wz). With `write_back` (Nav2's clamp_raw_controls) the controls
        are then replaced by what was achievable (u[i-1] = v[i]), so the softmax
        averages feasible sequences; by default it averages the raw samples, as Nav2's.
        """
        up, down, symmetric = self._accel_steps(v.shape[2])
        v[0] = speed[:, None]
        tmp = np.empty_like(v[0])
        if symmetric:
            neg = down  # -up
            for i in range(1, u.shape[0]):
                np.subtract(u[i - 1], v[i - 1], out=tmp)
                np.minimum(tmp, up, out=tmp)
                np.maximum(tmp, neg, out=tmp)
                np.add(v[i - 1], tmp, out=v[i])
        else:
            up, down = up[:, :1], down[:, :1]
            for i in range(1, u.shape[0]):
                prev = v[i - 1]
                pos = prev > 0
                lo = prev + np.where(pos, down, -up)
                hi = prev + np.where(pos, up, -down)
                np.clip(u[i - 1], lo, hi, out=v[i])
        if write_back:
            u[:-1] = v[1:]


@register("motion_model", "mppi::DiffDriveMotionModel")
class DiffDriveMotionModel(MotionModel):
    pass


@register("motion_model", "mppi::OmniMotionModel")
class OmniMotionModel(MotionModel):
    holonomic = True


@register("motion_model", "mppi::AckermannMotionModel")
class AckermannMotionModel(MotionModel):
    """Car-like: |wz| <= |vx| / min_turning_r (no turning on the spot)."""

    class Params(MotionModel.Params):
        min_turning_r: float = Field(0.2, gt=0.0, description="the tightest turn's radius, m")

    params: Params

    @property
    def min_turning_r(self) -> float:  # type: ignore[override]
        return float(self.params.min_turning_r)

    def apply_constraints(self, control_sequence: NDArray[np.float32]) -> None:
        """|wz| <= |vx| / min_turning_r at every step of the sequence (its columns vx, vy, wz)."""
        cs = control_sequence
        limit = np.abs(cs[:, SEQ_VX]) / np.float32(self.min_turning_r)
        np.clip(cs[:, SEQ_WZ], -limit, limit, out=cs[:, SEQ_WZ])


def make_motion_model(
    cls: type[MotionModel], constraints: ControlConstraints, model_dt: float, params: Any = None
) -> MotionModel:
    """A motion model built and configured, as the controller makes its own."""
    model = cls(cls.plugin_name, params)
    model.configure(constraints, model_dt)
    return model


#: Nav2 Jazzy's spelling: `motion_model: DiffDrive` with no plugin section.
LEGACY_NAMES = {
    "DiffDrive": "mppi::DiffDriveMotionModel",
    "Omni": "mppi::OmniMotionModel",
    "Ackermann": "mppi::AckermannMotionModel",
}
