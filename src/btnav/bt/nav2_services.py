"""Nav2's service client nodes: the clear-costmap services, ValidatePath and
ReinitializeGlobalLocalization.

A Nav2 `BtServiceNode` sends its request on the first tick and returns RUNNING until
the answer comes (FAILURE after `server_timeout`). btnav's services answer within the
call, so these nodes finish on the tick they start. The services are the stack's
(`NavStack.services()`, Nav2's names such as
`local_costmap/clear_entirely_local_costmap`), given with `context={"stack": stack}`.
A constant `service_name` the stack does not offer is a load error (Nav2 waits for
the service when it builds the node and gives up); with no stack the node fails.
The clear-costmap nodes count as recoveries (`number_recoveries`), as in Nav2.
"""

from __future__ import annotations

from types import SimpleNamespace
from typing import Any, ClassVar

import numpy as np
import yaml
from py_trees.common import Status
from py_trees.ports import PortInformation

from ..behaviors.collision import CollisionChecker
from ..control.path_handler import integrated_index
from ..core import fmath
from ..core.errors import UnknownNameError
from ..core.geometry import Pose2D
from ..core.messages import Path, PoseStamped
from ..core.suggest import best_match
from ..costmap.cost_values import INSCRIBED_INFLATED_OBSTACLE, LETHAL_OBSTACLE, NO_INFORMATION
from ..plugins import register
from .base import F, S, input_port
from .nav2_context import Nav2Leaf, PoseLike, increment_recovery_count

SERVICE_INPUTS: dict[str, PortInformation] = {
    "service_name": input_port(str, "Service name"),
    "server_timeout": input_port(int, "Service server timeout (ms); the sim answers at once"),
}


class BtServiceNode(Nav2Leaf):
    """Base of the nodes that call one of the stack's services."""

    #: The service used when `service_name` is not given ("" = it must be given).
    SERVICE: ClassVar[str] = ""
    #: The last service name found among the stack's (looked up once, not every tick).
    _known: str | None = None

    @property
    def service_name(self) -> str:
        return self.optional("service_name") or self.SERVICE

    def available(self) -> list[str] | None:
        """The services there are (None without a stack)."""
        return None if self.stack is None else sorted(self.stack.services())

    def has_service(self, name: str, services: list[str]) -> bool:
        return name in services

    def setup_ports(self, *args: Any, **kwargs: Any) -> None:
        super().setup_ports(*args, **kwargs)
        services = self.available()
        if services is None or not self.blackboard_client.exists("service_name"):
            return
        name = self.get_input("service_name")
        if not self.has_service(name, services):
            raise UnknownNameError(
                f"{type(self).__name__} '{self.name}': service '{name}' not available; "
                f"services: {', '.join(services)}",
                suggestion=best_match(name, services),
            )

    def update(self) -> Status:
        name = self.service_name
        if name and self.stack is not None and self._known == name:
            return self.call(name)  # found before: services do not go away
        services = self.available()
        if services is None:
            self.feedback_message = "no stack: load the tree with context={'stack': nav_stack}"
            return F
        if not name or not self.has_service(name, services):
            self.feedback_message = f"no service '{name}'; services: {', '.join(services)}"
            return F
        self._known = name
        return self.call(name)

    def call(self, name: str) -> Status:
        raise NotImplementedError


class _ClearCostmap(BtServiceNode):
    """Clear-costmap services (nav2_costmap_2d's ClearCostmapService)."""

    INPUT_PORTS: ClassVar = {
        **SERVICE_INPUTS,
        "plugins": input_port(list[str], "Costmap plugins to clear (all if not given)"),
    }
    OUTPUT_PORTS: ClassVar = {}

    def call(self, name: str) -> Status:
        increment_recovery_count()
        if self.optional("plugins"):
            self.feedback_message = "clearing named costmap plugins is not supported yet"
            return F
        self.clear(name)
        return S

    def costmap_server(self, name: str) -> Any:
        return getattr(self.stack, name.split("/")[0])

    def clear(self, name: str) -> None:
        self.stack.services()[name]()


@register("bt_node", "ClearEntireCostmap")
class ClearEntireCostmap(_ClearCostmap):
    """Reset a whole costmap (`service_name`, e.g. local_costmap/clear_entirely_local_costmap)."""


@register("bt_node", "ClearCostmapExceptRegion")
class ClearCostmapExceptRegion(_ClearCostmap):
    """Clear a costmap outside the square of side `reset_distance` round the robot."""

    INPUT_PORTS: ClassVar = {
        "reset_distance": input_port(float, "Side of the square round the robot kept", 1.0),
        **_ClearCostmap.INPUT_PORTS,
    }

    def clear(self, name: str) -> None:
        self.stack.services()[name](self.get_input("reset_distance"))


@register("bt_node", "ClearCostmapAroundRobot")
class ClearCostmapAroundRobot(ClearCostmapExceptRegion):
    """Clear a costmap inside the square of side `reset_distance` round the robot."""

    INPUT_PORTS: ClassVar = {
        "reset_distance": input_port(float, "Side of the square round the robot cleared", 1.0),
        **_ClearCostmap.INPUT_PORTS,
    }


