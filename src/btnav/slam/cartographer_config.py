"""Cartographer's `.lua` configuration, run by a real Lua runtime and checked like a params file.

A Cartographer user's `my_robot.lua` is a program (`include`, `math.rad`, assignments
into tables the defaults built), so btnav runs it with lupa in a sandbox instead of
guessing at its text: no `os`, `io`, `require`, `dofile` or `load`, a cap on instructions
and memory, and `include` resolved the way `cartographer_node` does (the file's own
folder and `search_dirs`, then btnav's copies of Cartographer's defaults). Where Lua
cannot say where a key came from, a small scan of the source finds the `KEY =` that
wrote it, so every mistake names its file, line and dotted key, as btnav's YAML does.
"""

from __future__ import annotations

import functools
import math
import re
import typing
from bisect import bisect_right
from collections.abc import Callable, Sequence
from dataclasses import dataclass, fields, is_dataclass
from pathlib import Path
from typing import Any

from ..core.errors import BtnavError
from ..core.suggest import best_match

DEFAULTS_DIR = Path(__file__).resolve().parent / "cartographer_defaults"
#: What a runaway configuration may spend before it is stopped (a real one needs ~1e4 steps).
MAX_INSTRUCTIONS, MAX_MEMORY = 10_000_000, 64 * 2**20
Key = tuple[str, ...]
TB2D: Key = ("trajectory_builder", "trajectory_builder_2d")
TB3D: Key = ("trajectory_builder", "trajectory_builder_3d")
PG: Key = ("map_builder", "pose_graph")
#: The globals Cartographer's defaults define, used to spell a key as users write it.
GLOBALS: dict[Key, str] = {
    ("map_builder",): "MAP_BUILDER", ("trajectory_builder",): "TRAJECTORY_BUILDER",
    TB2D: "TRAJECTORY_BUILDER_2D", TB3D: "TRAJECTORY_BUILDER_3D", PG: "POSE_GRAPH",
}  # fmt: skip
#: Keys cartographer_ros and the builders read only when present.
OPTIONAL: set[Key] = {
    ("publish_to_tf",), ("publish_tracked_pose",), ("use_pose_extrapolator",),
    ("ignore_out_of_order",), ("trajectory_builder", "pure_localization_trimmer"),
    ("trajectory_builder", "pose_graph_odometry_motion_filter"), (*PG, "overlapping_submaps_trimmer_2d"),
}  # fmt: skip
#: Leaf names Cartographer reads with GetInt/GetNonNegativeInt; every other number is a double.
_INTEGERS = (
    "branch_and_bound_depth fresh_submaps_count full_resolution_depth max_num_final_iterations "
    "max_num_iterations max_submaps_to_keep min_added_submaps_count num_accumulated_range_data "
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
#: Names a configuration may not touch; reaching for one says why instead of "nil value".
FORBIDDEN = ("os", "io", "require", "dofile", "loadfile", "load", "loadstring", "package",
             "debug", "collectgarbage", "coroutine", "python", "module", "setfenv", "getfenv", "read")  # fmt: skip


class CartographerConfigError(BtnavError):
    """A Cartographer configuration btnav cannot run or accept (file, line, dotted key)."""


# -- typed views of what btnav implements (field name = Cartographer key unless `PATHS` says) --


@dataclass(frozen=True)
class Frames:
    """The REP-105 frames Cartographer reads and publishes between (map -> odom -> published)."""

    map_frame: str
    tracking_frame: str
    published_frame: str
    odom_frame: str
    provide_odom_frame: bool
    use_odometry: bool


@dataclass(frozen=True)
class RealTimeCorrelativeScanMatcher:
    linear_search_window: float
    angular_search_window: float
    translation_delta_cost_weight: float
    rotation_delta_cost_weight: float


@dataclass(frozen=True)
class CeresScanMatcher:
    occupied_space_weight: float
    translation_weight: float
    rotation_weight: float


@dataclass(frozen=True)
class MotionFilter:
    max_time_seconds: float
    max_distance_meters: float
    max_angle_radians: float


@dataclass(frozen=True)
class Submaps2D:
    """`submaps`, flattened: a probability grid is the only kind btnav builds (`PATHS`: where)."""

    PATHS: typing.ClassVar[dict[str, Key]] = {
        "resolution": ("grid_options_2d", "resolution"),
        "hit_probability": ("range_data_inserter", "probability_grid_range_data_inserter", "hit_probability"),
        "miss_probability": ("range_data_inserter", "probability_grid_range_data_inserter", "miss_probability"),
    }  # fmt: skip
    num_range_data: int
    resolution: float
    hit_probability: float
    miss_probability: float


@dataclass(frozen=True)
class TrajectoryBuilder2D:
    min_range: float
    max_range: float
    missing_data_ray_length: float
    num_accumulated_range_data: int
    voxel_filter_size: float
    use_online_correlative_scan_matching: bool
    real_time_correlative_scan_matcher: RealTimeCorrelativeScanMatcher
    ceres_scan_matcher: CeresScanMatcher
    motion_filter: MotionFilter
    submaps: Submaps2D


@dataclass(frozen=True)
class FastCorrelativeScanMatcher:
    linear_search_window: float
    angular_search_window: float
    branch_and_bound_depth: int


@dataclass(frozen=True)
class ConstraintBuilder:
    sampling_ratio: float
    max_constraint_distance: float
    min_score: float
    global_localization_min_score: float
    loop_closure_translation_weight: float
    loop_closure_rotation_weight: float
    fast_correlative_scan_matcher: FastCorrelativeScanMatcher


@dataclass(frozen=True)
class OptimizationProblem:
    huber_scale: float
    local_slam_pose_translation_weight: float
    local_slam_pose_rotation_weight: float
    odometry_translation_weight: float
    odometry_rotation_weight: float


@dataclass(frozen=True)
class PoseGraph:
    optimize_every_n_nodes: int
    constraint_builder: ConstraintBuilder
    matcher_translation_weight: float
    matcher_rotation_weight: float
    optimization_problem: OptimizationProblem
    global_sampling_ratio: float


@dataclass(frozen=True)
class CartographerConfig:
    """A loaded configuration: the whole table as Python, btnav's typed view of what it acts
    on, and the keys it accepts but will not act on (the caller warns about them once)."""

    options: dict[str, Any]
    file: Path
    ignored: list[str]
    frames: Frames
    trajectory_builder_2d: TrajectoryBuilder2D
    pose_graph: PoseGraph


#: Where each typed view sits in the options table.
VIEWS: dict[str, tuple[type, Key]] = {
    "frames": (Frames, ()), "trajectory_builder_2d": (TrajectoryBuilder2D, TB2D), "pose_graph": (PoseGraph, PG),
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
    run = _LuaRun(file, [file.parent, *map(Path, search_dirs), DEFAULTS_DIR])
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


# -- running the Lua ---------------------------------------------------------------------

_BOOT = """function(resolve, forbidden, limit)
  local load, error, type, pairs, getinfo = load, error, type, pairs, debug.getinfo
  local function copy(t) local c = {} for k, v in pairs(t) do c[k] = v end return c end
  local env = {
    math = copy(math), string = copy(string), table = copy(table),
    pairs = pairs, ipairs = ipairs, next = next, type = type, tostring = tostring,
    tonumber = tonumber, select = select, error = error, assert = assert, rawget = rawget,
    rawset = rawset, rawequal = rawequal, rawlen = rawlen, setmetatable = setmetatable,
    getmetatable = getmetatable, unpack = table.unpack or unpack, _VERSION = _VERSION,
    print = function() end,
  }
  env._G = env
  local function run(code, chunkname)
    local chunk, err = load(code, chunkname, "t", env)
    if not chunk then error(err, 0) end
    return chunk()
  end
  env.include = function(name)
    local caller = getinfo(2, "Sl")
    return run(resolve(name, caller.short_src, caller.currentline))
  end
  env.choose = function(condition, a, b)
    if type(condition) ~= "boolean" then error("choose(condition, a, b) needs a boolean condition", 2) end
    if condition then return a end
    return b
  end
  setmetatable(env, {__index = function(_, name)
    if forbidden[name] then
      error("'" .. name .. "' is not available: btnav runs Cartographer configurations in a "
        .. "sandbox (no os, io, require, dofile, load; only include reads files)", 2)
    end
  end})
  debug.sethook(function() error("still running after " .. limit .. " Lua steps: an endless loop?", 2) end, "", limit)
  local function aliases(root)
    local paths, out = {}, {}
    local function walk(t, path)
      if paths[t] then return end
      paths[t] = path
      for k, v in pairs(t) do
        if type(k) == "string" and type(v) == "table" then walk(v, path .. "\\1" .. k) end
      end
    end
    walk(root, "")
    for name, v in pairs(env) do
      if type(name) == "string" and type(v) == "table" and paths[v] then out[name] = paths[v] end
    end
    return out
  end
  return run, aliases
end"""
_CHUNK = re.compile(r"^btnav#(\d+):(\d+): (.*)", re.S)


def _lupa(file: Path) -> Any:
    """The Lua Cartographer links (5.2), else the nearest lupa ships."""
    import importlib

    for name in ("lupa.lua52", "lupa.lua53", "lupa.lua54", "lupa"):
        try:
            return importlib.import_module(name)
        except ImportError:
            continue
    raise CartographerConfigError(
        "reading Cartographer's .lua configuration needs the Lua runtime lupa: "
        "pip install 'btnav[cartographer]'",
        file=file,
    )


class _LuaRun:
    """One sandboxed Lua state running one configuration and the files it includes."""

    def __init__(self, file: Path, dirs: list[Path]) -> None:
        self.lupa = _lupa(file)
        self.dirs = dirs
        self.files: list[Path] = [file]
        self.texts: list[str] = [_read(file, None, None)]
        self.included_by: dict[Path, tuple[Path, int]] = {}
        lua = self.lupa.LuaRuntime(
            register_eval=False, register_builtins=False, unpack_returned_tuples=True,
            max_memory=MAX_MEMORY,
        )  # fmt: skip
        forbidden = lua.table_from({n: True for n in FORBIDDEN})
        self._run, self._aliases = lua.eval(_BOOT)(self._include, forbidden, MAX_INSTRUCTIONS)
        self.aliases: dict[str, Key] = {}

    def _include(self, name: Any, src: str, line: int) -> tuple[str, str]:
        """`include "x.lua"`: the first folder that has it, as Cartographer's FileResolver."""
        m = re.match(r"btnav#(\d+)", src)
        by, at = (self.files[int(m.group(1))] if m else None), line
        if not isinstance(name, str) or not name:
            raise CartographerConfigError("include takes a file name", file=by, line=at)
        found = next((d / name for d in self.dirs if (d / name).is_file()), None)
        if found is None:
            loaded = {f.name for f in self.files}
            names = sorted({p.name for d in self.dirs for p in d.glob("*.lua")} - loaded)
            where = ", ".join(str(d) for d in self.dirs)
            raise CartographerConfigError(
                f'include "{name}": no such file in {where}', file=by, line=at,
                suggestion=best_match(name, names),
            )  # fmt: skip
        found = found.resolve()
        if found in self.included_by or found == self.files[0].resolve():
            first = self.included_by.get(found)
            before = f" (first by {first[0]}:{first[1]})" if first else ""
            raise CartographerConfigError(
                f'include "{name}": {found} is already included{before}; Cartographer refuses '
                "to include a file twice", file=by, line=at,
            )  # fmt: skip
        self.included_by[found] = (by or self.files[0], at)
        self.files.append(found)
        self.texts.append(_read(found, by, at))
        return self.texts[-1], f"=btnav#{len(self.files) - 1}"

    def options(self) -> Any:
        """Run the file; the table it returns, as Python, and the globals naming its parts."""
        try:
            result = self._run(self.texts[0], "=btnav#0")
            if self.lupa.lua_type(result) != "table":
                raise CartographerConfigError(
                    "returns no table: a Cartographer configuration ends with `return options`",
                    file=self.files[0],
                )
            self.aliases = {
                name: tuple(p for p in path.split("\1") if p)
                for name, path in self._aliases(result).items()
            }
            return _to_python(result, self.lupa.lua_type, (), self.files[0], [100_000])
        except self.lupa.LuaMemoryError:
            raise CartographerConfigError(
                f"uses more than {MAX_MEMORY >> 20} MB of memory", file=self.files[0]
            ) from None
        except self.lupa.LuaError as err:
            text = str(err).split("\nstack traceback:", 1)[0]
            if m := _CHUNK.match(text):
                file, line, text = self.files[int(m.group(1))], int(m.group(2)), m.group(3)
                raise CartographerConfigError(text, file=file, line=line) from None
            raise CartographerConfigError(text, file=self.files[0]) from None


def _read(file: Path, by: Path | None, line: int | None) -> str:
    try:
        return file.read_text(encoding="utf-8")
    except (OSError, UnicodeDecodeError) as err:
        raise CartographerConfigError(f"cannot read {file}: {err}", file=by, line=line) from None


def _to_python(
    value: Any, lua_type: Callable[[Any], str | None], path: Key, file: Path, budget: list[int]
) -> Any:
    """A Lua value as Python: tables with keys 1..n become lists, other tables dicts.

    `budget` counts values down: a table that holds itself (or shares one table many
    times over) would otherwise unfold without end."""
    budget[0] -= 1
    kind = lua_type(value)
    if kind is None:
        return value
    if kind != "table":
        raise CartographerConfigError(f"is a {kind}: a configuration holds data", file=file, key=spell(path))  # fmt: skip
    if len(path) > 40 or budget[0] < 0:
        raise CartographerConfigError("tables nest too deep (a table inside itself?)", file=file, key=spell(path[:3]))  # fmt: skip
    items = sorted(value.items(), key=lambda kv: (isinstance(kv[0], str), kv[0]))
    keys = [k for k, _ in items]
    if keys and keys == list(range(1, len(keys) + 1)):
        return [_to_python(v, lua_type, (*path, str(k)), file, budget) for k, v in items]
    return {k: _to_python(v, lua_type, (*path, str(k)), file, budget) for k, v in items}


@functools.lru_cache(maxsize=1)
def _reference() -> dict[str, Any]:
    """Every key a configuration may hold, with its default (shared: never mutate it)."""
    return _LuaRun(DEFAULTS_DIR / "options_reference.lua", [DEFAULTS_DIR]).options()


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

    def __init__(self, run: _LuaRun) -> None:
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


def spell(key: Key) -> str:
    """A key as users write it: under the global that holds it (`TRAJECTORY_BUILDER_2D.min_range`)."""
    for n in range(len(key), 0, -1):
        if key[:n] in GLOBALS:
            return ".".join((GLOBALS[key[:n]], *key[n:]))
    return ".".join(key)


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
