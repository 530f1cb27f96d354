"""`btnav run`: one mission, start to end, and the folder of what it did.

The run builds the bring-up (`Mission.navigator`), adds the recorders its outputs
need, sends the task as nav2_simple_commander would and polls it on sim time until
it ends or `time_limit` passes (then it is canceled, as BasicNavigator's examples
do). It writes `report.json`, `trajectory.csv`, `bt_log.jsonl`, the map and the SLAM
pose graph as the mission's `outputs` ask, then hands the run to each `output` plugin asked for
(`png` with the viz extra). A navigation failure is a report with Nav2's error code,
never an exception; a missed waypoint is reported with its error and the tree node
that failed last (`FailedNodes`, a tick listener).
"""

from __future__ import annotations

import shutil
import time
from collections.abc import Callable, Mapping
from contextlib import ExitStack
from pathlib import Path
from typing import Any

from py_trees.common import Status

from ..bt.nav2_actions import BtActionNode
from ..core.error_codes import NavResult
from ..core.geometry import Pose2D
from ..navigators.basic_navigator import BasicNavigator
from .bt_log import BtLog, depth_first
from .counters import NavigationCounters
from .mission import TASK_ACTION, Mission
from .outputs import BUILTIN_OUTPUTS, RunOutput, output_files, output_plugin, start_outputs
from .report import RunReport, waypoint_status
from .spec import builds_map
from .trajectory import TrajectoryRecorder


def start_task(nav: BasicNavigator, mission: Mission) -> bool:
    """Send the mission's task; False if the server rejected it."""
    task = mission.spec.task
    if mission.task == "explore":
        return nav.explore()
    if mission.task == "drive":
        drive = task.drive
        return drive is not None and nav.drive(drive.commands, assisted=drive.assisted)
    dock = task.dock
    if mission.task == "dock" and dock is not None:
        if dock.dock_id is not None:
            return nav.dock_robot_by_id(
                dock.dock_id, dock.navigate_to_staging_pose, dock.max_staging_time
            )
        assert dock.dock_pose is not None  # the spec asks for one of the two
        return nav.dock_robot_by_pose(
            dock.dock_pose, dock.dock_type, dock.navigate_to_staging_pose, dock.max_staging_time
        )
    poses = [Pose2D(*p) for p in task.poses]
    if mission.task == "navigate_to_pose":
        return nav.go_to_pose(poses[0])
    if mission.task == "navigate_through_poses":
        return nav.go_through_poses(poses)
    return nav.follow_waypoints(poses)


class FailedNodes:
    """bt_navigator tick listener: per navigation goal, the tree node that failed last.

    A BT action node (ComputePathToPose, FollowPath, Spin...) is preferred, as it is
    what Nav2's error code comes from; a condition's or another leaf's failure counts
    when no action node failed. Status changes are heard through each node's
    `status_listener`, so a failure its parent halts within the same tick is heard too;
    a listener already set there (the bt_log's) is kept and called first, so add this
    listener after the bt_log.
    """

    def __init__(self) -> None:
        #: goal handle -> the last failed action node and the last failed leaf of any kind
        self._failed: dict[Any, dict[str, dict[str, str]]] = {}
        self._roots: list[Any] = []  # the trees heard already (few: one per navigator)

    def __call__(self, navigator: Any, now: float) -> None:
        root = navigator.root
        if root is not None and not any(r is root for r in self._roots):
            self._roots.append(root)
            for node in depth_first(root):
                if not node.children and hasattr(type(node), "status_listener"):
                    node.status_listener = self._listener(navigator, node.status_listener)

    def _listener(self, navigator: Any, before: Callable[..., None] | None) -> Any:
        def changed(node: Any, old: Status, new: Status) -> None:
            if before is not None:
                before(node, old, new)
            if new is Status.FAILURE and navigator.current is not None:
                seen = {"name": node.name, "type": type(node).__name__}
                failed = self._failed.setdefault(navigator.current, {})
                failed["leaf"] = seen
                if isinstance(node, BtActionNode):
                    failed["action"] = seen

        return changed

    def failed_node(self, goal: Any) -> dict[str, str] | None:
        """The node that failed last in the navigation of `goal` (a goal handle), or None."""
        failed = self._failed.get(goal, {})
        node = failed.get("action") or failed.get("leaf")
        return None if node is None else dict(node)

    def goal_ended_at(self, stamp: float) -> Any:
        """The navigation goal that ended at sim time `stamp` (a missed waypoint's)."""
        for goal in self._failed:
            if goal.end_time is not None and abs(goal.end_time - stamp) < 1e-9:
                return goal
        return None


