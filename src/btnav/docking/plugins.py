"""Importing this module registers btnav's dock plugins and the simulated dock detector
(entry point `btnav.plugins`, name `docking`)."""

from ..sim import dock_detector as _dock_detector  # noqa: F401
from . import simple_charging_dock as _simple_charging_dock  # noqa: F401
from . import simple_non_charging_dock as _simple_non_charging_dock  # noqa: F401
