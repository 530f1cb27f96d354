"""The ground-truth localiser: the estimate is exact wherever a sensor measures."""

from __future__ import annotations

from pathlib import Path

from btnav.core.geometry import Pose2D, angle_diff
from btnav.core.messages import Twist
from btnav.nav.runtime import Runtime
from btnav.sim.world import World

WORLD = Path(__file__).resolve().parents[2] / "worlds" / "small_office.yaml"


def test_every_scan_is_placed_where_the_robot_truly_is():
    """map -> laser at each scan is the true laser pose, odometry drift or not (corrected
    only at the localiser's rate, a scan was placed with one period of odometry noise)."""
    world = World.from_file(WORLD, seed=3)
    runtime = Runtime(world, seed=3)
    runtime.use_localizer("ground_truth")
    errors: list[tuple[float, float]] = []

    def on_scan(scan) -> None:
        placed = runtime.frames.lookup("map", scan.frame_id)
        truth = world.robot_pose @ Pose2D(0.1, 0.0, 0.0)  # the lidar's mount
        errors.append((placed.distance_to(truth), abs(angle_diff(placed.yaw, truth.yaw))))

    runtime.subscribe("scan", on_scan)
    runtime.set_cmd_vel(Twist(linear_x=0.3, angular_z=0.4))
    runtime.spin_for(5.0)
    start = Pose2D(*world.spec.robot.pose)
    drift = (start @ runtime.latest_odom.pose).distance_to(world.robot_pose)
    assert len(errors) == 50 and drift > 0.005  # odometry alone is centimetres off
    assert max(e[0] for e in errors) < 1e-9 and max(e[1] for e in errors) < 1e-9
