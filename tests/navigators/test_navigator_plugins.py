"""bt_navigator's navigators are `navigator` plugins, configured from their params sections."""

from __future__ import annotations

import pytest
import yaml

from btnav import Navigator
from btnav.core.errors import BtnavError
from btnav.navigators.bt_navigator import NavigateThroughPosesNavigator, NavigateToPoseNavigator
from btnav.params import load_params
from btnav.plugins import lookup, register, unregister

from .test_navigator import MAP, PARAMS, WORLD


def params_with(tmp_path, **navigator_sections):
    doc = yaml.safe_load(PARAMS.read_text())
    bt = doc["bt_navigator"]["ros__parameters"]
    for name, section in navigator_sections.items():
        bt[name] = section
    out = tmp_path / "nav2_params.yaml"
    out.write_text(yaml.safe_dump(doc, sort_keys=False))
    return out


def test_nav2s_navigator_names_are_btnavs_classes():
    assert lookup("navigator", "nav2_bt_navigator::NavigateToPoseNavigator") is (
        NavigateToPoseNavigator
    )
    assert lookup("navigator", "nav2_bt_navigator/NavigateThroughPosesNavigator") is (
        NavigateThroughPosesNavigator
    )
    nav = Navigator.from_files(WORLD, PARAMS, MAP)
    to_pose = nav.bt_navigator.navigators["navigate_to_pose"]
    assert to_pose.action == "NavigateToPose" and to_pose.search_window == 2.0
    assert to_pose.rate == 100.0  # bt_loop_duration 10 ms
    through = nav.bt_navigator.navigators["navigate_through_poses"]
    assert through.default_tree == "navigate_through_poses_w_replanning_and_recovery"


def test_a_navigator_section_is_validated_like_any_plugins(tmp_path):
    bad = params_with(
        tmp_path,
        navigate_to_pose={
            "plugin": "nav2_bt_navigator::NavigateToPoseNavigator",
            "search_windw": 3.0,
        },
    )
    with pytest.raises(BtnavError) as info:
        load_params(bad)
    assert info.value.suggestion == "search_window"
    assert info.value.key == "bt_navigator.navigate_to_pose.search_windw"
    good = params_with(
        tmp_path,
        navigate_to_pose={
            "plugin": "nav2_bt_navigator::NavigateToPoseNavigator",
            "search_window": 3.5,
        },
    )
    nav = Navigator.from_files(WORLD, good, MAP)
    assert nav.bt_navigator.navigators["navigate_to_pose"].search_window == 3.5


def test_a_users_navigator_is_a_peer(tmp_path):
    @register("navigator", "my_pkg/LoggingNavigator")
    class LoggingNavigator(NavigateToPoseNavigator):
        goals: list = []

        def _set_goal(self, goal):
            type(self).goals.append(goal.pose)
            super()._set_goal(goal)

    try:
        params = params_with(tmp_path, navigate_to_pose={"plugin": "my_pkg::LoggingNavigator"})
        nav = Navigator.from_files(WORLD, params, MAP)
        assert isinstance(nav.bt_navigator.navigators["navigate_to_pose"], LoggingNavigator)
        assert nav.go_to_pose((1.5, 1.0, 0.0))
        nav.is_task_complete()
        assert len(LoggingNavigator.goals) == 1
    finally:
        unregister("navigator", "my_pkg/LoggingNavigator")
