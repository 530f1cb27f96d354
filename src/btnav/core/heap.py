"""The run loop's heap: what was alive before a run is left out of the run's collections.

A bring-up (world, maps, params, costmaps, trees, imports) leaves some 90k objects that
CPython's cyclic garbage collector tracks. They are still young when the loop starts,
so the first full collection comes during the run: on the office tour one pause of
80-130 ms, 4-5 % of the tour's wall time, landing in whichever component allocates at
that moment. `frozen_heap()` moves every tracked object into the permanent generation
(`gc.freeze()`, CPython's tool for long-lived start-up state; a list splice, O(1)) while
the loop runs, so collections during the run only scan what the run allocates, and
gives them back to the collector (`gc.unfreeze()`) when it returns: nothing is kept
alive longer than the run. Garbage collection never changes what a run computes.
"""

from __future__ import annotations

import gc
from collections.abc import Iterator
from contextlib import contextmanager

#: What the interpreter itself keeps frozen: CPython 3.12 starts with a few hundred
#: objects in the permanent generation, which are nobody's freeze.
_FROZEN_AT_START = gc.get_freeze_count()


@contextmanager
def frozen_heap() -> Iterator[None]:
    """Freeze the heap for the duration of the block, unless the collector is off or
    someone (the user, an enclosing loop) froze it already: their freeze is theirs."""
    if not gc.isenabled() or gc.get_freeze_count() > _FROZEN_AT_START:
        yield
        return
    gc.freeze()
    try:
        yield
    finally:
        gc.unfreeze()
