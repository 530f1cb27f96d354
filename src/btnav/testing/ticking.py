"""`tick_until(tree_or_navigator, condition, timeout=...)`: advance sim time until something holds.

Only sim time passes (never wall time), so a test is as fast as the machine allows and
gives the same answer on any machine. The condition is checked after every tick of a
tree under test, and before every physics step of a navigator. It is:

- None: the tree leaves RUNNING / the navigator's task ends (at once if none was sent);
- a status: "SUCCESS", "FAILURE", "RUNNING" (a tree's, or a navigator task's in the
  same words, plus "CANCELED" and "IDLE" when no task was sent);
- a callable: with no argument, or with the tree or navigator as its one argument.

The answer unpacks as `status, ticks = tick_until(...)`; `met` says whether the
condition came true before `timeout` sim seconds passed.
"""

from __future__ import annotations

import inspect
from collections.abc import Callable, Iterator
from dataclasses import dataclass
from typing import Any

#: A navigator task's goal status -> the status word tick_until reports.
_TASK_STATUS = {
    "ACCEPTED": "RUNNING",
    "EXECUTING": "RUNNING",
    "CANCELING": "RUNNING",
    "SUCCEEDED": "SUCCESS",
    "ABORTED": "FAILURE",
    "CANCELED": "CANCELED",
    "UNKNOWN": "FAILURE",  # a rejected goal
}
STATUSES = ("SUCCESS", "FAILURE", "RUNNING", "CANCELED", "IDLE")


@dataclass
class TickResult:
    """What `tick_until` did: the status at the end, the BT ticks and sim seconds used."""

    status: str
    ticks: int
    sim_time: float
    met: bool
    #: A navigator's task result (outcome, error_code, error_msg), None for a tree.
    result: Any = None

    @property
    def timed_out(self) -> bool:
        return not self.met

    def __iter__(self) -> Iterator[Any]:
        yield self.status
        yield self.ticks


def task_status(nav: Any) -> str:
    """A navigator's task in BT.CPP's words (IDLE before any task)."""
    handle = nav.handle
    if handle is None:
        return "IDLE"
    return _TASK_STATUS[handle.status.name]


def _predicate(
    target: Any, condition: Any, status: Callable[[], str], busy: tuple[str, ...]
) -> Callable[[], bool]:
    if condition is None:
        return lambda: status() not in busy
    if isinstance(condition, str):
        if condition not in STATUSES:
            from ..core.errors import UnknownNameError
            from ..core.suggest import best_match

            raise UnknownNameError(
                f"unknown status '{condition}'; statuses: {', '.join(STATUSES)}",
                suggestion=best_match(condition, STATUSES),
            )
        return lambda: status() == condition
    if not callable(condition):
        raise TypeError(f"a condition is None, a status or a callable, not {condition!r}")
    try:
        takes_target = len(inspect.signature(condition).parameters) >= 1
    except (TypeError, ValueError):
        takes_target = False
    if takes_target:
        return lambda: bool(condition(target))
    return lambda: bool(condition())


def tick_until(target: Any, condition: Any = None, timeout: float = 60.0) -> TickResult:
    """Tick a tree under test (or poll a navigator) until `condition` or `timeout` sim s."""
    if not timeout > 0:
        raise ValueError(f"timeout is in sim seconds and positive, got {timeout}")
    if hasattr(target, "tick") and hasattr(target, "period"):
        return _tick_tree(target, condition, timeout)
    if hasattr(target, "runtime") and hasattr(target, "bt_navigator"):
        return _poll_navigator(target, condition, timeout)
    raise TypeError(
        f"tick_until takes a tree (btnav_tree) or a navigator (btnav_navigator), not {target!r}"
    )


def _tick_tree(tree: Any, condition: Any, timeout: float) -> TickResult:
    done = _predicate(tree, condition, lambda: tree.status, ("RUNNING", "IDLE"))
    start, ticks = tree.now, 0
    steps = max(round(timeout / tree.period), 1)
    while True:
        status = tree.tick()
        ticks += 1
        if done():
            return TickResult(status, ticks, tree.now - start, True)
        if ticks >= steps:
            return TickResult(status, ticks, tree.now - start, False)


def _poll_navigator(nav: Any, condition: Any, timeout: float) -> TickResult:
    done = _predicate(nav, condition, lambda: task_status(nav), ("RUNNING",))
    navigators = list(nav.bt_navigator.navigators.values())
    ticks0 = sum(n.ticks for n in navigators)
    start = nav.now
    met = nav.runtime.run_until(done, timeout)
    ticks = sum(n.ticks for n in navigators) - ticks0
    return TickResult(task_status(nav), ticks, nav.now - start, met, nav.get_result())
