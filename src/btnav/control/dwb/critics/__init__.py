"""dwb_critics: one critic per module, each registered as kind `critic` under Nav2's name."""

from . import (  # noqa: F401
    base_obstacle,
    goal_align,
    goal_dist,
    obstacle_footprint,
    oscillation,
    path_align,
    path_dist,
    prefer_forward,
    rotate_to_goal,
    twirling,
)
