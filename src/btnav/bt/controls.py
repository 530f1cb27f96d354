"""BehaviorTree.CPP v4's control nodes, with its semantics (not py_trees' defaults).

Sequence and Fallback are one loop (`OrderedControl`): tick the children in order
until one returns the status that ends the run early (FAILURE for a sequence, a
SUCCESS that was not SKIPPED for a fallback); when every child is through, the run
ends the other way. The variants differ only in where a tick starts and what a
halt forgets:

* `Sequence` / `Fallback` keep their place: a RUNNING child is resumed next tick
  without re-ticking the children before it; the end of a run resets them.
* `SequenceWithMemory` does not even reset on FAILURE (nor on halt): it retries
  the failed child next time.
* `ReactiveSequence` / `ReactiveFallback` re-tick from the first child on every
  tick and halt a RUNNING child when an earlier one changes the outcome.

The others:

* `Parallel` counts successes and failures against `success_count` /
  `failure_count` (negative = "all but n-1") and does not re-tick finished children.
* `IfThenElse` evaluates its condition once per run; `WhileDoElse` on every tick.
"""

from __future__ import annotations

from typing import ClassVar

from py_trees.common import Status
from py_trees.composites import Parallel as _PtParallel
from py_trees.composites import Selector as _PtSelector
from py_trees.composites import Sequence as _PtSequence
from py_trees.ports import PortInformation

from ..plugins import register
from .base import ControlNode, F, R, S
from .errors import TreeError


class OrderedControl(ControlNode):
    """BT.CPP's Sequence and Fallback, one loop: `ENDS_ON` is the child status that
    ends the run early (FAILURE: a sequence; SUCCESS, unless SKIPPED: a fallback);
    `REACTIVE` re-ticks from the first child every tick (else RUNNING resumes in place)."""

    ENDS_ON: ClassVar[Status] = F
    REACTIVE: ClassVar[bool] = False

    def reset_state(self) -> None:
        self.current_child_idx = 0

    def tick_children(self) -> Status:
        children = self.children
        ends_on = self.ENDS_ON
        reactive = self.REACTIVE
        index = 0 if reactive else self.current_child_idx
        count = len(children)
        ticks = self.child_ticks
        if ticks is None:
            ticks = self.bind_child_ticks()
        while index < count:
            child = children[index]
            self.current_child = child
            status = ticks[index]()
            if status is R:
                if reactive:
                    self.halt_others(index)
                else:
                    self.current_child_idx = index
                return R
            if status is ends_on and (ends_on is F or not getattr(child, "skipped", False)):
                return self.end_run(status, index)
            index += 1
        return self.end_run(S if ends_on is F else F, count)

    def end_run(self, status: Status, index: int) -> Status:
        """The run ended with `status` at child `index` (len(children): all went through):
        children back to idle, own place reset."""
        self.halt_self()
        return status


@register("bt_node", "Sequence")
class Sequence(OrderedControl, _PtSequence):
    """Tick children in order; FAILURE restarts from the first, RUNNING resumes in place."""

    MEMORY: ClassVar = True


@register("bt_node", "SequenceWithMemory", aliases=["SequenceStar"])
class SequenceWithMemory(OrderedControl, _PtSequence):
    """A Sequence that resumes at the failed child: neither FAILURE nor halt resets it."""

    MEMORY: ClassVar = True

    def reset_state(self) -> None:
        if not hasattr(self, "current_child_idx"):
            self.current_child_idx = 0
        # BT.CPP v4 keeps the index on halt too ("memory").

    def end_run(self, status: Status, index: int) -> Status:
        if status is F:
            self.current_child_idx = index
            self.halt_children(index)
        else:
            self.halt_children()
            self.current_child_idx = 0
        return status


@register("bt_node", "ReactiveSequence")
class ReactiveSequence(OrderedControl, _PtSequence):
    """Every tick from the first child; a FAILURE halts whatever was RUNNING."""

    MEMORY: ClassVar = False
    REACTIVE: ClassVar = True


