"""Nav2's action client nodes: BtActionNode and the nodes that call btnav's action servers.

`BtActionNode` ticks as nav2_behavior_tree's BtActionNode does, on the runtime's
`send_goal -> GoalHandle`:

* the first tick of a run (the node was not RUNNING) builds the goal from the input
  ports (`make_goal`, Nav2's `on_tick`) and sends it to `server_name` (Nav2's default
  server name unless the port says otherwise); a rejected goal is FAILURE with
  `error_code_id` GOAL_REJECTED;
* while the goal is active the node returns RUNNING; each tick `on_wait_for_result`
  may find that its inputs changed (FollowPath's new path, controller id, ...), and
  then the new goal is sent to the same server, which preempts the old one;
* when the goal ends, SUCCEEDED -> `on_success` (SUCCESS), ABORTED -> `on_aborted`
  (FAILURE), CANCELED -> `on_cancelled` (SUCCESS), each writing Nav2's output ports:
  `error_code_id` and `error_msg` always, `path` etc. where Nav2 writes them;
* a halt while RUNNING cancels the goal (the server stops it on its next cycle) and
  writes what Nav2 writes after the cancel (`on_cancelled`), e.g. an empty `path`.

The single-threaded sim answers a goal request at once, so `server_timeout` never
expires; it is accepted for Nav2's trees. A missing server is what Nav2 refuses when
it builds the tree: a constant `server_name` that the runtime does not serve is a
load error naming the servers there are; a tree built without a runtime (to draw or
check it) fails such a node with SEND_GOAL_FAILURE and says what to pass.
"""

from __future__ import annotations

import dataclasses
from typing import Any, ClassVar

from py_trees.common import Status
from py_trees.ports import PortInformation

from ..core.error_codes import NavErrorCode, NavResult, error_codes
from ..core.errors import UnknownNameError
from ..core.messages import Path
from ..core.nav2_msgs import (
    ComputePathThroughPosesGoal,
    ComputePathToPoseGoal,
    FollowPathGoal,
    SmoothPathGoal,
)
from ..core.suggest import best_match
from ..nav.actions import GoalHandle, GoalStatus
from ..plugins import register
from .base import F, R, S, input_port, output_port
from .blackboard import read, recording
from .nav2_context import Nav2Leaf, PoseLike, empty_path, increment_recovery_count, same_path

_UNSET = object()
_EXECUTING = GoalStatus.EXECUTING

#: Every BtActionNode's ports (Nav2's `providedBasicPorts`).
BASIC_INPUTS: dict[str, PortInformation] = {
    "server_name": input_port(str, "Action server name"),
    "server_timeout": input_port(int, "Action server timeout (ms); the sim answers at once"),
}
BASIC_OUTPUTS: dict[str, PortInformation] = {
    "error_code_id": output_port(int, "The action error code"),
    "error_msg": output_port(str, "The action error message"),
}


