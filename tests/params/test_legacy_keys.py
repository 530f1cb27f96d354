"""Keys Nav2 itself skips (ROS 1 names, older distributions' names, BT ports) are one
warning each and the run goes on as Nav2's; a near miss of a real key stays an error."""

from __future__ import annotations

import fnmatch
from pathlib import Path

import pytest

from btnav import plugins as registry
from btnav.cli import main
from btnav.cli.params import check_main
from btnav.control.dwb.local_planner import DWBParams
from btnav.core.errors import BtnavWarning, ParamsError
from btnav.mission.mission import Mission
from btnav.params import apply_overrides, load_params, validate_update
from btnav.params.legacy_keys import CATALOGUE, Family, legacy_key
from btnav.params.servers import SERVERS

from .tutorial import SKIPPED, line_of

REPO = Path(__file__).resolve().parents[2]


def warned(path: Path) -> tuple[object, list[BtnavWarning]]:
    """The loaded file and the warnings loading it gave, in order."""
    with pytest.warns(BtnavWarning) as caught:
        params = load_params(path)
    return params, [w.message for w in caught if isinstance(w.message, BtnavWarning)]


def only(path: Path) -> BtnavWarning:
    _, warnings = warned(path)
    assert len(warnings) == 1, [str(w) for w in warnings]
    return warnings[0]


def error_of(path: Path) -> ParamsError:
    with pytest.raises(ParamsError) as info:
        load_params(path)
    return info.value


# -- the tutorial's sections, pasted into Nav2's file ----------------------------------------


def test_tutorial_file_checks_with_one_warning_per_skipped_key(tutorial_params, capsys):
    assert check_main(tutorial_params) == 0
    captured = capsys.readouterr()
    lines = captured.err.splitlines()
    assert len(lines) == len(SKIPPED) == 13
    for line, (key, _) in zip(lines, SKIPPED, strict=True):
        where = f"btnav: warning: {tutorial_params}:{line_of(tutorial_params, key)}: {key}: "
        assert line.startswith(where), line
        assert "Nav2 ignores it too" in line
    assert "13 keys Nav2 skips too" in captured.out.splitlines()[-1]


def test_tutorial_warnings_name_the_current_equivalent(tutorial_params, capsys):
    check_main(tutorial_params)
    err = capsys.readouterr().err
    assert "goal_checker_plugin: Nav2 Foxy's name" in err
    assert "(current equivalent: goal_checker_plugins)" in err
    assert "min_rot_vel: a ROS 1 dwa_local_planner name" in err
    assert "(current equivalent: min_speed_theta)" in err
    assert "(current equivalent: max_vel_theta)" in err
    assert "spin_dist: a port of the Spin BT node" in err
    assert '(set it in the tree: <Spin spin_dist="1.57"/>)' in err
    assert '(set it in the tree: <BackUp backup_speed="0.025"/>)' in err


def test_tutorial_file_through_the_cli(tutorial_params, capsys):
    assert main(["params", "check", str(tutorial_params)]) == 0
    err = capsys.readouterr().err.splitlines()
    assert len(err) == 13 and all(line.startswith("btnav: warning: ") for line in err)


def test_tutorial_file_fails_a_strict_check_naming_file_and_line(tutorial_params, capsys):
    assert check_main(tutorial_params, strict=True) == 2
    captured = capsys.readouterr()
    assert captured.out == ""
    (line,) = captured.err.splitlines()
    first = SKIPPED[0][0]
    assert line.startswith(
        f"btnav: error: {tutorial_params}:{line_of(tutorial_params, first)}: {first}: "
    )
    assert line.endswith("(--strict makes a key Nav2 skips an error; 12 more keys Nav2 skips)")


