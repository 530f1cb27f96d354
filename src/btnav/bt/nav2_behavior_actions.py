"""Nav2's behavior_server action nodes (Spin, BackUp, DriveOnHeading, Wait,
AssistedTeleop): BtActionNodes."""

from __future__ import annotations

from typing import Any, ClassVar

from py_trees.common import Status

from ..core.error_codes import NavResult
from ..core.nav2_msgs import AssistedTeleopGoal, BackUpGoal, DriveOnHeadingGoal, SpinGoal, WaitGoal
from ..plugins import register
from .base import S, input_port
from .nav2_actions import BASIC_INPUTS, BASIC_OUTPUTS, BtActionNode
from .nav2_context import increment_recovery_count

# -- behavior_server -----------------------------------------------------------------------


@register("bt_node", "Spin")
class Spin(BtActionNode):
    """Turn in place by `spin_dist` radians (a recovery unless `is_recovery` is false)."""

    ACTION = "Spin"
    SERVER = "spin"
    INPUT_PORTS: ClassVar = {
        "spin_dist": input_port(float, "Spin distance (radians)", 1.57),
        "time_allowance": input_port(float, "Time allowed before the behaviour fails (s)", 10.0),
        "is_recovery": input_port(bool, "True if the action is being used as a recovery", True),
        "disable_collision_checks": input_port(bool, "Disable collision checking", False),
        **BASIC_INPUTS,
    }
    OUTPUT_PORTS: ClassVar = dict(BASIC_OUTPUTS)

    def make_goal(self) -> Any:
        if self.get_input("is_recovery"):
            increment_recovery_count()
        return SpinGoal(
            target_yaw=self.get_input("spin_dist"),
            time_allowance=self.get_input("time_allowance"),
            disable_collision_checks=self.get_input("disable_collision_checks"),
        )


@register("bt_node", "BackUp")
class BackUp(BtActionNode):
    """Drive backwards `backup_dist` metres at `backup_speed` (a recovery)."""

    ACTION = "BackUp"
    SERVER = "backup"
    IS_RECOVERY = True
    INPUT_PORTS: ClassVar = {
        "backup_dist": input_port(float, "Total distance to back up (m)", 0.15),
        "backup_speed": input_port(float, "Backup speed (m/s)", 0.025),
        "time_allowance": input_port(float, "Time allowed before the behaviour fails (s)", 10.0),
        "disable_collision_checks": input_port(bool, "Disable collision checking", False),
        **BASIC_INPUTS,
    }
    OUTPUT_PORTS: ClassVar = dict(BASIC_OUTPUTS)

    def make_goal(self) -> Any:
        return BackUpGoal(
            target=self.get_input("backup_dist"),
            speed=self.get_input("backup_speed"),
            time_allowance=self.get_input("time_allowance"),
            disable_collision_checks=self.get_input("disable_collision_checks"),
        )


@register("bt_node", "DriveOnHeading")
class DriveOnHeading(BtActionNode):
    """Drive straight `dist_to_travel` metres at `speed` (not counted as a recovery)."""

    ACTION = "DriveOnHeading"
    SERVER = "drive_on_heading"
    INPUT_PORTS: ClassVar = {
        "dist_to_travel": input_port(float, "Distance to travel (m)", 0.15),
        "speed": input_port(float, "Speed at which to travel (m/s)", 0.025),
        "time_allowance": input_port(float, "Time allowed before the behaviour fails (s)", 10.0),
        "disable_collision_checks": input_port(bool, "Disable collision checking", False),
        **BASIC_INPUTS,
    }
    OUTPUT_PORTS: ClassVar = dict(BASIC_OUTPUTS)

    def make_goal(self) -> Any:
        return DriveOnHeadingGoal(
            target=self.get_input("dist_to_travel"),
            speed=self.get_input("speed"),
            time_allowance=self.get_input("time_allowance"),
            disable_collision_checks=self.get_input("disable_collision_checks"),
        )


@register("bt_node", "Wait")
class Wait(BtActionNode):
    """Wait `wait_duration` seconds of sim time (a recovery; a negative time counts as positive)."""

    ACTION = "Wait"
    SERVER = "wait"
    IS_RECOVERY = True
    INPUT_PORTS: ClassVar = {
        "wait_duration": input_port(float, "Wait time (s)", 1.0),
        **BASIC_INPUTS,
    }
    OUTPUT_PORTS: ClassVar = dict(BASIC_OUTPUTS)

    def make_goal(self) -> Any:
        return WaitGoal(time=abs(self.get_input("wait_duration")))


@register("bt_node", "AssistedTeleop")
class AssistedTeleop(BtActionNode):
    """Teleop through the local costmap for `time_allowance` seconds. A failure is the
    node's FAILURE only as a recovery (`is_recovery`); otherwise the node succeeds, as
    Nav2's does (the person driving decides)."""

    ACTION = "AssistedTeleop"
    SERVER = "assisted_teleop"
    INPUT_PORTS: ClassVar = {
        "is_recovery": input_port(bool, "If true increment the recovery counter", False),
        "time_allowance": input_port(float, "Time to invoke the behaviour for (s)", 10.0),
        **BASIC_INPUTS,
    }
    OUTPUT_PORTS: ClassVar = dict(BASIC_OUTPUTS)

    def make_goal(self) -> Any:
        if self.get_input("is_recovery"):
            increment_recovery_count()
        return AssistedTeleopGoal(time_allowance=self.get_input("time_allowance"))

    def on_aborted(self, result: NavResult) -> Status:
        status = super().on_aborted(result)
        return status if self.get_input("is_recovery") else S
