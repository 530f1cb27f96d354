"""The run loop leaves the bring-up's objects out of the collections it triggers."""

from __future__ import annotations

import gc
import weakref
from pathlib import Path

from btnav.core.heap import frozen_heap
from btnav.nav.runtime import Runtime
from btnav.sim.world import World

REPO = Path(__file__).resolve().parents[2]


class _Node:
    other: _Node


def test_what_was_alive_before_is_out_of_the_collections_and_given_back_after():
    a, b = _Node(), _Node()
    a.other, b.other = b, a  # a cycle only the collector frees
    alive = weakref.ref(a)
    with frozen_heap():
        assert gc.get_freeze_count() > 0
        del a, b  # dropped only once frozen: an automatic collection before would free it
        gc.collect()
        assert alive() is not None  # frozen: no collection during the run frees it
    assert gc.get_freeze_count() == 0
    gc.collect()
    assert alive() is None  # given back: the next collection does


def test_a_freeze_made_outside_is_left_alone():
    gc.freeze()
    try:
        frozen = gc.get_freeze_count()
        with frozen_heap():
            pass
        assert gc.get_freeze_count() == frozen
    finally:
        gc.unfreeze()


def test_the_runtime_loop_runs_frozen():
    runtime = Runtime(World.from_file(REPO / "worlds" / "small_office.yaml", seed=0), seed=0)
    seen: list[int] = []

    class Probe:
        rate = 10.0

        def update(self, now: float) -> None:
            seen.append(gc.get_freeze_count())

    runtime.add(Probe())
    runtime.spin_for(0.3)
    runtime.run_until(lambda: False, 0.3)
    assert len(seen) == 6 and all(seen)
    assert gc.get_freeze_count() == 0
