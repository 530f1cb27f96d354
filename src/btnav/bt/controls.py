"""BehaviorTree.CPP v4's control nodes, with its semantics (not py_trees' defaults).

Where they differ from py_trees' own composites:

* `Sequence` keeps its place: a RUNNING child is resumed next tick without
  re-ticking the children before it; a FAILURE resets it to the first child.
* `SequenceWithMemory` does not even reset on FAILURE (nor on halt): it retries
  the failed child next time.
* `ReactiveSequence` / `ReactiveFallback` re-tick from the first child on every
  tick and halt a RUNNING child when an earlier one changes the outcome.
* `Fallback` keeps its place as `Sequence` does.
* `Parallel` counts successes and failures against `success_count` /
  `failure_count` (negative = "all but n-1") and does not re-tick finished children.
* `IfThenElse` evaluates its condition once per run; `WhileDoElse` on every tick.
"""

from __future__ import annotations

from typing import ClassVar

from py_trees.composites import Parallel as _PtParallel
from py_trees.composites import Selector as _PtSelector
from py_trees.composites import Sequence as _PtSequence
from py_trees.ports import PortInformation

from ..plugins import register
from .base import ControlNode, F, R, S, TickGen, is_skipped
from .errors import TreeError


@register("bt_node", "Sequence")
class Sequence(ControlNode, _PtSequence):
    """Tick children in order; FAILURE restarts from the first, RUNNING resumes in place."""

    MEMORY: ClassVar = True

    def reset_state(self) -> None:
        self.current_child_idx = 0

    def tick_children(self) -> TickGen:
        while self.current_child_idx < len(self.children):
            child = self.children[self.current_child_idx]
            status = yield from self.tick_child(child)
            if status == R:
                return R
            if status == F:
                self.halt_self()
                return F
            self.current_child_idx += 1
        self.halt_self()
        return S


@register("bt_node", "SequenceWithMemory", aliases=["SequenceStar"])
class SequenceWithMemory(ControlNode, _PtSequence):
    """A Sequence that resumes at the failed child: neither FAILURE nor halt resets it."""

    MEMORY: ClassVar = True

    def reset_state(self) -> None:
        if not hasattr(self, "current_child_idx"):
            self.current_child_idx = 0
        # BT.CPP v4 keeps the index on halt too ("memory").

    def tick_children(self) -> TickGen:
        while self.current_child_idx < len(self.children):
            child = self.children[self.current_child_idx]
            status = yield from self.tick_child(child)
            if status == R:
                return R
            if status == F:
                self.halt_children(self.current_child_idx)
                return F
            self.current_child_idx += 1
        self.halt_children()
        self.current_child_idx = 0
        return S


@register("bt_node", "ReactiveSequence")
class ReactiveSequence(ControlNode, _PtSequence):
    """Every tick from the first child; a FAILURE halts whatever was RUNNING."""

    MEMORY: ClassVar = False

    def tick_children(self) -> TickGen:
        for index, child in enumerate(self.children):
            status = yield from self.tick_child(child)
            if status == R:
                self.halt_others(index)
                return R
            if status == F:
                self.halt_children()
                return F
        self.halt_children()
        return S


@register("bt_node", "Fallback")
class Fallback(ControlNode, _PtSelector):
    """Tick children in order until one succeeds; RUNNING resumes in place."""

    MEMORY: ClassVar = True

    def reset_state(self) -> None:
        self.current_child_idx = 0

    def tick_children(self) -> TickGen:
        while self.current_child_idx < len(self.children):
            child = self.children[self.current_child_idx]
            status = yield from self.tick_child(child)
            if status == R:
                return R
            if status == S and not is_skipped(child):
                self.halt_self()
                return S
            self.current_child_idx += 1
        self.halt_self()
        return F


@register("bt_node", "ReactiveFallback")
class ReactiveFallback(ControlNode, _PtSelector):
    """Every tick from the first child; a SUCCESS halts whatever was RUNNING."""

    MEMORY: ClassVar = False

    def tick_children(self) -> TickGen:
        for index, child in enumerate(self.children):
            status = yield from self.tick_child(child)
            if status == R:
                self.halt_others(index)
                return R
            if status == S and not is_skipped(child):
                self.halt_children()
                return S
        self.halt_children()
        return F


@register("bt_node", "Parallel")
class Parallel(ControlNode, _PtParallel):
    """Tick every unfinished child; SUCCESS at `success_count` successes, FAILURE at `failure_count` failures."""

    INPUT_PORTS: ClassVar = {
        "success_count": PortInformation(
            int,
            required=False,
            default_value=-1,
            description="number of children that must succeed (-1 means all)",
        ),
        "failure_count": PortInformation(
            int,
            required=False,
            default_value=1,
            description="number of children that must fail for the node to fail (-1 means all)",
        ),
    }

    def reset_state(self) -> None:
        self.completed: set[int] = set()
        self.success_total = 0
        self.failure_total = 0

    def _threshold(self, value: int) -> int:
        n = len(self.children)
        return max(n + value + 1, 0) if value < 0 else value

    def tick_children(self) -> TickGen:
        n = len(self.children)
        need_success = self._threshold(self.get_input("success_count"))
        need_failure = self._threshold(self.get_input("failure_count"))
        if n < need_success:
            raise TreeError(f"Parallel '{self.name}': success_count {need_success} > {n} children")
        if n < need_failure:
            raise TreeError(f"Parallel '{self.name}': failure_count {need_failure} > {n} children")
        for i, child in enumerate(self.children):
            if i not in self.completed:
                status = yield from self.tick_child(child)
                if status == S:
                    self.completed.add(i)
                    self.success_total += 1
                elif status == F:
                    self.completed.add(i)
                    self.failure_total += 1
            if self.success_total >= need_success:
                self.halt_self()
                return S
            if n - self.failure_total < need_success or self.failure_total == need_failure:
                self.halt_self()
                return F
        return R


@register("bt_node", "IfThenElse")
class IfThenElse(ControlNode):
    """`if child0 then child1 else child2` (no else: FAILURE); the condition is not re-checked while a branch runs."""

    CHILDREN: ClassVar = (2, 3)

    def reset_state(self) -> None:
        self.child_idx = 0

    def tick_children(self) -> TickGen:
        if self.child_idx == 0:
            status = yield from self.tick_child(self.children[0])
            if status == R:
                return R
            if status == S:
                self.child_idx = 1
            elif len(self.children) == 3:
                self.child_idx = 2
            else:
                self.halt_self()
                return F
        status = yield from self.tick_child(self.children[self.child_idx])
        if status == R:
            return R
        self.halt_self()
        return status


@register("bt_node", "WhileDoElse")
class WhileDoElse(ControlNode):
    """Re-check child0 every tick: run child1 while it succeeds, child2 (if any) while it fails."""

    CHILDREN: ClassVar = (2, 3)

    def tick_children(self) -> TickGen:
        condition = yield from self.tick_child(self.children[0])
        if condition == R:
            return R
        if condition == S:
            if len(self.children) == 3:
                self.halt_child(2)
            status = yield from self.tick_child(self.children[1])
        elif len(self.children) == 3:
            self.halt_child(1)
            status = yield from self.tick_child(self.children[2])
        else:
            status = F
        if status != R:
            self.halt_children()
        return status
