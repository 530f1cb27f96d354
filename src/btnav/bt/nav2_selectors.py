"""Nav2's selector nodes: which planner, controller, goal checker, ... the tree uses.

Each writes the last id received on its topic (`topic_name`, a std_msgs/String: a
`str` or anything with `.data`, published on the runtime) to its output port, or its
default when nothing was received; with neither it fails ("required selection"
mode). `topic_name` is read, and the subscription made (or moved to a new topic),
on a tick that starts a run (the node was idle), as Nav2's `initialize()` does; the
other ticks only write the selection.
"""

from __future__ import annotations

from typing import Any, ClassVar

from py_trees.common import Status
from py_trees.ports import PortInformation

from ..plugins import register
from .base import S
from .blackboard import recording, write
from .nav2_context import Nav2Leaf


class _Selector(Nav2Leaf):
    #: (kind) e.g. "planner": ports `default_planner`, `selected_planner`, topic `planner_selector`.
    KIND: ClassVar[str] = ""
    #: The output port the selection is written to (`selected_<KIND>`).
    SELECTED: ClassVar[str] = ""

    #: Whether a tick with the selection made may take the short way (`execute_tick`).
    _STEADY: ClassVar[bool] = False
    #: The storage key of the bound `selected_<KIND>` output where a tick may take the
    #: short way (None: the full tick, py_trees writing it when the binding cannot).
    _selected_key: str | None = None
    #: `_selected_key` while `last_selected` is a selection (a non-empty str) the short way
    #: may write, else None: worked out when either changes, not on every tick.
    _steady_key: str | None = None

    def __init_subclass__(cls, **kwargs: Any) -> None:
        super().__init_subclass__(**kwargs)
        cls._STEADY = cls._HOOKLESS and cls.update is _Selector.update

    def __init__(self, name: str, **kwargs: Any) -> None:
        self._select("")  # (tick state first: _BtNode's note)
        super().__init__(name=name, **kwargs)
        self.topic: str | None = None

    def setup_ports(self, *args: Any, **kwargs: Any) -> None:
        super().setup_ports(*args, **kwargs)
        slot = self.bound_outputs.get(self.SELECTED)
        steady = self._STEADY and slot is not None and slot.types == (str,)
        self._selected_key = slot.key if steady else None  # type: ignore[union-attr]
        self._select(self.last_selected)

    def _select(self, selected: Any) -> None:
        self.last_selected = selected
        steady = type(selected) is str and selected
        self._steady_key = self._selected_key if steady else None

    def execute_tick(self) -> Status:
        """Once a selection is made a tick of an active selector only writes it again (five
        selectors tick 100 times a second): that write, straight to its bound key, where
        the full tick would do nothing else (no hooks, no logging, no activity stream)."""
        if self.status is S and not recording():
            key = self._steady_key
            if key is not None:
                write(key, self.last_selected)
                return S
        return super().execute_tick()

    @classmethod
    def ports_for(cls, kind: str, label: str) -> tuple[dict[str, Any], dict[str, Any]]:
        inputs = {
            "topic_name": PortInformation(
                str,
                required=False,
                default_value=f"{kind}_selector",
                description="The topic the selection arrives on",
            ),
            f"default_{kind}": PortInformation(
                str, required=False, description=f"The {label} used until one is selected"
            ),
        }
        outputs = {
            f"selected_{kind}": PortInformation(
                str, required=False, description=f"The selected {label} id"
            ),
        }
        return inputs, outputs

    def _on_select(self, msg: Any) -> None:
        self._select(str(getattr(msg, "data", msg)))

    def update(self) -> Status:
        if self.status is Status.INVALID and self.runtime is not None:
            # Nav2's initialize(), on a tick while the node is not active
            topic = self.get_input("topic_name")
            if topic != self.topic:
                self.topic = topic
                self.runtime.subscribe(topic, self._on_select)
        if not self.last_selected:
            default = self.optional(f"default_{self.KIND}")
            if not default:
                self.feedback_message = f"no {self.KIND} selected and no default_{self.KIND}"
                return Status.FAILURE
            self._select(default)
        self._set_output(self.SELECTED, self.last_selected)
        return Status.SUCCESS


def _selector(node_id: str, kind: str, label: str) -> type[_Selector]:
    inputs, outputs = _Selector.ports_for(kind, label)
    cls = type(
        node_id,
        (_Selector,),
        {
            "KIND": kind,
            "SELECTED": f"selected_{kind}",
            "INPUT_PORTS": inputs,
            "OUTPUT_PORTS": outputs,
            "__doc__": f"Nav2's {node_id}: the {label} id for the nodes that take one.",
            "__module__": __name__,
        },
    )
    return register("bt_node", node_id)(cls)


PlannerSelector = _selector("PlannerSelector", "planner", "planner")
ControllerSelector = _selector("ControllerSelector", "controller", "controller")
SmootherSelector = _selector("SmootherSelector", "smoother", "smoother")
GoalCheckerSelector = _selector("GoalCheckerSelector", "goal_checker", "goal checker")
ProgressCheckerSelector = _selector(
    "ProgressCheckerSelector", "progress_checker", "progress checker"
)
PathHandlerSelector = _selector("PathHandlerSelector", "path_handler", "path handler")
