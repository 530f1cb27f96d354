"""A DWB section from a params file is read as Nav2 reads it; one built in code is the
documented example.

Nav2 (dwb_local_planner.cpp loadCritics, trajectory_critic.hpp, kinematic_parameters.cpp):
a section without `critics` does not configure ("No critics defined for FollowPath"), a
listed critic without `scale` weighs 1.0, GoalAlign's and PathAlign's forward point is
0.325 m ahead, every velocity and acceleration limit left out is 0.0.
"""

from __future__ import annotations

from pathlib import Path

import pytest

from btnav.cli import main
from btnav.control.dwb import DWBLocalPlanner
from btnav.control.dwb.local_planner import DOCUMENTED_CRITICS, DWBParams
from btnav.control.exceptions import NoValidControl
from btnav.core.errors import BtnavWarning, ParamsError
from btnav.core.geometry import Pose2D
from btnav.core.messages import Twist
from btnav.params import load_params

from ...params.tutorial import (
    DOCUMENTED_CRITICS as DOCUMENTED_LINES,
)
from ...params.tutorial import (
    line_of,
    with_completed_sections,
    with_tutorial_sections,
)
from ..unicycle import free_costmap, straight_path

REPO = Path(__file__).resolve().parents[3]
DWB = "dwb_core::DWBLocalPlanner"
#: The DWB files btnav ships (each lists its critics and their scales).
BUNDLED = [
    "nav2_params_dwb.yaml",
    "turtlebot3_burger_nav2_params.yaml",
    "omni_nav2_params.yaml",
    "fishbot_nav2_params.yaml",
]


def load(path: Path):
    with pytest.warns(BtnavWarning):  # the tutorial's keys Nav2 skips, one warning each
        return load_params(path)


def follow_path(params, name: str = "FollowPath") -> DWBParams:
    section = params.server("controller_server").plugins[name].params
    assert isinstance(section, DWBParams)
    return section


# -- no critics: Nav2 does not start; btnav says so and prints the fix ----------------------


def test_a_section_without_critics_is_one_located_error_with_the_fix(tmp_path, nav2_params_file):
    path = with_tutorial_sections(nav2_params_file, tmp_path / "tutorial.yaml")
    with pytest.raises(ParamsError) as info:
        load_params(path)
    err = info.value
    # the section's first line (its plugin: key), the key to add
    assert (err.file, err.line, err.key) == (
        str(path),
        line_of(path, "controller_server.FollowPath.plugin"),
        "controller_server.FollowPath.critics",
    )
    head, *block = err.message.splitlines()
    assert 'Nav2 refuses this section too ("No critics defined for FollowPath"' in head
    assert "controller_server does not start" in head
    assert "params/nav2_params_dwb.yaml" in head
    # the fix: the documented list and scales, indented as the section's keys
    assert "\n".join(block) + "\n" == DOCUMENTED_LINES


def test_pasting_what_the_error_prints_gives_the_documented_critics(tmp_path, nav2_params_file):
    with pytest.raises(ParamsError) as info:
        load_params(with_tutorial_sections(nav2_params_file, tmp_path / "tutorial.yaml"))
    fix = "\n".join(info.value.message.splitlines()[1:])
    pasted = with_tutorial_sections(nav2_params_file, tmp_path / "pasted.yaml", critics=fix)
    dwb = follow_path(load(pasted))
    assert dwb.critics == list(DOCUMENTED_CRITICS)
    for name, keys in DOCUMENTED_CRITICS.items():
        for key, value in keys.items():
            assert getattr(dwb.critic_params[name], key) == value, (name, key)


def test_params_check_refuses_it_naming_file_line_and_key(tmp_path, nav2_params_file, capsys):
    path = with_tutorial_sections(nav2_params_file, tmp_path / "tutorial.yaml")
    assert main(["params", "check", str(path)]) == 2
    err = capsys.readouterr().err
    line = line_of(path, "controller_server.FollowPath.plugin")
    assert err.startswith(f"btnav: error: {path}:{line}: controller_server.FollowPath.critics: ")
    assert '      critics: ["RotateToGoal", "Oscillation", "BaseObstacle"' in err


def test_in_code_a_section_without_critics_is_the_documented_one():
    # Tests, benchmarks and scripts build DWB in code: the documented critics and scales.
    dwb = DWBParams()
    assert dwb.critics == list(DOCUMENTED_CRITICS)
    assert dwb.critic_params["BaseObstacle"].scale == 0.02
    assert dwb.critic_params["GoalAlign"].forward_point_distance == 0.1
    assert DWBParams(max_vel_x=0.5).critic_params["PathAlign"].scale == 32.0


