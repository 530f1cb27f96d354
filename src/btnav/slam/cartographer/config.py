"""Cartographer's `.lua` configuration, run by a real Lua runtime and checked like a params file.

A Cartographer user's `my_robot.lua` is a program (`include`, `math.rad`, assignments
into tables the defaults built), so btnav runs it with lupa in a sandbox instead of
guessing at its text: no `os`, `io`, `require`, `dofile` or `load`, a cap on instructions
and memory, and `include` resolved the way `cartographer_node` does (the file's own
folder and `search_dirs`, then btnav's copies of Cartographer's defaults). Where Lua
cannot say where a key came from, a small scan of the source finds the `KEY =` that
wrote it, so every mistake names its file, line and dotted key, as btnav's YAML does.

The Lua sandbox lives in `lua_sandbox`, the typed views in `options`; this
module loads, checks and types (their names are re-exported here).
"""

from __future__ import annotations

import functools
import math
import re
import typing
from bisect import bisect_right
from collections.abc import Callable, Sequence
from dataclasses import fields, is_dataclass
from pathlib import Path
from typing import Any

from ...core.suggest import best_match
from .lua_sandbox import FORBIDDEN, MAX_INSTRUCTIONS, MAX_MEMORY, CartographerConfigError, LuaRun
from .options import (
    GLOBALS,
    PG,
    TB2D,
    TB3D,
    VIEWS,
    AdaptiveVoxelFilter,
    CartographerConfig,
    CeresScanMatcher,
    ConstraintBuilder,
    FastCorrelativeScanMatcher,
    Frames,
    Key,
    MotionFilter,
    OptimizationProblem,
    PoseGraph,
    RealTimeCorrelativeScanMatcher,
    Submaps2D,
    TrajectoryBuilder2D,
    spell,
)

__all__ = [
    "DEFAULTS_DIR",
    "FORBIDDEN",
    "GLOBALS",
    "MAX_INSTRUCTIONS",
    "MAX_MEMORY",
    "PG",
    "TB2D",
    "TB3D",
    "VIEWS",
    "AdaptiveVoxelFilter",
    "CartographerConfig",
    "CartographerConfigError",
    "CeresScanMatcher",
    "ConstraintBuilder",
    "FastCorrelativeScanMatcher",
    "Frames",
    "Key",
    "MotionFilter",
    "OptimizationProblem",
    "PoseGraph",
    "RealTimeCorrelativeScanMatcher",
    "Submaps2D",
    "TrajectoryBuilder2D",
    "load_cartographer_config",
    "spell",
]  # fmt: skip

DEFAULTS_DIR = Path(__file__).resolve().parent / "defaults"

#: Keys cartographer_ros and the builders read only when present.
OPTIONAL: set[Key] = {
    ("publish_to_tf",), ("publish_tracked_pose",), ("use_pose_extrapolator",),
    ("ignore_out_of_order",), ("trajectory_builder", "pure_localization_trimmer"),
    ("trajectory_builder", "pose_graph_odometry_motion_filter"), (*PG, "overlapping_submaps_trimmer_2d"),
}  # fmt: skip
#: Leaf names Cartographer reads with GetInt/GetNonNegativeInt; every other number is a double.
_INTEGERS = (
    "branch_and_bound_depth fresh_submaps_count full_resolution_depth max_num_final_iterations "
    "max_num_iterations max_submaps_to_keep min_added_submaps_count min_num_points num_accumulated_range_data "
    "num_background_threads num_free_space_voxels num_normal_samples num_range_data num_threads "
    "optimize_every_n_nodes rotational_histogram_size update_weight_range_exponent num_laser_scans "
    "num_multi_echo_laser_scans num_subdivisions_per_laser_scan num_point_clouds"
)
INTEGER_KEYS = frozenset(_INTEGERS.split())
#: Keys btnav's models do not carry but whose value is what btnav does anyway (so not "ignored").
BEHAVES_AS: dict[Key, Any] = {
    (*TB2D, "use_imu_data"): False, ("map_builder", "use_trajectory_builder_2d"): True,
    (*TB2D, "submaps", "grid_options_2d", "grid_type"): "PROBABILITY_GRID",
    (*TB2D, "submaps", "range_data_inserter", "range_data_inserter_type"): "PROBABILITY_GRID_INSERTER_2D",
    (*TB2D, "submaps", "range_data_inserter", "probability_grid_range_data_inserter", "insert_free_space"): True,
}  # fmt: skip

