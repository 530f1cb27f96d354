"""SmacPlannerLattice: plans judged by geometry; lattice files and params as Nav2 users write them."""

from __future__ import annotations

import json
import math
import subprocess
from pathlib import Path
from types import SimpleNamespace

import numpy as np
import pytest

from btnav.core.errors import BtnavError, ParamsError
from btnav.core.geometry import Pose2D
from btnav.costmap.cost_values import INSCRIBED_INFLATED_OBSTACLE, LETHAL_OBSTACLE
from btnav.costmap.costmap_2d import Costmap2D
from btnav.costmap.footprint_cost import footprint_costs
from btnav.maps import load_map
from btnav.params import load_params
from btnav.planning.exceptions import (
    NoValidPathCouldBeFound,
    PlannerCancelled,
    PlannerTimedOut,
    StartOccupied,
)
from btnav.planning.smac_common import max_curvature
from btnav.planning.smac_planner_lattice import SmacPlannerLattice, load_lattice

from .conftest import inflate

REPO = Path(__file__).resolve().parents[2]
NAV2_PARAMS = REPO.parent / "shared" / "nav2" / "params" / "nav2_params.yaml"
NAV2_MIRROR = Path("/work/.mirror/ros-navigation+navigation2/repo")
NAV2_SAMPLES = "nav2_smac_planner/lattice_primitives/sample_primitives/5cm_resolution"
RACECAR = "lattice/racecar_ackermann_1.4m_5cm.json"
DIFF = "lattice/turtlebot3_diff_0.4m_5cm.json"
OMNI = "lattice/omni_0.5m_5cm.json"


@pytest.fixture(scope="module")
def office() -> Costmap2D:
    """btnav's small office map, inflated as Nav2's default inflation layer would."""
    grid = load_map(REPO / "maps" / "small_office.yaml")
    costs = np.where(grid.data >= 65, 254, np.where(grid.data < 0, 255, 0)).astype(np.uint8)
    costs = inflate(costs, grid.resolution, 0.22, 0.55, 3.0)
    return Costmap2D(costs, grid.resolution, grid.origin.x, grid.origin.y)


def corridor(width_m: float, closed: bool = False) -> Costmap2D:
    """A corridor along x, 10 m long, lethal walls around (no inflation)."""
    res = 0.05
    costs = np.full((60, 200), 254, np.uint8)
    half = round(width_m / res / 2)
    costs[30 - half : 30 + half, 2 : (198 if not closed else 196)] = 0
    return Costmap2D(costs, res, 0.0, 0.0)


def planner(**params) -> SmacPlannerLattice:
    return SmacPlannerLattice("GridBased", SmacPlannerLattice.Params(**params))


def yaw_gap(a: float, b: float) -> float:
    return abs(math.remainder(a - b, 2 * math.pi))


def assert_reaches(path, costmap: Costmap2D, goal: Pose2D, tolerance: float = 0.25) -> None:
    poses = path.poses
    assert np.all(costmap.cost_at(poses[:, :2]) < INSCRIBED_INFLATED_OBSTACLE)
    assert math.hypot(poses[-1, 0] - goal.x, poses[-1, 1] - goal.y) <= tolerance
    assert yaw_gap(poses[-1, 2], goal.yaw) <= math.pi / 16 + 1e-9  # half a lattice bin


def backing(poses: np.ndarray) -> np.ndarray:
    """Per step, whether the base moves against its heading."""
    heading = np.stack([np.cos(poses[:-1, 2]), np.sin(poses[:-1, 2])], axis=1)
    return np.sum(heading * np.diff(poses[:, :2], axis=0), axis=1) < -1e-9


@pytest.mark.parametrize(
    ("lattice", "reverse", "radius"),
    [("lattice/ackermann_0.5m_5cm.json", False, 0.5), (RACECAR, True, 1.4), (DIFF, False, 0.4)],
)
def test_office_plans_avoid_obstacles_reach_the_goal_and_keep_the_turning_radius(
    office, lattice, reverse, radius
):
    goal = Pose2D(6.0, 3.0, 3.14)
    p = planner(lattice_filepath=lattice, allow_reverse_expansion=reverse)
    path = p.create_plan(Pose2D(1.0, 1.0, 0.0), goal, office)
    assert_reaches(path, office, goal)
    assert max_curvature(path.poses) <= 1.0 / radius * 1.05  # rotations in place aside
    length = np.hypot(*np.diff(path.poses[:, :2], axis=0).T).sum()
    assert length >= math.hypot(5.0, 2.0)


