"""`bt_log.jsonl`: every status change of every node of the running tree, one JSON per line.

Each line is a nav2_msgs/BehaviorTreeStatusChange in JSON: `timestamp` (sim seconds),
`node_name`, `uid` (the node's place in the tree, depth first from 0, as BT.CPP
numbers them), `previous_status` and `current_status` in BT.CPP's words (IDLE,
RUNNING, SUCCESS, FAILURE), plus the node's `type` and the `navigator` that ticked it.
btnav's nodes report each change as it happens (`status_listener`), so a condition
that fails and is halted within one tick shows both changes, as Groot's logger does;
any other node is compared after each tick and halt. bt_navigator's
`bt_log_idle_transitions: false` leaves out changes to IDLE, as Nav2's logger does.
"""

from __future__ import annotations

import json
from collections.abc import Callable
from typing import Any, TextIO

from py_trees.common import Status

#: py_trees' statuses in BT.CPP's words.
STATUS_NAMES = {
    Status.INVALID: "IDLE",
    Status.RUNNING: "RUNNING",
    Status.SUCCESS: "SUCCESS",
    Status.FAILURE: "FAILURE",
}


class BtLog:
    """A bt_navigator tick listener writing node status changes."""

    def __init__(
        self, sink: TextIO | None, now: Callable[[], float], *, idle_transitions: bool = True
    ) -> None:
        self.sink: TextIO | None = sink
        self.now = now
        self.idle_transitions = idle_transitions
        self.changes = 0
        self._root: Any = None
        self._navigator = ""
        self._nodes: list[Any] = []
        self._uid: dict[int, int] = {}
        self._last: list[Status] = []

    def __call__(self, navigator: Any, now: float) -> None:
        root = navigator.root
        if root is None:
            return
        if root is not self._root:
            self._attach(root)
        self._navigator = navigator.name
        last = self._last
        for uid, node in enumerate(self._nodes):
            if node.status is not last[uid]:
                self._write(uid, node, last[uid], node.status, now)

    def _attach(self, root: Any) -> None:
        for node in self._nodes:  # the last tree's nodes stop reporting here
            if "status_listener" in node.__dict__:
                node.status_listener = None
        self._root = root
        self._nodes = list(depth_first(root))
        self._uid = {id(node): uid for uid, node in enumerate(self._nodes)}
        self._last = [Status.INVALID] * len(self._nodes)  # a tree starts idle
        for node in self._nodes:
            if hasattr(type(node), "status_listener"):
                node.status_listener = self._changed

    def close(self) -> None:
        """Write no more (the file is about to close); the nodes may go on reporting."""
        self.sink = None

    def _changed(self, node: Any, old: Status, new: Status) -> None:
        uid = self._uid.get(id(node))
        if uid is not None:
            self._write(uid, node, self._last[uid], new, self.now())

    def _write(self, uid: int, node: Any, before: Status, status: Status, now: float) -> None:
        self._last[uid] = status
        if self.sink is None:
            return
        if status is Status.INVALID and not self.idle_transitions:
            return
        self.changes += 1
        if self.sink is None:
            return
        record = {
            "timestamp": now,
            "navigator": self._navigator,
            "node_name": node.name,
            "type": type(node).__name__,
            "uid": uid,
            "previous_status": STATUS_NAMES[before],
            "current_status": STATUS_NAMES[status],
        }
        self.sink.write(json.dumps(record) + "\n")


def depth_first(node: Any) -> Any:
    """The node, then its children's subtrees in order (BT.CPP's uid order)."""
    yield node
    for child in node.children:
        yield from depth_first(child)
