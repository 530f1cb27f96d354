"""The `amcl` localiser on the runtime: gating, initial poses, services, map, params, errors."""

from __future__ import annotations

import hashlib
import math
from pathlib import Path

import numpy as np
import pytest
import yaml

from btnav.cli import main
from btnav.core.errors import BtnavError
from btnav.core.geometry import Pose2D
from btnav.core.messages import Twist
from btnav.localization.amcl import Amcl
from btnav.mission import Mission, run_mission
from btnav.mission.navigator import Navigator

REPO = Path(__file__).resolve().parents[2]
TOUR = REPO / "missions" / "office_tour.yaml"
PARAMS = REPO / "params" / "nav2_params.yaml"
AMCL = {"mission.localization": "amcl"}


def amcl_nav(**overrides) -> Navigator:
    return Navigator.from_mission(TOUR, overrides={**AMCL, **overrides})


def drive(nav: Navigator, v: float, w: float, seconds: float) -> None:
    nav.runtime.set_cmd_vel(Twist(linear_x=v, angular_z=w))
    nav.runtime.spin_for(seconds)
    nav.runtime.set_cmd_vel(Twist())


def test_the_first_scan_updates_then_only_motion_past_update_min_d_or_a():
    nav = amcl_nav()
    amcl = nav.runtime.localizer
    assert isinstance(amcl, Amcl) and amcl.field is not None  # map_server's map
    nav.runtime.spin_for(1.0)  # ten scans standing still: only the first updates
    assert amcl.updates == 1 and amcl.first_pose_sent
    est = nav.runtime.robot_pose()
    assert math.hypot(est.x - 1.0, est.y - 1.0) < 0.05
    drive(nav, 0.2, 0.0, 1.0)  # 0.2 m: below update_min_d (0.25)
    assert amcl.updates == 1
    drive(nav, 0.2, 0.0, 0.5)  # 0.3 m in all
    assert amcl.updates == 2 and amcl.resamples == 2
    drive(nav, 0.0, 0.5, 1.0)  # ~0.5 rad: past update_min_a (0.2), under 2 x 0.2 m
    assert amcl.updates >= 3
    n = amcl.updates
    nav.runtime.spin_for(0.3)
    assert amcl.updates == n  # standing still
    amcl.request_nomotion_update()
    nav.runtime.spin_for(0.1)
    assert amcl.updates == n + 1
    cov = amcl.pose.covariance
    assert cov.shape == (3, 3) and cov[0, 0] > 0 and cov[2, 2] > 0 and amcl.pose.frame_id == "map"


def test_map_to_odom_puts_the_estimate_on_the_map_and_tf_broadcast_false_leaves_it():
    nav = amcl_nav()
    drive(nav, 0.3, 0.2, 3.0)
    amcl = nav.runtime.localizer
    est = nav.runtime.robot_pose()
    assert est.distance_to(amcl.pose.pose) < 0.3  # odometry since the last update
    truth = nav.world.robot_pose
    assert est.distance_to(truth) < 0.3
    quiet = amcl_nav(**{"amcl.tf_broadcast": False})
    before = quiet.runtime.lookup("map", "odom")
    drive(quiet, 0.3, 0.2, 3.0)
    assert quiet.runtime.lookup("map", "odom") == before and quiet.runtime.localizer.updates > 1


def test_initial_pose_from_params_first_map_only_and_reset():
    nav = amcl_nav()
    rt = nav.runtime
    base = nav.stack.params.server("amcl").model
    params = type(base).model_validate(
        {
            **base.model_dump(),
            "set_initial_pose": True,
            "first_map_only": True,
            "initial_pose": {"x": 2.0, "y": 1.5, "z": 0.0, "yaw": 0.5},
        }
    )
    amcl = Amcl("amcl", params)
    amcl.configure(rt)
    assert amcl.initial_pose_is_known
    assert np.allclose(amcl.pf.poses, [2.0, 1.5, 0.5])  # zero covariance: all on the pose
    first = nav.stack.map_server.map
    amcl.set_map(first)
    other = type(first)(np.zeros((10, 10), np.int8), 0.1)
    amcl.set_map(other)
    assert amcl.field.grid is first  # first_map_only
    amcl.reset()
    assert amcl.initial_pose_is_known and np.allclose(amcl.pf.poses[:, :2], [2.0, 1.5])
    forget = Amcl(
        "amcl",
        params.model_copy(update={"always_reset_initial_pose": True, "set_initial_pose": False}),
    )
    forget.configure(rt)
    forget.set_initial_pose(Pose2D(1.0, 1.0, 0.0))
    forget.reset()
    assert not forget.initial_pose_is_known


def test_global_localisation_from_the_navigator_and_the_bt_node():
    nav = amcl_nav()
    amcl = nav.runtime.localizer
    assert nav.reinitialize_global_localization()
    poses = amcl.pf.poses
    assert amcl.pf.count == 2000 and np.ptp(poses[:, 0]) > 8 and np.ptp(poses[:, 1]) > 5
    cells = amcl.field.grid.world_to_cell(poses[:, :2])
    assert (amcl.field.grid.data[cells[:, 0], cells[:, 1]] == 0).all()  # free cells only
    amcl.set_initial_pose(Pose2D(1.0, 1.0, 0.0))
    assert "reinitialize_global_localization" in nav.stack.services()
    nav.stack.services()["reinitialize_global_localization"]()
    assert np.ptp(amcl.pf.poses[:, 0]) > 8
    gt = Navigator.from_mission(TOUR, overrides={"mission.localization": "ground_truth"})
    assert not gt.reinitialize_global_localization()  # ground truth has no such service