def test_a_dead_end_is_left_in_reverse_only_when_reverse_expansion_is_allowed():
    cm = corridor(0.8, closed=True)  # too narrow for a 1.4 m radius to turn in
    start, goal = Pose2D(8.5, 1.5, 0.0), Pose2D(3.0, 1.5, 0.0)  # the goal is behind
    path = planner(lattice_filepath=RACECAR, allow_reverse_expansion=True).create_plan(
        start, goal, cm
    )
    assert_reaches(path, cm, goal)
    assert np.sum(backing(path.poses)) >= 0.9 * (len(path.poses) - 1)  # it backs out
    with pytest.raises(NoValidPathCouldBeFound):  # forward only, it cannot get out
        planner(lattice_filepath=RACECAR).create_plan(start, goal, cm)


def test_a_polygon_footprint_from_the_costmap_server_is_checked_along_the_primitives():
    cm = corridor(1.0)
    start, goal = Pose2D(2.0, 1.5, 0.0), Pose2D(8.0, 1.5, 0.0)
    wide = np.array([[-0.2, -0.6], [0.6, -0.6], [0.6, 0.6], [-0.2, 0.6]])  # 1.2 m wide
    p = planner(lattice_filepath=RACECAR)
    p.configure(SimpleNamespace(use_radius=False, footprint=wide, circumscribed_cost=lambda: 0.0))
    with pytest.raises(StartOccupied):
        p.create_plan(start, goal, cm)
    narrow = wide * [1.0, 0.6]  # 0.72 m wide: fits a 1.0 m corridor, not when it turns much
    p.configure(SimpleNamespace(use_radius=False, footprint=narrow, circumscribed_cost=lambda: 0.0))
    path = p.create_plan(start, goal, cm)
    assert_reaches(path, cm, goal)
    along = footprint_costs(cm, narrow, path.poses[:, 0], path.poses[:, 1], path.poses[:, 2])
    assert np.all(along < LETHAL_OBSTACLE)


def test_an_omni_lattice_slides_sideways_facing_ahead():
    cm = Costmap2D.empty(80, 80, 0.05)
    # 0.9 m to the left: six of the lattice's 0.15 m slides. No analytic shortcut: the
    # lattice's own primitives must get there.
    start, goal = Pose2D(1.025, 1.025, 0.0), Pose2D(1.025, 1.925, 0.0)  # mid-cell
    path = planner(lattice_filepath=OMNI, analytic_expansion_max_length=0.01).create_plan(
        start, goal, cm
    )
    assert_reaches(path, cm, goal)
    assert all(yaw_gap(yaw, 0.0) < 1e-9 for yaw in path.poses[:, 2])  # never turns
    assert path.length() == pytest.approx(0.9, abs=1e-6)


def test_a_diff_lattice_turns_on_the_spot_where_no_arc_fits():
    cm = corridor(0.2)  # no 0.4 m radius arc fits (a point base, no inflation)
    start, goal = Pose2D(5.0, 1.5, 0.0), Pose2D(4.0, 1.5, math.pi)
    path = planner(lattice_filepath=DIFF).create_plan(start, goal, cm)
    assert_reaches(path, cm, goal)
    d = np.hypot(*np.diff(path.poses[:, :2], axis=0).T)
    turned = [yaw_gap(a, b) for a, b in zip(path.poses[:-1, 2], path.poses[1:, 2], strict=True)]
    on_the_spot = sum(t for t, step in zip(turned, d, strict=True) if step < 1e-9)
    # Most of the half turn in place; the last bit is the analytic curve's gentle arc.
    assert on_the_spot >= 0.75 * math.pi
    assert np.all(np.abs(path.poses[:, 1] - 1.5) <= 0.1)  # never leaves the corridor


def nav2_sample(model: str, tmp_path: Path) -> Path:
    text = subprocess.run(
        ["git", "-C", str(NAV2_MIRROR), "show",
         f"HEAD:{NAV2_SAMPLES}/0.5m_turning_radius/{model}/output.json"],
        capture_output=True, text=True, check=True,
    ).stdout  # fmt: skip
    out = tmp_path / f"{model}.json"
    out.write_text(text)
    return out


@pytest.mark.skipif(not NAV2_MIRROR.is_dir(), reason="Nav2's repository is not mirrored here")
@pytest.mark.parametrize("model", ["ackermann", "diff", "omni"])
def test_nav2s_own_lattice_files_load_unchanged_and_plan(office, model, tmp_path):
    path_to = nav2_sample(model, tmp_path)
    lattice = load_lattice(path_to)
    assert lattice.motion_model == model and lattice.num_of_headings == 16
    goal = Pose2D(6.0, 3.0, 3.14)
    path = planner(lattice_filepath=str(path_to)).create_plan(Pose2D(1.0, 1.0, 0.0), goal, office)
    assert_reaches(path, office, goal)


