"""Importing this module registers btnav's built-in tree nodes (entry point `btnav.plugins`)."""

from . import controls as _controls  # noqa: F401
from . import decorators as _decorators  # noqa: F401
from . import explore_nodes as _explore_nodes  # noqa: F401
from . import leaves as _leaves  # noqa: F401
from . import nav2_actions as _nav2_actions  # noqa: F401
from . import nav2_behavior_actions as _nav2_behavior_actions  # noqa: F401
from . import nav2_collision_nodes as _nav2_collision_nodes  # noqa: F401
from . import nav2_conditions as _nav2_conditions  # noqa: F401
from . import nav2_controls as _nav2_controls  # noqa: F401
from . import nav2_decorators as _nav2_decorators  # noqa: F401
from . import nav2_docking_nodes as _nav2_docking_nodes  # noqa: F401
from . import nav2_path_actions as _nav2_path_actions  # noqa: F401
from . import nav2_pose_decorators as _nav2_pose_decorators  # noqa: F401
from . import nav2_route_nodes as _nav2_route_nodes  # noqa: F401
from . import nav2_selectors as _nav2_selectors  # noqa: F401
from . import nav2_services as _nav2_services  # noqa: F401
