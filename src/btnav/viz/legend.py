"""A plot's legend entries, the same on every matplotlib the package supports.

matplotlib < 3.11 has no legend handler for a `PatchCollection`, so a labelled
collection (the world's walls and obstacles, drawn as one collection) is left out of
`get_legend_handles_labels()`; a plain patch of the collection's colour stands in.
"""

from __future__ import annotations

from typing import Any


def legend_entries(ax: Any) -> dict[str, Any]:
    """Each label once (the first artist that has it) -> its legend handle."""
    from matplotlib.collections import PatchCollection
    from matplotlib.patches import Patch

    handles, labels = ax.get_legend_handles_labels()
    entries = dict(zip(labels, handles, strict=True))
    for collection in ax.collections:
        label = collection.get_label()
        missing = not label.startswith("_") and label not in entries
        if missing and isinstance(collection, PatchCollection):
            face = collection.get_facecolor()
            entries[label] = Patch(
                facecolor=face[0] if len(face) else "none", alpha=collection.get_alpha()
            )
    return entries
