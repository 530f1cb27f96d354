"""Nav2's cost values (nav2_costmap_2d/cost_values.hpp), so costmaps read the same in both."""

from __future__ import annotations

FREE_SPACE = 0
#: The robot's centre in this cell means its footprint touches an obstacle.
INSCRIBED_INFLATED_OBSTACLE = 253
LETHAL_OBSTACLE = 254
NO_INFORMATION = 255
#: The highest cost a cell can have and still be traversable by a planner.
MAX_NON_OBSTACLE = 252
