"""The mission file: what it accepts, and a located error with a suggestion for every mistake."""

from __future__ import annotations

import warnings
from pathlib import Path

import pytest

from btnav.core.errors import BtnavError, BtnavWarning, FrameError, ParamsError
from btnav.mission import Mission, MissionError

from .missions import MAP, PARAMS, REPO, TOUR, WORLD, write_mission


def error_of(path: Path, **kw) -> BtnavError:
    with pytest.raises(BtnavError) as info:
        Mission.load(path, **kw).navigator()
    return info.value


def test_the_demo_mission_loads_with_nav2s_params_unchanged():
    m = Mission.load(TOUR)
    assert m.name == "office_tour" and m.seed == 0 and m.task == "follow_waypoints"
    assert len(m.spec.task.poses) == 4
    assert m.params.path.name == "nav2_params.yaml"
    assert m.spec.outputs == ["report", "trajectory", "bt_log"]
    assert m.tree is None  # bt_navigator's default tree


def test_paths_are_relative_to_the_mission_and_defaults_fill_the_rest(tmp_path):
    (tmp_path / "sub").mkdir()
    (tmp_path / "world.yaml").write_text(WORLD.read_text())
    path = write_mission(tmp_path / "sub", world="../world.yaml", task={"navigate_to_pose": [3, 2]})
    m = Mission.load(path)
    assert m.world.file == str(tmp_path / "world.yaml")
    assert m.spec.task.poses == [(3.0, 2.0, 0.0)]  # [x, y] means yaw 0
    assert m.spec.time_limit == 600 and m.spec.seed == 0
    nav = m.navigator()
    assert nav.robot_pose.x == 1.0  # the world's start pose


def test_a_misspelt_key_names_file_line_and_spelling(tmp_path):
    path = write_mission(tmp_path, task={"navigate_to_pose": [3, 2]}, tiem_limit=20)
    err = error_of(path)
    assert isinstance(err, MissionError)
    line = path.read_text().splitlines().index("tiem_limit: 20") + 1
    assert err.file == str(path) and err.line == line and err.key == "tiem_limit"
    assert err.suggestion == "time_limit"


def test_a_task_is_exactly_one_of_four(tmp_path):
    path = write_mission(
        tmp_path, task={"navigate_to_pose": [3, 2], "follow_waypoints": [[1, 2], [3, 2]]}
    )
    err = error_of(path)
    assert err.key == "task" and "exactly one of" in err.message
    assert "navigate_to_pose, follow_waypoints" in err.message
    err = error_of(write_mission(tmp_path, task={"folow_waypoints": [[1, 2]]}))
    assert err.key == "task.folow_waypoints" and err.suggestion == "follow_waypoints"
    err = error_of(write_mission(tmp_path, task={"navigate_to_pose": [3, "x", 0]}))
    assert err.key.startswith("task.navigate_to_pose")


def test_exploring_without_slam_is_a_mistake_named_at_the_localization_line(tmp_path):
    err = error_of(write_mission(tmp_path, task="explore", localization="amcl"))
    assert err.key == "localization" and "localization: slam" in err.message
    assert err.line is not None


def test_a_misspelt_output_names_the_closest(tmp_path):
    err = error_of(write_mission(tmp_path, outputs=["reprot"], task={"navigate_to_pose": [3, 2]}))
    assert err.suggestion == "report"


def test_missing_files_name_the_key_that_names_them(tmp_path):
    err = error_of(write_mission(tmp_path, map="nowhere.yaml", task={"navigate_to_pose": [3, 2]}))
    assert err.key == "map" and "not found" in err.message and err.line == 4
    doc = write_mission(tmp_path, task={"navigate_to_pose": [3, 2]})
    doc.write_text(doc.read_text().replace(f"map: {MAP}\n", ""))
    err = error_of(doc)
    assert err.key == "localization" and "needs a map" in err.message


def test_a_start_pose_in_the_table_names_the_missions_line(tmp_path):
    path = write_mission(tmp_path, initial_pose=[6.5, 1.2, 0.0], task={"navigate_to_pose": [3, 2]})
    err = error_of(path)
    assert err.file == str(path) and err.key == "initial_pose"
    assert "overlaps" in err.message and str(WORLD) in err.message