def test_tutorial_file_loads_as_nav2_reads_it(tutorial_params):
    params, warnings = warned(tutorial_params)
    assert [(w.key, w.line) for w in warnings] == [
        (key, line_of(tutorial_params, key)) for key, _ in SKIPPED
    ]
    assert [s.family for s in params.skipped] == [family for _, family in SKIPPED]
    controller = params.server("controller_server")
    # Neither singular key is read: Nav2's default lists and types run.
    assert controller.model.goal_checker_plugins == ["goal_checker"]
    assert controller.plugins["goal_checker"].type == "nav2_controller::SimpleGoalChecker"
    assert controller.plugins["progress_checker"].defaulted
    dwb = controller.plugins["FollowPath"].params
    assert (dwb.min_vel_x, dwb.max_vel_x, dwb.vtheta_samples) == (-0.3, 0.3, 40)
    # max_rot_vel: 0.5 is not max_vel_theta: Nav2's default for a limit left out, 0.0, stays.
    assert dwb.max_vel_theta == 0.0
    behaviors = params.server("behavior_server")
    assert list(behaviors.plugins) == ["Spin", "BackUp", "Wait"]
    # The skipped keys are out of the section as kept, so set_parameters re-validates it.
    assert "spin_dist" not in behaviors.doc["Spin"]
    updated = validate_update(params, "behavior_server", {"cycle_frequency": 5.0})
    assert updated.model.cycle_frequency == 5.0


# -- one family at a time --------------------------------------------------------------------


def test_ros1_amcl_name_is_skipped_and_nav2s_default_runs(nav2_copy):
    path, line = nav2_copy("    alpha1: 0.2", "    odom_alpha1: 0.9")
    params, (warning,) = warned(path)
    assert (warning.line, warning.key) == (line, "amcl.odom_alpha1")
    assert "a ROS 1 amcl name; Nav2 ignores it too (current equivalent: alpha1)" in str(warning)
    assert params.server("amcl").model.alpha1 == 0.2  # Nav2's default, not the 0.9 written


def test_ros1_move_base_names(nav2_copy):
    path, line = nav2_copy(
        "    controller_frequency: 20.0",
        "    controller_frequency: 20.0\n    base_local_planner: dwa_local_planner/DWAPlannerROS",
    )
    warning = only(path)
    assert (warning.line, warning.key) == (line + 1, "controller_server.base_local_planner")
    assert "a ROS 1 move_base name" in str(warning) and "FollowPath.plugin" in str(warning)


def test_ros1_move_base_node_at_the_top(nav2_params_file, tmp_path):
    path = tmp_path / "p.yaml"
    text = nav2_params_file.read_text()
    path.write_text(text + "move_base:\n  ros__parameters:\n    controller_frequency: 5.0\n")
    params, (warning,) = warned(path)
    assert (warning.line, warning.key) == (len(text.splitlines()) + 1, "move_base")
    assert "Nav2 has none of that name" in str(warning) and "bt_navigator" in str(warning)
    assert params.server("controller_server").model.controller_frequency == 20.0


def test_ros1_dwa_names_in_a_dwb_section(tmp_path):
    from ..nav.navstack_helpers import DWB, params_with_controller

    path = params_with_controller(tmp_path, {**DWB, "max_rot_vel": 0.4, "acc_lim_th": 1.0})
    params, warnings = warned(path)
    assert [w.key for w in warnings] == [
        "controller_server.FollowPath.max_rot_vel",
        "controller_server.FollowPath.acc_lim_th",
    ]
    assert "current equivalent: acc_lim_theta" in str(warnings[1])
    section = params.server("controller_server").plugins["FollowPath"].params
    assert section.max_vel_theta == DWB.get("max_vel_theta", DWBParams().max_vel_theta) != 0.4


@pytest.mark.parametrize(
    ("before", "added", "key", "equivalent"),
    [
        (
            "    controller_plugins:",
            "    goal_checker_plugin: general_goal_checker",
            "controller_server.goal_checker_plugin",
            "goal_checker_plugins",
        ),
        (
            "    behavior_plugins:",
            "    recovery_plugins: [spin]",
            "behavior_server.recovery_plugins",
            "behavior_plugins",
        ),
        (
            "    error_code_name_prefixes:",
            "    default_bt_xml_filename: my_tree.xml",
            "bt_navigator.default_bt_xml_filename",
            "default_nav_to_pose_bt_xml",
        ),
    ],
)
def test_names_renamed_between_nav2_distributions(nav2_copy, before, added, key, equivalent):
    path, line = nav2_copy(before, f"{added}\n{before}")  # `added` takes the line
    warning = only(path)
    assert (warning.line, warning.key) == (line, key)
    assert "Nav2 ignores it too" in str(warning)
    assert f"(current equivalent: {equivalent})" in str(warning)


