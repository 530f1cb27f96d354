"""A built tree as text (py_trees' own display), for `btnav tree show` and tests."""

from __future__ import annotations

import py_trees
from py_trees.behaviour import Behaviour


def tree_text(root: Behaviour, *, show_status: bool = False) -> str:
    """py_trees' ASCII rendering of the tree (node names and kinds; statuses on request)."""
    return py_trees.display.ascii_tree(root, show_status=show_status)
