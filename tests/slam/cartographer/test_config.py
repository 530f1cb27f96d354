"""A Cartographer user's .lua runs as cartographer_node runs it, and every mistake names its line."""

from __future__ import annotations

import math
from pathlib import Path

import pytest

from btnav.slam.cartographer.config import (
    DEFAULTS_DIR,
    CartographerConfigError,
    load_cartographer_config,
)

pytest.importorskip("lupa")  # the `cartographer` extra

REPO = Path(__file__).resolve().parents[3]

# turtlebot3_cartographer's turtlebot3_lds_2d.lua, the seeds' typical file (tracking_frame adapted).
TURTLEBOT3 = """\
include "map_builder.lua"
include "trajectory_builder.lua"

options = {
  map_builder = MAP_BUILDER,
  trajectory_builder = TRAJECTORY_BUILDER,
  map_frame = "map",
  tracking_frame = "base_link",
  published_frame = "odom",
  odom_frame = "odom",
  provide_odom_frame = false,
  publish_frame_projected_to_2d = true,
  use_odometry = true,
  use_nav_sat = false,
  use_landmarks = false,
  num_laser_scans = 1,
  num_multi_echo_laser_scans = 0,
  num_subdivisions_per_laser_scan = 1,
  num_point_clouds = 0,
  lookup_transform_timeout_sec = 0.2,
  submap_publish_period_sec = 0.3,
  pose_publish_period_sec = 5e-3,
  trajectory_publish_period_sec = 30e-3,
  rangefinder_sampling_ratio = 1.,
  odometry_sampling_ratio = 1.,
  fixed_frame_pose_sampling_ratio = 1.,
  imu_sampling_ratio = 1.,
  landmarks_sampling_ratio = 1.,
}

MAP_BUILDER.use_trajectory_builder_2d = true

TRAJECTORY_BUILDER_2D.min_range = 0.12
TRAJECTORY_BUILDER_2D.max_range = 3.5
TRAJECTORY_BUILDER_2D.missing_data_ray_length = 3.
TRAJECTORY_BUILDER_2D.use_imu_data = false
TRAJECTORY_BUILDER_2D.use_online_correlative_scan_matching = true
TRAJECTORY_BUILDER_2D.motion_filter.max_angle_radians = math.rad(0.1)

POSE_GRAPH.constraint_builder.min_score = 0.65
POSE_GRAPH.constraint_builder.global_localization_min_score = 0.7

-- POSE_GRAPH.optimize_every_n_nodes = 0

return options
"""


def write(folder: Path, text: str, name: str = "my_robot.lua") -> Path:
    path = folder / name
    path.write_text(text)
    return path


def line_of(text: str, needle: str) -> int:
    """The 1-based line of the first line containing `needle` (what the error must name)."""
    return next(i for i, line in enumerate(text.splitlines(), 1) if needle in line)


def error_of(folder: Path, text: str, **kwargs) -> CartographerConfigError:
    path = write(folder, text)
    with pytest.raises(CartographerConfigError) as info:
        load_cartographer_config(path, **kwargs)
    return info.value


def test_the_shipped_configuration_gives_btnavs_robot_its_values():
    config = load_cartographer_config(REPO / "params" / "cartographer_2d.lua")
    assert config.ignored == []
    assert config.frames.tracking_frame == "base_link"
    assert config.frames.published_frame == "odom" and config.frames.use_odometry
    assert not config.frames.provide_odom_frame
    tb = config.trajectory_builder_2d
    assert (tb.min_range, tb.max_range, tb.missing_data_ray_length) == (0.12, 8.0, 8.0)
    assert tb.use_online_correlative_scan_matching
    assert tb.motion_filter.max_angle_radians == pytest.approx(math.radians(1.0))
    assert tb.submaps.resolution == 0.05 and tb.submaps.num_range_data == 90
    assert (tb.submaps.hit_probability, tb.submaps.miss_probability) == (0.55, 0.49)
    assert tb.real_time_correlative_scan_matcher.angular_search_window == pytest.approx(
        math.radians(20.0)
    )
    pg = config.pose_graph
    assert pg.constraint_builder.min_score == 0.65
    assert pg.constraint_builder.global_localization_min_score == 0.7
    assert pg.constraint_builder.fast_correlative_scan_matcher.branch_and_bound_depth == 7
    assert pg.optimize_every_n_nodes == 90 and pg.optimization_problem.huber_scale == 10.0
    # The whole table is there as Python, typed as Cartographer reads it.
    assert config.options["map_builder"]["pose_graph"]["global_sampling_ratio"] == 0.003
    assert isinstance(config.options["trajectory_builder"]["trajectory_builder_2d"]["max_z"], float)