def test_renamed_node_at_the_top_is_skipped_and_behavior_server_keeps_its_own(nav2_copy):
    path, line = nav2_copy("behavior_server:", "recoveries_server:")
    params, (warning,) = warned(path)
    assert (warning.line, warning.key) == (line, "recoveries_server")
    assert "current equivalent: behavior_server" in str(warning)
    # Nav2's defaults run: its four behaviour names, none of the section's settings.
    server = params.server("behavior_server")
    assert not server.in_file
    assert list(server.plugins) == ["spin", "backup", "drive_on_heading", "wait"]


def test_bt_ports_in_the_behavior_servers_own_section(nav2_copy):
    path, line = nav2_copy(
        "    simulate_ahead_time: 2.0", "    simulate_ahead_time: 2.0\n    backup_dist: 0.3"
    )
    warning = only(path)
    assert (warning.line, warning.key) == (line + 1, "behavior_server.backup_dist")
    assert str(warning).endswith(
        "a port of the BackUp BT node, which the behavior_server does not read; Nav2 ignores "
        'it too (set it in the tree: <BackUp backup_dist="0.3"/>)'
    )


def test_bt_port_of_followpath_in_the_controller_server(nav2_copy):
    path, _ = nav2_copy(
        "    controller_frequency: 20.0",
        "    controller_frequency: 20.0\n    controller_id: FollowPath",
    )
    warning = only(path)
    assert warning.key == "controller_server.controller_id"
    assert "a port of the FollowPath BT node, which controller_server does not read" in str(warning)


def test_a_key_read_by_another_server(nav2_copy):
    path, line = nav2_copy(
        "      update_frequency: 5.0", "      controller_frequency: 5.0", count=1
    )
    warning = only(path)
    assert (warning.line, warning.key) == (line, "local_costmap.local_costmap.controller_frequency")
    assert "current equivalent: controller_server.controller_frequency" in str(warning)


# -- near misses, refusals and what no catalogue knows ---------------------------------------


def test_a_near_miss_stays_an_error_with_did_you_mean(nav2_copy):
    path, line = nav2_copy("controller_frequency: 20.0", "controller_frequncy: 20.0")
    err = error_of(path)
    assert (err.line, err.key, err.suggestion) == (
        line,
        "controller_server.controller_frequncy",
        "controller_frequency",
    )


def test_a_near_miss_in_a_plugin_section_stays_an_error(tutorial_params):
    text = tutorial_params.read_text().replace("      vx_samples: 20", "      vx_sample: 20")
    tutorial_params.write_text(text)
    err = error_of(tutorial_params)
    assert (err.key, err.suggestion) == ("controller_server.FollowPath.vx_sample", "vx_samples")


def test_the_catalogue_wins_over_did_you_mean():
    # Both are within did-you-mean of a real key; both are names Nav2 used to read.
    assert legacy_key("controller_server", "goal_checker_plugin").family is Family.RENAMED
    assert legacy_key("controller:dwb_core/DWBLocalPlanner", "trans_stopped_vel") is not None


def test_a_key_no_catalogue_knows_and_no_key_is_close_to(nav2_copy):
    path, line = nav2_copy(
        "    controller_frequency: 20.0", "    controller_frequency: 20.0\n    my_own_key: 3"
    )
    warning = only(path)
    assert (warning.line, warning.key) == (line + 1, "controller_server.my_own_key")
    assert str(warning).endswith(
        "unknown key 'my_own_key' (not a parameter controller_server reads); Nav2 ignores it too"
    )


