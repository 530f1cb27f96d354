"""Nav2's own nav2_params.yaml loads unchanged, and `params check` says what btnav makes of it."""

from __future__ import annotations

from collections import Counter
from pathlib import Path

import pytest

from btnav.cli.params import check_main, check_report
from btnav.core.resources import bundled_dir
from btnav.params import load_params

IMPLEMENTED = {
    "amcl",
    "bt_navigator",
    "controller_server",
    "local_costmap",
    "global_costmap",
    "map_server",
    "map_saver",
    "planner_server",
    "smoother_server",
    "behavior_server",
    "waypoint_follower",
    "velocity_smoother",
    "collision_monitor",
    "docking_server",
    "keepout_filter_mask_server",
    "keepout_costmap_filter_info_server",
    "speed_filter_mask_server",
    "speed_costmap_filter_info_server",
    "route_server",
}


@pytest.fixture(scope="module")
def nav2(nav2_params_file: Path):
    return load_params(nav2_params_file)


def test_every_implemented_server_is_loaded(nav2) -> None:
    assert set(nav2.servers) == IMPLEMENTED
    assert nav2.server("controller_server").model.controller_frequency == 20.0
    assert nav2.server("local_costmap").model.rolling_window is True
    assert nav2.server("local_costmap").key == "local_costmap.local_costmap"
    assert nav2.server("amcl").model.max_particles == 2000
    assert nav2.server("velocity_smoother").model.max_velocity == [0.5, 0.0, 2.0]


def test_plugin_sections_resolve_to_nav2_types(nav2) -> None:
    from btnav.behaviors.assisted_teleop import AssistedTeleop

    teleop = nav2.server("behavior_server").plugins["assisted_teleop"]
    assert (teleop.kind, teleop.type, teleop.cls) == (
        "behavior",
        "nav2_behaviors::AssistedTeleop",
        AssistedTeleop,
    )
    kinds = {p.kind for p in nav2.plugins()}
    assert kinds >= {
        "planner",
        "controller",
        "goal_checker",
        "progress_checker",
        "path_handler",
        "smoother",
        "behavior",
        "costmap_layer",
        "navigator",
        "waypoint_task_executor",
    }
    # The behavior list in the file (five names, assisted_teleop included) wins over Nav2's four.
    assert list(nav2.server("behavior_server").plugins) == [
        "spin",
        "backup",
        "drive_on_heading",
        "assisted_teleop",
        "wait",
    ]


def test_check_main_succeeds_and_reports(nav2_params_file: Path, capsys) -> None:
    assert check_main(nav2_params_file) == 0
    out = capsys.readouterr().out
    assert "assisted_teleop -> nav2_behaviors::AssistedTeleop: btnav.behaviors" in out
    assert "FollowPath -> nav2_mppi_controller::MPPIController" in out
    assert "GridBased -> nav2_navfn_planner::NavfnPlanner" in out
    assert "simple_charging_dock -> opennav_docking::SimpleChargingDock" in out
    assert "loopback_simulator" in out and "route_server" in out
    assert out.rstrip().splitlines()[-1].startswith(f"OK: {len(IMPLEMENTED)} servers")


def test_check_main_returns_2_with_one_line_on_a_mistake(nav2_copy, capsys) -> None:
    path, line = nav2_copy("controller_frequency: 20.0", "controller_frequncy: 20.0")
    assert check_main(path) == 2
    err = capsys.readouterr().err.strip()
    assert err == (
        f"btnav: error: {path}:{line}: controller_server.controller_frequncy: unknown key "
        "'controller_frequncy' (did you mean 'controller_frequency'?)"
    )


def test_ignored_entries_are_listed_once_each(nav2) -> None:
    counts = Counter(e.key for e in nav2.ignored)
    assert [k for k, n in counts.items() if n > 1] == []
    by_key = {e.key: e for e in nav2.ignored}
    # nav2_params.yaml's docking controller writes simulation_step; Nav2 reads simulation_time_step
    assert by_key["docking_server.controller.simulation_step"].line == 589
    assert by_key["controller_server.use_realtime_priority"].line == 104
    assert by_key["amcl.introspection_mode"].line == 34
    # Listed in neither plugins nor filters: Nav2 never loads it, and btnav says so.
    static = by_key["local_costmap.local_costmap.static_layer"]
    assert "not listed in plugins" in static.reason and static.line == 289
    # Costmap filters are run: their sections are read, not listed as ignored.
    assert "global_costmap.global_costmap.speed_filter" not in by_key


def test_keys_left_at_defaults_are_not_listed(nav2) -> None:
    # waypoint_follower sets introspection_mode but not use_sim_time: only the first is listed.
    keys = {e.key for e in nav2.ignored}
    assert "waypoint_follower.introspection_mode" in keys
    assert "waypoint_follower.use_sim_time" not in keys


def test_placeholders_resolve(nav2) -> None:
    dirs = nav2.server("bt_navigator").model.bt_search_directories
    assert dirs == [str(bundled_dir("trees"))]
    tokens = {(p.key, p.text) for p in nav2.placeholders}
    assert ("local_costmap.local_costmap.keepout_filter.enabled", "KEEPOUT_ZONE_ENABLED") in tokens
    assert ("global_costmap.global_costmap.speed_filter.enabled", "SPEED_ZONE_ENABLED") in tokens


def test_other_packages_shares_are_left_as_written(tmp_path: Path) -> None:
    path = tmp_path / "p.yaml"
    path.write_text(
        "bt_navigator:\n"
        "  ros__parameters:\n"
        "    bt_search_directories:\n"
        "      - $(find-pkg-share nav2_bt_navigator)\n"
        "      - $(find-pkg-share my_robot)/trees\n"
        "    default_nav_to_pose_bt_xml: $(find-pkg-share nav2_bt_navigator)/behavior_trees/x.xml\n"
    )
    model = load_params(path).server("bt_navigator").model
    trees = str(bundled_dir("trees"))
    assert model.bt_search_directories == [trees, "$(find-pkg-share my_robot)/trees"]
    assert model.default_nav_to_pose_bt_xml == trees + "/x.xml"


def test_report_is_the_same_text_check_main_prints(nav2_params_file: Path, capsys) -> None:
    report = check_report(nav2_params_file)
    check_main(nav2_params_file)
    assert capsys.readouterr().out.strip() == report.strip()