def tiny_lattice(file: Path) -> Path:
    """A hand-written lattice in Nav2's exact format: 8 headings, one cell straight ahead
    from each, and a rotation in place to each neighbour (a diff base)."""
    dirs = [(1, 0), (1, 1), (0, 1), (-1, 1), (-1, 0), (-1, -1), (0, -1), (1, -1)]
    angles = [i * math.pi / 4 for i in range(8)]
    prims = []
    for k, (i, j) in enumerate(dirs):
        length = 0.05 * math.hypot(i, j)
        prims.append({
            "trajectory_id": len(prims), "start_angle_index": k, "end_angle_index": k,
            "left_turn": True, "trajectory_radius": 0.0, "trajectory_length": round(length, 5),
            "arc_length": 0.0, "straight_length": round(length, 5),
            "poses": [[0.05 * i, 0.05 * j, angles[k]]],
        })  # fmt: skip
        for end in ((k + 1) % 8, (k - 1) % 8):
            turn = math.remainder(angles[end] - angles[k], 2 * math.pi)
            prims.append({
                "trajectory_id": len(prims), "start_angle_index": k, "end_angle_index": end,
                "left_turn": True, "trajectory_radius": 0.0, "trajectory_length": 0.0,
                "arc_length": 0.0, "straight_length": 0.0,
                "poses": [[0.0, 0.0, (angles[k] + t * turn) % (2 * math.pi)] for t in (0.0, 0.5, 1.0)],
            })  # fmt: skip
    doc = {
        "version": 1.0,
        "date_generated": "2026-01-01",
        "lattice_metadata": {
            "motion_model": "diff", "turning_radius": 0.2, "grid_resolution": 0.05,
            "stopping_threshold": 5, "num_of_headings": 8, "heading_angles": angles,
            "number_of_trajectories": len(prims),
        },
        "primitives": prims,
    }  # fmt: skip
    file.write_text(json.dumps(doc, indent="\t"))
    return file


def test_a_hand_written_lattice_in_nav2s_format_plans_with_its_primitives_only(tmp_path):
    cm = Costmap2D.empty(60, 60, 0.05)
    cm.costs[10:50, 30] = 254  # a wall between start and goal
    start, goal = Pose2D(0.525, 1.525, 0.0), Pose2D(2.525, 1.525, 0.0)
    p = planner(lattice_filepath=str(tiny_lattice(tmp_path / "tiny.json")),
                analytic_expansion_max_length=0.01)  # fmt: skip
    path = p.create_plan(start, goal, cm)
    poses = path.poses
    assert np.all(cm.cost_at(poses[:, :2]) < INSCRIBED_INFLATED_OBSTACLE)
    assert np.floor(poses[-1, :2] / 0.05).tolist() == [50, 30]  # the goal's cell
    steps = np.diff(poses[:, :2], axis=0) / 0.05
    moved = np.hypot(*steps.T) > 1e-9
    # every move is one cell along one of the 8 headings, facing it
    assert np.allclose(steps[moved], np.round(steps[moved]), atol=1e-9)
    assert np.all(np.abs(steps[moved]).max(axis=1) == pytest.approx(1.0))
    assert max(poses[:, 1]) > 2.5 or min(poses[:, 1]) < 0.5  # around the wall's end


def test_the_same_request_gives_the_same_path_bit_for_bit(office):
    a = planner().create_plan(Pose2D(1, 1, 0), Pose2D(6, 3, 3.14), office)
    b = planner().create_plan(Pose2D(1, 1, 0), Pose2D(6, 3, 3.14), office)
    assert a.poses.tobytes() == b.poses.tobytes()


def test_cancel_and_max_iterations_are_nav2s_planner_errors(office):
    start, goal = Pose2D(1, 1, 0), Pose2D(10, 6, 1.57)
    with pytest.raises(PlannerCancelled):
        planner().create_plan(start, goal, office, cancel_checker=lambda: True)
    with pytest.raises(PlannerTimedOut) as err:
        planner(max_iterations=50).create_plan(start, goal, office)
    assert err.value.error_code == 207


# -- params as Nav2 users write them ------------------------------------------------------

#: planner_server's GridBased section of Nav2's nav2_params.yaml, and a lattice one in
#: its place (the keys and values of Nav2's SmacPlannerLattice documentation).
NAVFN_SECTION = """    GridBased:
      plugin: "nav2_navfn_planner::NavfnPlanner"
      tolerance: 0.5
      use_astar: false
      max_cycles_factor: 4
      allow_unknown: true
"""
LATTICE_SECTION = """    GridBased:
      plugin: "nav2_smac_planner/SmacPlannerLattice"
      allow_unknown: true
      tolerance: 0.25
      max_iterations: 1000000
      max_on_approach_iterations: 1000
      max_planning_time: 5.0
      analytic_expansion_ratio: 3.5
      analytic_expansion_max_length: 3.0
      analytic_expansion_max_cost: 200.0
      analytic_expansion_max_cost_override: false
      reverse_penalty: 2.0
      change_penalty: 0.05
      non_straight_penalty: 1.05
      cost_penalty: 2.0
      rotation_penalty: 5.0
      retrospective_penalty: 0.015
      lattice_filepath: "LATTICE"
      lookup_table_size: 20.0
      cache_obstacle_heuristic: false
      allow_reverse_expansion: false
      smooth_path: true
      debug_visualizations: false
      smoother:
        max_iterations: 1000
        w_smooth: 0.3
        w_data: 0.2
        tolerance: 1.0e-10
        do_refinement: true
        refinement_num: 2
"""