_GT0 = ("> 0", lambda v: v > 0)
_UNIT = ("within [0, 1]", lambda v: 0 <= v <= 1)
#: Range rules by leaf name (any path) or full path; Cartographer CHECK-fails on most of these.
BOUNDS: dict[str | Key, tuple[str, Callable[[float], bool]]] = {
    "num_accumulated_range_data": ("at least 1", lambda v: v >= 1), "num_range_data": ("at least 1", lambda v: v >= 1),
    "branch_and_bound_depth": ("at least 1", lambda v: v >= 1), "resolution": _GT0, "huber_scale": _GT0,
    "hit_probability": ("within (0.5, 1)", lambda v: 0.5 < v < 1), "miss_probability": ("within (0, 0.5)", lambda v: 0 < v < 0.5),
    "sampling_ratio": _UNIT, "global_sampling_ratio": _UNIT, "min_score": _UNIT, "global_localization_min_score": _UNIT,
    ("num_subdivisions_per_laser_scan",): ("at least 1", lambda v: v >= 1),
}  # fmt: skip


def load_cartographer_config(
    path: str | Path, *, search_dirs: Sequence[Path] = ()
) -> CartographerConfig:
    """Run `path` as `cartographer_node -configuration_basename` would, then check and type it."""
    file = Path(path)
    if not file.is_file():
        near = best_match(file.name, [p.name for p in file.parent.glob("*.lua")])
        raise CartographerConfigError("no such configuration file", file=file, suggestion=near)
    run = LuaRun(file, [file.parent, *map(Path, search_dirs), DEFAULTS_DIR])
    options = run.options()
    reference = _reference()
    places = _Places(run)
    problems: list[CartographerConfigError] = []
    options = _check(options, reference, (), places, problems)
    if not problems:
        _check_meaning(options, places, problems)
    if problems:
        raise min(problems, key=places.order)
    views = {name: _view(cls, _get(options, at)) for name, (cls, at) in VIEWS.items()}
    return CartographerConfig(
        options=options, file=file, ignored=_ignored(options, reference, ()), **views
    )


@functools.lru_cache(maxsize=1)
def _reference() -> dict[str, Any]:
    """Every key a configuration may hold, with its default (shared: never mutate it)."""
    return LuaRun(DEFAULTS_DIR / "options_reference.lua", [DEFAULTS_DIR]).options()


# -- where a key was written ---------------------------------------------------------------

_TOKEN = re.compile(
    r"""--\[(?P<lc>=*)\[.*?\](?P=lc)\]|--[^\n]*|\[(?P<ls>=*)\[(?P<lstr>.*?)\](?P=ls)\]"""
    r"""|"(?P<dq>(?:\\.|[^"\\\n])*)"|'(?P<sq>(?:\\.|[^'\\\n])*)'|(?P<name>[A-Za-z_]\w*)"""
    r"""|(?P<num>\d[\w.]*|\.\d[\w.]*)|(?P<op>==|~=|<=|>=|\.\.\.?|\S)""",
    re.S,
)
#: How the scan names the table a file's top-level `return {...}` builds.
RETURNED: Key = ("\0return",)
_LUA_KEYWORDS = (
    "and break do else elseif end false for function goto if in local nil not or repeat "
    "return then true until while"
)
_KEYWORDS = frozenset(_LUA_KEYWORDS.split())


def _assignments(text: str) -> tuple[list[tuple[int, Key]], int | None]:
    """Each `A.B = ...`, `[A.B = ]{k = ...}` in a source as (line, written dotted key), and the
    line of the last top-level `return`; a scan, not a parser, enough to point at a key."""
    starts = [0] + [i + 1 for i, c in enumerate(text) if c == "\n"]
    out: list[tuple[int, Key]] = []
    stack: list[Key | None] = []  # the key each open `{` is the value of
    chain: list[str] = []
    chain_line = 0
    after: Key | None = None  # the key an `=` just assigned (its `{` opens that table)
    returns: int | None = None
    prev = ""
    for m in _TOKEN.finditer(text):
        tok, name, op = m.group(0), m.group("name"), m.group("op")
        line = bisect_right(starts, m.start())
        if tok.startswith("--"):
            continue
        opening = after
        after = None
        string = m.group("dq") if m.group("dq") is not None else m.group("sq")
        if name and name not in _KEYWORDS:
            if prev == "." and chain:
                chain.append(name)
            else:
                chain, chain_line = [name], line
        elif string is not None and prev == "[" and (stack or chain):
            chain = [*chain, string] if chain and not stack else [string]
            chain_line = line
        elif op in ("]", ".") and chain:
            pass
        elif op == "=" and chain:
            parent = stack[-1] if stack else ()
            key = None if parent is None else (*parent, *chain)
            if key is not None:
                out.append((chain_line, key))
            after, chain = key, []
        elif op == "{":
            stack.append(RETURNED if prev == "return" and not stack else opening)
            chain = []
        elif op == "}":
            if stack:
                stack.pop()
            chain = []
        else:
            if name == "return" and not stack:
                returns = line
            chain = [] if op != "[" else chain
        prev = op or ("" if name is None else name)
    return out, returns


