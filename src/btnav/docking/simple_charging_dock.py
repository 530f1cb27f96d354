"""opennav_docking's SimpleChargingDock: a charger found by pose or by detection.

btnav simulates no battery, so the robot counts as charging while it is docked (Nav2's
behaviour with `use_battery_status: false`); `use_battery_status` and
`charging_threshold` are accepted and listed as ignored. Charging stops as soon as the
robot leaves the dock, so `disable_charging` always succeeds.
"""

from __future__ import annotations

from ..params.schema import ignored
from ..plugins import register
from .simple_dock import SimpleDock, SimpleDockParams

_NO_BATTERY = "btnav simulates no battery: a docked robot counts as charging"


@register("charging_dock", "opennav_docking::SimpleChargingDock")
class SimpleChargingDock(SimpleDock):
    class Params(SimpleDockParams):
        use_battery_status: bool = ignored(True, _NO_BATTERY)
        charging_threshold: float = ignored(0.5, _NO_BATTERY)

    params: Params

    def is_charging(self) -> bool:
        return self.is_docked()

    def disable_charging(self) -> bool:
        return True

    def has_stopped_charging(self) -> bool:
        return not self.is_charging()
