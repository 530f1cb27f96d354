"""BehaviorTree.CPP v4's decorators, with its semantics, timed on sim time.

`Repeat` and `RetryUntilSuccessful` re-tick their child within the same tick, as
BT.CPP does, except with an endless count (-1): then each new cycle starts on the
next tick, so a child that finishes at once cannot hang the loop. `Delay` and
`Timeout` measure sim time from the clock the loader injects.
"""

from __future__ import annotations

from typing import Any, ClassVar

from py_trees.behaviour import Behaviour
from py_trees.common import Status
from py_trees.ports import PortInformation

from ..plugins import register
from .base import TIME_EPS, DecoratorNode, F, R, S, halt


@register("bt_node", "Inverter")
class Inverter(DecoratorNode):
    """SUCCESS <-> FAILURE; RUNNING stays RUNNING."""

    def tick_decorated(self) -> Status:
        status = self.tick_child()
        if status == R:
            return R
        halt(self.decorated)
        return F if status == S else S


@register("bt_node", "ForceSuccess")
class ForceSuccess(DecoratorNode):
    """SUCCESS once the child finishes, whatever it returned."""

    def tick_decorated(self) -> Status:
        status = self.tick_child()
        if status == R:
            return R
        halt(self.decorated)
        return S


@register("bt_node", "ForceFailure")
class ForceFailure(DecoratorNode):
    """FAILURE once the child finishes, whatever it returned."""

    def tick_decorated(self) -> Status:
        status = self.tick_child()
        if status == R:
            return R
        halt(self.decorated)
        return F


@register("bt_node", "Repeat")
class Repeat(DecoratorNode):
    """Run the child `num_cycles` times while it succeeds (-1: forever); FAILURE stops it."""

    INPUT_PORTS: ClassVar = {
        "num_cycles": PortInformation(
            int, description="Repeat a successful child up to N times; -1 for an endless loop"
        ),
    }

    def reset_state(self) -> None:
        self.repeat_count = 0

    def tick_decorated(self) -> Status:
        cycles = self.get_input("num_cycles")
        while cycles == -1 or self.repeat_count < cycles:
            status = self.tick_child()
            if status == R:
                return R
            halt(self.decorated)
            if status == F:
                self.repeat_count = 0
                return F
            self.repeat_count += 1
            if cycles == -1:
                return R
        self.repeat_count = 0
        return S


@register("bt_node", "RetryUntilSuccessful")
class RetryUntilSuccessful(DecoratorNode):
    """Re-run a failing child up to `num_attempts` times (-1: forever); SUCCESS stops it."""

    INPUT_PORTS: ClassVar = {
        "num_attempts": PortInformation(
            int, description="Run a failing child up to N times; -1 for no limit"
        ),
    }

    def reset_state(self) -> None:
        self.try_count = 0

    def tick_decorated(self) -> Status:
        attempts = self.get_input("num_attempts")
        while attempts == -1 or self.try_count < attempts:
            status = self.tick_child()
            if status == R:
                return R
            halt(self.decorated)
            if status == S:
                self.try_count = 0
                return S
            self.try_count += 1
            if attempts == -1:
                return R
        self.try_count = 0
        return F


@register("bt_node", "KeepRunningUntilFailure")
class KeepRunningUntilFailure(DecoratorNode):
    """RUNNING (restarting the child) while it succeeds; FAILURE when it fails."""

    def tick_decorated(self) -> Status:
        status = self.tick_child()
        if status == R:
            return R
        halt(self.decorated)
        return F if status == F else R


class _TimedDecorator(DecoratorNode):
    INJECT: ClassVar = ("clock",)

    def __init__(self, name: str, child: Behaviour, clock: Any = None, **kwargs: Any):
        super().__init__(name=name, child=child, **kwargs)
        self.clock = clock


@register("bt_node", "Delay")
class Delay(_TimedDecorator):
    """Wait `delay_msec` of sim time (RUNNING), then tick the child until it finishes."""

    INPUT_PORTS: ClassVar = {
        "delay_msec": PortInformation(
            int, description="Tick the child after this many milliseconds of sim time"
        ),
    }

    def reset_state(self) -> None:
        self.delay_end: float | None = None

    def tick_decorated(self) -> Status:
        if self.delay_end is None:
            self.delay_end = self.now() + self.get_input("delay_msec") / 1000.0
        if self.now() + TIME_EPS < self.delay_end:
            return R
        status = self.tick_child()
        if status != R:
            self.delay_end = None
            halt(self.decorated)
        return status


@register("bt_node", "Timeout")
class Timeout(_TimedDecorator):
    """Halt the child and fail when it is still RUNNING after `msec` of sim time (0: no limit)."""

    INPUT_PORTS: ClassVar = {
        "msec": PortInformation(
            int, description="Halt the child after this many milliseconds of sim time"
        ),
    }

    def reset_state(self) -> None:
        self.deadline: float | None = None

    def tick_decorated(self) -> Status:
        if self.deadline is None:
            msec = self.get_input("msec")
            self.deadline = self.now() + msec / 1000.0 if msec > 0 else float("inf")
        elif self.now() + TIME_EPS >= self.deadline and self.decorated.status == R:
            halt(self.decorated)
            self.deadline = None
            return F
        status = self.tick_child()
        if status != R:
            self.deadline = None
            halt(self.decorated)
        return status


@register("bt_node", "RunOnce")
class RunOnce(DecoratorNode):
    """Run the child to completion once; afterwards skip it (or repeat its result)."""

    INPUT_PORTS: ClassVar = {
        "then_skip": PortInformation(
            bool,
            required=False,
            default_value=True,
            description="After the first run, return SKIPPED (true) or the first result (false)",
        ),
    }

    def __init__(self, name: str, child: Behaviour, **kwargs: Any):
        super().__init__(name=name, child=child, **kwargs)
        self.returned: Status | None = None  # not reset by halt, as in BT.CPP

    def tick_decorated(self) -> Status:
        if self.returned is not None:
            if self.get_input("then_skip"):
                self.skipped = True
                return S
            return self.returned
        status = self.tick_child()
        if status != R:
            self.returned = status
            halt(self.decorated)
        return status
