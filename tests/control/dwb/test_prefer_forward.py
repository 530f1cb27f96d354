"""PreferForward: for a robot that cannot see behind it.

Nav2 (prefer_forward.cpp): a trajectory commanded backwards scores `penalty`; one slower
than `strafe_x` while turning slower than `strafe_theta` (creeping) scores `penalty` too;
any other scores |turning rate| * `theta_scale`. Defaults: penalty 1, strafe_x 0.1,
strafe_theta 0.2, theta_scale 10.
"""

from __future__ import annotations

import pytest

from btnav.control.dwb import DWBLocalPlanner
from btnav.control.dwb.critics.prefer_forward import PreferForwardCritic
from btnav.control.dwb.local_planner import DWBParams
from btnav.core.geometry import Pose2D
from btnav.core.messages import Twist
from btnav.plugins import lookup

from ..unicycle import free_costmap, straight_path
from .trajs import costmap, velocity_set


def critic(**params) -> PreferForwardCritic:
    return PreferForwardCritic("PreferForward", PreferForwardCritic.Params(**params))


def test_registered_under_nav2s_names():
    assert lookup("critic", "dwb_critics::PreferForward") is PreferForwardCritic
    assert lookup("critic", "dwb_critics::PreferForwardCritic") is PreferForwardCritic


@pytest.mark.parametrize(
    ("vx", "wz", "expected"),
    [
        (-0.2, 0.0, 1.0),  # backwards
        (-0.05, 1.0, 1.0),  # backwards, however it turns
        (0.05, 0.1, 1.0),  # creeping: slow and hardly turning
        (0.0, -0.15, 1.0),
        (0.0, 0.5, 5.0),  # turning on the spot: |wz| * theta_scale
        (0.05, -0.3, 3.0),
        (0.3, 0.0, 0.0),  # driving straight ahead
        (0.3, 0.2, 2.0),
        (0.1, 0.0, 0.0),  # exactly strafe_x is not creeping
        (0.05, 0.2, 2.0),  # nor exactly strafe_theta
    ],
)
def test_backwards_and_creeping_pay_the_penalty_turning_pays_its_rate(vx, wz, expected):
    got = critic().score(velocity_set([(vx, 0.0, wz)]), costmap())[0]
    assert got == pytest.approx(expected, rel=1e-12, abs=1e-12)


def test_params_as_nav2_names_them():
    c = critic(penalty=7.0, strafe_x=0.3, strafe_theta=0.5, theta_scale=2.0)
    got = c.score(
        velocity_set([(-0.1, 0, 0), (0.2, 0, 0.4), (0.2, 0, 0.6), (0.4, 0, 0.1)]), costmap()
    )
    assert got == pytest.approx([7.0, 7.0, 1.2, 0.2])
    p = DWBParams.model_validate({"critics": ["PreferForward"], "PreferForward.penalty": 3.0})
    assert p.critic_params["PreferForward"].penalty == 3.0
    assert p.critic_params["PreferForward"].scale == 1.0  # Nav2's default scale


def test_dwb_with_prefer_forward_does_not_back_up_to_a_goal_behind_it():
    """A path straight back from the robot: with reversing allowed (min_vel_x < 0) DWB
    backs along it, unless PreferForward's penalty outweighs what reversing gains."""

    def first_command(critics: list[str]) -> Twist:
        keys = {"min_vel_x": -0.3, "max_vel_x": 0.5, "max_speed_xy": 0.5, "critics": critics}
        if "PreferForward" in critics:
            keys |= {"PreferForward.scale": 50.0, "PreferForward.penalty": 100.0}
        params = DWBParams.model_validate(keys)
        dwb = DWBLocalPlanner(params=params)
        path = straight_path()
        path.poses[:, 0] *= -1.0  # from (0, 0) to (-4, 0), the robot facing +x
        dwb.set_plan(path)
        return dwb.compute_velocity_commands(Pose2D(), Twist(), free_costmap(origin=-5.0))

    assert first_command(["PathAlign", "PathDist", "GoalDist"]).linear_x < 0.0
    assert first_command(["PreferForward", "PathAlign", "PathDist", "GoalDist"]).linear_x >= 0.0