def run_mission(
    mission: Mission,
    out_dir: str | Path | None = None,
    progress: Callable[[BasicNavigator], None] | None = None,
    attach: Callable[[BasicNavigator], None] | None = None,
    plugins: Mapping[str, Any] | None = None,
) -> RunReport:
    """Run `mission` to its end; write its outputs into `out_dir` (None: write nothing).

    `progress(nav)` is called at every poll of the wait (before each physics step) for
    a live status; it must only read, so the run is the same with or without it.
    `attach(nav)` is called once the bring-up is built, before the task is sent (the
    live view adds its component there).
    `plugins` are output plugins the caller built (the CLI's `--foxglove` server, with
    its flags), started and written as the mission's own; one replaces its namesake.
    """
    outputs = list(mission.spec.outputs) if out_dir is not None else []
    outputs += [name for name in plugins or {} if name not in outputs and out_dir is not None]
    out = Path(out_dir) if out_dir is not None else None
    if out is not None:
        out.mkdir(parents=True, exist_ok=True)
        for name in outputs:  # no stale file (or folder: a bag) from an earlier run
            for stale in output_files(name):
                target = out / stale
                if target.is_dir():
                    shutil.rmtree(target)
                else:
                    target.unlink(missing_ok=True)
    given = dict(plugins or {})
    plugins = {n: given.get(n) or output_plugin(n) for n in outputs if n not in BUILTIN_OUTPUTS}
    nav = mission.navigator()
    bt = nav.bt_navigator
    bring_up = [*nav.runtime.components, *bt.tick_listeners]
    log: BtLog | None = None
    with ExitStack() as files:

        def sink(name: str) -> Any:
            if name not in outputs or out is None:
                return None
            return files.enter_context(open(out / output_files(name)[0], "w", newline="\n"))

        recorder = TrajectoryRecorder(
            nav.runtime,
            nav.stack.controller_server.rate,
            sink("trajectory"),
            global_frame=bt.params.global_frame,
            keep_track=bool(plugins),
        )
        nav.runtime.add(recorder)
        counters = NavigationCounters()
        bt.tick_listeners.append(counters)
        log_file = sink("bt_log")
        if log_file is not None:
            log = BtLog(
                log_file,
                lambda: nav.runtime.now,
                idle_transitions=bt.params.bt_log_idle_transitions,
            )
            bt.tick_listeners.append(log)
            for navigator in bt.navigators.values():  # the task's tree is built already
                if navigator.action == TASK_ACTION[mission.task] and navigator.root is not None:
                    log(navigator, nav.now)
        failures = None
        if mission.task == "follow_waypoints":  # after the bt_log: it chains the log's hook
            failures = FailedNodes()
            bt.tick_listeners.append(failures)

        if out is not None:
            start_outputs({n: p for n, p in plugins.items() if n not in given}, nav, out)
        # What the caller brought (a live view, `--foxglove`) stays after the run's end.
        seen = {id(c) for c in (*nav.runtime.components, *bt.tick_listeners)}
        if out is not None:
            start_outputs({n: p for n, p in plugins.items() if n in given}, nav, out)
        if attach is not None:
            attach(nav)
        bring_up += [c for c in (*nav.runtime.components, *bt.tick_listeners) if id(c) not in seen]
        wall0 = time.perf_counter()
        limit_reached = False
        if start_task(nav, mission):
            poll = None if progress is None else lambda: progress(nav)
            result = nav.wait_until_done(mission.spec.time_limit, poll=poll)
            if result is None:
                limit_reached = True
                nav.cancel_task()
                result = nav.get_result()
        else:
            result = nav.get_result()
        wall = time.perf_counter() - wall0

    report = build_report(
        mission, nav, result, recorder, counters, wall, limit_reached, outputs, failures
    )
    if out is not None:
        if "map" in outputs and nav.stack.map_server.map is not None:
            nav.save_map(out / output_files("map")[0])
        if "pose_graph" in outputs:  # slam_toolbox's SerializePoseGraph (checked on load)
            nav.runtime.localizer.serialize_pose_graph(out / output_files("pose_graph")[0])
        for plugin in plugins.values():
            plugin.write(RunOutput(out, mission, nav, report, recorder.track))
        if "report" in outputs:
            report.write(out / output_files("report")[0])
    _end_recording(nav, bring_up, log)
    return report


