"""The route server in the office stack: ComputeRoute by poses and by node ids, its error
codes, and ComputeAndTrackRoute's feedback and cancel; brought up only with a graph."""

from __future__ import annotations

from pathlib import Path

import pytest

from btnav.core.error_codes import ComputeRouteError
from btnav.core.geometry import Pose2D
from btnav.core.nav2_route_msgs import (
    ComputeAndTrackRouteFeedback,
    ComputeAndTrackRouteGoal,
    ComputeRouteGoal,
)
from btnav.mission.mission import Mission
from btnav.nav.actions import GoalStatus

ROOT = Path(__file__).resolve().parents[2]
MISSION = ROOT / "missions" / "office_route.yaml"


@pytest.fixture(scope="module")
def nav():  # type: ignore[no-untyped-def]
    return Mission.load(MISSION, overrides={"mission.localization": "ground_truth"}).navigator()


def ask(nav, server: str, goal):  # type: ignore[no-untyped-def]
    handle = nav.runtime.action_client(server).send_goal(goal)
    nav.runtime.run_until(lambda: handle.done, 0.1)
    return handle


def test_compute_route_by_poses_goes_through_the_lower_doorway(nav) -> None:  # type: ignore[no-untyped-def]
    handle = ask(
        nav, "compute_route", ComputeRouteGoal(goal=Pose2D(10.6, 1.0, 0.0), use_poses=True)
    )
    assert handle.succeeded, handle.error_msg
    route, path = handle.result.value.route, handle.result.value.path
    assert [n.nodeid for n in route.nodes] == [1, 2, 3, 4, 5, 6]
    assert len(route.edges) == 5 and route.route_cost > 0
    # the dense path: from node 1 to node 6, 5 cm apart, corners rounded (Nav2's
    # smooth_corners: true) so it misses the inner nodes by a little
    xy = path.poses[:, :2]
    assert tuple(xy[0]) == (2.6, 1.6) and tuple(xy[-1]) == (10.5, 1.2)
    step = (xy[1:] - xy[:-1]) ** 2
    assert step.sum(axis=1).max() ** 0.5 <= 0.05 + 1e-9


def test_compute_route_by_ids_and_its_error_codes(nav) -> None:  # type: ignore[no-untyped-def]
    handle = ask(nav, "compute_route", ComputeRouteGoal(start_id=9, goal_id=6))
    assert [n.nodeid for n in handle.result.value.route.nodes] == [9, 12, 2, 3, 4, 5, 6]
    bad = ask(nav, "compute_route", ComputeRouteGoal(start_id=9, goal_id=77))
    assert bad.error_code == ComputeRouteError.UNKNOWN and "77" in bad.error_msg
    # the costmap scorer (Nav2's file) refuses an edge through a lethal cell
    services = nav.stack.servers["route_server"].services()
    assert "route_server/ReroutingService/reroute" in services
    cm = nav.stack.global_costmap.costmap
    (mx, my), _ = cm.world_to_map([4.0, 3.5])  # the lower doorway
    saved = cm.costs.copy()
    try:
        cm.costs[my - 2 : my + 3, mx - 2 : mx + 3] = 254
        nav.stack.global_costmap.costmap_ros.update = lambda **kw: None  # keep the block
        handle = ask(nav, "compute_route", ComputeRouteGoal(start_id=1, goal_id=6))
        assert [n.nodeid for n in handle.result.value.route.nodes][:5] == [1, 2, 12, 9, 10]
    finally:
        del nav.stack.global_costmap.costmap_ros.update
        cm.costs[:] = saved


def test_compute_and_track_route_publishes_the_route_and_cancels(nav) -> None:  # type: ignore[no-untyped-def]
    goal = ComputeAndTrackRouteGoal(goal=Pose2D(10.6, 1.0, 0.0), use_poses=True)
    handle = nav.runtime.action_client("compute_and_track_route").send_goal(goal)
    nav.runtime.run_until(lambda: handle.feedback is not None, 0.5)
    feedback = handle.feedback
    assert isinstance(feedback, ComputeAndTrackRouteFeedback) and feedback.rerouted
    assert feedback.next_node_id == 1 and len(feedback.path) > 100
    nav.runtime.run_until(lambda: False, 0.5)
    assert handle.status is GoalStatus.EXECUTING  # the robot stands still: still on the way
    handle.cancel()
    nav.runtime.run_until(lambda: handle.done, 0.5)
    assert handle.status is GoalStatus.CANCELED


def test_no_graph_no_route_server() -> None:
    tour = ROOT / "missions" / "office_tour.yaml"
    nav = Mission.load(tour, overrides={"mission.localization": "ground_truth"}).navigator()
    assert "route_server" not in nav.stack.servers
    assert "compute_route" not in nav.runtime.action_servers