def test_the_turtlebot3_file_loads_and_lists_only_what_btnav_would_not_do(tmp_path):
    config = load_cartographer_config(write(tmp_path, TURTLEBOT3))
    assert config.trajectory_builder_2d.max_range == 3.5
    assert config.trajectory_builder_2d.motion_filter.max_angle_radians == pytest.approx(
        math.radians(0.1)
    )
    # use_nav_sat = false, use_imu_data = false, sampling ratios 1: all what btnav does.
    assert config.ignored == []
    asks_more = TURTLEBOT3.replace("use_nav_sat = false", "use_nav_sat = true").replace(
        "return options",
        "POSE_GRAPH.optimization_problem.log_solver_summary = true\n"
        "TRAJECTORY_BUILDER.pure_localization_trimmer = { max_submaps_to_keep = 3 }\n"
        "TRAJECTORY_BUILDER_3D.num_accumulated_range_data = 2\n"
        "return options",
    )
    config = load_cartographer_config(write(tmp_path, asks_more))
    assert config.ignored == [
        "POSE_GRAPH.optimization_problem.log_solver_summary",
        "TRAJECTORY_BUILDER.pure_localization_trimmer",
        "TRAJECTORY_BUILDER_3D.num_accumulated_range_data",
        "use_nav_sat",
    ]


def test_an_include_is_found_in_the_files_folder_before_btnavs_defaults(tmp_path):
    own = (DEFAULTS_DIR / "trajectory_builder_2d.lua").read_text()
    write(tmp_path, own.replace("num_range_data = 90", "num_range_data = 35"), "trajectory_builder_2d.lua")  # fmt: skip
    config = load_cartographer_config(write(tmp_path, TURTLEBOT3))
    assert config.trajectory_builder_2d.submaps.num_range_data == 35
    # Extra directories come after the file's own folder and before the defaults.
    extra = tmp_path / "common"
    extra.mkdir()
    write(extra, "TRAJECTORY_BUILDER_2D.voxel_filter_size = 0.05\n", "common.lua")
    text = TURTLEBOT3.replace("return options", 'include "common.lua"\nreturn options')
    config = load_cartographer_config(write(tmp_path, text), search_dirs=[extra])
    assert config.trajectory_builder_2d.voxel_filter_size == 0.05


def test_a_misspelt_key_names_file_line_and_spelling(tmp_path):
    text = TURTLEBOT3.replace("return options", "TRAJECTORY_BUILDER_2D.max_rnage = 3.5\nreturn options")  # fmt: skip
    err = error_of(tmp_path, text)
    assert (err.file, err.line) == (str(tmp_path / "my_robot.lua"), line_of(text, "max_rnage"))
    assert err.key == "TRAJECTORY_BUILDER_2D.max_rnage" and err.suggestion == "max_range"
    assert f"my_robot.lua:{err.line}:" in str(err)

    text = TURTLEBOT3.replace('  tracking_frame = "base_link"', '  tracking_fame = "base_link"')
    err = error_of(tmp_path, text)
    assert err.line == line_of(text, "tracking_fame")
    assert (err.key, err.suggestion) == ("tracking_fame", "tracking_frame")


def test_a_misspelt_key_in_an_included_copy_of_the_defaults_names_that_copy(tmp_path):
    own = (DEFAULTS_DIR / "trajectory_builder_2d.lua").read_text()
    own = own.replace("hit_probability = 0.55", "hit_probabilty = 0.55")
    write(tmp_path, own, "trajectory_builder_2d.lua")
    err = error_of(tmp_path, TURTLEBOT3)
    assert err.file.endswith("trajectory_builder_2d.lua")
    assert err.line == line_of(own, "hit_probabilty") and err.suggestion == "hit_probability"


def test_a_key_in_the_wrong_table_says_where_it_belongs(tmp_path):
    text = TURTLEBOT3.replace("return options", "TRAJECTORY_BUILDER_2D.min_score = 0.6\nreturn options")  # fmt: skip
    err = error_of(tmp_path, text)
    assert err.line == line_of(text, "TRAJECTORY_BUILDER_2D.min_score")
    assert err.suggestion == "POSE_GRAPH.constraint_builder.min_score"


def test_a_wrong_type_or_range_names_the_line(tmp_path):
    text = TURTLEBOT3.replace("max_range = 3.5", 'max_range = "3.5"')
    err = error_of(tmp_path, text)
    assert err.line == line_of(text, 'max_range = "3.5"') and "must be a number" in err.message

    text = TURTLEBOT3.replace("min_score = 0.65", "min_score = 65")
    err = error_of(tmp_path, text)
    assert err.line == line_of(text, "min_score = 65") and "[0, 1]" in err.message

    text = TURTLEBOT3.replace("-- POSE_GRAPH.optimize_every_n_nodes = 0", "POSE_GRAPH.optimize_every_n_nodes = 2.5")  # fmt: skip
    err = error_of(tmp_path, text)
    assert (
        err.line == line_of(text, "optimize_every_n_nodes = 2.5") and "whole number" in err.message
    )


