"""btnav_example: one plugin of each kind a btnav user most often writes.

- `astar_planner.AStarPlanner` (`planner`, `btnav_example::AStarPlanner`);
- `pure_pursuit.PurePursuitController` (`controller`, `btnav_example::PurePursuitController`);
- `keepout_zones_layer.KeepoutZonesLayer` (`costmap_layer`, `btnav_example::KeepoutZonesLayer`);
- `is_path_longer_than.IsPathLongerThan` (`bt_node`, `IsPathLongerThan`).

Each module registers its plugin when it is imported. An installed package is found
through its `btnav.plugins` entry points (pyproject.toml), one per module, so btnav
imports them when a params file or a tree names one of their plugins; importing this
package imports all four (a mission's `plugins: [btnav_example]` does that).
"""

from . import astar_planner, is_path_longer_than, keepout_zones_layer, pure_pursuit

__all__ = ["astar_planner", "is_path_longer_than", "keepout_zones_layer", "pure_pursuit"]
