"""The exploration tree's own nodes: ComputeFrontiers, BlacklistFrontier, IsExplorationComplete.

They call the stack's `explore/*` services (explore_lite's decisions, `nav.explore_server`)
as Nav2's service nodes call theirs, and pass the frontier goal to Nav2's own
ComputePathToPose and FollowPath through the blackboard (`trees/explore.yaml`).
"""

from __future__ import annotations

from typing import Any, ClassVar

from py_trees.common import Status

from ..core.geometry import Pose2D
from ..plugins import register
from .base import F, R, S, input_port
from .nav2_context import Nav2Leaf, PoseLike
from .nav2_services import SERVICE_INPUTS, BtServiceNode
from .ports import output_port


@register("bt_node", "ComputeFrontiers")
class ComputeFrontiers(BtServiceNode):
    """SUCCESS with the frontier to visit next in `goal`; FAILURE when none is left;
    RUNNING while the map around the robot is still unknown."""

    SERVICE: ClassVar[str] = "explore/compute_frontiers"
    INPUT_PORTS: ClassVar = dict(SERVICE_INPUTS)
    OUTPUT_PORTS: ClassVar = {
        "goal": output_port(Pose2D, "The goal that visits the chosen frontier"),
        "frontiers_left": output_port(int, "Reachable frontiers (0: exploration is complete)"),
    }
    DEFAULT_KEYS: ClassVar = {"goal": "{goal}", "frontiers_left": "{frontiers_left}"}

    def call(self, name: str) -> Status:
        step: Any = self.stack.services()[name]()
        if step.waiting:
            self.feedback_message = "waiting for the map around the robot"
            return R
        self._set_output("frontiers_left", len(step.frontiers))
        if step.goal is None:
            self.feedback_message = "no reachable frontier left"
            return F
        self._set_output("goal", step.goal)
        return S


@register("bt_node", "BlacklistFrontier")
class BlacklistFrontier(BtServiceNode):
    """Never choose the frontier of `goal` again (it could not be reached); SUCCESS."""

    SERVICE: ClassVar[str] = "explore/blacklist_frontier"
    INPUT_PORTS: ClassVar = {
        **SERVICE_INPUTS,
        "goal": input_port(PoseLike, "The goal that failed"),
    }
    OUTPUT_PORTS: ClassVar = {}
    DEFAULT_KEYS: ClassVar = {"goal": "{goal}"}

    def call(self, name: str) -> Status:
        goal = self.optional("goal")
        self.stack.services()[name](getattr(goal, "pose", goal))
        return S


@register("bt_node", "IsExplorationComplete")
class IsExplorationComplete(Nav2Leaf):
    """SUCCESS when ComputeFrontiers found no reachable frontier left."""

    NODE_KIND: ClassVar[str] = "Condition"
    INPUT_PORTS: ClassVar = {
        "frontiers_left": input_port(int, "ComputeFrontiers' count"),
    }
    OUTPUT_PORTS: ClassVar = {}
    DEFAULT_KEYS: ClassVar = {"frontiers_left": "{frontiers_left}"}

    def update(self) -> Status:
        return S if self.optional("frontiers_left") == 0 else F
