"""BT.CPP v4 decorators, timed on sim time."""

from __future__ import annotations

from py_trees.common import Status

from .fakes import Ticker

S, F, R = Status.SUCCESS, Status.FAILURE, Status.RUNNING


def deco(kind: str, script: str, **ports: object) -> Ticker:
    extra = "".join(f", {k}: {v}" for k, v in ports.items())
    return Ticker(f"{kind}: {{child: {{TestScript: {{name: c, script: '{script}'}}}}{extra}}}")


def test_inverter_and_forcers():
    assert deco("Inverter", "S").tick() == F
    assert deco("Inverter", "F").tick() == S
    assert deco("Inverter", "R").tick() == R
    assert deco("ForceSuccess", "F").tick() == S
    assert deco("ForceFailure", "S").tick() == F


def test_repeat_runs_a_quick_child_num_cycles_times_in_one_tick():
    t = deco("Repeat", "S", num_cycles=3)
    assert t.tick() == S
    assert t["c"].ticks == 3
    t = deco("Repeat", "S S F", num_cycles=5)
    assert t.tick() == F


def test_retry_until_successful():
    t = deco("RetryUntilSuccessful", "F F S", num_attempts=3)
    assert t.tick() == S and t["c"].ticks == 3
    t = deco("RetryUntilSuccessful", "F F S", num_attempts=2)
    assert t.tick() == F


def test_endless_repeat_yields_between_cycles():
    t = deco("Repeat", "S", num_cycles=-1)
    assert [t.tick(), t.tick()] == [R, R]
    assert t["c"].ticks == 2


def test_keep_running_until_failure():
    t = deco("KeepRunningUntilFailure", "S S F")
    assert [t.tick(), t.tick(), t.tick()] == [R, R, F]


def test_delay_waits_on_sim_time():
    t = deco("Delay", "S", delay_msec=500)
    assert t.tick() == R
    assert t.tick(dt=0.4) == R
    assert t["c"].ticks == 0
    assert t.tick(dt=0.1) == S
    assert t["c"].ticks == 1
    assert t.tick() == R  # a new run waits again


def test_timeout_halts_a_child_that_runs_too_long_on_sim_time():
    t = deco("Timeout", "R", msec=1000)
    assert t.tick() == R
    assert t.tick(dt=0.9) == R
    assert t.tick(dt=0.1) == F
    assert t["c"].halts == 1
    t = deco("Timeout", "R R S", msec=1000)
    assert [t.tick(), t.tick(dt=0.5), t.tick(dt=0.4)] == [R, R, S]


def test_run_once_skips_afterwards():
    t = Ticker(
        "Fallback:\n  children:\n"
        "    - RunOnce: {child: {TestScript: {name: once, script: F}}}\n"
        "    - TestScript: {name: after, script: S}\n"
    )
    assert t.tick() == S
    assert t.tick() == S  # RunOnce is skipped (passed over), not a SUCCESS of the Fallback
    assert t["once"].ticks == 1 and t["after"].ticks == 2
    t = deco("RunOnce", "F", then_skip="false")
    assert [t.tick(), t.tick()] == [F, F]
    assert t["c"].ticks == 1