class _Places:
    """Maps a key of the options table to the file and line a user wrote it at."""

    def __init__(self, run: LuaRun) -> None:
        self.files = run.files
        self.user = [i for i, f in enumerate(run.files) if f.parent != DEFAULTS_DIR]
        self.returns: int | None = None
        self.written: dict[Key, list[tuple[int, int]]] = {}  # resolved key -> (file, line)
        self.loose: dict[str, list[tuple[int, int]]] = {}  # leaf name -> places of unresolved keys
        for i in self.user:
            found, returns = _assignments(run.texts[i])
            self.returns = returns if i == 0 else self.returns
            for line, key in found:
                root = () if key[:1] == RETURNED and i == 0 else run.aliases.get(key[0])
                if root is None:
                    self.loose.setdefault(key[-1], []).append((i, line))
                else:
                    self.written.setdefault((*root, *key[1:]), []).append((i, line))

    def where(self, key: Key) -> tuple[Path, int | None]:
        """The last place (options file last: it runs after its includes) that writes `key`,
        else its closest written parent, else the options file's `return`."""
        for k in (key[:n] for n in range(len(key), -1, -1)):
            found = self.written.get(k) or (self.loose.get(k[-1]) if k == key and k else None)
            if found:
                i, line = max(found, key=lambda p: (p[0] == 0, self.user.index(p[0]), p[1]))
                return self.files[i], line
        return self.files[0], self.returns

    def error(
        self, key: Key, message: str, suggestion: str | None = None
    ) -> CartographerConfigError:
        file, line = self.where(key)
        return CartographerConfigError(message, file=file, line=line, key=spell(key), suggestion=suggestion)  # fmt: skip

    def order(self, err: CartographerConfigError) -> tuple[bool, bool, int, int]:
        """Direct mistakes before missing keys, the options file first, then by line."""
        i = next((i for i, f in enumerate(self.files) if str(f) == err.file), len(self.files))
        return (getattr(err, "consequence", False), i != 0, i, err.line or 10**9)


# -- checking --------------------------------------------------------------------------------


def _kind(value: Any) -> str:
    """The Lua type name a user knows (`array` for a table of 1..n)."""
    if isinstance(value, bool):
        return "boolean"
    if isinstance(value, int | float):
        return "number"
    if isinstance(value, str):
        return "string"
    return "array" if isinstance(value, list) else "table"


def _check(value: Any, ref: Any, key: Key, places: _Places, problems: list) -> Any:
    """`value` with its numbers typed as Cartographer reads them; problems appended, not raised."""
    if key[:2] == TB3D:
        return value  # 2D only: accepted unchecked, listed as ignored
    want, got = _kind(ref), _kind(value)
    if want != got:
        shown = f" ({value!r})" if got not in ("table", "array") else ""
        article = "an" if got == "array" else "a"
        problems.append(places.error(key, f"must be a {want}, not {article} {got}{shown}"))
        return value
    if want == "number":
        if key[-1] not in INTEGER_KEYS:
            return float(value)
        if float(value).is_integer():
            return int(value)
        problems.append(places.error(key, f"must be a whole number, not {value!r}"))
        return value
    if want != "table":
        return value
    out: dict[str, Any] = {}
    meant = set()  # what the unknown keys here are misspellings of: not missing, misspelt
    for k, v in value.items():
        if k not in ref:
            problems.append(_unknown((*key, str(k)), ref, places))
            meant.add(problems[-1].suggestion)
        else:
            out[k] = _check(v, ref[k], (*key, k), places, problems)
    missing = [k for k in ref if k not in value and k not in meant and (*key, k) not in OPTIONAL]
    if missing:
        more = (
            f" (and {len(missing) - 1} more: {', '.join(missing[1:4])}...)" if missing[1:] else ""
        )
        hint = "" if not key else ' (include "map_builder.lua" and "trajectory_builder.lua")'
        problems.append(places.error((*key, missing[0]), f"missing: Cartographer needs it{more}{hint}"))  # fmt: skip
        problems[-1].consequence = True  # reported only when nothing more direct is wrong
    return out


