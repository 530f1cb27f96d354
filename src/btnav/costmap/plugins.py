"""Importing this module registers btnav's built-in costmap plugins (entry point `btnav.plugins`)."""

from . import inflation_layer, obstacle_layer, static_layer  # noqa: F401  (they register on import)
from .filters import plugins as _filters  # noqa: F401  (keepout, speed, binary filters)