class BtActionNode(Nav2Leaf):
    """Base of the nodes that call an action server (Nav2's `BtActionNode<ActionT>`).

    Subclasses set `ACTION` (Nav2's action type: its error codes) and `SERVER` (the
    default server name) and write `make_goal`, and the `on_*` hooks they need.
    """

    ACTION: ClassVar[str] = ""
    SERVER: ClassVar[str] = ""
    #: Whether a run of this node is a recovery (`number_recoveries` + 1 per run).
    IS_RECOVERY: ClassVar[bool] = False

    def __init__(self, name: str, **kwargs: Any) -> None:
        # (tick state first: _BtNode's note)
        self.handle: GoalHandle[Any] | None = None
        self.goal: Any = None
        self.goal_updated = False
        self._feedback_stamp: float | None = None
        super().__init__(name=name, **kwargs)
        self.goals_sent = 0

    @property
    def codes(self) -> type[NavErrorCode]:
        return error_codes(self.ACTION)

    # -- the server ---------------------------------------------------------------------

    @property
    def server_name(self) -> str:
        return self.optional("server_name") or self.SERVER

    def setup_ports(self, *args: Any, **kwargs: Any) -> None:
        """Nav2 checks its action server when it builds the node: so does btnav, when the
        tree is built with a runtime and `server_name` is a constant or left to default."""
        super().setup_ports(*args, **kwargs)
        if self.runtime is None:
            return
        if self.blackboard_client.exists("server_name"):
            name = self.get_input("server_name")
        elif self._get_blackboard_key("server_name") == self._default_port_storage_key(
            "server_name"
        ):
            name = self.SERVER
        else:  # a blackboard entry not set yet: checked when the goal is sent
            return
        servers = self.runtime.action_servers
        if name not in servers:
            names = servers.names()
            same = [n for n in names if servers.get(n).action == self.ACTION]
            if name == self.SERVER and len(same) == 1:  # behavior_plugins: [Spin, ...]
                raise UnknownNameError(
                    f"the tree's {type(self).__name__} node calls the action server '{name}', "
                    f"but the {self.ACTION} server is named '{same[0]}' (its *_plugins name); "
                    f"Nav2 fails here too: rename the plugin '{name}', or set the node's "
                    f'server_name="{same[0]}"'
                )
            raise UnknownNameError(
                f"{type(self).__name__} '{self.name}': action server '{name}' not available; "
                f"servers: {', '.join(names) or '(none)'}",
                suggestion=best_match(name, names),
            )

    def client_problem(self) -> str | None:
        """Why a goal cannot be sent now (no runtime, no such server), or None."""
        if self.runtime is None:
            return "no runtime: load the tree with context={'runtime': runtime}"
        name = self.server_name
        if name not in self.runtime.action_servers:
            names = self.runtime.action_servers.names()
            return f"no action server '{name}'; servers: {', '.join(names) or '(none)'}"
        return None

    def send_new_goal(self) -> bool:
        """Send `self.goal`; False (and the failure's outputs written) if it did not go."""
        self.goal_updated = False
        problem = self.client_problem()
        if problem is not None:
            self.handle = None
            self.feedback_message = problem
            self.write_error(self.codes["SEND_GOAL_FAILURE"], f"Failed to send goal: {problem}")
            return False
        self.handle = self.runtime.action_client(self.server_name).send_goal(self.goal)
        self.goals_sent += 1
        self._feedback_stamp = None
        if not self.handle.accepted:
            result = self.handle.result
            msg = (result.error_msg if result is not None else "") or (
                "Goal was rejected by the action server."
            )
            self.feedback_message = msg
            self.write_error(self.codes["GOAL_REJECTED"], msg)
            self.handle = None
            return False
        return True

    # -- the tick -----------------------------------------------------------------------

    def update(self) -> Status:
        if self.status is not R:  # a new run: goal from the ports, then send it
            self.handle = None
            problem = self.client_problem()
            if problem is not None:  # Nav2 would not have built the node
                self.feedback_message = problem
                self.write_error(self.codes["SEND_GOAL_FAILURE"], f"Failed to send goal: {problem}")
                return F
            self.goal = self.make_goal()
            if self.IS_RECOVERY:
                increment_recovery_count()
            if self.goal is None:
                return F
            if not self.send_new_goal():
                return F
            return R
        handle = self.handle
        if handle is None:
            return F
        # handle.active, without its two properties while the server executes the goal
        if (handle.status is _EXECUTING and handle.accepted) or handle.active:
            feedback = None
            if handle.feedback is not None and handle.feedback_stamp != self._feedback_stamp:
                feedback = handle.feedback
                self._feedback_stamp = handle.feedback_stamp
            self.on_wait_for_result(feedback)
            if (
                self.goal_updated
                and handle.status in (GoalStatus.ACCEPTED, _EXECUTING)
                and not self.send_new_goal()
            ):
                return F
            return R
        self.handle = None
        result = handle.result if handle.result is not None else NavResult.failure(0)
        if handle.status is GoalStatus.SUCCEEDED:
            return self.on_success(result)
        if handle.status is GoalStatus.CANCELED:
            return self.on_cancelled()
        return self.on_aborted(result)

    def terminate(self, new_status: Status) -> None:
        if new_status == Status.INVALID and self.status == R:
            handle, self.handle = self.handle, None
            if handle is not None and handle.status in (GoalStatus.ACCEPTED, GoalStatus.EXECUTING):
                handle.cancel()
                self.on_cancelled()
            self.on_halt()

    # -- hooks (Nav2's on_tick, on_wait_for_result, on_success, ...) ----------------------

    def make_goal(self) -> Any:
        """The goal from the input ports; None not to send one (the node fails)."""
        raise NotImplementedError

    def on_wait_for_result(self, feedback: Any) -> None:
        """Each tick while the goal runs; set `goal_updated` to send `self.goal` again."""

    def on_success(self, result: NavResult) -> Status:
        self.write_error(0, "")
        return S

    def on_aborted(self, result: NavResult) -> Status:
        self.write_error(result.error_code, result.error_msg)
        return F

    def on_cancelled(self) -> Status:
        self.write_error(0, "")
        return S

    def on_halt(self) -> None:
        """What the node resets when halted (after the goal is canceled)."""

    def write_error(self, code: int, msg: str) -> None:
        self._set_output("error_code_id", int(code))
        self._set_output("error_msg", str(msg))


