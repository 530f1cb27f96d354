"""Importing this module registers nav2_route's plugins (entry point `btnav.plugins`):
edge cost functions, route operations and the GeoJSON graph file loader and saver."""

from . import geojson as _geojson  # noqa: F401
from .edge_cost_functions import costmap_scorer as _costmap_scorer  # noqa: F401
from .edge_cost_functions import distance_scorer as _distance_scorer  # noqa: F401
from .edge_cost_functions import dynamic_edges_scorer as _dynamic_edges_scorer  # noqa: F401
from .edge_cost_functions import orientation_scorers as _orientation_scorers  # noqa: F401
from .edge_cost_functions import penalty_scorer as _penalty_scorer  # noqa: F401
from .edge_cost_functions import semantic_scorer as _semantic_scorer  # noqa: F401
from .edge_cost_functions import time_scorer as _time_scorer  # noqa: F401
from .route_operations import adjust_speed_limit as _adjust_speed_limit  # noqa: F401
from .route_operations import collision_monitor as _collision_monitor  # noqa: F401
from .route_operations import rerouting_service as _rerouting_service  # noqa: F401
from .route_operations import time_marker as _time_marker  # noqa: F401
from .route_operations import trigger_event as _trigger_event  # noqa: F401
