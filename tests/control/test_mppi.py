"""MPPI drives a unicycle along paths, around obstacles, within limits, deterministically."""

from __future__ import annotations

import math

import numpy as np
import pytest

from btnav.control.goal_checkers import SimpleGoalChecker
from btnav.control.mppi import MPPIController, MPPIParams
from btnav.core.geometry import Pose2D
from btnav.core.messages import Path, Twist
from btnav.costmap.cost_values import INSCRIBED_INFLATED_OBSTACLE, LETHAL_OBSTACLE
from btnav.costmap.costmap_2d import Costmap2D
from btnav.params import load_params

from .unicycle import curved_path, drive, free_costmap, straight_path


@pytest.fixture(scope="module")
def nav2_mppi(nav2_params_file) -> MPPIParams:
    """The FollowPath section of Nav2's nav2_params.yaml, validated by the loader."""
    section = load_params(nav2_params_file).servers["controller_server"].plugin("FollowPath")
    assert section.cls is MPPIController
    return section.params  # type: ignore[return-value]


def with_obstacle(
    center: tuple[float, float], radius: float, robot_radius: float = 0.22
) -> Costmap2D:
    """A free costmap with a lethal disc inflated as Nav2's inflation layer does it."""
    cm = free_costmap()
    mx, my = np.meshgrid(np.arange(cm.size_x), np.arange(cm.size_y))
    wx = cm.origin_x + (mx + 0.5) * cm.resolution
    wy = cm.origin_y + (my + 0.5) * cm.resolution
    d = np.hypot(wx - center[0], wy - center[1]) - radius  # distance to the obstacle's edge
    cost = np.where(d <= 0, LETHAL_OBSTACLE, 0)
    cost = np.where((d > 0) & (d <= robot_radius), INSCRIBED_INFLATED_OBSTACLE, cost)
    ring = (d > robot_radius) & (d <= 0.55)
    cost = np.where(ring, np.floor(252 * np.exp(-3.0 * (d - robot_radius))), cost)
    cm.costs[:] = cost.astype(np.uint8)
    return cm


def cells_under(cm: Costmap2D, poses: np.ndarray) -> np.ndarray:
    return cm.cost_at(poses[:, :2])


@pytest.mark.parametrize("make_path", [straight_path, curved_path])
def test_reaches_the_end_of_the_path(nav2_mppi, make_path):
    path = make_path()
    pose, cmds, poses, reached = drive(
        MPPIController("FollowPath", nav2_mppi, seed=3), path, free_costmap(), SimpleGoalChecker()
    )
    assert reached, f"stopped at {pose} after {len(cmds)} cycles"
    goal = path.poses[-1]
    assert math.hypot(pose.x - goal[0], pose.y - goal[1]) < 0.25
    # It follows the path: never far from it on the way.
    d = np.hypot(
        poses[:, None, 0] - path.poses[None, :, 0], poses[:, None, 1] - path.poses[None, :, 1]
    )
    assert d.min(axis=1).max() < 0.2
    # And it drives forward at a sensible speed (no creeping).
    assert max(v for v, _ in cmds) > 0.3
    assert min(v for v, _ in cmds) > -0.05


@pytest.mark.parametrize(
    "obstacle", [(2.0, 0.32), (2.0, 0.2)], ids=["beside_path", "over_path_edge"]
)
def test_keeps_clear_of_a_lethal_obstacle(nav2_mppi, obstacle):
    cm = with_obstacle(obstacle, 0.1)
    controller = MPPIController("FollowPath", nav2_mppi, seed=5)
    path = straight_path(length=4.0)
    controller.set_plan(path)
    gc = SimpleGoalChecker()
    pose, vel = Pose2D(), Twist()
    goal = Pose2D.from_array(path.poses[-1])
    poses = [pose.as_array()]
    for _ in range(400):
        if gc.is_goal_reached(pose, goal, vel):
            break
        cmd = controller.compute_velocity_commands(pose, vel, cm, gc)
        # The plan MPPI settles on never runs into the obstacle's lethal cells.
        best = controller.optimal_trajectory(pose)
        assert (cells_under(cm, best) < LETHAL_OBSTACLE).all()
        v, w = cmd.linear_x, cmd.angular_z
        yaw = pose.yaw + 0.5 * w * 0.05
        pose = Pose2D(
            pose.x + v * 0.05 * math.cos(yaw),
            pose.y + v * 0.05 * math.sin(yaw),
            pose.yaw + w * 0.05,
        )
        vel = Twist(linear_x=v, angular_z=w)
        poses.append(pose.as_array())
    assert gc.is_goal_reached(pose, goal, vel), f"stopped at {pose}"
    # The robot's centre never entered a cell where a round robot would touch the obstacle.
    assert (cells_under(cm, np.array(poses)) < INSCRIBED_INFLATED_OBSTACLE).all()