# -- a listed critic without scale: Nav2's own default -----------------------------------


def test_a_listed_critic_without_scale_weighs_nav2s_default(tmp_path):
    text = (REPO / "params" / "nav2_params_dwb.yaml").read_text()
    for line in ("      PathAlign.scale: 32.0\n", "      GoalAlign.forward_point_distance: 0.1\n"):
        assert text.count(line) == 1
        text = text.replace(line, "")
    text = text.replace('"PathDist", "GoalDist"]', '"PathDist", "GoalDist", "Twirling"]')
    path = tmp_path / "params.yaml"
    path.write_text(text)
    dwb = follow_path(load_params(path))
    assert dwb.critic_params["PathAlign"].scale == 1.0  # not the documented 32.0
    assert dwb.critic_params["Twirling"].scale == 1.0
    assert dwb.critic_params["GoalAlign"].forward_point_distance == pytest.approx(0.325)
    assert dwb.critic_params["GoalAlign"].scale == 24.0  # as written
    # in code, a list written out is read the same way
    assert DWBParams(critics=["PathAlign"]).critic_params["PathAlign"].scale == 1.0


@pytest.mark.parametrize("name", BUNDLED)
def test_the_bundled_dwb_files_keep_their_scales(name):
    path = REPO / "params" / name
    text = path.read_text()
    params = load_params(path)
    sections = [
        s
        for s in params.server("controller_server").plugins.values()
        if s.type.endswith("DWBLocalPlanner")
    ]
    assert sections
    for section in sections:
        dwb = section.params
        for critic in dwb.critics:
            written = f"{critic}.scale: "
            scale = dwb.critic_params[critic].scale
            if written in text:
                assert f"{written}{scale}\n" in text, (name, critic, scale)
            else:  # unwritten: 1.0, which the documented example gives it too
                assert scale == 1.0 == DOCUMENTED_CRITICS.get(critic, {}).get("scale", 1.0)


# -- the limits a section leaves out: Nav2's 0.0 ------------------------------------------


def test_a_section_from_a_file_takes_nav2s_code_defaults(tmp_path, nav2_params_file):
    path = with_completed_sections(nav2_params_file, tmp_path / "tutorial.yaml")
    dwb = follow_path(load(path))
    # written by the tutorial
    assert (dwb.min_vel_x, dwb.max_vel_x, dwb.acc_lim_theta, dwb.vtheta_samples) == (
        -0.3,
        0.3,
        0.5,
        40,
    )
    # left out: Nav2's defaults (max_rot_vel: 0.5 is ROS 1's name, which Nav2 does not read)
    assert (dwb.max_vel_theta, dwb.max_speed_xy, dwb.min_speed_xy, dwb.min_speed_theta) == (
        0.0,
        0.0,
        0.0,
        0.0,
    )
    assert dwb.linear_granularity == 0.5 and dwb.angular_granularity == 0.025
    assert dwb.sim_time == 1.7 and dwb.xy_goal_tolerance == 0.25
    # in code, the documented example
    doc = DWBParams()
    assert (doc.max_vel_theta, doc.max_speed_xy, doc.linear_granularity) == (1.0, 0.26, 0.05)


def test_no_velocity_to_sample_says_which_limits_are_zero(tmp_path, nav2_params_file):
    dwb = follow_path(load(with_completed_sections(nav2_params_file, tmp_path / "t.yaml")))
    ctrl = DWBLocalPlanner(params=dwb)
    ctrl.set_plan(straight_path())
    with pytest.raises(NoValidControl) as info:
        ctrl.compute_velocity_commands(Pose2D(), Twist(), free_costmap())
    msg = str(info.value)
    assert msg.startswith("No valid velocity samples in the dynamic window: ")
    assert "max_speed_xy and max_vel_theta are 0.0" in msg and "in Nav2 too" in msg
    assert msg.endswith("(the documented example has max_speed_xy: 0.26, max_vel_theta: 1.0)")
    # with them set, it drives
    fixed = dwb.model_copy(update={"max_speed_xy": 0.3, "max_vel_theta": 0.5})
    ctrl = DWBLocalPlanner(params=fixed)
    ctrl.set_plan(straight_path())
    cmd = ctrl.compute_velocity_commands(Pose2D(), Twist(), free_costmap())
    assert cmd.linear_x > 0.0