def _unknown(key: Key, ref: dict[str, Any], places: _Places) -> CartographerConfigError:
    home = next((k for k in _keys(_reference()) if k[-1] == key[-1]), None)
    if home is not None:  # a real key in the wrong table beats a similar spelling here
        return places.error(key, f"unknown key here: it belongs in {spell(home[:-1])}", spell(home))  # fmt: skip
    return places.error(key, "unknown key", best_match(key[-1], list(ref)))


def _leaves(tree: Any, key: Key = ()) -> list[Key]:
    if not isinstance(tree, dict):
        return [key]
    return [leaf for k, v in tree.items() for leaf in _leaves(v, (*key, k))]


def _keys(tree: Any, key: Key = ()) -> list[Key]:
    """Every key at any depth, sections included (to find where a misplaced key belongs)."""
    if not isinstance(tree, dict):
        return []
    return [k for name, v in tree.items() for k in [(*key, name), *_keys(v, (*key, name))]]


def _get(tree: Any, key: Key) -> Any:
    for part in key:
        tree = tree[part]
    return tree


def _implemented(cls: type, at: Key) -> list[Key]:
    """The option keys a typed view reads."""
    hints = typing.get_type_hints(cls)
    paths = getattr(cls, "PATHS", {})
    out: list[Key] = []
    for f in fields(cls):
        sub = (*at, *paths.get(f.name, (f.name,)))
        out += _implemented(hints[f.name], sub) if is_dataclass(hints[f.name]) else [sub]
    return out


IMPLEMENTED = frozenset(k for cls, at in VIEWS.values() for k in _implemented(cls, at))


def _check_meaning(options: dict[str, Any], places: _Places, problems: list) -> None:
    """Ranges and cross-key rules on what btnav acts on (and what Cartographer CHECKs)."""
    for key in sorted(IMPLEMENTED | {k for k in BOUNDS if isinstance(k, tuple)}):
        value = _get(options, key)
        rule = BOUNDS.get(key) or BOUNDS.get(key[-1])
        if isinstance(value, str) and not value:
            problems.append(places.error(key, "must not be empty"))
        elif isinstance(value, float) and not math.isfinite(value):
            problems.append(places.error(key, f"must be a finite number, not {value}"))
        elif rule and not rule[1](value):
            problems.append(places.error(key, f"must be {rule[0]}, not {value!r}"))
        elif _kind(value) == "number" and value < 0:
            problems.append(places.error(key, f"must be >= 0, not {value!r}"))
    tb = _get(options, TB2D)
    if tb["max_range"] <= tb["min_range"]:
        problems.append(places.error((*TB2D, "max_range"), f"must be above min_range ({tb['min_range']})"))  # fmt: skip
    if options["map_builder"]["use_trajectory_builder_3d"]:
        problems.append(places.error(("map_builder", "use_trajectory_builder_3d"), "btnav builds 2D maps only; set it false"))  # fmt: skip
    elif not options["map_builder"]["use_trajectory_builder_2d"]:
        problems.append(places.error(("map_builder", "use_trajectory_builder_2d"), "must be true: Cartographer runs exactly one builder and btnav's is 2D"))  # fmt: skip
    if not any(options[k] for k in ("num_laser_scans", "num_multi_echo_laser_scans", "num_point_clouds")):  # fmt: skip
        problems.append(places.error(("num_laser_scans",), "must be at least 1: no range sensor is configured"))  # fmt: skip


def _view(cls: type, tree: dict[str, Any]) -> Any:
    hints = typing.get_type_hints(cls)
    paths = getattr(cls, "PATHS", {})
    args = {}
    for f in fields(cls):
        value = _get(tree, paths.get(f.name, (f.name,)))
        args[f.name] = _view(hints[f.name], value) if is_dataclass(hints[f.name]) else value
    return cls(**args)


def _ignored(options: Any, reference: Any, key: Key) -> list[str]:
    """Keys btnav does not act on whose value asks for something btnav does not do
    (it differs from btnav's default); a key left as btnav behaves is not worth a warning."""
    if key[:2] == TB3D:
        return [spell((*key, *leaf)) for leaf in _leaves(options) if leaf] if options else []
    if isinstance(options, dict) and key in OPTIONAL:
        return [spell(key)]  # an optional section switches a feature on: btnav has none of them
    if isinstance(options, dict):
        return sorted(
            k for name, v in options.items() for k in _ignored(v, reference[name], (*key, name))
        )
    if key in IMPLEMENTED or options == BEHAVES_AS.get(key, reference):
        return []
    return [spell(key)]