def _end_recording(nav: BasicNavigator, keep: list[Any], log: BtLog | None) -> None:
    """Take the run's recorders off the runtime (their files are closed): a live view may
    keep the sim going after the run, for the user's own goals."""
    kept = {id(k) for k in keep}
    for component in nav.runtime.components:
        if id(component) not in kept:
            nav.runtime.remove(component)
    listeners = nav.bt_navigator.tick_listeners
    listeners[:] = [c for c in listeners if id(c) in kept]
    if log is not None:
        log.close()


def build_report(
    mission: Mission,
    nav: BasicNavigator,
    result: NavResult | None,
    recorder: TrajectoryRecorder,
    counters: NavigationCounters,
    wall: float,
    limit_reached: bool,
    outputs: list[str],
    failures: FailedNodes | None = None,
) -> RunReport:
    """The run's report from what its recorders kept (also for a run driven by hand);
    `failures` names the node that failed last for each missed waypoint."""
    if result is None:  # a goal rejected outright, or a cancel that did not end in time
        status, code, msg = "failed", None, "the task did not start or did not end"
    else:
        status = str(result.outcome)
        code = result.error_code if result.failed else None
        msg = result.error_msg if result.failed else None
    if limit_reached:
        msg = f"time_limit of {mission.spec.time_limit:g} s reached"
    value = result.value if result is not None else None
    missed = list(getattr(value, "missed_indices", []))
    statuses = [
        _missed_status(m, mission, failures) for m in getattr(value, "missed_waypoints", [])
    ]
    return RunReport(
        mission=mission.name,
        seed=mission.seed,
        status=status,
        error_code=code,
        error_msg=msg,
        sim_time=nav.now,
        wall_time=wall,
        path_length=recorder.path_length,
        collisions=nav.world.collisions,
        recoveries=counters.recoveries,
        replans=counters.replans,
        missed_waypoints=missed,
        localization_error=recorder.localization_error(),
        task=mission.task,
        goals=len(mission.spec.task.poses),
        outputs=[f for name in outputs for f in output_files(name)],
        contacts=[c.to_dict() for c in nav.world.contacts],
        explored_area=(
            nav.stack.explore_server.explored_area()
            if builds_map(mission.spec.localization)
            else None
        ),
        missed_waypoint_statuses=statuses,
    )


def _missed_status(missed: Any, mission: Mission, failures: FailedNodes | None) -> dict[str, Any]:
    """report.json's entry for a missed waypoint (nav2_msgs' MissedWaypoint/WaypointStatus)."""
    stamp = getattr(missed, "stamp", None)
    goal = failures.goal_ended_at(stamp) if failures is not None and stamp is not None else None
    poses = mission.spec.task.poses
    pose = poses[missed.index] if missed.index < len(poses) else _xyyaw(missed.goal)
    return waypoint_status(
        missed.index,
        Pose2D(*pose),
        missed.error_code,
        missed.error_msg,
        stamp,
        failures.failed_node(goal) if failures is not None and goal is not None else None,
    )


def _xyyaw(goal: Any) -> tuple[float, float, float]:
    pose = getattr(goal, "pose", goal)
    return (float(pose.x), float(pose.y), float(getattr(pose, "yaw", 0.0)))
