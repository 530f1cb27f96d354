"""Actions as Nav2 uses them: `send_goal -> GoalHandle`, polled, advanced by the server.

A server (`ActionServer`) holds at most one running goal and one pending goal, as
nav2_util's SimpleActionServer does:

- `send_goal(goal)` returns a `GoalHandle` at once: ACCEPTED (or rejected, when
  `validate_goal` names a reason). Nothing runs until the server's `update(now)`,
  called on the runtime's schedule at the server's rate.
- On `update(now)` the server, in this order: finishes a canceled pending goal;
  starts the pending goal (`on_start`) or, if a goal is running, preempts it
  (`on_preempt`; the old goal is ABORTED with error code NONE, as Nav2's
  `accept_pending_goal` aborts it with an empty result) or, on a server that does
  not allow preemption, aborts the newcomer; then gives the running goal its step:
  `on_cancel` if the client asked to cancel, `execute` otherwise.
- `execute`, `on_start`, `on_preempt` and `on_cancel` return `None` to go on, or a
  `NavResult` to finish: SUCCEEDED, ABORTED (failed, with Nav2's error code) or
  CANCELED. An exception in them aborts the goal with the action's UNKNOWN code and
  is raised again (a bug in a plugin should stop the run, not hide in a report).

The client (a BT node) keeps the handle and polls `handle.done`, `handle.status`,
`handle.feedback` and `handle.result` on each tick, as a Nav2 BtActionNode does;
`handle.cancel()` asks the server to cancel, the server answers on its next update.
"""

from __future__ import annotations

from collections.abc import Callable
from enum import IntEnum
from itertools import count
from typing import Any, Generic, TypeVar

from ..core.error_codes import ERROR_CODES, NavResult, Outcome
from ..core.errors import UnknownNameError
from ..core.per_class import copy_hot_methods
from ..core.suggest import best_match

G = TypeVar("G")


class GoalStatus(IntEnum):
    """action_msgs/GoalStatus."""

    UNKNOWN = 0
    ACCEPTED = 1
    EXECUTING = 2
    CANCELING = 3
    SUCCEEDED = 4
    CANCELED = 5
    ABORTED = 6


TERMINAL = frozenset({GoalStatus.SUCCEEDED, GoalStatus.CANCELED, GoalStatus.ABORTED})
#: Read by every server's every update: a module global, as an Enum's attribute is a slow read.
_CANCELING = GoalStatus.CANCELING
_STATUS_OF = {
    Outcome.SUCCEEDED: GoalStatus.SUCCEEDED,
    Outcome.FAILED: GoalStatus.ABORTED,
    Outcome.CANCELED: GoalStatus.CANCELED,
}


class GoalHandle(Generic[G]):
    """One goal as its client sees it; the server updates it in place."""

    def __init__(self, server: ActionServer[G], goal: G, goal_id: int) -> None:
        self.server = server
        self.goal = goal
        self.goal_id = goal_id
        self.status = GoalStatus.ACCEPTED
        self.accepted = True
        self.feedback: Any = None
        self.feedback_stamp: float | None = None
        self.result: NavResult | None = None
        self.start_time: float | None = None  # sim time the server started executing it
        self.end_time: float | None = None

    # -- the client's side ------------------------------------------------------------

    @property
    def action(self) -> str:
        return self.server.action

    @property
    def done(self) -> bool:
        """True once the goal is SUCCEEDED, CANCELED or ABORTED (or was rejected)."""
        return self.status in TERMINAL or not self.accepted

    @property
    def active(self) -> bool:
        return not self.done

    @property
    def succeeded(self) -> bool:
        return self.status is GoalStatus.SUCCEEDED

    @property
    def error_code(self) -> int:
        return self.result.error_code if self.result is not None else 0

    @property
    def error_msg(self) -> str:
        return self.result.error_msg if self.result is not None else ""

    def cancel(self) -> bool:
        """Ask the server to cancel; False if the goal has already ended (ROS rejects that too)."""
        if self.done:
            return False
        if self.status is not GoalStatus.CANCELING:
            self.status = GoalStatus.CANCELING
        return True

    # -- the server's side ------------------------------------------------------------

    def publish_feedback(self, feedback: Any, now: float | None = None) -> None:
        self.feedback = feedback
        self.feedback_stamp = now

    def _finish(
        self, result: NavResult, now: float | None, status: GoalStatus | None = None
    ) -> None:
        self.result = result
        self.status = status if status is not None else _STATUS_OF[result.outcome]
        self.end_time = now

    def __repr__(self) -> str:
        return f"GoalHandle({self.action} #{self.goal_id}, {self.status.name})"