def test_a_3d_builder_is_refused_and_2d_must_be_switched_on(tmp_path):
    text = TURTLEBOT3.replace(
        "use_trajectory_builder_2d = true", "use_trajectory_builder_3d = true"
    )
    err = error_of(tmp_path, text)
    assert err.line == line_of(text, "use_trajectory_builder_3d") and "2D" in err.message
    err = error_of(tmp_path, TURTLEBOT3.replace("MAP_BUILDER.use_trajectory_builder_2d = true", ""))
    assert err.key == "MAP_BUILDER.use_trajectory_builder_2d"


def test_a_syntax_error_names_its_line_even_in_an_included_file(tmp_path):
    text = TURTLEBOT3.replace('  odom_frame = "odom",', '  odom_frame = "odom"')
    err = error_of(tmp_path, text)
    # Lua notices at the next key, the line after the missing comma.
    assert err.line == line_of(text, "provide_odom_frame") and err.file.endswith("my_robot.lua")

    write(tmp_path, "TRAJECTORY_BUILDER_2D.max_range = = 3\n", "broken.lua")
    err = error_of(tmp_path, TURTLEBOT3.replace("return options", 'include "broken.lua"\nreturn options'))  # fmt: skip
    assert err.file == str(tmp_path / "broken.lua") and err.line == 1


def test_a_missing_include_names_the_including_line(tmp_path):
    text = TURTLEBOT3.replace('include "trajectory_builder.lua"', 'include "trajectory_bulder.lua"')
    err = error_of(tmp_path, text)
    assert err.line == 2 and err.file == str(tmp_path / "my_robot.lua")
    assert err.suggestion == "trajectory_builder.lua"


def test_a_file_included_twice_is_refused_as_cartographer_does(tmp_path):
    text = TURTLEBOT3.replace("return options", 'include "pose_graph.lua"\nreturn options')
    err = error_of(tmp_path, text)
    assert err.line == line_of(text, 'include "pose_graph.lua"') and "twice" in err.message


@pytest.mark.parametrize(
    "code",
    ['os.execute("touch PWNED")', 'io.open("PWNED", "w")', 'require("os")', 'dofile("x.lua")'],
)
def test_the_sandbox_has_no_os_io_or_file_loading(tmp_path, monkeypatch, code):
    monkeypatch.chdir(tmp_path)
    text = TURTLEBOT3.replace("return options", f"{code}\nreturn options")
    err = error_of(tmp_path, text)
    assert err.line == line_of(text, code) and "not available" in err.message
    assert not (tmp_path / "PWNED").exists()


def test_an_endless_loop_is_stopped_at_its_line(tmp_path):
    text = TURTLEBOT3.replace("return options", "while true do\nend\nreturn options")
    err = error_of(tmp_path, text)
    assert err.line in (line_of(text, "while true"), line_of(text, "while true") + 1)


def test_a_file_that_returns_nothing_or_lacks_keys_says_so(tmp_path):
    err = error_of(tmp_path, TURTLEBOT3.replace("return options", ""))
    assert "return options" in err.message
    text = TURTLEBOT3.replace("  use_odometry = true,\n", "")
    err = error_of(tmp_path, text)
    assert err.key == "use_odometry" and "missing" in err.message
    with pytest.raises(CartographerConfigError) as info:
        load_cartographer_config(tmp_path / "my_robt.lua")
    assert info.value.suggestion == "my_robot.lua"


def test_the_filters_and_solver_limits_btnav_acts_on_are_typed_not_ignored(tmp_path):
    text = TURTLEBOT3.replace(
        "return options",
        "TRAJECTORY_BUILDER_2D.adaptive_voxel_filter.min_num_points = 150\n"
        "POSE_GRAPH.constraint_builder.ceres_scan_matcher.ceres_solver_options.max_num_iterations = 5\n"
        "POSE_GRAPH.max_num_final_iterations = 100\n"
        "return options",
    )
    config = load_cartographer_config(write(tmp_path, text))
    assert config.ignored == []
    assert config.trajectory_builder_2d.adaptive_voxel_filter.min_num_points == 150
    assert config.pose_graph.constraint_builder.ceres_scan_matcher.max_num_iterations == 5
    assert config.pose_graph.max_num_final_iterations == 100
    # Cartographer reads a point count as an integer
    err = error_of(tmp_path, text.replace("min_num_points = 150", "min_num_points = 150.5"))
    assert err.line == line_of(text, "min_num_points") and "whole number" in err.message
