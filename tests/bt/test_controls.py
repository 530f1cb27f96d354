"""BT.CPP v4 control nodes: the semantics Nav2's trees rely on, with fake leaves."""

from __future__ import annotations

from py_trees.common import Status

from .fakes import Ticker, set_bb

S, F, R = Status.SUCCESS, Status.FAILURE, Status.RUNNING


def seq(kind: str, *children: str) -> str:
    body = "\n".join(f"    - {c}" for c in children)
    return f"{kind}:\n  children:\n{body}\n"


def test_sequence_resumes_the_running_child_without_reticking_earlier_ones():
    t = Ticker(seq("Sequence", "TestScript: {name: a}", "TestScript: {name: b, script: R R S}"))
    assert [t.tick(), t.tick(), t.tick()] == [R, R, S]
    assert t["a"].ticks == 1 and t["b"].ticks == 3


def test_sequence_failure_restarts_from_the_first_child():
    t = Ticker(seq("Sequence", "TestScript: {name: a}", "TestScript: {name: b, script: F S}"))
    assert t.tick() == F
    assert t.tick() == S
    assert t["a"].ticks == 2


def test_sequence_with_memory_retries_the_failed_child_only():
    t = Ticker(
        seq("SequenceWithMemory", "TestScript: {name: a}", "TestScript: {name: b, script: F S}")
    )
    assert t.tick() == F
    assert t.tick() == S
    assert t["a"].ticks == 1 and t["b"].ticks == 2


def test_reactive_sequence_halts_the_running_child_when_a_condition_fails():
    t = Ticker(
        seq("ReactiveSequence", 'TestFlag: {value: "{ok}"}', "TestScript: {name: act, script: R}")
    )
    set_bb("ok", True)
    assert [t.tick(), t.tick()] == [R, R]
    assert t["TestFlag"].ticks == 2  # the condition is re-checked every tick
    set_bb("ok", False)
    assert t.tick() == F
    assert t["act"].halts == 1
    assert t["act"].status == Status.INVALID


def test_fallback_keeps_its_place_and_reactive_fallback_preempts():
    t = Ticker(
        seq("Fallback", "TestScript: {name: a, script: F}", "TestScript: {name: b, script: R S}")
    )
    assert [t.tick(), t.tick()] == [R, S]
    assert t["a"].ticks == 1

    t = Ticker(
        seq("ReactiveFallback", 'TestFlag: {value: "{done}"}', "TestScript: {name: act, script: R}")
    )
    set_bb("done", False)
    assert t.tick() == R
    set_bb("done", True)
    assert t.tick() == S
    assert t["act"].halts == 1


def test_parallel_counts_successes_and_failures():
    t = Ticker(
        "Parallel:\n  success_count: 2\n  children:\n"
        "    - TestScript: {name: a, script: S}\n"
        "    - TestScript: {name: b, script: R R S}\n"
        "    - TestScript: {name: c, script: R}\n"
    )
    assert [t.tick(), t.tick(), t.tick()] == [R, R, S]
    assert t["a"].ticks == 1  # a finished child is not ticked again
    assert t["c"].halts == 1  # the one still running is halted on completion

    t = Ticker(
        "Parallel:\n  failure_count: 1\n  children:\n"
        "    - TestScript: {name: a, script: R F}\n    - TestScript: {name: b, script: R}\n"
    )
    assert [t.tick(), t.tick()] == [R, F]
    assert t["b"].halts == 1


def test_if_then_else_checks_its_condition_once_per_run():
    src = seq(
        "IfThenElse",
        'TestFlag: {value: "{c}"}',
        "TestScript: {name: then, script: R S}",
        "TestScript: {name: other}",
    )
    t = Ticker(src)
    set_bb("c", True)
    assert t.tick() == R
    set_bb("c", False)  # not re-checked while the branch runs
    assert t.tick() == S
    assert t["other"].ticks == 0
    assert t.tick() == S and t["other"].ticks == 1


def test_while_do_else_switches_branch_and_halts_the_other():
    src = seq(
        "WhileDoElse",
        'TestFlag: {value: "{c}"}',
        "TestScript: {name: do, script: R}",
        "TestScript: {name: else, script: R}",
    )
    t = Ticker(src)
    set_bb("c", True)
    assert t.tick() == R
    set_bb("c", False)
    assert t.tick() == R
    assert t["do"].halts == 1 and t["else"].ticks == 1


def test_halting_a_running_subtree_halts_its_running_leaves():
    t = Ticker(
        "ReactiveSequence:\n  children:\n"
        '    - TestFlag: {value: "{ok}"}\n'
        "    - Sequence:\n        children:\n"
        "          - Inverter: {child: {TestScript: {name: deep, script: R}}}\n"
    )
    set_bb("ok", True)
    assert t.tick() == R
    set_bb("ok", False)
    assert t.tick() == F
    assert t["deep"].halts == 1
    assert all(n.status == Status.INVALID for n in t.root.children[1].iterate())
