"""Hot methods copied into each subclass, so that every call site in them sees one class.

CPython (3.11 on) specialises each attribute read, attribute write and method call of a
function in place, for the one class it last saw there. A base-class method that runs
for many classes in turn (`ControlNode.execute_tick` for every control of a tree,
`ActionServer.update` for every server) keeps missing those caches and runs its lookups
the generic way: a hash probe of the class's attributes and of the instance's, a few
cache misses each on a loop that finds the caches cold after the costmaps and the
controller ran. Each subclass gets its own copy of the methods named hot: the same code
and behaviour, a code object (and so inline caches) of its own.
"""

from __future__ import annotations

import types
from collections.abc import Iterable
from typing import Any


def copy_hot_methods(cls: type, names: Iterable[str]) -> None:
    """Give `cls` its own copy of each method in `names` that it inherits (a class's own
    methods are left alone; it already has them to itself)."""
    for name in names:
        inherited = getattr(cls, name, None)
        if name not in cls.__dict__ and isinstance(inherited, types.FunctionType):
            setattr(cls, name, _own_copy(inherited))


def original(method: Any) -> Any:
    """The function a class's copy of a hot method was made from (itself if not a copy):
    compare this, not the attribute, to ask whether a class overrides a method."""
    return getattr(method, "_btnav_original", method)


def _own_copy(func: types.FunctionType) -> types.FunctionType:
    func = original(func)
    copy = types.FunctionType(
        func.__code__.replace(),
        func.__globals__,
        func.__name__,
        func.__defaults__,
        func.__closure__,
    )
    copy.__kwdefaults__ = func.__kwdefaults__
    copy.__qualname__, copy.__doc__, copy.__module__ = (
        func.__qualname__,
        func.__doc__,
        func.__module__,
    )
    copy.__annotations__ = func.__annotations__
    copy._btnav_original = func  # type: ignore[attr-defined]
    return copy
