"""Importing this module registers btnav's costmap filters (kind `costmap_filter`)."""

from . import binary_filter, keepout_filter, speed_filter  # noqa: F401  (they register on import)
