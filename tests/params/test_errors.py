"""A mistake in a params file names the file, the exact line, the key and the right spelling."""

from __future__ import annotations

from pathlib import Path

import pytest

from btnav.core.errors import BtnavWarning, ParamsError
from btnav.params import load_params

from .conftest import TEST_INFLATION


def error_of(path: Path) -> ParamsError:
    with pytest.raises(ParamsError) as info:
        load_params(path)
    return info.value


def test_misspelt_server_key(nav2_copy) -> None:
    path, line = nav2_copy("controller_frequency: 20.0", "controller_frequncy: 20.0")
    err = error_of(path)
    assert (err.file, err.line, err.key, err.suggestion) == (
        str(path),
        line,
        "controller_server.controller_frequncy",
        "controller_frequency",
    )
    assert line == 94
    assert str(err).startswith(f"{path}:94: controller_server.controller_frequncy: unknown key")


def test_negative_frequency(nav2_copy) -> None:
    path, line = nav2_copy("controller_frequency: 20.0", "controller_frequency: -20.0")
    err = error_of(path)
    assert (err.line, err.key) == (line, "controller_server.controller_frequency")
    assert "greater than 0" in err.message and "-20.0" in err.message


def test_out_of_range_in_nested_costmap(nav2_copy) -> None:
    path, line = nav2_copy("resolution: 0.05", "resolution: 0.0")
    err = error_of(path)
    assert (err.line, err.key) == (line, "local_costmap.local_costmap.resolution")


def test_misspelt_key_in_a_registered_plugin_section(with_test_inflation) -> None:
    path, line = with_test_inflation("inflation_radius: 0.70", "inflation_radus: 0.70")
    err = error_of(path)
    assert err.line == line == 262
    assert err.key == "local_costmap.local_costmap.inflation_layer.inflation_radus"
    assert err.suggestion == "inflation_radius"


def test_out_of_range_in_a_registered_plugin_section(with_test_inflation) -> None:
    path, line = with_test_inflation("inflation_radius: 0.7\n", "inflation_radius: -0.7\n")
    err = error_of(path)
    assert (err.line, err.key) == (
        line,
        "global_costmap.global_costmap.inflation_layer.inflation_radius",
    )
    assert line == 344


def test_registered_plugin_section_is_validated_by_its_params(
    with_test_inflation, inflation_plugin
):
    path, _ = with_test_inflation()
    params = load_params(path)
    layer = params.server("local_costmap").plugins["inflation_layer"]
    assert layer.cls is inflation_plugin
    assert layer.params.inflation_radius == 0.70
    assert layer.params.cost_scaling_factor == 3.0
    assert layer.status.endswith("TestInflation")
    assert "local_costmap.local_costmap.inflation_layer" not in {e.key for e in params.ignored}


def test_unknown_plugin_type_suggests_the_closest(nav2_copy) -> None:
    path, line = nav2_copy("nav2_navfn_planner::NavfnPlanner", "nav2_navfn_planner::NavFnPlaner")
    err = error_of(path)
    assert (err.line, err.key) == (line, "planner_server.GridBased.plugin")
    assert err.suggestion == "nav2_navfn_planner::NavfnPlanner"
    assert "unknown planner plugin 'nav2_navfn_planner::NavFnPlaner'" in err.message


def test_unknown_server_suggests_the_closest(nav2_copy) -> None:
    path, line = nav2_copy("controller_server:", "controler_server:")
    err = error_of(path)
    assert (err.line, err.key, err.suggestion) == (line, "controler_server", "controller_server")
    assert line == 92


def test_listed_plugin_without_section(nav2_copy) -> None:
    path, line = nav2_copy(
        'controller_plugins: ["FollowPath"]', 'controller_plugins: ["FollowPth"]'
    )
    err = error_of(path)
    assert (err.line, err.key, err.suggestion) == (
        line,
        "controller_server.controller_plugins",
        "FollowPath",
    )
    assert "no section 'FollowPth:'" in err.message


def test_misspelt_ros_parameters(nav2_copy) -> None:
    path, _ = nav2_copy("  ros__parameters:", "  ros_parameters:")
    err = error_of(path)
    assert (err.line, err.key, err.suggestion) == (2, "amcl.ros_parameters", "ros__parameters")


def test_misspelt_costmap_node_in_its_namespace(nav2_copy) -> None:
    path, line = nav2_copy("  global_costmap:", "  global_costmp:")
    err = error_of(path)
    assert (err.line, err.key, err.suggestion) == (
        line,
        "global_costmap.global_costmp",
        "global_costmap",
    )


def test_wrong_choice_suggests_the_closest(nav2_copy) -> None:
    path, line = nav2_copy(
        'laser_model_type: "likelihood_field"', 'laser_model_type: "likelyhood_field"'
    )
    err = error_of(path)
    assert (err.line, err.key, err.suggestion) == (
        line,
        "amcl.laser_model_type",
        "likelihood_field",
    )


def test_cross_key_check_points_at_the_key(nav2_copy) -> None:
    path, line = nav2_copy("min_particles: 500", "min_particles: 5000")
    err = error_of(path)
    assert (err.line, err.key) == (line, "amcl.min_particles")
    assert "above max_particles (2000)" in err.message


