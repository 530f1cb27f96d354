"""Nav2-style params files: loading, schemas and checks.

`load_params(path)` reads a Nav2 params file as Nav2 writes it and returns a
`ParamsFile`: each server's validated model, its plugin sections (resolved to a
registered btnav plugin or "not implemented yet"), the keys btnav ignores, and the
keys Nav2 itself skips (`skipped`: one warning each; see `legacy_keys`).
Key paths everywhere are ROS parameter paths as the file nests them, without
`ros__parameters`: `local_costmap.local_costmap.inflation_layer.inflation_radius`.
"""

from .check import ParamsCheck, check_params
from .loader import load_params, load_params_doc
from .nav2_known import known_plugin_type
from .paramsfile import (
    IgnoredEntry,
    ParamsFile,
    Placeholder,
    PluginSection,
    ServerParams,
    SkippedKey,
)
from .schema import FieldProblem, ParamsModel, Points, Why, ignored, one_of, validate_section
from .servers import SERVERS, PluginList, ServerSpec
from .updates import apply_overrides, parse_set_option, validate_update

__all__ = [
    "SERVERS",
    "FieldProblem",
    "IgnoredEntry",
    "ParamsCheck",
    "ParamsFile",
    "ParamsModel",
    "Placeholder",
    "PluginList",
    "PluginSection",
    "Points",
    "ServerParams",
    "ServerSpec",
    "SkippedKey",
    "Why",
    "apply_overrides",
    "check_params",
    "ignored",
    "known_plugin_type",
    "load_params",
    "load_params_doc",
    "one_of",
    "parse_set_option",
    "validate_section",
    "validate_update",
]