def test_an_initial_pose_moves_the_robot(tmp_path):
    path = write_mission(tmp_path, initial_pose=[2.0, 1.0, 1.0], task={"navigate_to_pose": [3, 2]})
    nav = Mission.load(path).navigator()
    assert (nav.robot_pose.x, nav.robot_pose.y, nav.robot_pose.yaw) == (2.0, 1.0, 1.0)
    assert nav.runtime.robot_pose().x == pytest.approx(2.0)  # map -> base_footprint agrees


def test_a_tree_is_a_bundled_name_or_a_file_and_mistakes_point_into_it(tmp_path, nav2_dir):
    ok = write_mission(
        tmp_path, tree="navigate_w_replanning_time", task={"navigate_to_pose": [3, 2]}
    )
    assert Mission.load(ok).tree.endswith("navigate_w_replanning_time.yaml")
    err = error_of(
        write_mission(
            tmp_path, tree="navigate_to_pose_w_replaning", task={"navigate_to_pose": [3, 2]}
        )
    )
    assert err.key == "tree" and err.suggestion == "navigate_to_pose_w_replanning_and_recovery"
    xml = (
        nav2_dir / "behavior_trees" / "navigate_to_pose_w_replanning_and_recovery.xml"
    ).read_text()
    bad = tmp_path / "bad.xml"
    bad.write_text(xml.replace("ComputePathToPose goal=", "ComputePathToPose gaol="))
    err = error_of(write_mission(tmp_path, tree=str(bad), task={"navigate_to_pose": [3, 2]}))
    assert err.file == str(bad) and err.line is not None and err.suggestion == "goal"


def test_set_overrides_the_mission_and_the_params(tmp_path):
    m = Mission.load(
        TOUR,
        seed=4,
        overrides={
            "mission.time_limit": 12,
            "local_costmap.local_costmap.inflation_layer.inflation_radius": 0.4,
        },
    )
    assert m.seed == 4 and m.spec.time_limit == 12
    inflation = m.params.server("local_costmap").plugins["inflation_layer"].params
    assert inflation.inflation_radius == 0.4
    with pytest.raises(MissionError) as info:
        Mission.load(TOUR, overrides={"mission.time_limt": 3})
    assert info.value.suggestion == "time_limit" and info.value.file == "--set mission.time_limt=3"
    with pytest.raises(ParamsError) as info:
        Mission.load(TOUR, overrides={"controller_server.controller_frequncy": 3})
    assert info.value.suggestion == "controller_frequency"
    assert info.value.file == "--set controller_server.controller_frequncy=3"


def test_a_frame_the_params_name_must_be_in_the_robots_tree(tmp_path):
    params = tmp_path / "params.yaml"
    text = PARAMS.read_text()
    params.write_text(text.replace("robot_base_frame: base_link", "robot_base_frame: base_lnk", 1))
    line = text.splitlines().index("    robot_base_frame: base_link") + 1
    path = write_mission(tmp_path, params=str(params), task={"navigate_to_pose": [3, 2]})
    err = error_of(path)
    assert isinstance(err, FrameError)
    assert err.key == "bt_navigator.robot_base_frame" and err.suggestion == "base_link"
    assert err.file == str(params) and err.line == line


def test_a_value_given_by_set_is_blamed_on_the_set_not_on_a_file_line():
    """What `btnav run --set` prints: `--set KEY=VALUE: key: message`, no file line."""
    err = error_of(TOUR, overrides={"bt_navigator.robot_base_frame": "base_lnk"})
    assert isinstance(err, FrameError) and err.suggestion == "base_link"
    assert str(err).startswith(
        "--set bt_navigator.robot_base_frame=base_lnk: bt_navigator.robot_base_frame: "
        "frame 'base_lnk' is not in the robot's frame tree"
    )
    assert err.line is None
    # The option as typed, when the caller knows it (the CLI does).
    err = error_of(
        TOUR,
        overrides={"controller_server.controller_frequency": -3.0},
        origins={
            "controller_server.controller_frequency": "--set controller_server.controller_frequency=-3.0"
        },
    )
    assert isinstance(err, ParamsError) and err.line is None
    assert str(err) == (
        "--set controller_server.controller_frequency=-3.0: controller_server.controller_frequency:"
        " Input should be greater than 0 (got -3.0)"
    )
    err = error_of(TOUR, overrides={"mission.tree": "navigate_w_replanning_tme"})
    assert err.file == "--set mission.tree=navigate_w_replanning_tme" and err.key == "tree"
    assert err.suggestion == "navigate_w_replanning_time"
    err = error_of(TOUR, overrides={"mission.world": "no_world.yaml"})
    assert err.file == "--set mission.world=no_world.yaml" and err.line is None
    err = error_of(TOUR, overrides={"mission.initial_pose": [6.5, 1.2]})
    assert err.file == "--set mission.initial_pose=[6.5, 1.2]"
    assert "is inside an obstacle of the map" in str(err)
    err = error_of(TOUR, seed=-1)
    assert str(err).startswith("--seed -1: seed: ")


