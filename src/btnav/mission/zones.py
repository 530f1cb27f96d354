"""A mission's keepout and speed zones, handed to the params as nav2_bringup's launch does.

bringup_launch.py takes `use_keepout_zones` / `use_speed_zones` and writes them into the
params file where it says KEEPOUT_ZONE_ENABLED / SPEED_ZONE_ENABLED (RewrittenYaml), and
starts keepout_filter_mask_server / speed_filter_mask_server with `yaml_filename` set to
its `keepout_mask` / `speed_mask` arguments. A mission does the same:
`load_zoned_params` loads the params file with the mission's values written in, and
`with_zone_masks` sets each used zone's mask (the mission's `keepout_mask:`, relative to
the mission, else the mask server's own `yaml_filename`, relative to the params file),
checked now so a missing or broken mask is a load error.
"""

from __future__ import annotations

import warnings
from collections.abc import Callable
from pathlib import Path
from typing import Any

from ..core.yaml_io import load_yaml
from ..maps.map_io import load_map
from ..params.loader import load_params_doc, refuse_skipped
from ..params.paramsfile import ParamsFile
from ..params.placeholders import rewrite_launch_tokens
from ..params.updates import apply_overrides
from .errors import MissionError
from .spec import MissionSpec, resolve

#: (mission switch, mission mask key, mask server, the params file's launch token).
ZONES: tuple[tuple[str, str, str, str], ...] = (
    ("use_keepout_zones", "keepout_mask", "keepout_filter_mask_server", "KEEPOUT_ZONE_ENABLED"),
    ("use_speed_zones", "speed_mask", "speed_filter_mask_server", "SPEED_ZONE_ENABLED"),
)


def launch_values(spec: MissionSpec) -> dict[str, bool]:
    """The launch tokens' values this mission writes into its params file."""
    return {token: bool(getattr(spec, switch)) for switch, _, _, token in ZONES}


def load_zoned_params(spec: MissionSpec, path: Path, *, strict: str | None) -> ParamsFile:
    """`load_params(path, strict=...)` of the file the mission's zone switches rewrote."""
    doc = load_yaml(path)
    found = rewrite_launch_tokens(doc, launch_values(spec))
    params = load_params_doc(doc, path)
    params.placeholders += found
    if strict:
        refuse_skipped(params, strict)
    else:
        for skipped in params.skipped:
            warnings.warn(skipped.warning(), stacklevel=3)
    return params


def with_zone_masks(
    spec: MissionSpec, base: Path, params: ParamsFile, where: Callable[..., dict[str, Any]]
) -> ParamsFile:
    """The params with each used zone's mask as its mask server's `yaml_filename`."""
    overrides: dict[str, str] = {}
    for switch, mask_key, server, _ in ZONES:
        if not getattr(spec, switch):
            continue
        given = getattr(spec, mask_key)
        if given is not None:
            path = resolve(base, given)
            if not path.is_file():
                raise MissionError(f"{mask_key} file not found: {path}", **where(mask_key))
        else:
            path = _params_mask(switch, mask_key, server, params, where)
        load_map(path)  # read once now, so a bad mask is a load error
        overrides[f"{server}.yaml_filename"] = str(path)
    return apply_overrides(params, overrides) if overrides else params


def _params_mask(
    switch: str,
    mask_key: str,
    server: str,
    params: ParamsFile,
    where: Callable[..., dict[str, Any]],
) -> Path:
    """The mask the params file's mask server names (relative to the file), or the error
    saying what to give."""
    named = params.server(server).model.yaml_filename if server in params else ""
    if not named:
        raise MissionError(
            f"{switch}: true needs a mask: give {mask_key}: (a map_server YAML, as Nav2's "
            f"launch argument) or set {server}.yaml_filename in {params.path}",
            **where(switch),
        )
    path = Path(named).expanduser()
    path = path if path.is_absolute() else params.path.parent / path
    if not path.is_file():
        raise MissionError(
            f"{switch}: true, but {server}.yaml_filename ({named}) is not a file: {path}",
            **where(switch),
        )
    return path
