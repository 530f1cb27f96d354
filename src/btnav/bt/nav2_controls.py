"""Nav2's control nodes (nav2_behavior_tree/plugins/control), as Nav2 1.5 ticks them."""

from __future__ import annotations

from collections.abc import Callable
from typing import ClassVar

from py_trees.common import Status
from py_trees.composites import Selector as _PtSelector
from py_trees.composites import Sequence as _PtSequence
from py_trees.ports import PortInformation

from ..plugins import register
from .base import ControlNode, F, R, S, is_skipped
from .errors import TreeError


@register("bt_node", "PipelineSequence")
class PipelineSequence(ControlNode, _PtSequence):
    """A sequence that re-ticks its earlier children while a later one runs.

    Child i RUNNING ends the tick only if no later child has run yet; an earlier
    child still RUNNING (e.g. a planner behind a RateController) lets the tick go
    on to the child that runs. Any FAILURE halts all and fails.
    """

    def reset_state(self) -> None:
        self.last_child_ticked = 0

    def tick_children(self) -> Status:
        # (current_child is set once the tick ends: no child of a btnav tree reads it)
        children = self.children
        ticks = self.child_ticks
        if ticks is None:
            ticks = self.bind_child_ticks()
        last = self.last_child_ticked
        i = -1
        for tick in ticks:
            i += 1
            status = tick()
            if status is S:  # (most children, most ticks)
                continue
            if status is R:
                if i >= last:
                    self.current_child = children[i]
                    self.last_child_ticked = i
                    return R
            elif status is F:
                self.current_child = children[i]
                self.halt_self()
                return F
        if children:
            self.current_child = children[-1]
        self.halt_self()
        return S


@register("bt_node", "RecoveryNode")
class RecoveryNode(ControlNode, _PtSelector):
    """Run child 0; when it fails, run child 1 (the recovery) and, if that succeeds,
    child 0 again, up to `number_of_retries` recoveries. Fails when the recovery
    fails or the retries are used up."""

    INPUT_PORTS: ClassVar = {
        "number_of_retries": PortInformation(
            int, required=False, default_value=1, description="How many times the recovery may run"
        ),
    }
    CHILDREN: ClassVar = (2, 2)

    def reset_state(self) -> None:
        self.current_child_idx = 0
        self.retry_count = 0

    def bind_child_ticks(self) -> tuple[Callable[[], Status], ...]:
        if len(self.children) != 2:  # (checked again whenever the children change)
            raise TreeError(f"RecoveryNode '{self.name}' must only have 2 children")
        return super().bind_child_ticks()

    def tick_children(self) -> Status:
        ticks = self.child_ticks
        if ticks is None:
            ticks = self.bind_child_ticks()
        retries = self.get_input("number_of_retries")
        children = self.children
        while (index := self.current_child_idx) < 2 and self.retry_count <= retries:
            child = children[index]
            self.current_child = child
            status = ticks[index]()
            if status is R:
                return R
            if index == 0:
                if status is S:
                    self.halt_self()
                    if is_skipped(child):
                        self.skipped = True
                    return S
                if self.retry_count < retries:
                    self.halt_child(0)
                    self.current_child_idx = 1
                else:
                    self.halt_self()
                    return F
            else:
                if status is S and is_skipped(child):
                    # a skipped recovery cannot help: fail, without counting a retry
                    self.current_child_idx = 0
                    self.halt_child(1)
                    return F
                if status is S:
                    self.halt_child(1)
                    self.retry_count += 1
                    self.current_child_idx = 0
                else:
                    self.halt_self()
                    return F
        self.halt_self()
        return F


@register("bt_node", "RoundRobin")
class RoundRobin(ControlNode, _PtSelector):
    """Tick one child per run, moving to the next after each finished child, so
    successive recoveries try successive actions. SUCCESS on the first child that
    succeeds. After the last child: wrap to the first (`wrap_around`) or FAILURE."""

    INPUT_PORTS: ClassVar = {
        "wrap_around": PortInformation(
            bool,
            required=False,
            default_value=False,
            description="After the last child, start again from the first (true) or fail (false)",
        ),
    }

    def reset_state(self) -> None:
        self.current_child_idx = 0
        self.num_failed_children = 0

    def tick_children(self) -> Status:
        n = len(self.children)
        wrap_around = self.get_input("wrap_around")
        num_skipped = 0
        while self.num_failed_children + num_skipped < n:
            child = self.children[self.current_child_idx]
            self.current_child = child
            status = child.execute_tick()
            skipped = is_skipped(child)
            if status is not R:
                self.current_child_idx += 1
                if self.current_child_idx == n:
                    if wrap_around:
                        self.current_child_idx = 0
                    else:
                        if skipped:
                            num_skipped += 1
                        elif status is F:
                            self.num_failed_children += 1
                        break
            if status is R:
                return R
            if skipped:
                num_skipped += 1
            elif status is S:
                self.num_failed_children = 0
                self.halt_children()
                return S
            else:
                self.num_failed_children += 1
        all_skipped = num_skipped == n
        self.halt_self()
        if all_skipped:
            self.skipped = True
            return S
        return F