def test_a_task_pose_in_an_obstacle_or_off_the_map_is_a_warning(tmp_path):
    path = write_mission(
        tmp_path, task={"follow_waypoints": [[3.0, 2.0], [6.5, 1.2, 0.0], [-3, 2]]}
    )
    lines = path.read_text().splitlines()
    with pytest.warns(BtnavWarning) as caught:
        Mission.load(path)
    warned = [w.message for w in caught if isinstance(w.message, BtnavWarning)]
    assert [(w.file, w.line, w.key) for w in warned] == [
        (str(path), lines.index("  - - 6.5") + 1, "task.follow_waypoints[1]"),
        (str(path), lines.index("  - - -3") + 1, "task.follow_waypoints[2]"),
    ]
    assert warned[0].message == (
        f"task pose [6.5, 1.2, 0] is inside an obstacle of the map ({MAP}); "
        "Nav2 will try it and fail"
    )
    assert warned[1].message.startswith(f"task pose [-3, 2, 0] is outside the map ({MAP} covers")
    with warnings.catch_warnings():
        warnings.simplefilter("error")  # the demo's poses are all free
        Mission.load(TOUR)
    with pytest.warns(BtnavWarning) as caught:  # a pose given by --set is placed there
        Mission.load(TOUR, overrides={"mission.task": {"navigate_to_pose": [6.5, 1.2]}})
    assert str(caught[0].message).startswith(
        '--set mission.task={"navigate_to_pose": [6.5, 1.2]}: task.navigate_to_pose: '
    )


def test_a_file_given_by_set_is_relative_to_the_current_directory(tmp_path, monkeypatch):
    """`btnav run missions/x.yaml --set mission.params=params/y.yaml` from the repository
    root names the repository's params/y.yaml, as any path typed on a command line."""
    monkeypatch.chdir(REPO)
    m = Mission.load(
        TOUR,
        overrides={
            "mission.params": "params/nav2_params_dwb.yaml",
            "mission.tree": "navigate_w_replanning_time",
        },
    )
    assert m.params.path == REPO / "params" / "nav2_params_dwb.yaml"
    assert m.tree is not None and Path(m.tree).stem == "navigate_w_replanning_time"  # bundled
    monkeypatch.chdir(tmp_path)
    err = error_of(TOUR, overrides={"mission.params": "params/nav2_params_dwb.yaml"})
    assert err.file == "--set mission.params=params/nav2_params_dwb.yaml"
    assert str(tmp_path / "params" / "nav2_params_dwb.yaml") in str(err)


def test_a_misspelt_localization_names_the_closest(tmp_path):
    err = error_of(write_mission(tmp_path, localization="acml", task={"navigate_to_pose": [3, 2]}))
    assert err.key == "localization" and err.suggestion == "amcl" and err.line is not None


USER_LOCALIZER = '''
from btnav.localization.ground_truth import GroundTruthLocalizer
from btnav.plugins import register


@register("localizer", "my_pkg/OracleLocalizer")
class OracleLocalizer(GroundTruthLocalizer):
    """A user's localiser: here the ground truth under another name."""
'''


def test_a_users_localizer_from_the_missions_plugins_is_a_peer_of_amcl(tmp_path):
    (tmp_path / "oracle.py").write_text(USER_LOCALIZER)
    path = write_mission(
        tmp_path,
        localization="my_pkg/OracleLocalizer",
        plugins=["oracle.py"],
        task={"navigate_to_pose": [3, 2]},
    )
    nav = Mission.load(path).navigator()
    assert type(nav.runtime.localizer).__name__ == "OracleLocalizer"
