"""Where route graphs are found: btnav's bundled `graphs/` folder stands in for nav2_route's
share folder, so Nav2's `$(find-pkg-share nav2_route)/graphs/x.geojson` (resolved when the
params file loads, `params.placeholders`) finds btnav's copy of `x.geojson`.
"""

from __future__ import annotations

from pathlib import Path


def resolve_graph_path(text: str, base_dir: Path | None = None) -> Path:
    """A `graph_filepath` -> a file path (a relative one from `base_dir`)."""
    path = Path(text).expanduser()
    if not path.is_absolute() and base_dir is not None:
        path = base_dir / path
    return path