class ActionServer(Generic[G]):
    """A Nav2 SimpleActionServer on sim time. Subclass it, or pass the hooks as callables.

    `action` is Nav2's action type (`FollowPath`, `Spin`, ...), which picks the error
    code table; `name` is the server's address (`follow_path`, `spin`, ...).
    If `rate` is given the server is itself a runtime component; otherwise its owner
    (e.g. the controller_server at `controller_frequency`) calls `update(now)`.
    """

    def __init__(
        self,
        action: str,
        name: str | None = None,
        *,
        rate: float | None = None,
        preemptible: bool = True,
        execute: Callable[[GoalHandle[G], float], NavResult | None] | None = None,
        on_start: Callable[[GoalHandle[G], float], NavResult | None] | None = None,
        on_cancel: Callable[[GoalHandle[G], float], NavResult | None] | None = None,
        on_preempt: Callable[[GoalHandle[G], GoalHandle[G], float], NavResult | None] | None = None,
        validate_goal: Callable[[G], str | None] | None = None,
    ) -> None:
        self.action = action
        self.name = name if name is not None else action
        self.codes = ERROR_CODES.get(action)
        if rate is not None:
            self.rate = float(rate)
        self.preemptible = preemptible
        self._execute = execute
        self._on_start = on_start
        self._on_cancel = on_cancel
        self._on_preempt = on_preempt
        self._validate = validate_goal
        self.current: GoalHandle[G] | None = None
        self.pending: GoalHandle[G] | None = None
        self.now: float | None = None  # time of the latest update
        self._ids = count(1)  # goal ids per server, so two runs number their goals alike

    def __init_subclass__(cls, **kwargs: Any) -> None:
        super().__init_subclass__(**kwargs)
        copy_hot_methods(cls, ("update", "_run"))  # run by every server, every cycle

    # -- the client's entry point -----------------------------------------------------

    def send_goal(self, goal: G) -> GoalHandle[G]:
        """Accept (or reject) a goal now; it starts on the server's next `update`."""
        handle = GoalHandle(self, goal, next(self._ids))
        reason = self.validate_goal(goal)
        if reason is not None:
            handle.accepted = False
            handle.status = GoalStatus.UNKNOWN
            code = 0
            if self.codes is not None and "GOAL_REJECTED" in self.codes.__members__:
                code = self.codes["GOAL_REJECTED"]
            handle.result = NavResult.failure(code, f"goal rejected: {reason}")
            return handle
        if self.pending is not None and self.pending.active:
            # The pending slot holds one goal: the older one is terminated, as in Nav2.
            self._terminate(self.pending, "replaced by a newer goal before it started")
        self.pending = handle
        return handle

    @property
    def is_active(self) -> bool:
        """A goal is running or waiting to run."""
        return (self.current is not None and self.current.active) or (
            self.pending is not None and self.pending.active
        )

    # -- scheduling -------------------------------------------------------------------

    def update(self, now: float) -> None:
        """Advance the goals by one server cycle."""
        self.now = now
        pending = self.pending
        if pending is not None:
            self.pending = None
            if pending.status is _CANCELING:
                pending._finish(NavResult.cancellation(), now)
            elif self.current is not None and self.current.active:
                if self.preemptible:
                    old = self.current
                    self._terminate(old, f"preempted by goal #{pending.goal_id}")
                    self._begin(pending, now, preempted=old)
                else:
                    self._terminate(pending, f"{self.name} is busy and does not allow preemption")
            else:
                self._begin(pending, now, preempted=None)
        handle = self.current
        if handle is None or handle.status in TERMINAL or not handle.accepted:  # handle.done
            return
        if handle.status is _CANCELING:
            self._run(handle, self.on_cancel, now)
        else:
            self._run(handle, self.execute, now)

    def _begin(self, handle: GoalHandle[G], now: float, preempted: GoalHandle[G] | None) -> None:
        self.current = handle
        handle.status = GoalStatus.EXECUTING
        handle.start_time = now
        if preempted is None:
            self._run(handle, self.on_start, now)
        else:
            self._run(handle, lambda h, t: self.on_preempt(preempted, h, t), now)

    def _run(
        self,
        handle: GoalHandle[G],
        hook: Callable[[GoalHandle[G], float], NavResult | None],
        now: float,
    ) -> None:
        """Give a running goal `hook`'s step (both callers pass a goal not done: `update`
        tests it, `_begin` has just started it)."""
        try:
            result = hook(handle, now)
        except Exception as exc:
            code = self.codes.UNKNOWN if self.codes is not None else 0
            handle._finish(NavResult.failure(code, f"{type(exc).__name__}: {exc}"), now)
            raise
        if result is None:
            return
        if handle.status is GoalStatus.CANCELING and result.outcome is not Outcome.FAILED:
            # A goal being canceled ends CANCELED unless the server says it failed.
            result = NavResult(Outcome.CANCELED, 0, result.error_msg, result.value)
        handle._finish(result, now)

    def _terminate(self, handle: GoalHandle[G], why: str) -> None:
        """Nav2's `terminate`: CANCELED if the client was canceling it, ABORTED otherwise."""
        if handle.status is GoalStatus.CANCELING:
            handle._finish(NavResult.cancellation(msg=why), self.now)
        else:
            handle._finish(NavResult(Outcome.FAILED, 0, why), self.now)

    # -- the hooks a server implements ------------------------------------------------

    def validate_goal(self, goal: G) -> str | None:
        """A reason to reject the goal outright, or None to accept it."""
        return self._validate(goal) if self._validate is not None else None

    def on_start(self, handle: GoalHandle[G], now: float) -> NavResult | None:
        """A goal begins (nothing was running)."""
        return self._on_start(handle, now) if self._on_start is not None else None

    def on_preempt(self, old: GoalHandle[G], new: GoalHandle[G], now: float) -> NavResult | None:
        """`new` replaces the running `old` (already ABORTED); by default it starts afresh.

        Override (or pass `on_preempt`) to carry state over, as controller_server keeps
        its progress checker when a new path arrives.
        """
        if self._on_preempt is not None:
            return self._on_preempt(old, new, now)
        return self.on_start(new, now)

    def execute(self, handle: GoalHandle[G], now: float) -> NavResult | None:
        """One cycle of the running goal."""
        if self._execute is None:
            raise NotImplementedError(f"{type(self).__name__} has no execute step")
        return self._execute(handle, now)

    def on_cancel(self, handle: GoalHandle[G], now: float) -> NavResult | None:
        """The client asked to cancel; default: stop now. Return None to take more cycles."""
        if self._on_cancel is not None:
            return self._on_cancel(handle, now)
        return NavResult.cancellation()

    def __repr__(self) -> str:
        return f"ActionServer({self.action!r}, name={self.name!r}, current={self.current})"