def test_a_node_no_one_knows_at_the_top_is_skipped(nav2_params_file, tmp_path):
    path = tmp_path / "p.yaml"
    path.write_text(
        nav2_params_file.read_text() + "ekf_filter_node:\n  ros__parameters:\n    frequency: 30.0\n"
    )
    warning = only(path)
    assert warning.key == "ekf_filter_node" and "not a Nav2 node" in str(warning)


@pytest.mark.parametrize(
    ("old", "new", "key", "words"),
    [
        (
            "    error_code_name_prefixes:",
            "    error_code_names: [compute_path_error_code]\n    error_code_name_prefixes:",
            "bt_navigator.error_code_names",
            "Nav2 refuses to start with it (current equivalent: error_code_name_prefixes)",
        ),
        (
            '      plugin: "nav2_behaviors::Spin"',
            '      plugin: "nav2_recoveries::Spin"',
            "behavior_server.spin.plugin",
            "Nav2 cannot load that plugin any more (it stops at start-up): "
            "write nav2_behaviors::Spin",
        ),
        (
            '    robot_model_type: "nav2_amcl::DifferentialMotionModel"',
            '    robot_model_type: "differential"',
            "amcl.robot_model_type",
            "write nav2_amcl::DifferentialMotionModel",
        ),
    ],
)
def test_old_names_nav2_refuses_are_errors_naming_the_new_one(nav2_copy, old, new, key, words):
    path, line = nav2_copy(old, new)
    err = error_of(path)
    assert err.key == key and err.line in (line, line + 1)
    assert words in err.message


# -- overrides, strict missions ----------------------------------------------------------------


def test_set_of_a_key_nav2_skips_is_an_error(nav2_params_file):
    params = load_params(nav2_params_file)
    with pytest.raises(ParamsError) as info:
        apply_overrides(params, {"controller_server.goal_checker_plugin": "x"})
    assert info.value.message.startswith("unknown key 'goal_checker_plugin', which Nav2 does not")
    assert "(value given by --set)" in info.value.message
    with pytest.raises(ParamsError, match="set_parameters"):
        validate_update(params, "behavior_server", {"spin_dist": 1.0})


def test_strict_params_in_a_mission_makes_a_skipped_key_an_error(tutorial_params, tmp_path):
    from ..mission.missions import write_mission

    mission = write_mission(
        tmp_path, params=str(tutorial_params), strict_params=True, task={"navigate_to_pose": [3, 2]}
    )
    with pytest.raises(ParamsError) as info:
        Mission.load(mission)
    first = SKIPPED[0][0]
    assert (info.value.file, info.value.line, info.value.key) == (
        str(tutorial_params),
        line_of(tutorial_params, first),
        first,
    )
    assert f"strict_params: true in {mission} makes a key Nav2 skips an error" in info.value.message


# -- the catalogue itself ----------------------------------------------------------------------


def _models_in_scope(pattern: str) -> list[type]:
    if pattern == "/":
        return []
    if ":" not in pattern:
        return [SERVERS[pattern].model]
    kind, type_glob = pattern.split(":", 1)
    registry.load_entry_points()
    return [
        getattr(registry.lookup(kind, name), "Params", None)
        for name in registry.names(kind)
        if fnmatch.fnmatchcase(registry.canonical(name), type_glob)
    ]


def test_every_catalogue_entry_names_a_key_its_section_does_not_have():
    """An entry for a key the section's model has would never be looked up."""
    live = []
    for entry in CATALOGUE:
        for pattern in entry.scopes:
            for model in _models_in_scope(pattern):
                if model is not None:
                    live.append((entry.name, pattern, entry.name in model.model_fields))
    assert live and [x for x in live if x[2]] == []


def test_every_family_is_in_the_catalogue():
    assert {e.family for e in CATALOGUE} == set(Family)


@pytest.mark.parametrize("name", sorted(p.name for p in (REPO / "params").glob("*.yaml")))
def test_the_shipped_params_files_have_no_key_nav2_skips(name):
    assert load_params(REPO / "params" / name, strict="a shipped file").skipped == []
