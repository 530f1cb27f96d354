"""KeepoutFilter: a mask's zone is lethal in the costmap, uninflated, and a robot inside can leave."""

from __future__ import annotations

import numpy as np

from btnav.core.frames import FrameTree
from btnav.core.geometry import Pose2D
from btnav.costmap import FREE_SPACE, LETHAL_OBSTACLE
from btnav.costmap.filters import KEEPOUT_FILTER, CostmapFilterInfo, KeepoutFilter

from .zones import ZONE, costmap_with, zone_mask

INFO = CostmapFilterInfo(KEEPOUT_FILTER, "keepout_filter_mask")


def keepout(**params) -> KeepoutFilter:
    return KeepoutFilter(
        "keepout_filter",
        KeepoutFilter.Params(filter_info_topic="keepout_costmap_filter_info", **params),
    )


def test_the_zone_is_lethal_in_a_global_costmap_and_not_inflated() -> None:
    ros = costmap_with(keepout(), INFO, zone_mask(100))
    ros.update(Pose2D(1.0, 1.0, 0.0), force=True)
    costs = ros.costmap.costs
    assert (costs[ZONE] == LETHAL_OBSTACLE).all()
    # Filters run after inflation: the cell beside the zone keeps the layers' cost.
    assert costs[100, 78] == FREE_SPACE
    # ... and the layers' own grid never holds the zone, so nothing lingers in it.
    assert ros.layered.primary is not None
    assert (ros.layered.primary.costs[ZONE] == FREE_SPACE).all()


def test_a_disabled_filter_changes_nothing_and_toggles_on() -> None:
    f = keepout(enabled=False)
    ros = costmap_with(f, INFO, zone_mask(100))
    ros.update(Pose2D(1.0, 1.0, 0.0), force=True)
    assert (ros.costmap.costs[ZONE] == FREE_SPACE).all()
    f.toggle(True)  # Nav2's toggle_filter service
    ros.refresh()
    assert (ros.costmap.costs[ZONE] == LETHAL_OBSTACLE).all()


def test_the_zone_is_lethal_in_a_rolling_local_costmap_in_odom() -> None:
    # The mask is in map; the local costmap rolls in odom, 1 m away from map.
    tree = FrameTree.rep105()
    tree.set_transform("map", "odom", Pose2D(1.0, 0.0, 0.0), 0.0)
    tree.set_transform("odom", "base_footprint", Pose2D(3.0, 5.0, 0.0), 0.0)
    ros = costmap_with(keepout(), INFO, zone_mask(100), rolling=True, frame="odom")
    ros.update(frame_tree=tree, force=True)  # the robot at (4, 5) in map: at the zone's edge
    m = ros.costmap
    inside = m.cost_at_point(3.0 + 0.3, 5.0)  # odom (3.3, 5) = map (4.3, 5): in the zone
    outside = m.cost_at_point(3.0 - 0.3, 5.0)  # map (3.7, 5): out of it
    assert (inside, outside) == (LETHAL_OBSTACLE, FREE_SPACE)


def test_free_and_unknown_mask_cells_leave_the_layers_costs() -> None:
    mask = zone_mask(100, rest=-1)
    ros = costmap_with(keepout(), INFO, mask)
    ros.update(Pose2D(1.0, 1.0, 0.0), force=True)
    costs = ros.costmap.costs
    assert costs[0, 50] == LETHAL_OBSTACLE  # the room's wall, under an unknown mask cell
    assert costs[50, 50] == FREE_SPACE


def test_a_robot_inside_a_zone_sees_the_override_cost_and_can_leave() -> None:
    f = keepout(override_lethal_cost=True, lethal_override_cost=200)
    ros = costmap_with(f, INFO, zone_mask(100))
    ros.update(Pose2D(1.0, 1.0, 0.0), force=True)  # the new mask: painted lethal
    assert ros.costmap.costs[100, 100] == LETHAL_OBSTACLE
    ros.update(Pose2D(5.0, 5.0, 0.0), force=True)  # now inside
    assert f.is_pose_lethal
    window = ros.layered.last_window
    assert window is not None
    costs = ros.costmap.costs[window.slices]
    zone = zone_mask(100).data[window.slices] == 100
    assert (costs[zone] == 200).all()  # passable: the planner can find the way out
    ros.update(Pose2D(3.0, 3.0, 0.0), force=True)  # out again: lethal once more
    assert not f.is_pose_lethal
    assert ros.costmap.costs[100, 100] == LETHAL_OBSTACLE


def test_without_override_a_robot_inside_still_sees_lethal() -> None:
    f = keepout()
    ros = costmap_with(f, INFO, zone_mask(100))
    ros.update(Pose2D(1.0, 1.0, 0.0), force=True)
    ros.update(Pose2D(5.0, 5.0, 0.0), force=True)
    assert ros.costmap.costs[100, 100] == LETHAL_OBSTACLE


def test_lethal_override_cost_is_clamped_as_nav2_clamps_it() -> None:
    assert keepout(lethal_override_cost=300).lethal_override_cost == 252
    assert keepout(lethal_override_cost=-5).lethal_override_cost == 0


def test_a_scale_mask_adds_graded_costs_only_where_higher() -> None:
    ros = costmap_with(keepout(), INFO, zone_mask(50))
    ros.update(Pose2D(1.0, 1.0, 0.0), force=True)
    assert np.unique(ros.costmap.costs[ZONE]).tolist() == [127]