class ActionClient(Generic[G]):
    """The client end a BT node holds: finds its server by name in a registry of servers."""

    def __init__(self, servers: ActionServers, name: str) -> None:
        self.servers = servers
        self.name = name

    def wait_for_server(self) -> bool:
        """Whether the server exists (there is no waiting on a single-threaded sim clock)."""
        return self.name in self.servers

    def send_goal(self, goal: G) -> GoalHandle[G]:
        """Send a goal; a missing server is an `UnknownNameError` naming the servers that exist."""
        return self.servers.get(self.name).send_goal(goal)


class ActionServers:
    """The action servers a runtime holds, by name (what `ros2 action list` shows)."""

    def __init__(self) -> None:
        self._servers: dict[str, ActionServer[Any]] = {}

    def add(self, server: ActionServer[Any]) -> None:
        if server.name in self._servers:
            raise ValueError(f"an action server named '{server.name}' already exists")
        self._servers[server.name] = server

    def __contains__(self, name: object) -> bool:
        return name in self._servers

    def get(self, name: str) -> ActionServer[Any]:
        try:
            return self._servers[name]
        except KeyError:
            names = sorted(self._servers)
            raise UnknownNameError(
                f"no action server '{name}'; servers: {', '.join(names) or '(none)'}",
                suggestion=best_match(name, names),
            ) from None

    def names(self) -> list[str]:
        return sorted(self._servers)

    def client(self, name: str) -> ActionClient[Any]:
        return ActionClient(self, name)
