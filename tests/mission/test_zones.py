"""A mission's keepout and speed zones (nav2_bringup's use_keepout_zones / use_speed_zones):
the robot on Nav2's depot stays out of Nav2's keepout zones and keeps its speed zones' limits."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest
import yaml
from scipy import ndimage

from btnav.core.errors import BtnavError
from btnav.maps.map_io import load_map
from btnav.mission import Mission, MissionError
from btnav.mission.runner import run_mission

from .missions import REPO, read_report, write_mission

DEPOT_TOUR = [[10.0, 12.0, 0.6], [18.5, 11.0, 0.0], [26.0, 9.0, -1.57], [13.0, 3.0, 3.14], [5.0, 4.0, 3.14]]  # fmt: skip


def depot_mission(folder: Path, nav2_dir: Path, **fields) -> Path:
    """missions/nav2_depot_tour.yaml with Nav2's nav2_params.yaml as it is and the robot
    placed by ground truth (so the poses checked are the filters' doing, not AMCL's)."""
    return write_mission(
        folder,
        "depot_zones",
        world=str(REPO / "worlds" / "depot.yaml"),
        params=str(nav2_dir / "params" / "nav2_params.yaml"),
        map=str(nav2_dir / "maps" / "depot.yaml"),
        initial_pose=[2.0, 7.5, 0.0],
        task={"follow_waypoints": DEPOT_TOUR},
        time_limit=400,
        outputs=["report", "trajectory"],
        **fields,
    )


def trajectory(out: Path) -> dict[str, np.ndarray]:
    rows = np.genfromtxt(out / "trajectory.csv", delimiter=",", names=True)
    return {name: rows[name] for name in rows.dtype.names}


# -- loading ---------------------------------------------------------------------------------


def test_use_keepout_zones_enables_nav2s_keepout_filters_and_serves_the_mask(
    tmp_path, nav2_dir
) -> None:
    mask = nav2_dir / "maps" / "depot_keepout.yaml"
    m = Mission.load(
        depot_mission(tmp_path, nav2_dir, use_keepout_zones=True, keepout_mask=str(mask))
    )
    for costmap in ("local_costmap", "global_costmap"):
        assert m.params.server(costmap).plugins["keepout_filter"].params.enabled is True
    assert m.params.server("global_costmap").plugins["speed_filter"].params.enabled is False
    served = m.params.server("keepout_filter_mask_server").model.yaml_filename
    assert served == str(mask)
    glob = m.navigator().stack.global_costmap.costmap
    keepout = load_map(mask).data == 100
    assert (glob.costs[keepout] == 254).all()


def test_a_mask_path_is_relative_to_the_mission(tmp_path, nav2_dir) -> None:
    (tmp_path / "masks").mkdir()
    for suffix in ("yaml", "pgm"):
        src = nav2_dir / "maps" / f"depot_speed.{suffix}"
        (tmp_path / "masks" / src.name).write_bytes(src.read_bytes())
    path = depot_mission(
        tmp_path, nav2_dir, use_speed_zones=True, speed_mask="masks/depot_speed.yaml"
    )
    m = Mission.load(path)
    served = m.params.server("speed_filter_mask_server").model.yaml_filename
    assert served == str(tmp_path / "masks" / "depot_speed.yaml")


def test_zones_without_a_mask_are_a_located_mission_error(tmp_path, nav2_dir) -> None:
    # Nav2's file leaves yaml_filename commented out: the mask must come from the mission.
    path = depot_mission(tmp_path, nav2_dir, use_keepout_zones=True)
    with pytest.raises(MissionError) as info:
        Mission.load(path)
    err = info.value
    assert err.key == "use_keepout_zones" and err.line is not None
    assert "give keepout_mask:" in err.message


def test_a_missing_mask_file_is_named_at_its_key(tmp_path, nav2_dir) -> None:
    path = depot_mission(tmp_path, nav2_dir, use_speed_zones=True, speed_mask="nowhere.yaml")
    with pytest.raises(BtnavError) as info:
        Mission.load(path)
    assert info.value.key == "speed_mask" and "not found" in info.value.message


def test_the_params_files_own_yaml_filename_is_relative_to_it(tmp_path, nav2_dir) -> None:
    doc = yaml.safe_load((nav2_dir / "params" / "nav2_params.yaml").read_text())
    doc["keepout_filter_mask_server"]["ros__parameters"]["yaml_filename"] = "depot_keepout.yaml"
    (tmp_path / "params.yaml").write_text(yaml.safe_dump(doc, sort_keys=False))
    for suffix in ("yaml", "pgm"):
        src = nav2_dir / "maps" / f"depot_keepout.{suffix}"
        (tmp_path / src.name).write_bytes(src.read_bytes())
    path = depot_mission(tmp_path, nav2_dir, use_keepout_zones=True)
    m = Mission.load(path, overrides={"mission.params": str(tmp_path / "params.yaml")})
    served = m.params.server("keepout_filter_mask_server").model.yaml_filename
    assert served == str(tmp_path / "depot_keepout.yaml")


def test_without_the_switches_the_filters_stay_off(tmp_path, nav2_dir) -> None:
    m = Mission.load(depot_mission(tmp_path, nav2_dir))
    assert not any(f.enabled for f in m.navigator().stack.global_costmap.costmap_ros.filters)


# -- the depot tour with both zones --------------------------------------------------------


@pytest.fixture(scope="module")
def zoned_tour(tmp_path_factory, nav2_dir) -> Path:
    folder = tmp_path_factory.mktemp("depot_zones")
    maps = nav2_dir / "maps"
    path = depot_mission(
        folder,
        nav2_dir,
        use_keepout_zones=True,
        keepout_mask=str(maps / "depot_keepout.yaml"),
        use_speed_zones=True,
        speed_mask=str(maps / "depot_speed.yaml"),
    )
    out = folder / "out"
    run_mission(Mission.load(path), out)
    return out


@pytest.mark.slow
def test_the_robot_tours_the_depot_and_never_enters_a_keepout_zone(zoned_tour, nav2_dir) -> None:
    report = read_report(zoned_tour)
    assert report["status"] == "succeeded" and report["missed_waypoints"] == []
    assert report["contacts"] == []
    mask = load_map(nav2_dir / "maps" / "depot_keepout.yaml")
    keepout = mask.data == 100
    # The leg from (26, 9) to (13, 3) goes straight through the big zone: the robot went round.
    a, b = np.array(DEPOT_TOUR[2][:2]), np.array(DEPOT_TOUR[3][:2])
    line = mask.world_to_cell(a + np.linspace(0.0, 1.0, 200)[:, None] * (b - a))
    assert keepout[line[:, 0], line[:, 1]].any()
    t = trajectory(zoned_tour)
    cells = mask.world_to_cell(np.stack([t["gt_x"], t["gt_y"]], axis=-1))
    assert not keepout[cells[:, 0], cells[:, 1]].any()
    # ... and not the footprint either: every pose is farther than robot_radius from a zone.
    clearance = ndimage.distance_transform_edt(~keepout) * mask.resolution
    assert clearance[cells[:, 0], cells[:, 1]].min() > 0.22


@pytest.mark.slow
def test_the_robot_keeps_the_speed_zones_limits_and_speeds_up_outside(zoned_tour, nav2_dir) -> None:
    mask = load_map(nav2_dir / "maps" / "depot_speed.yaml")
    t = trajectory(zoned_tour)
    xy = np.stack([t["gt_x"], t["gt_y"]], axis=-1)
    speed = np.r_[0.0, np.hypot(*np.diff(xy, axis=0).T) / np.diff(t["t"])]
    cells = mask.world_to_cell(xy)
    value = mask.data[cells[:, 0], cells[:, 1]].astype(int)
    # Nav2's speed_costmap_filter_info_server: base 100, multiplier -1, in % of MPPI's vx_max
    v_max = 0.5
    limit = np.where((value > 0) & (value < 100), (100 - value) / 100.0 * v_max, np.inf)
    zoned = np.isfinite(limit)
    assert zoned.sum() > 500  # the tour crosses the zones (rows at 20 Hz)
    entered = np.maximum.accumulate(
        np.where(np.r_[True, value[1:] != value[:-1]], np.arange(len(t["t"])), 0)
    )
    in_zone_for = t["t"] - t["t"][entered]
    # The limit is the global costmap's (1 Hz): a zone is seen up to 1 s after entering,
    # then the controller slows down (at most 0.25 m/s at the robot's a_max 1 m/s^2) within
    # a control cycle or two. Measured on seed 0: over the limit at most 1.05 s into a
    # zone, by up to 0.21 m/s; never after that.
    settle = 1.0 + (v_max - 0.25) / 1.0 + 2 * 0.05
    settled = zoned & (in_zone_for > settle)
    assert settled.sum() > 300
    assert (speed[settled] <= limit[settled] + 0.005).all()
    # Out of the zones again, the limit is lifted: the robot runs near full speed.
    after_a_zone = ~zoned & (np.cumsum(zoned) > 0) & (value == 0)
    assert speed[after_a_zone].max() > 0.45