def test_velocity_limit_points_at_the_item(nav2_copy) -> None:
    path, line = nav2_copy("max_decel: [-3.0, 0.0, -3.5]", "max_decel: [-3.0, 0.0, 3.5]")
    err = error_of(path)
    assert (err.line, err.key) == (line, "velocity_smoother.max_decel[2]")


def test_launch_token_where_btnav_reads_a_bool(nav2_copy) -> None:
    path, line = nav2_copy("do_beamskip: false", "do_beamskip: KEEPOUT_ZONE_ENABLED")
    err = error_of(path)
    assert (err.line, err.key) == (line, "amcl.do_beamskip")
    assert "launch-file placeholder" in err.message


def test_collision_monitor_polygon_is_validated(nav2_copy) -> None:
    path, line = nav2_copy('action_type: "approach"', 'action_type: "aproach"')
    err = error_of(path)
    assert (err.line, err.key, err.suggestion) == (
        line,
        "collision_monitor.FootprintApproach.action_type",
        "approach",
    )
    path, line = nav2_copy("min_points: 6", "min_pionts: 6")
    err = error_of(path)
    assert (err.line, err.key, err.suggestion) == (
        line,
        "collision_monitor.FootprintApproach.min_pionts",
        "min_points",
    )


def test_collision_monitor_listed_source_without_section(nav2_copy) -> None:
    path, line = nav2_copy('observation_sources: ["scan"]', 'observation_sources: ["scna"]')
    err = error_of(path)
    assert (err.line, err.key, err.suggestion) == (
        line,
        "collision_monitor.observation_sources",
        "scan",
    )


def test_misspelt_section_of_a_defaulted_plugin(nav2_copy) -> None:
    # Nav2 would run PathHandler with its default type and skip PathHandlr's settings.
    path, line = nav2_copy("    PathHandler:", "    PathHandlr:")
    err = error_of(path)
    assert (err.line, err.key, err.suggestion) == (
        line,
        "controller_server.PathHandlr",
        "PathHandler",
    )


def test_unlisted_section_without_plugin_is_an_unknown_key(tmp_path: Path) -> None:
    path = write(
        tmp_path,
        "controller_server:\n  ros__parameters:\n    goal_checker:\n      plugin: nav2_controller::SimpleGoalChecker\n"
        "    precise_goal_checker:\n      xy_goal_tolerance: 0.1\n",
    )
    err = error_of(path)
    assert (err.line, err.key) == (5, "controller_server.precise_goal_checker")
    assert "unknown key" in err.message


def write(tmp_path: Path, text: str) -> Path:
    path = tmp_path / "p.yaml"
    path.write_text(text)
    return path


def test_footprint_string_is_parsed(tmp_path: Path) -> None:
    path = write(
        tmp_path,
        "local_costmap:\n"
        "  ros__parameters:\n"  # the single-nested form is accepted too
        '    footprint: "[[0.3, 0.2], [0.3, -0.2], [-0.3, -0.2], [-0.3, 0.2]]"\n',
    )
    server = load_params(path).server("local_costmap")
    assert server.key == "local_costmap"
    assert server.model.footprint == ((0.3, 0.2), (0.3, -0.2), (-0.3, -0.2), (-0.3, 0.2))


def test_malformed_footprint(tmp_path: Path) -> None:
    path = write(
        tmp_path,
        "global_costmap:\n  global_costmap:\n    ros__parameters:\n"
        '      footprint: "[[0.3, 0.2], [0.3]]"\n',
    )
    err = error_of(path)
    assert (err.line, err.key) == (4, "global_costmap.global_costmap.footprint")
    assert "[x, y]" in err.message


def test_absent_lists_get_nav2_defaults(tmp_path: Path) -> None:
    path = write(
        tmp_path, "planner_server:\n  ros__parameters:\n    allow_partial_planning: true\n"
    )
    params = load_params(path)
    grid = params.server("planner_server").plugins["GridBased"]
    assert (grid.type, grid.defaulted) == ("nav2_navfn_planner::NavfnPlanner", True)
    # Servers the file lacks run on Nav2's defaults.
    behaviors = params.server("behavior_server")
    assert not behaviors.in_file
    assert list(behaviors.plugins) == ["spin", "backup", "drive_on_heading", "wait"]
    assert params.server("controller_server").plugins["FollowPath"].type == (
        "nav2_mppi_controller::MPPIController"
    )


def test_a_custom_list_needs_every_section(tmp_path: Path) -> None:
    # ["GridBased"] is Nav2's default list, so its type is defaulted; a second name is not.
    path = write(
        tmp_path,
        "planner_server:\n  ros__parameters:\n    planner_plugins: [GridBased, Smac]\n"
        "    GridBased:\n      plugin: nav2_navfn_planner::NavfnPlanner\n",
    )
    err = error_of(path)
    assert (err.line, err.key) == (3, "planner_server.planner_plugins")


