"""opennav_docking_bt's DockRobot and UndockRobot: BtActionNodes on the docking server.

As in Nav2, DockRobot reads `dock_id` when `use_dock_id` (the default), else
`dock_pose`, `dock_type` and `max_staging_time`; `navigate_to_staging_pose` always. Both
write `success` (and DockRobot `num_retries`) after the goal, with Nav2's
`error_code_id` and `error_msg`; a canceled goal is SUCCESS with no error, as in Nav2.
"""

from __future__ import annotations

from typing import Any, ClassVar

from py_trees.common import Status

from ..core.error_codes import NavResult
from ..core.nav2_docking_msgs import DockRobotGoal, UndockRobotGoal
from ..plugins import register
from .base import input_port, output_port
from .nav2_actions import BASIC_INPUTS, BASIC_OUTPUTS, BtActionNode
from .nav2_context import PoseLike


@register("bt_node", "DockRobot")
class DockRobot(BtActionNode):
    """Dock at `dock_id` (or at `dock_pose` of `dock_type`), staging first if asked."""

    ACTION = "DockRobot"
    SERVER = "dock_robot"
    INPUT_PORTS: ClassVar = {
        "use_dock_id": input_port(bool, "Whether to use the dock's ID or dock pose fields", True),
        "dock_id": input_port(str, "Dock ID or name to use"),
        "dock_pose": input_port(PoseLike, "The dock pose, if not using dock id"),
        "dock_type": input_port(str, "The dock plugin type, if using dock pose"),
        "max_staging_time": input_port(
            float, "Maximum time to navigate to the staging pose", 1000.0
        ),
        "navigate_to_staging_pose": input_port(
            bool, "Whether to autonomously navigate to staging pose", True
        ),
        **BASIC_INPUTS,
    }
    OUTPUT_PORTS: ClassVar = {
        "success": output_port(bool, "If the action was successful"),
        "num_retries": output_port(int, "The number of retries executed"),
        **BASIC_OUTPUTS,
    }

    def make_goal(self) -> Any:
        goal = DockRobotGoal(
            use_dock_id=bool(self.get_input("use_dock_id")),
            navigate_to_staging_pose=bool(self.get_input("navigate_to_staging_pose")),
        )
        if goal.use_dock_id:
            goal.dock_id = self.optional("dock_id") or ""
        else:
            goal.dock_pose = self.optional("dock_pose")
            goal.dock_type = self.optional("dock_type") or ""
            goal.max_staging_time = float(self.get_input("max_staging_time"))
        return goal

    def _results(self, result: NavResult) -> None:
        value = result.value
        self._set_output("success", bool(getattr(value, "success", result.succeeded)))
        self._set_output("num_retries", int(getattr(value, "num_retries", 0)))

    def on_success(self, result: NavResult) -> Status:
        self._results(result)
        return super().on_success(result)

    def on_aborted(self, result: NavResult) -> Status:
        self._results(result)
        return super().on_aborted(result)


@register("bt_node", "UndockRobot")
class UndockRobot(BtActionNode):
    """Drive off the dock to its staging pose (`dock_type`: the dock docked at, by default)."""

    ACTION = "UndockRobot"
    SERVER = "undock_robot"
    INPUT_PORTS: ClassVar = {
        "dock_type": input_port(
            str, "The dock plugin type, if not previous instance used for docking"
        ),
        "max_undocking_time": input_port(
            float, "Maximum time to get back to the staging pose", 30.0
        ),
        **BASIC_INPUTS,
    }
    OUTPUT_PORTS: ClassVar = {
        "success": output_port(bool, "If the action was successful"),
        **BASIC_OUTPUTS,
    }

    def make_goal(self) -> Any:
        return UndockRobotGoal(
            dock_type=self.optional("dock_type") or "",
            max_undocking_time=float(self.get_input("max_undocking_time")),
        )

    def on_success(self, result: NavResult) -> Status:
        self._set_output("success", True)
        return super().on_success(result)

    def on_aborted(self, result: NavResult) -> Status:
        self._set_output("success", False)
        return super().on_aborted(result)
