"""nav2_core's route exceptions: each names the action error code it becomes.

The route server turns them into its actions' results (NO_VALID_ROUTE, TIMEOUT, ...),
never into an exception in the caller. A graph file the user got wrong is a
`GraphError` instead: a located `BtnavError` at load time.
"""

from __future__ import annotations

from ..core.errors import ConfigError


class GraphError(ConfigError):
    """A route graph file btnav cannot read (missing, not GeoJSON, a broken reference)."""


class RouteException(Exception):
    """Base: the action ends with `code_name` (an error code of both route actions)."""

    code_name = "UNKNOWN"


class NoValidRouteCouldBeFound(RouteException):
    code_name = "NO_VALID_ROUTE"


class RouteTimedOut(RouteException):
    code_name = "TIMEOUT"


class RouteTFError(RouteException):
    code_name = "TF_ERROR"


class NoValidGraph(RouteException):
    code_name = "NO_VALID_GRAPH"


class IndeterminantNodesOnGraph(RouteException):
    code_name = "INDETERMINANT_NODES_ON_GRAPH"


class InvalidEdgeScorerUse(RouteException):
    code_name = "INVALID_EDGE_SCORER_USE"


class OperationFailed(RouteException):
    """Only ComputeAndTrackRoute has this code (an operation failed while tracking)."""

    code_name = "OPERATION_FAILED"