def test_legacy_singular_progress_checker(tmp_path: Path) -> None:
    """Nav2 no longer reads Humble's key (a warning), but its default list names the same
    checker, so the section is used all the same."""
    path = write(
        tmp_path,
        "controller_server:\n  ros__parameters:\n    progress_checker_plugin: progress_checker\n"
        "    progress_checker:\n      plugin: nav2_controller::PoseProgressChecker\n",
    )
    with pytest.warns(BtnavWarning, match="current equivalent: progress_checker_plugins"):
        params = load_params(path)
    checker = params.server("controller_server").plugins["progress_checker"]
    assert (checker.kind, checker.type) == (
        "progress_checker",
        "nav2_controller::PoseProgressChecker",
    )


def test_dotted_parameter_names_mean_the_nested_ones(tmp_path: Path) -> None:
    path = write(
        tmp_path,
        "amcl:\n  ros__parameters:\n    set_initial_pose: true\n"
        "    initial_pose.x: 1.5\n    initial_pose:\n      yaw: 0.5\n",
    )
    pose = load_params(path).server("amcl").model.initial_pose
    assert (pose.x, pose.yaw) == (1.5, 0.5)


@pytest.mark.parametrize(
    "text, message",
    [
        ("", "empty"),
        ("- a\n- b\n", "not a YamlSeq"),
        ("amcl:\n  alpha1: 0.2\n", "ros__parameters"),
        ("amcl:\n  ros__parameters: 3\n", "must map parameter names"),
        ("amcl:\n  ros__parameters: {}\n  alpha1: 0.2\n", "beside 'ros__parameters:'"),
        ("amcl:\n  ros__parameters:\n    1: 2\n", "must be a non-empty string"),
        ("planner_server:\n  ros__parameters:\n    GridBased: 3\n", "not a single value"),
        ("/amcl:\n  ros__parameters: {}\namcl:\n  ros__parameters: {}\n", "configured twice"),
    ],
)
def test_structure_mistakes(tmp_path: Path, text: str, message: str) -> None:
    err = error_of(write(tmp_path, text))
    assert message in err.message
    assert err.file == str(tmp_path / "p.yaml")


def test_known_nodes_are_ignored_not_errors(tmp_path: Path) -> None:
    path = write(
        tmp_path,
        "lifecycle_manager_navigation:\n  ros__parameters:\n    autostart: true\n"
        "controller_server_rclcpp_node:\n  ros__parameters:\n    use_sim_time: true\n",
    )
    ignored = {e.key: e for e in load_params(path).ignored}
    assert ignored["lifecycle_manager_navigation"].keys == ("autostart",)
    assert "older Nav2" in ignored["controller_server_rclcpp_node"].reason


def test_test_plugin_name_is_not_nav2s(inflation_plugin) -> None:
    assert "::" in TEST_INFLATION and not TEST_INFLATION.startswith("nav2_")


def _dwb_params(tmp_path: Path, **keys: object) -> Path:
    """Nav2's params with DWB, ObstacleFootprint for BaseObstacle, PreferForward and
    Twirling added, plus `keys`."""
    from ..nav.navstack_helpers import DWB_FOOTPRINT, params_with_controller

    critics = [*DWB_FOOTPRINT["critics"], "PreferForward", "Twirling"]
    return params_with_controller(tmp_path, {**DWB_FOOTPRINT, "critics": critics, **keys})


def test_a_misspelt_dwb_critic_key_names_its_line_and_the_right_spelling(tmp_path: Path) -> None:
    path = _dwb_params(tmp_path, **{"PreferForward.theta_scal": 5.0})
    err = error_of(path)
    assert path.read_text().splitlines()[err.line - 1].strip() == "PreferForward.theta_scal: 5.0"
    assert err.key == "controller_server.FollowPath.PreferForward.theta_scal"
    assert err.suggestion == "theta_scale"
    assert "unknown key 'theta_scal' for critic PreferForward" in str(err)


def test_a_misspelt_dwb_critic_name_in_a_key_suggests_the_listed_critic(tmp_path: Path) -> None:
    path = _dwb_params(tmp_path, **{"PrefrForward.penalty": 2.0})
    err = error_of(path)
    assert path.read_text().splitlines()[err.line - 1].strip() == "PrefrForward.penalty: 2.0"
    assert (err.key, err.suggestion) == (
        "controller_server.FollowPath.PrefrForward",
        "PreferForward",
    )


def test_a_bad_dwb_critic_value_names_its_key(tmp_path: Path) -> None:
    err = error_of(_dwb_params(tmp_path, **{"Twirling.scale": "high"}))
    assert err.key == "controller_server.FollowPath.Twirling.scale"
    assert "valid number" in err.message


def test_keys_of_a_dwb_critic_left_out_of_the_list_are_ignored_as_in_nav2(tmp_path: Path) -> None:
    params = load_params(_dwb_params(tmp_path, **{"BaseObstacle.scale": 0.02}))
    section = params.server("controller_server").plugins["FollowPath"].params
    assert "BaseObstacle" not in section.critic_params
    assert section.critic_params["PreferForward"].theta_scale == 10.0
    ignored = {e.key: e.reason for e in params.ignored}
    assert "not used" in ignored["controller_server.FollowPath.BaseObstacle"]
