"""The zone servers of Nav2's params file, brought up by the stack and wired to the filters."""

from __future__ import annotations

from pathlib import Path
from typing import Any

import numpy as np
import pytest
import yaml

from btnav.core.errors import ParamsError
from btnav.core.geometry import Pose2D
from btnav.costmap import FREE_SPACE, LETHAL_OBSTACLE
from btnav.maps.map_io import load_map, save_map
from btnav.maps.occupancy_grid import OccupancyGrid
from btnav.nav.costmap_filter_servers import CostmapFilterInfoServer, FilterMaskServer

from .navstack_helpers import MAP, PARAMS, office, plan

#: A zone across the lower half of the office's left room, where the robot starts (1, 1).
ZONE_X, ZONE_Y = (1.8, 2.6), (0.0, 2.2)
IN_ZONE = (2.2, 1.0)


def mask_like_the_map(folder: Path, name: str, inside: int, mode: str) -> Path:
    grid = load_map(MAP)
    data = np.zeros_like(grid.data)
    xs = grid.origin.x + (np.arange(grid.width) + 0.5) * grid.resolution
    ys = grid.origin.y + (np.arange(grid.height) + 0.5) * grid.resolution
    zone = ((ys >= ZONE_Y[0]) & (ys <= ZONE_Y[1]))[:, None] & (
        (xs >= ZONE_X[0]) & (xs <= ZONE_X[1])
    )[None, :]
    data[zone] = inside
    yaml_path, _ = save_map(
        OccupancyGrid(data, grid.resolution, grid.origin),
        folder / f"{name}.yaml",
        mode=mode,
        free_thresh=0.0 if mode == "scale" else 0.25,
        occupied_thresh=1.0 if mode == "scale" else 0.65,
        image_format="pgm",
    )
    return yaml_path


def zoned_params(folder: Path, *, keepout: Any = True, speed: Any = True, **edits: Any) -> Path:
    """Nav2's params (as bundled) with the zone tokens written in, as nav2_bringup's launch
    writes them, the masks set, and `edits` (`{"server.key": value}`) applied."""
    doc = yaml.safe_load(PARAMS.read_text())
    for costmap in ("local_costmap", "global_costmap"):
        section = doc[costmap][costmap]["ros__parameters"]
        for name in section.get("filters", []):
            value = section[name]["enabled"]
            section[name]["enabled"] = keepout if value == "KEEPOUT_ZONE_ENABLED" else speed
    masks = {
        "keepout_filter_mask_server": mask_like_the_map(folder, "keepout", 100, "trinary"),
        "speed_filter_mask_server": mask_like_the_map(folder, "speed", 50, "scale"),
    }
    for server, mask in masks.items():
        doc.setdefault(server, {"ros__parameters": {}})["ros__parameters"]["yaml_filename"] = str(
            mask
        )
    for key, value in edits.items():
        server, name = key.split(".", 1)
        doc[server]["ros__parameters"][name] = value
    out = folder / "params.yaml"
    out.write_text(yaml.safe_dump(doc, sort_keys=False))
    return out


def test_nav2s_zone_servers_are_brought_up_and_the_plan_goes_round_the_zone(tmp_path) -> None:
    params = zoned_params(tmp_path)
    _, rt, stack = office(params)
    assert isinstance(stack.servers["keepout_filter_mask_server"], FilterMaskServer)
    assert isinstance(stack.servers["speed_costmap_filter_info_server"], CostmapFilterInfoServer)
    glob = stack.global_costmap.costmap
    assert glob.cost_at_point(*IN_ZONE) == LETHAL_OBSTACLE  # at t = 0 already
    # a goal straight across the zone: the plan goes round it, above it
    h = plan(rt, Pose2D(3.3, 1.0, 0.0))
    poses = h.result.value.poses[:, :2]
    assert len(poses) and not (glob.cost_at(poses) == LETHAL_OBSTACLE).any()
    assert poses[:, 1].max() > ZONE_Y[1]


def test_the_speed_zone_limits_the_controller_server(tmp_path) -> None:
    params = zoned_params(tmp_path, keepout=False)
    _, _, stack = office(params)
    controller = stack.controller_server
    assert controller.speed_limit == (0.0, True)  # the robot starts at (1, 1): no zone
    stack.global_costmap.costmap_ros.update(Pose2D(*IN_ZONE, 0.0), force=True)
    assert controller.speed_limit == (50.0, True)  # 100 - 50 %
    stack.global_costmap.costmap_ros.update(Pose2D(1.0, 1.0, 0.0), force=True)
    assert controller.speed_limit == (0.0, True)  # lifted on leaving


def test_a_speed_limit_topic_nobody_listens_to_limits_nothing(tmp_path) -> None:
    params = zoned_params(tmp_path, keepout=False)
    doc = yaml.safe_load(params.read_text())
    gc = doc["global_costmap"]["global_costmap"]["ros__parameters"]
    gc["speed_filter"]["speed_limit_topic"] = "other_limit"
    params.write_text(yaml.safe_dump(doc, sort_keys=False))
    _, _, stack = office(params)
    stack.global_costmap.costmap_ros.update(Pose2D(*IN_ZONE, 0.0), force=True)
    assert stack.controller_server.speed_limit == (0.0, True)


def test_disabled_zones_change_nothing(tmp_path) -> None:
    _, _, stack = office(zoned_params(tmp_path, keepout=False, speed=False))
    assert stack.global_costmap.costmap.cost_at_point(*IN_ZONE) == FREE_SPACE


def test_an_enabled_filter_without_a_mask_is_a_located_error(tmp_path) -> None:
    params = zoned_params(tmp_path, **{"keepout_filter_mask_server.yaml_filename": ""})
    with pytest.raises(ParamsError) as info:
        office(params)
    err = info.value
    # the global costmap's filter is wired first (either names the section to fix)
    assert err.key == "global_costmap.global_costmap.keepout_filter"
    assert err.line is not None and err.file == str(params)
    assert "keepout_filter_mask_server serves no mask" in err.message


def test_an_info_server_of_the_wrong_type_is_a_located_error(tmp_path) -> None:
    params = zoned_params(tmp_path, **{"speed_costmap_filter_info_server.type": 3})
    with pytest.raises(ParamsError, match=r"sends type 3 \(binary\) but a SpeedFilter reads"):
        office(params)


def test_a_filter_info_topic_no_server_publishes_is_a_located_error(tmp_path) -> None:
    params = zoned_params(
        tmp_path, **{"keepout_costmap_filter_info_server.filter_info_topic": "elsewhere"}
    )
    with pytest.raises(ParamsError, match="no costmap_filter_info_server publishes"):
        office(params)


def test_a_filter_is_switched_off_while_running_by_its_enabled_param(tmp_path) -> None:
    _, _, stack = office(zoned_params(tmp_path, speed=False))
    stack.set_parameters("global_costmap", {"keepout_filter.enabled": False})
    assert stack.global_costmap.costmap.cost_at_point(*IN_ZONE) == FREE_SPACE
    stack.set_parameters("global_costmap", {"keepout_filter.enabled": True})
    assert stack.global_costmap.costmap.cost_at_point(*IN_ZONE) == LETHAL_OBSTACLE
