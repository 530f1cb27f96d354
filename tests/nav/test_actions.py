"""Actions: send_goal -> handle, advanced by the server's update, polled by the client."""

from __future__ import annotations

from dataclasses import dataclass

import pytest

from btnav.core.error_codes import FollowPathError, WaitError
from btnav.core.errors import UnknownNameError
from btnav.core.resources import bundled_dir
from btnav.nav import ActionServer, GoalHandle, GoalStatus, NavResult, Runtime
from btnav.sim.world import World


@dataclass
class WaitGoal:
    time: float


class WaitServer(ActionServer[WaitGoal]):
    """Nav2's Wait behaviour in miniature: succeeds after `goal.time`, feedback `time_left`."""

    def __init__(self, **kw):
        super().__init__("Wait", "wait", **kw)
        self.started: list[int] = []
        self.preempted: list[tuple[int, int]] = []
        self.cancel_cycles = 0
        self.stop_cycles_needed = 0

    def validate_goal(self, goal):
        return "time must not be negative" if goal.time < 0 else None

    def on_start(self, handle, now):
        self.started.append(handle.goal_id)

    def on_preempt(self, old, new, now):
        self.preempted.append((old.goal_id, new.goal_id))
        return super().on_preempt(old, new, now)

    def execute(self, handle, now):
        left = handle.goal.time - (now - handle.start_time)
        handle.publish_feedback({"time_left": max(left, 0.0)}, now)
        if left <= 1e-9:
            return NavResult.success(value={"total_elapsed_time": now - handle.start_time})
        return None

    def on_cancel(self, handle, now):
        self.cancel_cycles += 1
        if self.cancel_cycles <= self.stop_cycles_needed:
            return None  # still braking
        return NavResult.cancellation()


def cycle(server: ActionServer, t0: float, n: int, dt: float = 0.1) -> float:
    t = t0
    for _ in range(n):
        t = round(t + dt, 9)
        server.update(t)
    return t


def test_a_goal_is_accepted_then_executes_then_succeeds_with_feedback():
    s = WaitServer()
    h = s.send_goal(WaitGoal(0.5))
    assert h.status is GoalStatus.ACCEPTED and h.accepted and not h.done
    assert h.action == "Wait" and s.is_active
    s.update(0.1)
    assert h.status is GoalStatus.EXECUTING and h.start_time == 0.1
    lefts = [h.feedback["time_left"]]
    for k in range(2, 6):
        s.update(k / 10)
        lefts.append(h.feedback["time_left"])
    assert lefts[:-1] == pytest.approx([0.5, 0.4, 0.3, 0.2])
    assert h.feedback_stamp == 0.5 and not h.done
    s.update(0.6)
    assert h.done and h.succeeded and h.status is GoalStatus.SUCCEEDED
    assert h.result.succeeded and h.error_code == 0
    assert h.result.value["total_elapsed_time"] == pytest.approx(0.5)
    assert h.end_time == 0.6 and not s.is_active
    assert h.cancel() is False  # too late


def test_abort_with_nav2s_error_code():
    def execute(handle, now):
        return NavResult.failure(FollowPathError.FAILED_TO_MAKE_PROGRESS)

    s = ActionServer("FollowPath", "follow_path", execute=execute)
    h = s.send_goal("path")
    s.update(0.05)
    assert h.status is GoalStatus.ABORTED and h.done and not h.succeeded
    assert h.error_code == 105 == FollowPathError.FAILED_TO_MAKE_PROGRESS
    assert "progress" in h.error_msg


def test_on_start_may_fail_a_goal_at_once():
    s = ActionServer(
        "FollowPath",
        on_start=lambda h, now: NavResult.failure(FollowPathError.INVALID_PATH, "empty path"),
        execute=lambda h, now: pytest.fail("a failed start never executes"),
    )
    h = s.send_goal([])
    s.update(0.0)
    assert h.status is GoalStatus.ABORTED and h.error_code == 103 and h.error_msg == "empty path"


def test_cancel_a_running_goal():
    s = WaitServer()
    h = s.send_goal(WaitGoal(5.0))
    t = cycle(s, 0.0, 3)
    assert h.cancel() is True
    assert h.status is GoalStatus.CANCELING and not h.done
    cycle(s, t, 1)
    assert h.status is GoalStatus.CANCELED and h.result.canceled and h.done


