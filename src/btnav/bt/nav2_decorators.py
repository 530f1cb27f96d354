"""Nav2's decorators that need no server (nav2_behavior_tree/plugins/decorator), on sim time."""

from __future__ import annotations

from typing import Any, ClassVar

from py_trees.behaviour import Behaviour
from py_trees.common import Status
from py_trees.ports import PortInformation

from ..core.per_class import original
from ..plugins import register
from .base import TIME_EPS, DecoratorNode, R, S

_INVALID = Status.INVALID  # a module global: an Enum's attribute is a slow read per tick


@register("bt_node", "RateController")
class RateController(DecoratorNode):
    """Tick the child at most `hz` times a second of sim time.

    The child is ticked on the first tick of a run, whenever the period has passed
    since the child last succeeded, and on every tick while it is RUNNING. Between
    those ticks the node returns RUNNING (Nav2's `return status()`).
    """

    INPUT_PORTS: ClassVar = {
        "hz": PortInformation(
            float,
            required=False,
            default_value=10.0,
            description="Most ticks of the child per second of sim time (Hz)",
        ),
    }
    INJECT: ClassVar = ("clock",)

    def __init__(self, name: str, child: Behaviour, clock: Any = None, **kwargs: Any):
        super().__init__(name=name, child=child, **kwargs)
        self.clock = clock
        # the short way of `execute_tick` is the full tick only with this class's tick
        self._steady = original(type(self).tick_decorated) is RateController.tick_decorated

    def reset_state(self) -> None:
        self.start = 0.0
        self.period = 0.1
        self.first_time = False

    def execute_tick(self) -> Status:
        """Between the child's ticks a running RateController only says RUNNING again (most
        of its ticks): that answer at once, where the full tick would change nothing
        (its status stays RUNNING, no hook runs, the child is not ticked)."""
        if (
            self.status is R
            and self._steady
            and not self.first_time
            and self.decorated.status is not R
        ):
            clock = self.clock
            if clock is not None and clock.now - self.start + TIME_EPS < self.period:
                return R
        return super().execute_tick()

    def tick_decorated(self) -> Status:
        if self.status is _INVALID:  # a new run (BT.CPP: status not active)
            self.period = 1.0 / self.get_input("hz")
            self.start = self.now()
            self.first_time = True
        clock = self.clock  # self.now(), inline
        elapsed = (float(clock.now) if clock is not None else self.now()) - self.start
        if self.first_time or self.decorated.status is R or elapsed + TIME_EPS >= self.period:
            self.first_time = False
            status = self.tick_child()
            if status is S:
                self.start = self.now()
            return status
        return R