@register("bt_node", "ClearCostmapAroundPose")
class ClearCostmapAroundPose(_ClearCostmap):
    """Clear a costmap within `reset_distance` of `pose` (service `<costmap>/clear_around_pose`)."""

    INPUT_PORTS: ClassVar = {
        "pose": input_port(PoseLike, "Pose around which to clear the costmap"),
        "reset_distance": input_port(
            float, "Distance from the pose under which obstacles are cleared", 1.0
        ),
        **_ClearCostmap.INPUT_PORTS,
    }

    def has_service(self, name: str, services: list[str]) -> bool:
        return getattr(self.stack, name.split("/")[0], None) is not None

    def clear(self, name: str) -> None:
        server = self.costmap_server(name)
        pose = self.in_frame(self.get_input("pose"), server.global_frame)
        if pose is not None:
            server.costmap_ros.clear_around_pose(pose, self.get_input("reset_distance"))


@register("bt_node", "ValidatePath")
class ValidatePath(BtServiceNode):
    """SUCCESS if `path`, from the pose nearest the robot on, is clear on the global costmap.

    planner_server's IsPathValid: with a radius footprint (the costmap's `robot_radius`)
    a pose is invalid on a cost >= `max_cost`, LETHAL or INSCRIBED; with a polygon
    footprint (the costmap's, or `footprint`) on a footprint cost LETHAL or >= `max_cost`.
    Unknown cells are free unless `consider_unknown_as_obstacle`. The invalid poses go
    to `collision_poses` (the first only, if `stop_at_first_collision`).
    """

    SERVICE = "is_path_valid"
    INPUT_PORTS: ClassVar = {
        "path": input_port(Path, "The global path to check for validity"),
        "max_cost": input_port(int, "The maximum allowable cost for the path to be valid", 254),
        "consider_unknown_as_obstacle": input_port(
            bool, "Whether unknown cost is an obstacle", False
        ),
        "layer_name": input_port(str, "The costmap layer to check against (all if empty)", ""),
        "footprint": input_port(
            str, "Custom footprint [[x1,y1],[x2,y2],...] (the robot's if empty)", ""
        ),
        "stop_at_first_collision": input_port(bool, "Stop at the first invalid pose", True),
        "max_lookahead_distance": input_port(
            float, "Distance along the path checked (-1: all)", -1.0
        ),
        **SERVICE_INPUTS,
    }
    OUTPUT_PORTS: ClassVar = {
        "collision_poses": PortInformation(list, required=False, description="Invalid poses"),
    }

    def has_service(self, name: str, services: list[str]) -> bool:
        return name.endswith("is_path_valid")

    def available(self) -> list[str] | None:
        return None if self.stack is None else ["is_path_valid"]

    def call(self, name: str) -> Status:
        path = self.optional("path")
        if path is None or len(path) == 0:
            self.feedback_message = "empty path: cannot validate it"
            return F
        costmap_ros = self.stack.global_costmap.costmap_ros
        robot = self.robot_pose(frame=path.frame_id)
        if robot is None:
            return F
        costmap = costmap_ros.costmap
        layer_name = self.get_input("layer_name")
        if layer_name:
            try:
                costmap = costmap_ros.layer(layer_name).costmap
            except (KeyError, AttributeError, UnknownNameError):
                self.feedback_message = f"no costmap layer '{layer_name}' with a costmap"
                return F
        poses = np.asarray(path.poses, float)
        start = int(np.argmin(fmath.hypot(poses[:, 0] - robot.x, poses[:, 1] - robot.y)))
        end = len(poses)
        lookahead = self.get_input("max_lookahead_distance")
        if lookahead > 0.0:
            end = integrated_index(poses, start, lookahead, path.segment_lengths)
        check = poses[start:end]
        footprint_text = self.get_input("footprint")
        use_radius = footprint_text == "" and len(costmap_ros.params.footprint) == 0
        if use_radius:
            m, inside = costmap.world_to_map(check[:, :2])
            costs = np.full(len(check), LETHAL_OBSTACLE, dtype=np.int64)
            costs[inside] = costmap.costs[m[inside, 1], m[inside, 0]]
        else:
            footprint = costmap_ros.footprint
            if footprint_text:
                try:
                    footprint = np.asarray(yaml.safe_load(footprint_text), float).reshape(-1, 2)
                except (yaml.YAMLError, ValueError, TypeError):
                    self.feedback_message = f"invalid footprint '{footprint_text}'"
                    return F
            view = SimpleNamespace(costmap=costmap, footprint=footprint)
            costs = CollisionChecker(view).footprint_costs(check)
        unknown = costs == NO_INFORMATION
        costs = np.where(
            unknown,
            LETHAL_OBSTACLE if self.get_input("consider_unknown_as_obstacle") else 0,
            costs,
        )
        max_cost = self.get_input("max_cost")
        bad = (costs >= max_cost) | (costs == LETHAL_OBSTACLE)
        if use_radius:
            bad |= costs == INSCRIBED_INFLATED_OBSTACLE
        hits = np.flatnonzero(bad) + start
        if hits.size and self.get_input("stop_at_first_collision"):
            hits = hits[:1]
        self._set_output(
            "collision_poses",
            [PoseStamped(path.stamp, Pose2D.from_array(poses[i]), path.frame_id) for i in hits],
        )
        if hits.size:
            self.feedback_message = f"path invalid at poses {hits.tolist()}"
            return F
        return S


@register("bt_node", "ReinitializeGlobalLocalization")
class ReinitializeGlobalLocalization(BtServiceNode):
    """AMCL's `reinitialize_global_localization` service: spread the particles uniformly
    over the map's free space (std_srvs/Empty). FAILURE when the localiser has no such
    service (ground truth)."""

    SERVICE = "reinitialize_global_localization"
    INPUT_PORTS: ClassVar = dict(SERVICE_INPUTS)
    OUTPUT_PORTS: ClassVar = {}

    def call(self, name: str) -> Status:
        self.stack.services()[name]()
        return S