def nav2_params(tmp_path: Path, lattice: str, old: str = "", new: str = "") -> tuple[Path, int]:
    """Nav2's nav2_params.yaml with its planner section made a lattice one, and the line
    holding `old` (if any) edited to `new`; returns the file and that line."""
    text = NAV2_PARAMS.read_text()
    assert NAVFN_SECTION in text
    text = text.replace(NAVFN_SECTION, LATTICE_SECTION.replace("LATTICE", lattice))
    lines = text.splitlines(keepends=True)
    line = 0
    if old:
        (line,) = [i + 1 for i, text_line in enumerate(lines) if old in text_line]
        lines[line - 1] = lines[line - 1].replace(old, new)
    out = tmp_path / "nav2_params.yaml"
    out.write_text("".join(lines))
    return out, line


def test_a_nav2_params_file_selects_the_lattice(tmp_path):
    params, _ = nav2_params(tmp_path, RACECAR)
    loaded = load_params(params)
    section = loaded.server("planner_server").plugins["GridBased"]
    assert section.cls is SmacPlannerLattice
    assert section.params.lattice().turning_radius == 1.4
    ignored = {e.key for e in loaded.ignored}
    assert "planner_server.GridBased.max_planning_time" in ignored
    assert "planner_server.GridBased.lookup_table_size" in ignored


def test_a_misspelt_key_names_the_file_the_line_and_the_right_spelling(tmp_path):
    params, line = nav2_params(tmp_path, RACECAR, "rotation_penalty:", "rotation_penality:")
    with pytest.raises(ParamsError) as err:
        load_params(params)
    assert (err.value.file, err.value.line) == (str(params), line)
    assert err.value.suggestion == "rotation_penalty"
    assert "planner_server.GridBased.rotation_penality" in str(err.value)


def test_a_missing_lattice_file_names_the_params_file_line(tmp_path):
    params, line = nav2_params(
        tmp_path, "lattices/racecar.json", "lattice_filepath", "lattice_filepath"
    )
    with pytest.raises(BtnavError) as err:
        load_params(params)
    assert (err.value.file, err.value.line) == (str(params), line)
    assert "lattices/racecar.json" in err.value.message and "not found" in err.value.message
    # the same relative path beside the params file is found
    (tmp_path / "lattices").mkdir()
    (tmp_path / "lattices" / "racecar.json").write_text((REPO / "params" / RACECAR).read_text())
    section = load_params(params).server("planner_server").plugins["GridBased"]
    assert section.params.lattice_filepath == str(tmp_path / "lattices" / "racecar.json")


def test_a_broken_lattice_file_names_itself_and_where_it_is_broken(tmp_path):
    broken = json.loads((REPO / "params" / RACECAR).read_text())
    del broken["primitives"][3]["poses"]
    (tmp_path / "broken.json").write_text(json.dumps(broken))
    params, line = nav2_params(tmp_path, "broken.json", "lattice_filepath", "lattice_filepath")
    with pytest.raises(BtnavError) as err:
        load_params(params)
    assert err.value.line == line
    assert (
        str(tmp_path / "broken.json") in err.value.message and "primitives[3]" in err.value.message
    )
    (tmp_path / "broken.json").write_text('{"lattice_metadata": {')
    with pytest.raises(BtnavError, match="not a lattice file") as direct:
        load_lattice(tmp_path / "broken.json")
    assert direct.value.file == str(tmp_path / "broken.json") and direct.value.line == 1


def test_the_planner_server_plans_with_it(tmp_path):
    from ..nav.navstack_helpers import office, plan

    params, _ = nav2_params(tmp_path, "lattice/ackermann_0.5m_5cm.json")
    _w, rt, stack = office(params)
    plugin = stack.planner_server.plugins["GridBased"]
    assert isinstance(plugin, SmacPlannerLattice)
    goal = Pose2D(6.0, 3.0, 0.0)
    handle = plan(rt, goal)
    assert handle.succeeded, handle.result
    path = handle.result.value
    assert math.hypot(path.poses[-1, 0] - goal.x, path.poses[-1, 1] - goal.y) < 1e-6
    assert plugin.expansions > 0
    costs = stack.global_costmap.costmap.cost_at(path.poses[:, :2])
    assert np.all(costs < INSCRIBED_INFLATED_OBSTACLE)
