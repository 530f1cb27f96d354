"""`bt_log.jsonl`: every status change of every node of the running tree, one JSON per line.

Each line is a nav2_msgs/BehaviorTreeStatusChange in JSON: `timestamp` (sim seconds),
`node_name`, `uid` (the node's place in the tree, depth first from 0, as BT.CPP
numbers them), `previous_status` and `current_status` in BT.CPP's words (IDLE,
RUNNING, SUCCESS, FAILURE), plus the node's `type` and the `navigator` that ticked it.
bt_navigator's `bt_log_idle_transitions: false` leaves out changes to IDLE, as Nav2's
logger does. Lines stream to the file after each tick and halt.
"""

from __future__ import annotations

import json
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

    def __init__(self, sink: TextIO, *, idle_transitions: bool = True) -> None:
        self.sink = sink
        self.idle_transitions = idle_transitions
        self.changes = 0
        self._root: Any = None
        self._nodes: list[Any] = []
        self._last: list[Status] = []

    def __call__(self, navigator: Any, now: float) -> None:
        root = navigator.root
        if root is None:
            return
        if root is not self._root:
            self._root = root
            self._nodes = list(_depth_first(root))
            self._last = [Status.INVALID] * len(self._nodes)
        last = self._last
        for uid, node in enumerate(self._nodes):
            status = node.status
            before = last[uid]
            if status is before:
                continue
            last[uid] = status
            if status is Status.INVALID and not self.idle_transitions:
                continue
            self.changes += 1
            record = {
                "timestamp": now,
                "navigator": navigator.name,
                "node_name": node.name,
                "type": type(node).__name__,
                "uid": uid,
                "previous_status": STATUS_NAMES[before],
                "current_status": STATUS_NAMES[status],
            }
            self.sink.write(json.dumps(record) + "\n")


def _depth_first(node: Any) -> Any:
    """The node, then its children's subtrees in order (BT.CPP's uid order)."""
    yield node
    for child in node.children:
        yield from _depth_first(child)