# -- planner_server ------------------------------------------------------------------------


@register("bt_node", "ComputePathToPose")
class ComputePathToPose(BtActionNode):
    """Plan from the robot (or `start`) to `goal` with `planner_id`; the plan goes to `path`."""

    ACTION = "ComputePathToPose"
    SERVER = "compute_path_to_pose"
    INPUT_PORTS: ClassVar = {
        "start": input_port(
            PoseLike, "Start pose; used instead of the robot's if use_start is not false"
        ),
        "use_start": input_port(bool, "Whether to use `start`"),
        "goal": input_port(PoseLike, "Goal pose"),
        "viapoints": input_port(list, "Intermediate viapoints (excluding goal)"),
        "planner_id": input_port(str, "Mapped name of the planner plugin, e.g. GridBased", ""),
        **BASIC_INPUTS,
    }
    OUTPUT_PORTS: ClassVar = {
        "path": output_port(Path, "Path created by the action server"),
        **BASIC_OUTPUTS,
    }

    def make_goal(self) -> Any:
        goal = self.get_input("goal")
        viapoints = self.optional("viapoints")
        if viapoints:
            self.write_error(
                self.codes.UNKNOWN,
                "ComputePathToPose viapoints are not supported by btnav's planner_server; "
                "use ComputePathThroughPoses",
            )
            return None
        start = self.optional("start")
        use_start = self.optional("use_start")
        if use_start is None:
            use_start = start is not None
        elif use_start and start is None:
            use_start = False  # Nav2: falls back to the robot's pose
        return ComputePathToPoseGoal(
            goal=goal, planner_id=self.get_input("planner_id"), start=start, use_start=use_start
        )

    def on_success(self, result: NavResult) -> Status:
        self._set_output("path", result.value)
        return super().on_success(result)

    def on_aborted(self, result: NavResult) -> Status:
        self._set_output("path", empty_path())
        return super().on_aborted(result)

    def on_cancelled(self) -> Status:
        self._set_output("path", empty_path())
        return super().on_cancelled()

    def on_halt(self) -> None:
        self._set_output("path", empty_path())


@register("bt_node", "ComputePathThroughPoses")
class ComputePathThroughPoses(BtActionNode):
    """Plan through `goals` in order; the plan goes to `path`."""

    ACTION = "ComputePathThroughPoses"
    SERVER = "compute_path_through_poses"
    #: ComputePathThroughPoses' ALL_GOALS: the plan reaches every goal.
    ALL_GOALS: ClassVar[int] = -1
    INPUT_PORTS: ClassVar = {
        "start": input_port(PoseLike, "Start pose; used if given"),
        "goals": input_port(list, "Goal poses"),
        "planner_id": input_port(str, "Mapped name of the planner plugin, e.g. GridBased", ""),
        **BASIC_INPUTS,
    }
    OUTPUT_PORTS: ClassVar = {
        "path": output_port(Path, "Path created by the action server"),
        "last_reached_index": output_port(
            int, "Index of the last goal a partial plan reaches; -1: all"
        ),
        **BASIC_OUTPUTS,
    }

    def make_goal(self) -> Any:
        start = self.optional("start")
        return ComputePathThroughPosesGoal(
            goals=list(self.optional("goals") or []),
            planner_id=self.get_input("planner_id"),
            start=start,
            use_start=start is not None,
        )

    def _clear(self) -> None:
        self._set_output("path", empty_path())
        self._set_output("last_reached_index", self.ALL_GOALS)

    def on_success(self, result: NavResult) -> Status:
        self._set_output("path", result.value)
        self._set_output("last_reached_index", self.ALL_GOALS)
        return super().on_success(result)

    def on_aborted(self, result: NavResult) -> Status:
        self._clear()
        return super().on_aborted(result)

    def on_cancelled(self) -> Status:
        self._clear()
        return super().on_cancelled()

    def on_halt(self) -> None:
        self._clear()


