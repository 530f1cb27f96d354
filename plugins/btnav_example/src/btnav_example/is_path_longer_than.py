"""`IsPathLongerThan`: a condition node, SUCCESS when the planned path is longer than `length`.

A robot on a battery has a range; a tree can refuse a plan that goes beyond it
(`Inverter` over this node before `FollowPath`: see
`trees/navigate_w_path_budget.yaml`), or pick a faster controller for long paths.
It reads `path` (`"{path}"`, what ComputePathToPose writes, if not given) and writes
the length it measured to `path_length`, so the tick log and later nodes can see it.
An empty or missing path is FAILURE: there is nothing to measure.
"""

from __future__ import annotations

from typing import ClassVar

from btnav.bt.base import LeafNode, input_port, output_port
from btnav.core.messages import Path
from btnav.plugins import register
from py_trees.common import Status


@register("bt_node", "IsPathLongerThan")
class IsPathLongerThan(LeafNode):
    """SUCCESS when `path` is longer than `length` metres, FAILURE otherwise."""

    #: Groot's palette draws a leaf as an Action unless it says it is a Condition.
    NODE_KIND: ClassVar[str] = "Condition"
    INPUT_PORTS: ClassVar = {
        "path": input_port(Path, 'The path to measure; "{path}" if not given'),
        "length": input_port(float, "Length (m) above which the path counts as long", 10.0),
    }
    OUTPUT_PORTS: ClassVar = {
        "path_length": output_port(float, "The length (m) of the path this tick"),
    }
    #: BT.CPP's `InputPort("path", "{path}")`: an unset port reads this blackboard entry.
    DEFAULT_KEYS: ClassVar = {"path": "{path}"}

    def update(self) -> Status:
        path = self.optional("path")
        if path is None or len(path) == 0:
            self.feedback_message = "no path to measure"
            return Status.FAILURE
        measured = path.length()
        self._set_output("path_length", measured)
        limit = self.get_input("length")
        self.feedback_message = f"path {measured:.2f} m, limit {limit:.2f} m"
        return Status.SUCCESS if measured > limit else Status.FAILURE
