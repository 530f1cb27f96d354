"""BehaviorTree.CPP's built-in leaves that need no server."""

from __future__ import annotations

from py_trees.common import Status

from ..plugins import register
from .base import LeafNode


@register("bt_node", "AlwaysSuccess")
class AlwaysSuccess(LeafNode):
    def update(self) -> Status:
        return Status.SUCCESS


@register("bt_node", "AlwaysFailure")
class AlwaysFailure(LeafNode):
    def update(self) -> Status:
        return Status.FAILURE
