"""What every node of a tick may take as given, checked once per tick by the tree's root.

`TICK.plain` is True inside a `tick_once()` that found py_trees' blackboard activity
stream off and its logging above DEBUG: a node may then read and write the
blackboard's storage directly and skip py_trees' debug messages, with the same result
py_trees' own calls would give. Outside a tick it is False, so a port read by other
code (a test, a tool) takes py_trees' path. One module-global read, where asking
py_trees costs a class-attribute lookup that CPython 3.11 cannot specialise.
"""

from __future__ import annotations

import py_trees.logging as _pt_logging
from py_trees.blackboard import Blackboard

_INFO = _pt_logging.Level.INFO


class TickState:
    __slots__ = ("plain",)

    def __init__(self) -> None:
        self.plain = False


TICK = TickState()


def plain_now() -> bool:
    """Whether a tick starting now may take the plain path."""
    return Blackboard.activity_stream is None and _pt_logging.level >= _INFO