def test_cancel_that_takes_cycles_stays_canceling_until_the_server_stops():
    s = WaitServer()
    s.stop_cycles_needed = 2
    h = s.send_goal(WaitGoal(5.0))
    t = cycle(s, 0.0, 1)
    h.cancel()
    t = cycle(s, t, 2)
    assert h.status is GoalStatus.CANCELING
    cycle(s, t, 1)
    assert h.status is GoalStatus.CANCELED and s.cancel_cycles == 3


def test_cancel_before_the_server_starts_it():
    s = WaitServer()
    h = s.send_goal(WaitGoal(1.0))
    h.cancel()
    s.update(0.1)
    assert h.status is GoalStatus.CANCELED and s.started == []


def test_a_new_goal_preempts_the_running_one():
    s = WaitServer()
    a = s.send_goal(WaitGoal(5.0))
    t = cycle(s, 0.0, 3)
    b = s.send_goal(WaitGoal(0.2))
    assert a.status is GoalStatus.EXECUTING and b.status is GoalStatus.ACCEPTED
    t = cycle(s, t, 1)
    # As Nav2's SimpleActionServer: the old goal is aborted with an empty result.
    assert a.status is GoalStatus.ABORTED and a.error_code == 0 and "preempted" in a.error_msg
    assert b.status is GoalStatus.EXECUTING and s.current is b
    assert s.preempted == [(a.goal_id, b.goal_id)]
    assert s.started == [a.goal_id, b.goal_id]  # default on_preempt starts afresh
    cycle(s, t, 3)
    assert b.succeeded


def test_a_server_without_preemption_refuses_the_newcomer():
    s = WaitServer(preemptible=False)
    a = s.send_goal(WaitGoal(1.0))
    t = cycle(s, 0.0, 2)
    b = s.send_goal(WaitGoal(0.1))
    t = cycle(s, t, 1)
    assert b.status is GoalStatus.ABORTED and "preemption" in b.error_msg
    assert a.status is GoalStatus.EXECUTING
    cycle(s, t, 10)
    assert a.succeeded


def test_a_pending_goal_is_replaced_by_a_newer_one():
    s = WaitServer()
    a = s.send_goal(WaitGoal(1.0))
    b = s.send_goal(WaitGoal(1.0))
    assert a.status is GoalStatus.ABORTED and b.status is GoalStatus.ACCEPTED
    s.update(0.1)
    assert s.started == [b.goal_id]


def test_a_rejected_goal_is_done_with_goal_rejected():
    s = WaitServer()
    h = s.send_goal(WaitGoal(-1.0))
    assert not h.accepted and h.done and h.status is GoalStatus.UNKNOWN
    assert h.error_code == WaitError.GOAL_REJECTED == 1
    assert "negative" in h.error_msg
    assert not s.is_active


def test_an_exception_aborts_the_goal_with_unknown_and_is_raised():
    def execute(handle, now):
        raise RuntimeError("boom")

    s = ActionServer("Spin", execute=execute)
    h = s.send_goal(1.57)
    with pytest.raises(RuntimeError, match="boom"):
        s.update(0.1)
    assert h.status is GoalStatus.ABORTED and h.error_code == 700 and "boom" in h.error_msg


def test_the_runtime_advances_a_server_at_its_rate_and_clients_find_it_by_name():
    rt = Runtime(World.from_file(bundled_dir("worlds") / "small_office.yaml"), seed=0)
    server = rt.add(WaitServer(rate=10.0))
    client = rt.action_client("wait")
    assert client.wait_for_server()
    h: GoalHandle = client.send_goal(WaitGoal(1.0))
    assert rt.run_until(lambda: h.done, timeout=3.0)
    assert h.succeeded and h.start_time == pytest.approx(0.1) and h.end_time == pytest.approx(1.1)
    assert server.current is h
    with pytest.raises(UnknownNameError, match="wait") as err:
        rt.action_client("wiat").send_goal(WaitGoal(1.0))
    assert err.value.suggestion == "wait"
    assert not rt.action_client("spin").wait_for_server()
