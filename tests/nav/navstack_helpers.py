"""Helpers for the server and end-to-end tests: the small office with Nav2's params."""

from __future__ import annotations

import math
import time
from dataclasses import dataclass
from pathlib import Path

import yaml

from btnav.core.geometry import Pose2D
from btnav.core.nav2_msgs import ComputePathToPoseGoal, FollowPathGoal
from btnav.maps.map_io import load_map
from btnav.nav.runtime import Runtime
from btnav.nav.stack import NavStack
from btnav.sim.world import World

REPO = Path(__file__).resolve().parents[2]
WORLD = REPO / "worlds" / "small_office.yaml"
MAP = REPO / "maps" / "small_office.yaml"
PARAMS = REPO / "params" / "nav2_params.yaml"

#: Nav2's DWB section (nav2_params.yaml of Humble), speeds raised to this robot's 0.5 m/s.
DWB = {
    "plugin": "dwb_core::DWBLocalPlanner",
    "min_vel_x": 0.0,
    "min_vel_y": 0.0,
    "max_vel_x": 0.5,
    "max_vel_y": 0.0,
    "max_vel_theta": 1.0,
    "min_speed_xy": 0.0,
    "max_speed_xy": 0.5,
    "min_speed_theta": 0.0,
    "acc_lim_x": 2.5,
    "acc_lim_y": 0.0,
    "acc_lim_theta": 3.2,
    "decel_lim_x": -2.5,
    "decel_lim_y": 0.0,
    "decel_lim_theta": -3.2,
    "vx_samples": 20,
    "vy_samples": 5,
    "vtheta_samples": 20,
    "sim_time": 1.7,
    "linear_granularity": 0.05,
    "angular_granularity": 0.025,
    "transform_tolerance": 0.2,
    "xy_goal_tolerance": 0.25,
    "trans_stopped_velocity": 0.25,
    "short_circuit_trajectory_evaluation": True,
    "stateful": True,
    "critics": [
        "RotateToGoal",
        "Oscillation",
        "BaseObstacle",
        "GoalAlign",
        "PathAlign",
        "PathDist",
        "GoalDist",
    ],
    "BaseObstacle.scale": 0.02,
    "PathAlign.scale": 32.0,
    "PathAlign.forward_point_distance": 0.1,
    "GoalAlign.scale": 24.0,
    "GoalAlign.forward_point_distance": 0.1,
    "PathDist.scale": 32.0,
    "GoalDist.scale": 24.0,
    "RotateToGoal.scale": 32.0,
    "RotateToGoal.slowing_factor": 5.0,
    "RotateToGoal.lookahead_time": -1.0,
}


#: DWB as Nav2 documents it for a robot that is not round: ObstacleFootprint (the costmap's
#: footprint laid at every pose) in place of BaseObstacle (the cell under its centre).
DWB_FOOTPRINT = {
    **{k: v for k, v in DWB.items() if not k.startswith("BaseObstacle.")},
    "critics": ["ObstacleFootprint" if c == "BaseObstacle" else c for c in DWB["critics"]],
    "ObstacleFootprint.scale": 0.02,
}


def params_with_controller(tmp_path: Path, section: dict) -> Path:
    """A copy of Nav2's params whose FollowPath section is `section` (nothing else changes)."""
    doc = yaml.safe_load(PARAMS.read_text())
    doc["controller_server"]["ros__parameters"]["FollowPath"] = section
    out = tmp_path / "nav2_params.yaml"
    out.write_text(yaml.safe_dump(doc, sort_keys=False))
    return out


def world_with(tmp_path: Path, *obstacles: dict) -> Path:
    """A copy of the small office with extra obstacles (not in the map)."""
    doc = yaml.safe_load(WORLD.read_text())
    doc["obstacles"] = [*doc.get("obstacles", []), *obstacles]
    out = tmp_path / "office_plus.yaml"
    out.write_text(yaml.safe_dump(doc, sort_keys=False))
    return out


def office(
    params: Path = PARAMS, world: Path = WORLD, seed: int = 0
) -> tuple[World, Runtime, NavStack]:
    w = World.from_file(world, seed=seed)
    rt = Runtime(w, seed=seed)
    rt.use_localizer("ground_truth")
    stack = NavStack.build(rt, params, load_map(MAP), seed=seed)
    return w, rt, stack


def plan(rt: Runtime, goal: Pose2D, planner_id: str = ""):
    h = rt.action_client("compute_path_to_pose").send_goal(ComputePathToPoseGoal(goal, planner_id))
    assert rt.run_until(lambda: h.done, 1.0)
    return h


@dataclass
class Run:
    handle: object
    sim_time: float
    wall_time: float
    final: Pose2D
    collisions: int


def follow(world: World, rt: Runtime, path, timeout: float = 90.0, **goal_kw) -> Run:
    t0, w0 = rt.now, time.perf_counter()
    h = rt.action_client("follow_path").send_goal(FollowPathGoal(path, **goal_kw))
    rt.run_until(lambda: h.done, timeout)
    return Run(h, rt.now - t0, time.perf_counter() - w0, world.robot_pose, world.collisions)


def xy_dist(a: Pose2D, b: Pose2D) -> float:
    return math.hypot(a.x - b.x, a.y - b.y)