# -- controller_server ---------------------------------------------------------------------


@register("bt_node", "FollowPath")
class FollowPath(BtActionNode):
    """Follow `path` with `controller_id`; a new path (or id) while running is sent at once."""

    ACTION = "FollowPath"
    SERVER = "follow_path"
    INPUT_PORTS: ClassVar = {
        "path": input_port(Path, "The path to follow"),
        "controller_id": input_port(str, "Mapped name of the controller plugin, e.g. FollowPath"),
        "goal_checker_id": input_port(str, "Mapped name of the goal checker plugin"),
        "progress_checker_id": input_port(str, "Mapped name of the progress checker plugin"),
        "path_handler_id": input_port(str, "Mapped name of the path handler plugin"),
        **BASIC_INPUTS,
    }
    OUTPUT_PORTS: ClassVar = {
        "tracking_feedback": output_port(object, "The controller server's latest feedback"),
        **BASIC_OUTPUTS,
    }
    _IDS: ClassVar = ("controller_id", "goal_checker_id", "progress_checker_id")
    #: The storage keys of `path` and the `_IDS` when all four are bound (else None), and
    #: what they held when `goal` last matched them: (goal, path, ids...).
    _watch_keys: tuple[str, ...] | None = None
    _matched: tuple[Any, ...] | None = None

    def setup_ports(self, *args: Any, **kwargs: Any) -> None:
        super().setup_ports(*args, **kwargs)
        slots = [self.bound_inputs.get(k) for k in ("path", *self._IDS)]
        self._watch_keys = None if None in slots else tuple(s.key for s in slots)  # type: ignore[union-attr]
        self._matched = None

    def make_goal(self) -> Any:
        path = self.optional("path")
        self.path_handler_id = self.optional("path_handler_id") or ""
        return FollowPathGoal(
            path=path if path is not None else empty_path(),
            **{k: self.optional(k) or "" for k in self._IDS},
        )

    def __init__(self, name: str, **kwargs: Any) -> None:
        cls = type(self)
        #: Whether a tick may take the short way (`execute_tick`): not for a subclass with
        #: its own `update` or `on_wait_for_result`, whose full tick may do more.
        self._steady = (
            cls.update is BtActionNode.update
            and cls.on_wait_for_result is FollowPath.on_wait_for_result
        )
        self._matched = None
        super().__init__(name, **kwargs)

    def execute_tick(self) -> Status:
        """While the goal runs, a tick that brings no new feedback and finds the goal
        unchanged returns RUNNING and does nothing else, as the full tick would (FollowPath
        ticks 100 times a second for a whole mission; the controller reports at 20 Hz)."""
        if self.status is R and self._steady:
            handle = self.handle
            if (
                handle is not None
                and handle.status is _EXECUTING
                and handle.accepted
                and not self.goal_updated
                and (handle.feedback is None or handle.feedback_stamp == self._feedback_stamp)
                and self._unchanged()
            ):
                return R
        return super().execute_tick()

    def _unchanged(self) -> bool:
        """Whether the goal and the four ports' entries are the very objects the goal was
        last found to match (paths and ids are never changed in place): it still does."""
        matched = self._matched
        if matched is None or matched[0] is not self.goal or recording():
            return False
        k_path, k_controller, k_goal_checker, k_progress_checker = self._watch_keys  # type: ignore[misc]
        return (
            read(k_path, _UNSET) is matched[1]
            and read(k_controller, _UNSET) is matched[2]
            and read(k_goal_checker, _UNSET) is matched[3]
            and read(k_progress_checker, _UNSET) is matched[4]
        )

    def on_wait_for_result(self, feedback: Any) -> None:
        goal = self.goal
        if self._unchanged():
            if feedback is not None:
                self._set_output("tracking_feedback", feedback)
            return
        changes: dict[str, Any] = {}
        new_path = self.optional("path")
        if new_path is not None and len(new_path) and not same_path(goal.path, new_path):
            changes["path"] = new_path
        for key in self._IDS:
            value = self.optional(key) or ""
            if getattr(goal, key) != value:
                changes[key] = value
        if changes:
            # a new goal object: the running goal keeps what it was sent
            self.goal = dataclasses.replace(goal, **changes)
            self.goal_updated = True
        elif self._watch_keys is not None and not recording():
            self._matched = (goal, *(read(k, _UNSET) for k in self._watch_keys))
        if feedback is not None:
            self._set_output("tracking_feedback", feedback)

    def _reset_feedback(self) -> None:
        self._set_output("tracking_feedback", {})

    def on_success(self, result: NavResult) -> Status:
        self._reset_feedback()
        return super().on_success(result)

    def on_aborted(self, result: NavResult) -> Status:
        self._reset_feedback()
        return super().on_aborted(result)

    def on_cancelled(self) -> Status:
        self._reset_feedback()
        return super().on_cancelled()


