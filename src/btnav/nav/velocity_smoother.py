"""Nav2's velocity_smoother: the servers' `cmd_vel_nav` made kinematically feasible.

nav2_bringup puts it between the controller and behaviours (which publish `cmd_vel_nav`)
and the collision monitor (which takes `cmd_vel_smoothed`). Each timer tick, at
`smoothing_frequency`, it takes the newest command received, clamps it to
`min_velocity`/`max_velocity`, and moves from the current velocity towards it by at most
`max_accel / smoothing_frequency` per axis while the speed grows, `max_decel / ...` while
it shrinks or changes sign. The current velocity is the last smoothed command
(`feedback: OPEN_LOOP`) or the odometry's twist averaged over `odom_duration`
(`CLOSED_LOOP`). `scale_velocities` scales all axes by the most constrained one's
ratio, so the command keeps its direction (its curvature). Below `deadband_velocity` an
axis is sent as 0. No command for `velocity_timeout` seconds: it ramps down to zero, then
stays silent until the next command, as Nav2 does.

Six-value limits (x, y, z, roll, pitch, yaw) are read as Nav2 reads them; a 2D base uses
x, y and yaw. btnav's timer runs in phase with the controller (both start with the run),
so a command is smoothed in the step it is sent; Nav2's timers have arbitrary phase.
"""

from __future__ import annotations

from collections import deque
from collections.abc import Callable
from math import fsum

from ..core.messages import Odometry, Twist
from ..params.paramsfile import ServerParams
from .runtime import Runtime, Stage

#: Where x, y and yaw sit in a limit list of 3 (x, y, theta) or 6 (x, y, z, r, p, y) values.
_AXES = {3: (0, 1, 2), 6: (0, 1, 5)}


def _axis_bounds(current: float, command: float, accel: float, decel: float, hz: float):
    """The change allowed in one tick: accelerating while the speed grows in the same
    direction, decelerating otherwise (Nav2's rule, `decel` negative)."""
    if abs(command) >= abs(current) and current * command >= 0.0:
        return -accel / hz, accel / hz
    return decel / hz, -decel / hz


def _eta(current: float, command: float, accel: float, decel: float, hz: float) -> float:
    """The fraction of this axis's change that fits in one tick, or -1 if all of it does."""
    low, high = _axis_bounds(current, command, accel, decel, hz)
    dv = command - current
    if dv > high:
        return high / dv
    if dv < low:
        return low / dv
    return -1.0


class VelocitySmoother:
    """velocity_smoother: `command_received` takes `cmd_vel_nav`; each tick publishes the
    smoothed command to `publish` (the collision monitor, else the base)."""

    stage = Stage.SERVER

    def __init__(
        self, runtime: Runtime, params: ServerParams, publish: Callable[[Twist], None]
    ) -> None:
        self.runtime = runtime
        self.publish = publish
        self.set_parameters(params)
        self.command: Twist | None = None  # None until the first command arrives
        self.last_command_time = 0.0
        #: The last smoothed command before the deadband (OPEN_LOOP's current velocity).
        self.last_cmd = Twist()
        self.stopped = False
        self._odom: deque[Odometry] = deque()
        runtime.subscribe("odom", self._odom_received)

    def set_parameters(self, params: ServerParams) -> None:
        """Take new params (validated as the file is); the rate applies from the next tick."""
        self.params = params
        m = params.model
        self.rate = float(m.smoothing_frequency)
        axes = _AXES[len(m.max_velocity)]
        self._limits = [
            (m.min_velocity[i], m.max_velocity[i], m.max_accel[i], m.max_decel[i]) for i in axes
        ]
        self._deadband = [m.deadband_velocity[i] for i in axes]

    def command_received(self, cmd: Twist) -> None:
        """A new `cmd_vel_nav` (Nav2's inputCommandCallback): kept until the next tick."""
        self.command = cmd
        self.last_command_time = self.runtime.now

    def _odom_received(self, odom: Odometry) -> None:
        """Nav2's OdomSmoother: keep the twists of the last `odom_duration` seconds."""
        history = self._odom
        history.append(odom)
        while odom.stamp - history[0].stamp > self.params.model.odom_duration:
            history.popleft()

    def current_velocity(self) -> Twist:
        """What the command is smoothed from: the last command, or the odometry's mean."""
        if self.params.model.feedback == "OPEN_LOOP" or not self._odom:
            return self.last_cmd
        n = len(self._odom)  # fsum: correctly rounded, the same on every Python
        return Twist(
            linear_x=fsum(o.twist.linear_x for o in self._odom) / n,
            linear_y=fsum(o.twist.linear_y for o in self._odom) / n,
            angular_z=fsum(o.twist.angular_z for o in self._odom) / n,
        )

    def update(self, now: float) -> None:
        """One timer tick (Nav2's smootherTimer)."""
        if self.command is None:
            return
        if now - self.last_command_time > self.params.model.velocity_timeout:
            if self.stopped or self.last_cmd == Twist():
                self.stopped = True
                return
            self.command = Twist()  # ramp down to zero, then fall silent
        self.stopped = False

        hz = self.rate
        current = self.current_velocity()
        now_v = (current.linear_x, current.linear_y, current.angular_z)
        wanted = [
            min(max(v, low), high)
            for v, (low, high, _, _) in zip(
                (self.command.linear_x, self.command.linear_y, self.command.angular_z),
                self._limits,
                strict=True,
            )
        ]
        eta = 1.0
        if self.params.model.scale_velocities:
            for v0, v1, (_, _, accel, decel) in zip(now_v, wanted, self._limits, strict=True):
                axis_eta = _eta(v0, v1, accel, decel, hz)
                if axis_eta > 0.0 and abs(1.0 - axis_eta) > abs(1.0 - eta):
                    eta = axis_eta
        out = []
        for v0, v1, (_, _, accel, decel) in zip(now_v, wanted, self._limits, strict=True):
            low, high = _axis_bounds(v0, v1, accel, decel, hz)
            out.append(v0 + min(max(eta * (v1 - v0), low), high))
        self.last_cmd = Twist(*out)
        self.publish(
            Twist(
                *(0.0 if abs(v) < band else v for v, band in zip(out, self._deadband, strict=True))
            )
        )

    def __repr__(self) -> str:
        return f"VelocitySmoother({self.rate:g} Hz, {self.params.model.feedback})"
