"""opennav_docking's SimpleNonChargingDock: a dock the robot parks at, with no charging
(a cart, a conveyor station); docking succeeds as soon as the robot is docked."""

from __future__ import annotations

from ..plugins import register
from .charging_dock import NonChargingDock
from .simple_dock import SimpleDock


@register("charging_dock", "opennav_docking::SimpleNonChargingDock")
class SimpleNonChargingDock(SimpleDock, NonChargingDock):
    pass
