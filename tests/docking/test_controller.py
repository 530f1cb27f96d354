"""The docking controller: Nav2's graceful control law converges onto the dock, and its
look-ahead sees an obstacle on the way but not the dock itself."""

from __future__ import annotations

import math

import numpy as np
import pytest

from btnav.core.geometry import Pose2D, angle_diff
from btnav.costmap.cost_values import LETHAL_OBSTACLE
from btnav.costmap.costmap_2d import Costmap2D
from btnav.docking.controller import DockingController
from btnav.params.docking import DockingControllerParams

#: nav2_params.yaml's docking controller (v_linear_min = v_linear_max = 0.15).
NAV2 = DockingControllerParams(k_phi=3.0, k_delta=2.0, v_linear_min=0.15, v_linear_max=0.15)
DT = 0.02  # 50 Hz, the docking server's controller_frequency


def drive(controller, robot, target, done, backward=False, steps=3000):
    """Unicycle steps of DT towards `target` (world frame) until `done(robot)`."""
    for _ in range(steps):
        if done(robot):
            return robot
        cmd, _ = controller.compute_velocity_command(robot.inverse() @ target, True, backward)
        robot = robot @ Pose2D(cmd.linear_x * DT, 0.0, cmd.angular_z * DT)
    raise AssertionError(f"not there after {steps} steps: {robot}")


@pytest.mark.parametrize(
    "start",
    [(-0.7, 0.0, 0.0), (-0.7, 0.15, 0.0), (-0.7, -0.2, 0.3), (-0.8, 0.1, -0.4), (-1.0, 0.3, 0.5)],
)
def test_the_approach_reaches_the_dock_from_offsets_at_the_staging_pose(start):
    """As the docking server does: aim 0.25 m beyond the dock, stop within 5 cm of it."""
    controller = DockingController(NAV2, base_frame="base_link")
    dock = Pose2D(0.0, 0.0, 0.0)
    robot = drive(
        controller,
        Pose2D(*start),
        dock @ Pose2D(0.25, 0.0, 0.0),
        lambda r: math.hypot(r.x - dock.x, r.y - dock.y) < 0.05,
    )
    assert abs(robot.y) < 0.02  # on the dock's axis
    assert abs(angle_diff(robot.yaw, dock.yaw)) < 0.2


@pytest.mark.parametrize("start", [(0.0, 0.0, 0.0), (0.0, 0.02, 0.05), (-0.02, -0.03, -0.1)])
def test_backing_off_the_dock_reaches_the_staging_pose_within_the_undock_tolerances(start):
    controller = DockingController(NAV2, base_frame="base_link")
    staging = Pose2D(-0.7, 0.0, 0.0)
    robot = drive(
        controller,
        Pose2D(*start),
        staging,
        lambda r: (
            math.hypot(r.x - staging.x, r.y - staging.y) < 0.05
            and abs(angle_diff(staging.yaw, r.yaw)) < 0.1
        ),
        backward=True,
    )
    assert robot.x < -0.6  # it drove backwards, it did not turn round


def test_the_turn_rate_and_speed_stay_within_their_limits():
    controller = DockingController(DockingControllerParams(), base_frame="base_link")
    for target in (Pose2D(0.5, 0.5, 1.0), Pose2D(0.05, -0.3, -2.0), Pose2D(2.0, 0.0, 0.0)):
        cmd, free = controller.compute_velocity_command(target, True)
        assert free  # no costmap: nothing to collide with
        assert abs(cmd.angular_z) <= 0.75 + 1e-12 and 0.0 < cmd.linear_x <= 0.25 + 1e-12


def test_rotating_in_place_slows_to_stop_on_the_heading():
    controller = DockingController(NAV2, base_frame="base_link")
    assert controller.compute_rotate_to_heading_command(2.0, 0.0, DT).angular_z == pytest.approx(
        3.2 * DT
    )  # accelerating from rest
    assert controller.compute_rotate_to_heading_command(-2.0, -1.0, DT).angular_z == -1.0
    near = controller.compute_rotate_to_heading_command(0.01, 1.0, DT).angular_z
    assert near == pytest.approx(math.sqrt(2 * 3.2 * 0.01))


class Costmap:
    """A CostmapROS stand-in: an odom costmap 4 x 4 m with a wall across x = 1.0."""

    global_frame = "odom"
    footprint = np.array([[0.2, 0.2], [0.2, -0.2], [-0.2, -0.2], [-0.2, 0.2]])

    def __init__(self, wall_x: float) -> None:
        self.costmap = Costmap2D.empty(80, 80, 0.05, -2.0, -2.0, "odom")
        col = int((wall_x + 2.0) / 0.05)
        self.costmap.costs[:, col] = LETHAL_OBSTACLE


def controller_on(costmap, threshold=0.3):
    params = NAV2.model_copy(update={"dock_collision_threshold": threshold})
    return DockingController(
        params, base_frame="base_link", costmap_ros=costmap, lookup=lambda t, s: Pose2D()
    )


def test_an_obstacle_on_the_way_to_the_dock_stops_the_approach():
    # the look-ahead (projection_time 5 s at 0.15 m/s) reaches 0.73 m: the wall at 0.6 is in it
    controller = controller_on(Costmap(wall_x=0.6))
    _, free = controller.compute_velocity_command(Pose2D(2.0, 0.0, 0.0), True)
    assert not free
    assert controller.trajectory is not None and len(controller.trajectory) > 1


def test_the_dock_itself_is_not_an_obstacle_within_dock_collision_threshold():
    # the dock's face (the wall) 0.21 m ahead of the dock pose at x = 0.5; the target 0.25 beyond
    target = Pose2D(0.75, 0.0, 0.0)
    near_dock = controller_on(Costmap(wall_x=0.71), threshold=0.5)
    assert near_dock.compute_velocity_command(target, True)[1]
    checked_to_the_end = controller_on(Costmap(wall_x=0.71), threshold=0.05)
    assert not checked_to_the_end.compute_velocity_command(target, True)[1]
    off = controller_on(Costmap(wall_x=0.6))
    off.params = off.params.model_copy(update={"use_collision_detection": False})
    assert off.compute_velocity_command(Pose2D(2.0, 0.0, 0.0), True)[1]
