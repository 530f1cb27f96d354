"""Nav2's controls and RateController, ticked as Nav2 1.5 ticks them."""

from __future__ import annotations

from py_trees.common import Status

from .fakes import Ticker

S, F, R = Status.SUCCESS, Status.FAILURE, Status.RUNNING


def recovery(retries: int, main: str, rec: str) -> Ticker:
    return Ticker(
        f"RecoveryNode:\n  number_of_retries: {retries}\n  children:\n"
        f"    - TestScript: {{name: main, script: '{main}'}}\n"
        f"    - TestScript: {{name: rec, script: '{rec}'}}\n"
    )


def test_recovery_node_retries_its_first_child_after_the_recovery():
    t = recovery(1, "F S", "R S")
    assert [t.tick(), t.tick()] == [R, S]
    assert t["main"].ticks == 2 and t["rec"].ticks == 2


def test_recovery_node_fails_after_number_of_retries():
    t = recovery(2, "F", "R S R S R S")
    assert [t.tick(), t.tick(), t.tick()] == [R, R, F]
    assert t["main"].ticks == 3  # first try + 2 retries
    assert t["rec"].ticks == 4  # two recoveries, each RUNNING then SUCCESS
    # the count starts again on the next run
    assert t.tick() == R and t["main"].ticks == 4


def test_recovery_node_fails_when_the_recovery_fails():
    t = recovery(5, "F", "F")
    assert t.tick() == F
    assert t["main"].ticks == 1 and t["rec"].ticks == 1


def test_pipeline_sequence_reticks_earlier_children_while_a_later_one_runs():
    t = Ticker(
        "PipelineSequence:\n  children:\n"
        "    - TestScript: {name: plan, script: R S R R S}\n"
        "    - TestScript: {name: follow, script: R R R R S}\n"
    )
    assert t.tick() == R  # plan runs; follow has not started yet
    assert t["follow"].ticks == 0
    assert t.tick() == R  # plan done, follow starts
    assert t.tick() == R  # plan runs again, follow keeps running
    assert (t["plan"].ticks, t["follow"].ticks) == (3, 2)
    assert t["follow"].halts == 0
    assert [t.tick(), t.tick(), t.tick()] == [R, R, S]


def test_pipeline_sequence_failure_halts_the_running_child():
    t = Ticker(
        "PipelineSequence:\n  children:\n"
        "    - TestScript: {name: plan, script: S F}\n"
        "    - TestScript: {name: follow, script: R}\n"
    )
    assert [t.tick(), t.tick()] == [R, F]
    assert t["follow"].halts == 1


def test_round_robin_moves_to_the_next_child_per_failure():
    t = Ticker(
        "RoundRobin:\n  wrap_around: true\n  children:\n"
        "    - TestScript: {name: a, script: F S}\n"
        "    - TestScript: {name: b, script: R S}\n"
        "    - TestScript: {name: c, script: S}\n"
    )
    assert t.tick() == R  # a failed, b runs
    assert t.tick() == S  # b succeeds
    assert t.tick() == S  # next run starts at c, not a
    assert (t["a"].ticks, t["b"].ticks, t["c"].ticks) == (1, 2, 1)
    assert t.tick() == S  # wrapped around to a
    assert t["a"].ticks == 2


def test_round_robin_gives_each_recovery_the_next_action():
    def run(wrap: str, retries: int) -> Ticker:
        t = Ticker(
            f"RecoveryNode:\n  number_of_retries: {retries}\n  children:\n"
            "    - TestScript: {name: nav, script: F}\n"
            f"    - RoundRobin:\n        wrap_around: {wrap}\n        children:\n"
            "          - TestScript: {name: clear}\n"
            "          - TestScript: {name: spin}\n"
            "          - TestScript: {name: wait}\n"
        )
        assert t.tick() == F
        return t

    t = run("true", 4)
    assert [t[n].ticks for n in ("clear", "spin", "wait")] == [2, 1, 1]
    assert t["nav"].ticks == 5
    # Nav2 1.5's default (wrap_around false): after the last child, RoundRobin fails
    t = run("false", 6)
    assert [t[n].ticks for n in ("clear", "spin", "wait")] == [1, 1, 1]
    assert t["nav"].ticks == 3


def test_rate_controller_ticks_its_child_at_hz_on_sim_time():
    t = Ticker("RateController: {hz: 2.0, child: {TestScript: {name: plan}}}")
    statuses = [t.tick(dt=0.0 if i == 0 else 0.1) for i in range(21)]  # t = 0.0 .. 2.0
    assert t["plan"].ticks == 5  # t = 0, 0.5, 1.0, 1.5, 2.0
    assert statuses[0] == S and statuses[1] == R and statuses[5] == S


def test_rate_controller_ticks_a_running_child_every_tick():
    t = Ticker("RateController: {hz: 1.0, child: {TestScript: {name: plan, script: R R S}}}")
    assert [t.tick(), t.tick(dt=0.1), t.tick(dt=0.1), t.tick(dt=0.1)] == [R, R, S, R]
    assert t["plan"].ticks == 3
