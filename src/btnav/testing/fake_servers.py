"""Fake Nav2 servers for a tree under test: each answers as the test says.

`respond("FAILURE", ticks=3, error_code="NO_VALID_PATH")` is one answer: the BT action
node stays RUNNING for `ticks` ticks (at least 1: the tick that sends the goal), then
the server ends the goal SUCCEEDED (the node's SUCCESS), ABORTED with the error code
(FAILURE) or never (`"RUNNING"`, until the node cancels it). A list of answers is one
per goal the server receives (a preempting goal too), the last repeating. A success
carries what the node writes to its ports: a straight `path` from the start (or the
robot) to the goal for the planners, the goal's path for SmoothPath, the elapsed time
for the behaviours.

The fake stack offers Nav2's clear-costmap and localisation services as calls that
are only recorded (`stack.calls`). A node that needs a real costmap says so and
suggests `navigator=` (real servers) or a stub (`nodes={"ValidatePath": "SUCCESS"}`).
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from dataclasses import dataclass
from functools import partial
from itertools import pairwise
from typing import Any

import numpy as np

from ..bt.nav2_actions import BtActionNode, BtCancelActionNode
from ..bt.nav2_context import pose_of
from ..bt.registry import node_types
from ..core import fmath
from ..core.error_codes import NavResult, error_codes
from ..core.errors import UnknownNameError
from ..core.geometry import Pose2D
from ..core.messages import Path
from ..core.nav2_msgs import BehaviorResult
from ..core.suggest import best_match
from ..nav.actions import ActionServer, GoalHandle
from ..nav.runtime import Runtime
from ..planning.smoother import Smoothed

#: The answers a fake server can give, in BT.CPP's words for what the node then returns.
STATUSES = ("SUCCESS", "FAILURE", "RUNNING")
#: Spacing of the poses of a fake planner's straight path (m).
PATH_STEP = 0.05
BEHAVIORS = ("Spin", "BackUp", "DriveOnHeading", "Wait", "AssistedTeleop")


@dataclass(frozen=True)
class Response:
    """One answer of a fake server (see `respond`)."""

    status: str = "SUCCESS"
    ticks: int = 1
    error_code: int | str | None = None
    error_msg: str | None = None
    value: Any = None


def respond(
    status: str = "SUCCESS",
    ticks: int = 1,
    *,
    error_code: int | str | None = None,
    error_msg: str | None = None,
    value: Any = None,
) -> Response:
    """A fake server's answer to one goal: the node is RUNNING for `ticks` ticks, then
    `status` (SUCCESS, FAILURE; RUNNING: never ends). `error_code` (a number or Nav2's
    name, e.g. "NO_VALID_PATH"; default the action's UNKNOWN) and `error_msg` go with a
    FAILURE; `value` replaces the success payload."""
    if status not in STATUSES:
        raise UnknownNameError(
            f"unknown fake answer '{status}'; answers: {', '.join(STATUSES)}",
            suggestion=best_match(str(status), STATUSES),
        )
    if int(ticks) < 1:
        raise ValueError(f"ticks is at least 1 (the tick that sends the goal), got {ticks}")
    return Response(status, int(ticks), error_code, error_msg, value)


Answers = str | Response | Sequence[str | Response]


def as_responses(answers: Answers) -> list[Response]:
    """A status, a `Response` or a list of them -> the list, one per goal."""
    items = [answers] if isinstance(answers, str | Response) else list(answers)
    if not items:
        raise ValueError("a fake server needs at least one answer")
    return [a if isinstance(a, Response) else respond(a) for a in items]


class FakeServer(ActionServer[Any]):
    """An action server whose goals end as the test's answers say; it records its goals."""

    def __init__(
        self, action: str, name: str, answers: Answers, rate: float, runtime: Runtime | None = None
    ) -> None:
        super().__init__(action, name, rate=rate)
        self.responses = as_responses(answers)
        #: Every goal received, in order.
        self.goals: list[Any] = []
        #: How many goals were canceled by their client.
        self.canceled = 0
        self._cycles: dict[int, int] = {}
        self._answer: dict[int, Response] = {}
        self._runtime = runtime  # where the robot is, for a planner's start

    def on_start(self, handle: GoalHandle[Any], now: float) -> NavResult | None:
        self.goals.append(handle.goal)
        self._answer[handle.goal_id] = self.responses[min(len(self.goals), len(self.responses)) - 1]
        self._cycles[handle.goal_id] = 0
        return None  # the server's update runs `execute` next, in the same cycle

    def execute(self, handle: GoalHandle[Any], now: float) -> NavResult | None:
        answer = self._answer[handle.goal_id]
        self._cycles[handle.goal_id] += 1
        if answer.status == "RUNNING" or self._cycles[handle.goal_id] < answer.ticks:
            return None
        if answer.status == "FAILURE":
            return NavResult.failure(self._code(answer.error_code), answer.error_msg)
        value = answer.value if answer.value is not None else self._payload(handle, now)
        return NavResult.success(value)

    def on_cancel(self, handle: GoalHandle[Any], now: float) -> NavResult | None:
        self.canceled += 1
        return NavResult.cancellation()

    def _code(self, code: int | str | None) -> int:
        try:
            table = error_codes(self.action)
        except UnknownNameError:
            table = None
        if isinstance(code, int):
            return code
        if table is None:
            return 1 if code is None else int(code)
        if code is None:
            return table["UNKNOWN"]
        if code not in table.__members__:
            names = [n for n in table.__members__ if n != "NONE"]
            raise UnknownNameError(
                f"{self.action} has no error code '{code}'; codes: {', '.join(names)}",
                suggestion=best_match(code, names),
            )
        return table[code]

    def _payload(self, handle: GoalHandle[Any], now: float) -> Any:
        """What the real server's success carries, made from the goal."""
        goal = handle.goal
        if self.action == "ComputePathToPose":
            return straight_path([self._start(goal), pose_of(goal.goal)[0]], now)
        if self.action == "ComputePathThroughPoses":
            poses = [pose_of(p)[0] for p in goal.goals]
            return straight_path([self._start(goal), *poses], now)
        if self.action == "SmoothPath":
            return Smoothed(goal.path, True)
        if self.action in BEHAVIORS:
            return BehaviorResult(total_elapsed_time=now - (handle.start_time or now))
        return None

    def _start(self, goal: Any) -> Pose2D:
        if goal.use_start and goal.start is not None:
            return pose_of(goal.start)[0]
        runtime = self._runtime
        return runtime.robot_pose() if runtime is not None else Pose2D()


def straight_path(poses: Sequence[Pose2D], stamp: float) -> Path:
    """Straight segments through `poses`, a pose every PATH_STEP m, heading along each
    segment and the last pose's yaw at the end (as a planner's path ends on the goal)."""
    xy = np.array([(p.x, p.y) for p in poses], dtype=float)
    pieces = []
    for a, b in pairwise(xy):
        n = max(int(np.ceil(fmath.hypot(*(b - a)) / PATH_STEP)), 1)
        pieces.append(a + (b - a) * (np.arange(n)[:, None] / n))
    pts = np.vstack([*pieces, xy[-1:]]) if pieces else xy
    d = np.diff(pts, axis=0)
    yaw = np.append(fmath.arctan2(d[:, 1], d[:, 0]), poses[-1].yaw) if len(d) else [poses[-1].yaw]
    return Path(stamp, np.column_stack([pts, yaw]), "map")


class FakeStack:
    """The part of a NavStack BT nodes call: its services, recorded and always answered."""

    SERVICES = (
        *(
            f"{c}/clear_{what}_{c}"
            for c in ("global_costmap", "local_costmap")
            for what in ("entirely", "around", "except")
        ),
        "map_server/load_map",
        "reinitialize_global_localization",
        "request_nomotion_update",
    )

    def __init__(self, runtime: Runtime) -> None:
        self.runtime = runtime
        #: (service name, arguments) of every call, in order.
        self.calls: list[tuple[str, tuple[Any, ...]]] = []

    def services(self) -> dict[str, Any]:
        return {name: partial(self._call, name) for name in self.SERVICES}

    def _call(self, name: str, *args: Any) -> None:
        self.calls.append((name, args))

    def __getattr__(self, name: str) -> Any:
        if name.startswith("__"):
            raise AttributeError(name)
        raise AttributeError(
            f"a tree with fake servers has no {name}: build it with "
            "navigator=btnav_navigator(...) for the real servers, or stub the node that "
            "needs it (nodes={'ValidatePath': 'SUCCESS'})"
        )


def tree_servers(doc: Any) -> dict[str, tuple[str, set[str]]]:
    """The action servers a tree's nodes call: server name -> (action, node types)."""
    types = node_types()
    action_of = {
        cls.SERVER: cls.ACTION
        for cls in types.values()
        if isinstance(cls, type) and issubclass(cls, BtActionNode) and cls.SERVER
    }
    found: dict[str, tuple[str, set[str]]] = {}
    for elem in doc.root.iter():
        cls = types.get(elem.tag)
        if not (isinstance(cls, type) and issubclass(cls, BtActionNode | BtCancelActionNode)):
            continue
        server = elem.attrib.get("server_name", "")
        if not server or server.startswith("{"):
            server = cls.SERVER
        action = getattr(cls, "ACTION", "") or action_of.get(server, elem.tag)
        found.setdefault(server, (action, set()))[1].add(elem.tag)
    return found


def make_servers(
    runtime: Runtime, doc: Any, answers: Mapping[str, Answers] | None, rate: float
) -> dict[str, FakeServer]:
    """A FakeServer for every action server the tree calls (SUCCESS unless `answers` says
    otherwise; keys are node types, `FollowPath`, or server names, `follow_path`)."""
    used = tree_servers(doc)
    by_type = {t: server for server, (_, ts) in used.items() for t in ts}
    chosen: dict[str, Answers] = {}
    for key, value in (answers or {}).items():
        if key in used:
            chosen[key] = value
        elif key in by_type:
            chosen[by_type[key]] = value
        else:
            known = sorted({*used, *by_type})
            raise UnknownNameError(
                f"no node or action server '{key}' in the tree to answer for; "
                f"it calls: {', '.join(known) or '(no action servers)'}",
                suggestion=best_match(key, known),
            )
    servers: dict[str, FakeServer] = {}
    for server, (action, _) in sorted(used.items()):
        fake = FakeServer(action, server, chosen.get(server, "SUCCESS"), rate, runtime)
        servers[server] = runtime.add(fake)
    return servers
