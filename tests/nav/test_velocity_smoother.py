"""The velocity smoother as Nav2's: limits per axis, the timeout, feedback, and the chain."""

from __future__ import annotations

import pytest

from btnav.core.geometry import Pose2D
from btnav.core.messages import Odometry, Twist
from btnav.nav.velocity_smoother import VelocitySmoother
from btnav.params.loader import load_params_doc

from .navstack_helpers import office


class _Clock:
    """The runtime's face the smoother uses: `now` and `subscribe`."""

    def __init__(self) -> None:
        self.now = 0.0
        self.odom = None

    def subscribe(self, topic: str, callback) -> None:
        assert topic == "odom"
        self.odom = callback


def smoother(**keys):
    """A smoother on a fake clock with `keys` over Nav2's defaults; returns it and its output."""
    doc = {"velocity_smoother": {"ros__parameters": keys}}
    params = load_params_doc(doc, "smoother.yaml").server("velocity_smoother")
    clock, sent = _Clock(), []
    return VelocitySmoother(clock, params, publish=sent.append), clock, sent


def tick(vs, clock, n=1, command=None):
    """`n` timer ticks; `command` is sent before each, as a controller keeps sending it."""
    for _ in range(n):
        if command is not None:
            vs.command_received(command)
        clock.now += 1.0 / vs.rate
        vs.update(clock.now)


def test_it_stays_silent_until_the_first_command():
    vs, clock, sent = smoother()
    tick(vs, clock, 5)
    assert sent == []


def test_speeding_up_is_limited_by_max_accel_and_slowing_down_by_max_decel():
    vs, clock, sent = smoother(max_accel=[1.0, 0.0, 2.0], max_decel=[-2.0, 0.0, -4.0])
    vs.command_received(Twist(0.5, 0.0, 1.0))
    tick(vs, clock, 3)
    assert [c.linear_x for c in sent] == pytest.approx([0.05, 0.10, 0.15])
    assert [c.angular_z for c in sent] == pytest.approx([0.1, 0.2, 0.3])
    vs.command_received(Twist(0.0, 0.0, 0.0))
    tick(vs, clock)
    assert sent[-1].linear_x == pytest.approx(0.05)  # 0.15 - 2.0 / 20
    assert sent[-1].angular_z == pytest.approx(0.1)  # 0.3 - 4.0 / 20


def test_a_sign_change_decelerates_and_the_command_is_clamped_to_the_velocity_box():
    vs, clock, sent = smoother(max_velocity=[0.3, 0.0, 1.0], min_velocity=[-0.2, 0.0, -1.0])
    tick(vs, clock, 40, Twist(5.0, 0.0, 0.0))
    assert sent[-1].linear_x == pytest.approx(0.3)
    tick(vs, clock, 1, Twist(-5.0, 0.0, 0.0))
    assert sent[-1].linear_x == pytest.approx(0.3 - 2.5 / 20)  # Nav2's default max_decel
    tick(vs, clock, 40, Twist(-5.0, 0.0, 0.0))
    assert sent[-1].linear_x == pytest.approx(-0.2)


def test_scale_velocities_keeps_the_commands_direction():
    vs, clock, sent = smoother(scale_velocities=True, max_accel=[1.0, 0.0, 10.0])
    vs.command_received(Twist(0.5, 0.0, 1.0))  # curvature 2 rad/m
    tick(vs, clock, 4)
    for c in sent:
        assert c.angular_z == pytest.approx(2.0 * c.linear_x)
    vs_free, clock_free, sent_free = smoother(max_accel=[1.0, 0.0, 10.0])
    vs_free.command_received(Twist(0.5, 0.0, 1.0))
    tick(vs_free, clock_free)
    assert sent_free[0].angular_z == pytest.approx(0.5)  # unscaled: each axis on its own


def test_the_deadband_zeroes_small_commands_but_not_the_ramp():
    vs, clock, sent = smoother(deadband_velocity=[0.13, 0.0, 0.0])
    vs.command_received(Twist(0.5, 0.0, 0.0))
    tick(vs, clock, 2)
    assert [c.linear_x for c in sent] == pytest.approx([0.0, 0.25])  # 0.125 then 0.25 internally


def test_no_command_for_velocity_timeout_ramps_down_then_falls_silent():
    vs, clock, sent = smoother(velocity_timeout=0.5)
    vs.command_received(Twist(0.5, 0.0, 0.0))
    tick(vs, clock, 10)  # 0.5 s: at speed, not yet timed out
    assert sent[-1].linear_x == pytest.approx(0.5)
    tick(vs, clock, 10)
    assert sent[-1].linear_x == 0.0
    count = len(sent)
    tick(vs, clock, 10)
    assert len(sent) == count


def test_closed_loop_smooths_from_the_mean_odometry_twist():
    vs, clock, sent = smoother(feedback="CLOSED_LOOP", odom_duration=0.1)
    for stamp, v in ((0.0, 9.0), (0.5, 0.2), (0.55, 0.3), (0.6, 0.4)):
        clock.odom(Odometry(stamp, Pose2D(), Twist(v, 0.0, 0.0)))
    vs.command_received(Twist(0.5, 0.0, 0.0))
    tick(vs, clock)
    assert sent[-1].linear_x == pytest.approx(0.3 + 2.5 / 20)  # mean of the last 0.1 s


def test_six_value_limits_read_x_y_and_yaw():
    limits = dict(
        max_velocity=[0.5, 0.0, 0.0, 0.0, 0.0, 1.0],
        min_velocity=[-0.5, 0.0, 0.0, 0.0, 0.0, -1.0],
        max_accel=[2.5, 0.0, 0.0, 0.0, 0.0, 3.2],
        max_decel=[-2.5, 0.0, 0.0, 0.0, 0.0, -3.2],
        deadband_velocity=[0.0] * 6,
    )
    vs, clock, sent = smoother(**limits)
    tick(vs, clock, 20, Twist(1.0, 0.0, 2.0))
    assert (sent[-1].linear_x, sent[-1].angular_z) == pytest.approx((0.5, 1.0))


def test_nav2s_params_put_the_smoother_between_the_servers_and_the_base():
    world, rt, stack = office()
    assert stack.velocity_smoother is not None
    rt.set_cmd_vel(Twist(0.5, 0.0, 0.0))
    rt.spin_for(0.05)  # one tick: 3.0 m/s^2 (Nav2's file) for 50 ms
    assert rt.cmd_vel_nav.linear_x == 0.5
    assert rt.cmd_vel.linear_x == pytest.approx(0.15)
    rt.spin_for(0.5)
    assert rt.cmd_vel.linear_x == pytest.approx(0.5)
    assert world.robot.cmd_vel.linear_x == pytest.approx(0.5)


def test_a_params_file_without_the_section_drives_the_base_directly(tmp_path):
    import yaml

    from .navstack_helpers import PARAMS

    doc = yaml.safe_load(PARAMS.read_text())
    del doc["velocity_smoother"]
    path = tmp_path / "nav2_params.yaml"
    path.write_text(yaml.safe_dump(doc, sort_keys=False))
    _world, rt, stack = office(path)
    assert stack.velocity_smoother is None
    rt.set_cmd_vel(Twist(0.5, 0.0, 0.0))
    rt.spin_for(0.05)
    assert rt.cmd_vel.linear_x == 0.5