def test_respects_velocity_and_acceleration_limits(nav2_mppi):
    p = nav2_mppi.model_copy(
        update={"vx_max": 0.4, "wz_max": 1.0, "ax_max": 1.0, "ax_min": -1.0, "az_max": 2.0}
    )
    _pose, cmds, _poses, reached = drive(
        MPPIController("FollowPath", p, seed=7), curved_path(), free_costmap(), SimpleGoalChecker()
    )
    assert reached
    v = np.array([c[0] for c in cmds])
    w = np.array([c[1] for c in cmds])
    eps = 1e-4
    assert v.max() <= 0.4 + eps and v.min() >= p.vx_min - eps
    assert np.abs(w).max() <= 1.0 + eps
    dt = p.model_dt
    # Each command is reachable from the speed measured one cycle earlier.
    dv = np.diff(np.concatenate([[0.0], v])) / dt
    dw = np.diff(np.concatenate([[0.0], w])) / dt
    assert dv.max() <= p.ax_max * 1.05 and dv.min() >= p.ax_min * 1.05
    assert np.abs(dw).max() <= p.az_max * 1.05


def test_same_seed_same_commands(nav2_mppi):
    p = nav2_mppi.model_copy(update={"batch_size": 500})

    def run(seed: int) -> list[tuple[float, float]]:
        return drive(
            MPPIController("FollowPath", p, seed=seed),
            curved_path(),
            free_costmap(),
            SimpleGoalChecker(),
            max_steps=40,
        )[1]

    a, b, c = run(11), run(11), run(12)
    assert a == b
    assert a != c
    # A generator passed in is used as given.
    g1, g2 = np.random.default_rng(4), np.random.default_rng(4)
    cm, path = free_costmap(), straight_path()
    c1 = MPPIController("FollowPath", p, rng=g1)
    c2 = MPPIController("FollowPath", p, rng=g2)
    c1.set_plan(path)
    c2.set_plan(path)
    assert c1.compute_velocity_commands(Pose2D(), Twist(), cm) == c2.compute_velocity_commands(
        Pose2D(), Twist(), cm
    )


def test_no_valid_control_when_boxed_in(nav2_mppi):
    from btnav.control.exceptions import FollowPathError, NoValidControl

    cm = free_costmap()
    cm.costs[:] = LETHAL_OBSTACLE
    controller = MPPIController(
        "FollowPath", nav2_mppi.model_copy(update={"batch_size": 200}), seed=1
    )
    controller.set_plan(straight_path())
    with pytest.raises(NoValidControl) as info:
        controller.compute_velocity_commands(Pose2D(), Twist(), cm)
    assert info.value.error_code == FollowPathError.NO_VALID_CONTROL == 106


def test_empty_path_is_invalid(nav2_mppi):
    from btnav.control.exceptions import InvalidPath

    with pytest.raises(InvalidPath):
        MPPIController("FollowPath", nav2_mppi).set_plan(Path(0.0, np.zeros((0, 3)), "odom"))


def test_speed_limit_scales_velocities(nav2_mppi):
    c = MPPIController("FollowPath", nav2_mppi, seed=2)
    c.set_speed_limit(50.0, percentage=True)
    _pose, cmds, _poses, _ = drive(
        c, straight_path(), free_costmap(), SimpleGoalChecker(), max_steps=60
    )
    assert max(v for v, _ in cmds) <= 0.25 + 1e-4
    c.set_speed_limit(0.0, percentage=False)
    assert c.model.c.vx_max == nav2_mppi.vx_max