def test_the_bt_node_reinitializes_from_a_tree(tmp_path):
    tree = tmp_path / "tree.yaml"
    tree.write_text(
        yaml.safe_dump(
            {
                "main_tree": "T",
                "trees": {
                    "T": {
                        "Sequence": {
                            "children": [
                                {
                                    "ReinitializeGlobalLocalization": {
                                        "service_name": "reinitialize_global_localization"
                                    }
                                },
                                {"Wait": {"wait_duration": 0.5}},
                            ]
                        }
                    }
                },
            }
        )
    )
    nav = amcl_nav(**{"mission.tree": str(tree)})
    assert nav.go_to_pose((3.0, 2.0, 0.0))
    nav.runtime.spin_for(0.3)
    assert np.ptp(nav.runtime.localizer.pf.poses[:, 0]) > 8


def digest(out: Path) -> str:
    return hashlib.sha256((out / "trajectory.csv").read_bytes()).hexdigest()


def test_the_same_seed_gives_the_same_run_with_amcl_bit_for_bit(tmp_path):
    over = {**AMCL, "mission.time_limit": 12, "mission.outputs": ["trajectory"]}
    for name in ("a", "b"):
        run_mission(Mission.load(TOUR, overrides=over), tmp_path / name)
    assert digest(tmp_path / "a") == digest(tmp_path / "b")
    run_mission(Mission.load(TOUR, overrides={**over, "amcl.random_seed": 7}), tmp_path / "c")
    assert digest(tmp_path / "c") != digest(tmp_path / "a")


def write(tmp_path: Path, name: str, doc: dict) -> Path:
    path = tmp_path / name
    path.write_text(yaml.safe_dump(doc, sort_keys=False))
    return path


def mission_doc(**fields) -> dict:
    doc = {
        "mission": "m",
        "world": str(REPO / "worlds" / "small_office.yaml"),
        "params": str(PARAMS),
        "map": str(REPO / "maps" / "small_office.yaml"),
        "localization": "amcl",
        "initial_pose": [1.0, 1.0, 0.0],
        "task": {"navigate_to_pose": [3.0, 2.0, 0.0]},
    }
    doc.update(fields)
    return {k: v for k, v in doc.items() if v is not None}


def run_cli(path: Path, capsys) -> tuple[int, str]:
    code = main(["run", str(path), "--out", str(path.parent / "out")])
    return code, capsys.readouterr().err


def test_localization_amcl_without_a_map_is_one_error(tmp_path, capsys):
    code, err = run_cli(write(tmp_path, "m.yaml", mission_doc(map=None)), capsys)
    assert code == 2 and err.count("btnav: error:") == 1
    assert "needs a map" in err and "m.yaml:" in err and "Traceback" not in err


@pytest.mark.parametrize(
    ("pose", "words"),
    [([4.0, 1.0, 0.0], "inside an obstacle of the map"), ([30.0, 1.0, 0.0], "outside the map")],
)
def test_an_initial_pose_in_a_wall_or_off_the_map_is_one_error(tmp_path, capsys, pose, words):
    code, err = run_cli(write(tmp_path, "m.yaml", mission_doc(initial_pose=pose)), capsys)
    assert code == 2 and err.count("btnav: error:") == 1 and words in err
    assert "initial_pose" in err and "m.yaml:" in err


def amcl_params(tmp_path: Path, **keys) -> Path:
    doc = yaml.safe_load(PARAMS.read_text())
    doc["amcl"]["ros__parameters"].update(keys)
    return write(tmp_path, "params.yaml", doc)


def test_amcl_initial_pose_param_off_the_map_is_one_error(tmp_path):
    params = amcl_params(
        tmp_path, set_initial_pose=True, initial_pose={"x": -5.0, "y": 1.0, "z": 0.0, "yaw": 0.0}
    )
    with pytest.raises(BtnavError) as err:
        Mission.load(write(tmp_path, "m.yaml", mission_doc(params=str(params))))
    e = err.value
    assert e.file == str(params) and e.line is not None and "outside the map" in e.message


@pytest.mark.parametrize(
    ("key", "value", "words", "suggestion"),
    [
        ("z_hitt", 0.5, "z_hitt", "z_hit"),
        ("z_hit", 2.0, "z_hit", None),
        ("laser_model_type", "likelihood_feild", "likelihood", "likelihood_field"),
    ],
)
def test_a_misspelt_or_out_of_range_amcl_key_names_file_line_and_spelling(
    tmp_path, key, value, words, suggestion
):
    params = amcl_params(tmp_path, **{key: value})
    with pytest.raises(BtnavError) as err:
        Mission.load(write(tmp_path, "m.yaml", mission_doc(params=str(params))))
    e = err.value
    assert e.file == str(params) and e.line is not None and words in str(e)
    assert e.suggestion == suggestion
