"""The tree's blackboard by key: py_trees' one process-wide `Blackboard`, in one place.

The nodes' ports, bt_navigator (the goal, the path, `number_recoveries`) and the test
helpers read and write the blackboard here, by absolute key ("/goal"). A read is a
lookup in py_trees' storage (one dict for the process, cleared in place, never
rebound), which is all py_trees' own client does once a port is resolved to its key,
except for one thing: while py_trees' activity stream is on (`recording()`), a port
takes py_trees' client instead, so that the stream records the access (`ports`).
"""

from __future__ import annotations

from typing import Any

from py_trees.blackboard import Blackboard, KeyMetaData

_STORAGE: dict[str, Any] = Blackboard.storage
_METADATA: dict[str, KeyMetaData] = Blackboard.metadata  # (cleared in place too)


def read(key: str, default: Any = None) -> Any:
    """The entry at `key` (absolute, not nested: "/path"), or `default`."""
    return _STORAGE.get(key, default)


def write(key: str, value: Any) -> None:
    """Set the entry at `key` (absolute, not nested), as py_trees' `Blackboard.set` does."""
    _STORAGE[key] = value
    if key not in _METADATA:
        _METADATA[key] = KeyMetaData()


def recording() -> bool:
    """Whether py_trees' activity stream is on (a port then reads through its client)."""
    return Blackboard.activity_stream is not None


def stored_keys() -> list[str]:
    """The keys that hold a value now."""
    return list(_STORAGE)


def snapshot() -> dict[str, Any]:
    """Every entry, to `restore` later (a test leaves the process's blackboard as it was)."""
    return dict(_STORAGE)


def restore(entries: dict[str, Any]) -> None:
    """The blackboard as `snapshot` had it, and nothing else."""
    _STORAGE.clear()
    _STORAGE.update(entries)
