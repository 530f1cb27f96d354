"""What the batch's fork server imports once, so each run's process starts warm.

Importing this module loads the mission layer and btnav's own plugins (entry points),
the costly part of a run's start; it runs no mission, so no run's state is in the
processes forked from it.
"""

from __future__ import annotations

from ..mission import runner  # noqa: F401  (the import is the point)
from ..plugins import load_entry_points

load_entry_points()
