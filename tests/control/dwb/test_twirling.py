"""Twirling: every trajectory scores its commanded |turning rate| (Nav2's twirling.cpp),
weighed by `scale` (1 by default, as every critic's), so that of trajectories otherwise
alike DWB takes the one that spins least."""

from __future__ import annotations

from btnav.control.dwb import DWBLocalPlanner
from btnav.control.dwb.critics.twirling import TwirlingCritic
from btnav.control.dwb.local_planner import DWBParams
from btnav.core.geometry import Pose2D
from btnav.core.messages import Twist
from btnav.plugins import lookup

from ..unicycle import free_costmap, straight_path
from .trajs import costmap, velocity_set


def test_registered_under_nav2s_names():
    assert lookup("critic", "dwb_critics::Twirling") is TwirlingCritic
    assert lookup("critic", "dwb_critics::TwirlingCritic") is TwirlingCritic


def test_scores_the_turning_rate_whatever_the_speed():
    trajs = velocity_set([(0.3, 0.0, 0.0), (0.3, 0.0, 0.5), (0.0, 0.0, -1.2), (-0.2, 0.1, 0.25)])
    assert list(TwirlingCritic("Twirling").score(trajs, costmap())) == [0.0, 0.5, 1.2, 0.25]
    assert DWBParams(critics=["Twirling"]).critic_params["Twirling"].scale == 1.0


def test_dwb_turns_less_the_more_twirling_weighs():
    """0.4 m to the side of a straight path, heading along it: DWB turns towards the path,
    and more gently the more Twirling weighs."""

    def turn(scale: float | None) -> float:
        critics = ["PathAlign", "PathDist", "GoalDist"] + (["Twirling"] if scale else [])
        keys = {"max_vel_x": 0.5, "max_speed_xy": 0.5, "critics": critics}
        if scale:
            keys["Twirling.scale"] = scale
        dwb = DWBLocalPlanner(params=DWBParams.model_validate(keys))
        dwb.set_plan(straight_path())
        pose, speed = Pose2D(0.0, 0.4, 0.0), Twist(linear_x=0.3)
        return -dwb.compute_velocity_commands(pose, speed, free_costmap()).angular_z

    turns = [turn(scale) for scale in (None, 100.0, 300.0, 1000.0)]
    assert turns[0] > 0.5
    assert turns == sorted(turns, reverse=True) and turns[-1] < 0.3 * turns[0]
