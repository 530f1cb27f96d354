"""Both of Nav2's route trees drive the office on its route graph: the robot keeps to the
graph's edges (beyond the first and last mile) and reaches the goal without contact; the
warehouse mission loads with Nav2's own graph of that map."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

from btnav.mission import Mission
from btnav.mission.runner import run_mission
from btnav.route.geojson import load_graph

REPO = Path(__file__).resolve().parents[2]
OFFICE = REPO / "missions" / "office_route.yaml"
WAREHOUSE = REPO / "missions" / "nav2_warehouse_route.yaml"
#: The route through the lower doorway (graphs/small_office_graph.geojson's node ids).
OFFICE_ROUTE = [1, 2, 3, 4, 5, 6]


def distance_to_polyline(xy: np.ndarray, line: np.ndarray) -> np.ndarray:
    a, b = line[:-1], line[1:]
    ab = b - a
    t = np.clip(((xy[:, None, :] - a) * ab).sum(-1) / (ab * ab).sum(-1), 0.0, 1.0)
    nearest = a + t[..., None] * ab
    return np.hypot(*(xy[:, None, :] - nearest).transpose(2, 0, 1)).min(axis=1)


def drive(tmp_path: Path, tree: str) -> tuple[np.ndarray, np.ndarray, Mission]:
    mission = Mission.load(OFFICE, overrides={"mission.tree": tree})
    report = run_mission(mission, tmp_path / "out")
    assert report.status == "succeeded", report.error_msg
    assert report.collisions == 0, report.contacts
    track = np.genfromtxt(tmp_path / "out" / "trajectory.csv", delimiter=",", names=True)
    xy = np.column_stack([track["gt_x"], track["gt_y"]])
    graph = load_graph(REPO / "graphs" / "small_office_graph.geojson")
    line = np.array([(graph.node(i).x, graph.node(i).y) for i in OFFICE_ROUTE])
    return xy, line, mission


def on_route(xy: np.ndarray, line: np.ndarray, start: np.ndarray, goal: np.ndarray) -> np.ndarray:
    """The poses past the first mile (robot -> first node) and before the last."""
    first = np.hypot(*(line[0] - start)) + 0.3
    last = np.hypot(*(line[-1] - goal)) + 0.3
    return xy[(np.hypot(*(xy - start).T) > first) & (np.hypot(*(xy - goal).T) > last)]


@pytest.mark.slow
@pytest.mark.parametrize(
    ("tree", "tolerance"),
    [
        # the route's own dense path (corners rounded with a 1 m radius), followed by MPPI
        ("navigate_on_route_graph_w_recovery", 0.3),
        # NavFn through the next two route nodes: the route a prior, corners cut more
        ("navigate_w_routing_global_planning_and_control_w_recovery", 0.6),
    ],
)
def test_the_robot_follows_the_office_route_graph(
    tmp_path: Path, tree: str, tolerance: float
) -> None:
    xy, line, mission = drive(tmp_path, tree)
    goal = np.array(mission.spec.task.navigate_to_pose[:2])
    assert np.hypot(*(xy[-1] - goal)) < 0.25  # Nav2's goal checker's xy tolerance
    middle = on_route(xy, line, xy[0], goal)
    assert len(middle) > 0.6 * len(xy)
    off = distance_to_polyline(middle, line)
    assert off.max() < tolerance, f"{off.max():.2f} m off the route at {middle[off.argmax()]}"
    # it went through the lower doorway, as the route does (not round by the upper one)
    assert xy[:, 1].max() < 4.2


def test_the_warehouse_route_mission_brings_up_nav2s_graph() -> None:
    nav = Mission.load(WAREHOUSE, overrides={"mission.localization": "ground_truth"}).navigator()
    server = nav.stack.servers["route_server"]
    assert len(server.graph) == 96 and server.graph.source.endswith("warehouse_graph.geojson")
    assert "compute_route" in nav.runtime.action_servers