@register("bt_node", "Fallback")
class Fallback(OrderedControl, _PtSelector):
    """Tick children in order until one succeeds; RUNNING resumes in place."""

    MEMORY: ClassVar = True
    ENDS_ON: ClassVar = S


@register("bt_node", "ReactiveFallback")
class ReactiveFallback(OrderedControl, _PtSelector):
    """Every tick from the first child; a SUCCESS halts whatever was RUNNING."""

    MEMORY: ClassVar = False
    ENDS_ON: ClassVar = S
    REACTIVE: ClassVar = True


@register("bt_node", "Parallel")
class Parallel(ControlNode, _PtParallel):
    """Tick every unfinished child; SUCCESS at `success_count` successes, FAILURE at `failure_count` failures."""

    INPUT_PORTS: ClassVar = {
        "success_count": PortInformation(
            int,
            required=False,
            default_value=-1,
            description="Number of children that must succeed (-1 means all)",
        ),
        "failure_count": PortInformation(
            int,
            required=False,
            default_value=1,
            description="Number of children that must fail for the node to fail (-1 means all)",
        ),
    }

    def reset_state(self) -> None:
        self.completed: set[int] = set()
        self.success_total = 0
        self.failure_total = 0

    def _threshold(self, value: int) -> int:
        n = len(self.children)
        return max(n + value + 1, 0) if value < 0 else value

    def tick_children(self) -> Status:
        n = len(self.children)
        need_success = self._threshold(self.get_input("success_count"))
        need_failure = self._threshold(self.get_input("failure_count"))
        if n < need_success:
            raise TreeError(f"Parallel '{self.name}': success_count {need_success} > {n} children")
        if n < need_failure:
            raise TreeError(f"Parallel '{self.name}': failure_count {need_failure} > {n} children")
        for i, child in enumerate(self.children):
            if i not in self.completed:
                status = self.tick_child(child)
                if status is S:
                    self.completed.add(i)
                    self.success_total += 1
                elif status is F:
                    self.completed.add(i)
                    self.failure_total += 1
            if self.success_total >= need_success:
                self.halt_self()
                return S
            if n - self.failure_total < need_success or self.failure_total == need_failure:
                self.halt_self()
                return F
        return R

    def stop(self, new_status: Status = Status.INVALID) -> None:
        if new_status is Status.INVALID:  # py_trees' Parallel halts its RUNNING children first
            for child in self.children:
                if child.status is R:
                    child.stop(Status.INVALID)
        super().stop(new_status)


@register("bt_node", "IfThenElse")
class IfThenElse(ControlNode):
    """`if child0 then child1 else child2` (no else: FAILURE); the condition is not re-checked while a branch runs."""

    CHILDREN: ClassVar = (2, 3)

    def reset_state(self) -> None:
        self.child_idx = 0

    def tick_children(self) -> Status:
        if self.child_idx == 0:
            status = self.tick_child(self.children[0])
            if status is R:
                return R
            if status is S:
                self.child_idx = 1
            elif len(self.children) == 3:
                self.child_idx = 2
            else:
                self.halt_self()
                return F
        status = self.tick_child(self.children[self.child_idx])
        if status is R:
            return R
        self.halt_self()
        return status


@register("bt_node", "WhileDoElse")
class WhileDoElse(ControlNode):
    """Re-check child0 every tick: run child1 while it succeeds, child2 (if any) while it fails."""

    CHILDREN: ClassVar = (2, 3)

    def tick_children(self) -> Status:
        condition = self.tick_child(self.children[0])
        if condition is R:
            return R
        if condition is S:
            if len(self.children) == 3:
                self.halt_child(2)
            status = self.tick_child(self.children[1])
        elif len(self.children) == 3:
            self.halt_child(1)
            status = self.tick_child(self.children[2])
        else:
            status = F
        if status is not R:
            self.halt_children()
        return status
