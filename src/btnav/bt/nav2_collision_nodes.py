"""Nav2's ToggleCollisionMonitor: switch the collision monitor's zones on or off from a tree.

It calls the monitor's `toggle` service (nav2_msgs/srv/Toggle, Nav2's
`collision_monitor/toggle`; a leading "/" is accepted) with `enable`, and succeeds
when the service answers success, on the tick it starts (btnav's services answer within
the call). Typical use: turn the monitor off before docking and on again after.
"""

from __future__ import annotations

from typing import ClassVar

from py_trees.common import Status

from ..plugins import register
from .base import F, S, input_port
from .nav2_services import SERVICE_INPUTS, BtServiceNode


@register("bt_node", "ToggleCollisionMonitor")
class ToggleCollisionMonitor(BtServiceNode):
    """Enable (`enable: true`, the default) or disable the collision monitor."""

    INPUT_PORTS: ClassVar = {
        "enable": input_port(bool, "Whether to enable or disable the collision monitor", True),
        **SERVICE_INPUTS,
    }
    OUTPUT_PORTS: ClassVar = {}

    @property
    def service_name(self) -> str:
        return super().service_name.lstrip("/")

    def has_service(self, name: str, services: list[str]) -> bool:
        return name.lstrip("/") in services

    def call(self, name: str) -> Status:
        response = self.stack.services()[name.lstrip("/")](bool(self.get_input("enable")))
        self.feedback_message = response.message
        return S if response.success else F