# -- smoother_server -----------------------------------------------------------------------


@register("bt_node", "SmoothPath")
class SmoothPath(BtActionNode):
    """Smooth `unsmoothed_path` with `smoother_id`; the result goes to `smoothed_path`."""

    ACTION = "SmoothPath"
    SERVER = "smooth_path"
    INPUT_PORTS: ClassVar = {
        "unsmoothed_path": input_port(Path, "The path to smooth"),
        "max_smoothing_duration": input_port(float, "Maximum time to smooth for (seconds)", 3.0),
        "check_for_collisions": input_port(
            bool, "Whether to check the smoothed path for collisions", False
        ),
        "smoother_id": input_port(str, "The smoother plugin ID"),
        **BASIC_INPUTS,
    }
    OUTPUT_PORTS: ClassVar = {
        "smoothed_path": output_port(Path, "The smoothed path"),
        "smoothing_duration": output_port(float, "The time used for smoothing (s)"),
        "was_completed": output_port(bool, "Whether smoothing ran to completion"),
        **BASIC_OUTPUTS,
    }

    def make_goal(self) -> Any:
        path = self.optional("unsmoothed_path")
        return SmoothPathGoal(
            path=path if path is not None else empty_path(),
            smoother_id=self.optional("smoother_id") or "",
            max_smoothing_duration=self.get_input("max_smoothing_duration"),
            check_for_collisions=self.get_input("check_for_collisions"),
        )

    def on_success(self, result: NavResult) -> Status:
        smoothed = result.value
        self._set_output("smoothed_path", smoothed.path)
        self._set_output("smoothing_duration", 0.0)  # smoothing takes no sim time
        self._set_output("was_completed", bool(smoothed.was_completed))
        return super().on_success(result)


# -- cancel nodes (Nav2's BtCancelActionNode) ----------------------------------------------


class BtCancelActionNode(Nav2Leaf):
    """Cancel every goal of an action server (Nav2 cancels those sent before now - 10 ms:
    here, the running and the pending goal). SUCCESS once asked; FAILURE with no server."""

    SERVER: ClassVar[str] = ""
    INPUT_PORTS: ClassVar = dict(BASIC_INPUTS)
    OUTPUT_PORTS: ClassVar = {}

    def update(self) -> Status:
        name = self.optional("server_name") or self.SERVER
        if self.runtime is None or name not in self.runtime.action_servers:
            self.feedback_message = f"no action server '{name}' to cancel"
            return F
        server = self.runtime.action_servers.get(name)
        for handle in (server.current, server.pending):
            if handle is not None:
                handle.cancel()
        return S


def _cancel_node(node_id: str, server: str) -> type[BtCancelActionNode]:
    cls = type(
        node_id,
        (BtCancelActionNode,),
        {
            "SERVER": server,
            "__doc__": f"Nav2's {node_id}: cancel the `{server}` action's goals.",
            "__module__": __name__,
        },
    )
    return register("bt_node", node_id)(cls)


CancelControl = _cancel_node("CancelControl", "follow_path")
CancelSpin = _cancel_node("CancelSpin", "spin")
CancelBackUp = _cancel_node("CancelBackUp", "backup")
CancelDriveOnHeading = _cancel_node("CancelDriveOnHeading", "drive_on_heading")
CancelWait = _cancel_node("CancelWait", "wait")
CancelAssistedTeleop = _cancel_node("CancelAssistedTeleop", "assisted_teleop")
