"""nav2_smac_planner::SmacPlannerLattice: A* over a state lattice read from a lattice file.

The lattice file is Nav2's JSON (`lattice_generator` writes the same). A node is a
continuous (x, y) in cells and a heading index, its children the primitives that start at
that heading (reversed too with `allow_reverse_expansion`), step costs as Nav2's
NodeLattice; the heuristic, goal approach and analytic expansion are Hybrid-A*'s
(`smac_common`). btnav differs only to stay exact and machine-independent: the expansion
ends on the goal's own heading, a lattice for another resolution is laid on the costmap in
metres, and the search stops after `max_iterations`, never on wall-clock time. The full
restatement: docs/decisions/0073. `lattice_filepath` is looked up beside the params file,
then in btnav's bundled `params/` (see params/lattice/NOTICE.md).
"""

from __future__ import annotations

import itertools
import json
import math
import os
import warnings
from collections.abc import Callable, Mapping
from dataclasses import dataclass
from pathlib import Path as FilePath
from typing import Any

import numpy as np
from numpy.typing import NDArray
from pydantic import Field, field_validator, model_validator

from ..core import fmath
from ..core.errors import BtnavError, BtnavWarning
from ..core.geometry import Pose2D
from ..core.messages import Path
from ..core.resources import bundled_dir
from ..core.yaml_io import file_of
from ..costmap.costmap_2d import Costmap2D
from ..plugins import register
from .exceptions import GoalOccupied, GoalOutsideMapBounds, StartOccupied, StartOutsideMapBounds
from .global_planner import GlobalPlanner
from .smac_common import (
    AnalyticExpansion,
    AnalyticModel,
    CellPose,
    Child,
    GridCollisionChecker,
    HeuristicCache,
    Node,
    SmacParams,
    SmacSearch,
    cells_to_world,
    smooth_path,
    traversal_norms,
)

#: The lattice btnav ships for Nav2's default (relative to the bundled params folder).
DEFAULT_LATTICE = "lattice/ackermann_0.5m_5cm.json"
#: A primitive shorter than this (m) is a rotation in place; an arc shorter, a straight.
_ROTATION_LENGTH, _STRAIGHT_ARC = 1e-4, 1e-3
#: Consecutive poses this close (m, rad) are one (Nav2 drops the repeat).
_SAME_POSE = 1e-4


# -- the lattice file ------------------------------------------------------------------


@dataclass(frozen=True)
class LatticePrimitive:
    """One motion primitive of a lattice file (metres, radians)."""

    trajectory_id: int
    start_angle_index: int
    end_angle_index: int
    left_turn: bool
    trajectory_radius: float
    trajectory_length: float
    arc_length: float
    straight_length: float
    poses: NDArray[np.float64]


@dataclass(frozen=True)
class Lattice:
    """A lattice file's metadata and primitives, grouped by start heading."""

    path: str
    motion_model: str
    turning_radius: float
    grid_resolution: float
    heading_angles: tuple[float, ...]
    primitives: tuple[LatticePrimitive, ...]

    @property
    def num_of_headings(self) -> int:
        return len(self.heading_angles)

    def starting_at(self, heading: int) -> list[LatticePrimitive]:
        return [p for p in self.primitives if p.start_angle_index == heading]

    def closest_heading(self, yaw: float) -> int:
        """Nav2's getClosestAngularBin: the heading nearest `yaw` (the first of a tie)."""
        gaps = [abs(math.remainder(yaw - a, 2.0 * math.pi)) for a in self.heading_angles]
        return gaps.index(min(gaps))


_LATTICES: dict[tuple[str, int, int], Lattice] = {}


def load_lattice(path: str | os.PathLike[str]) -> Lattice:
    """Read a lattice file (Nav2's format); a mistake in it is a BtnavError naming it."""
    file = str(path)
    try:
        stat = os.stat(file)
    except OSError:
        raise BtnavError("lattice file not found", file=file) from None
    key = (os.path.realpath(file), stat.st_mtime_ns, stat.st_size)
    if key not in _LATTICES:
        _LATTICES[key] = _parse_lattice(file)
    return _LATTICES[key]


def _parse_lattice(file: str) -> Lattice:
    try:
        with open(file, encoding="utf-8") as f:
            doc = json.load(f)
    except json.JSONDecodeError as err:
        raise BtnavError(
            f"not a lattice file: {err.msg} (column {err.colno})", file=file, line=err.lineno
        ) from None
    except (OSError, UnicodeDecodeError) as err:
        raise BtnavError(f"cannot read the lattice file: {err}", file=file) from None

    def need(node: Any, key: str, where: str, kind: type | tuple[type, ...]) -> Any:
        if not isinstance(node, Mapping) or key not in node:
            raise BtnavError(f"a lattice file needs '{key}' here", file=file, key=where)
        value = node[key]
        if (isinstance(value, bool) and kind is not bool) or not isinstance(value, kind):
            raise BtnavError(
                f"'{key}' has the wrong type: {value!r}", file=file, key=f"{where}.{key}"
            )
        return value

    number = (int, float)
    meta = need(doc, "lattice_metadata", "", Mapping)
    where = "lattice_metadata"
    angles = need(meta, "heading_angles", where, list)
    count = need(meta, "num_of_headings", where, int)
    if len(angles) != count or not all(isinstance(a, number) for a in angles):
        raise BtnavError(
            f"heading_angles must be {count} numbers (num_of_headings), got {len(angles)}",
            file=file, key=f"{where}.heading_angles",
        )  # fmt: skip
    rows = need(doc, "primitives", "", list)
    prims: list[LatticePrimitive] = []
    for i, row in enumerate(rows):
        at = f"primitives[{i}]"
        start = need(row, "start_angle_index", at, int)
        end = need(row, "end_angle_index", at, int)
        for name, value in (("start_angle_index", start), ("end_angle_index", end)):
            if not 0 <= value < count:
                raise BtnavError(
                    f"{name} {value} is not a heading (0 to {count - 1})",
                    file=file,
                    key=f"{at}.{name}",
                )
        poses = need(row, "poses", at, list)
        try:
            arr = np.array(poses, dtype=np.float64).reshape(-1, 3)
        except (ValueError, TypeError):
            raise BtnavError(
                "poses must be [x, y, yaw] triples", file=file, key=f"{at}.poses"
            ) from None
        if len(arr) == 0 or len(arr) != len(poses) or not np.all(np.isfinite(arr)):
            raise BtnavError(
                "poses must be one or more finite [x, y, yaw]", file=file, key=f"{at}.poses"
            )
        prims.append(
            LatticePrimitive(
                int(need(row, "trajectory_id", at, int)),
                start,
                end,
                bool(need(row, "left_turn", at, bool)),
                float(need(row, "trajectory_radius", at, number)),
                float(need(row, "trajectory_length", at, number)),
                float(need(row, "arc_length", at, number)),
                float(need(row, "straight_length", at, number)),
                arr,
            )
        )
    radius = float(need(meta, "turning_radius", where, number))
    resolution = float(need(meta, "grid_resolution", where, number))
    if radius <= 0.0 or resolution <= 0.0:
        raise BtnavError(
            "turning_radius and grid_resolution must be positive", file=file, key=where
        )
    return Lattice(
        file,
        str(need(meta, "motion_model", where, str)),
        radius,
        resolution,
        tuple(float(a) for a in angles),
        tuple(prims),
    )


def resolve_lattice_path(value: str, params_file: str | None) -> str:
    """An absolute path as written; a relative one beside the params file, else in the
    bundled params folder (else as written, relative to the working directory)."""
    path = FilePath(os.path.expanduser(value))
    if path.is_absolute():
        return str(path)
    bases = [FilePath(params_file).parent] if params_file else []
    bases.append(bundled_dir("params"))
    for base in bases:
        if (base / path).is_file():
            return str(base / path)
    return value


# -- the motion table --------------------------------------------------------------------


@dataclass(frozen=True)
class _Move:
    """A primitive as a node applies it, in cells: the end offset and heading, the poses
    to check (x, y offsets and the base's yaw) and what its cost depends on."""

    ex: float
    ey: float
    end: int
    checks: tuple[tuple[float, float, float], ...]
    poses: tuple[tuple[float, float, float], ...]
    length: float
    rotation: bool
    straight: bool
    left_turn: bool
    backwards: bool


class _MotionTable:
    """Nav2's LatticeMotionTable for one lattice, costmap resolution and reverse option:
    per heading, the moves a node there can make."""

    def __init__(self, lattice: Lattice, resolution: float, reverse: bool) -> None:
        n = lattice.num_of_headings
        diag = math.sqrt(2.0) * resolution
        self.moves: list[_Move] = []
        self.by_heading: list[list[int]] = []
        groups = [lattice.starting_at(k) for k in range(n)]
        for heading in range(n):
            ids = []
            sources = [(groups[heading], False)]
            if reverse:
                sources.append((groups[(heading + n // 2) % n], True))
            for prims, backwards in sources:
                for prim in prims:
                    ids.append(len(self.moves))
                    self.moves.append(self._move(prim, resolution, diag, n, backwards, lattice))
            self.by_heading.append(ids)

    @staticmethod
    def _move(
        prim: LatticePrimitive, res: float, diag: float, n: int, backwards: bool, lattice: Lattice
    ) -> _Move:
        flip = math.pi if backwards else 0.0
        poses = [
            (x / res, y / res, math.fmod(yaw + flip, 2.0 * math.pi))
            for x, y, yaw in prim.poses.tolist()
        ]
        end = (prim.end_angle_index + n // 2) % n if backwards else prim.end_angle_index
        # Nav2's rule: a pose is checked when it is more than a cell's diagonal from the
        # last one checked; the end pose is checked with the lattice heading it ends on.
        checks = []
        last = (math.inf, math.inf)
        for (x, y, _), pose in zip(prim.poses.tolist(), poses, strict=True):
            if fmath.hypot(x - last[0], y - last[1]) > diag:
                last = (x, y)
                checks.append(pose)
        checks.append((poses[-1][0], poses[-1][1], lattice.heading_angles[end]))
        return _Move(
            poses[-1][0],
            poses[-1][1],
            end,
            tuple(checks),
            tuple(poses),
            prim.trajectory_length / res,
            prim.trajectory_length < _ROTATION_LENGTH,
            prim.arc_length < _STRAIGHT_ARC,
            prim.left_turn,
            backwards,
        )


# -- the planner -------------------------------------------------------------------------


@register(
    "planner",
    "nav2_smac_planner::SmacPlannerLattice",
    aliases=("btnav/SmacPlannerLattice",),
)
class SmacPlannerLattice(GlobalPlanner):
    """State Lattice A* with Nav2's params and defaults (see the module's docstring)."""

    class Params(SmacParams):
        lattice_filepath: str = Field(
            DEFAULT_LATTICE, description="Nav2's lattice file (JSON); relative: see the docs"
        )
        change_penalty: float = Field(0.05, ge=0.0)
        non_straight_penalty: float = Field(1.05, ge=1.0)
        rotation_penalty: float = Field(5.0, ge=0.0)
        allow_reverse_expansion: bool = False

        @model_validator(mode="before")
        @classmethod
        def _locate_lattice(cls, data: Any) -> Any:
            """A relative lattice_filepath is found beside the params file it is written in."""
            if isinstance(data, Mapping) and isinstance(data.get("lattice_filepath"), str):
                data = dict(data) | {
                    "lattice_filepath": resolve_lattice_path(
                        data["lattice_filepath"], file_of(data)
                    )
                }
            return data

        @field_validator("lattice_filepath")
        @classmethod
        def _readable(cls, value: str) -> str:
            if not value.strip():
                raise ValueError(
                    f"is empty: name a lattice file, such as btnav's {DEFAULT_LATTICE!r} "
                    "(params/lattice/NOTICE.md lists them)"
                )
            if not os.path.isfile(value):
                raise ValueError(
                    f"lattice file {value!r} not found (a relative path is looked up beside "
                    f"the params file, then in {bundled_dir('params')})"
                )
            try:
                load_lattice(value)
            except BtnavError as err:
                where = f"{err.file}" + (f":{err.line}" if err.line else "")
                inside = f" at {err.key}" if err.key else ""
                raise ValueError(f"lattice file {where}{inside}: {err.message}") from None
            return value

        @model_validator(mode="after")
        def _omni_never_reverses(self) -> SmacPlannerLattice.Params:
            if self.allow_reverse_expansion and self.lattice().motion_model == "omni":
                warnings.warn(
                    BtnavWarning(
                        "an omni lattice never reverses (its slides go every way): "
                        "not used, as Nav2 turns it off",
                        key="allow_reverse_expansion",
                    ),
                    stacklevel=2,
                )
            return self

        def lattice(self) -> Lattice:
            return load_lattice(resolve_lattice_path(self.lattice_filepath, None))

    params: Params

    def __init__(self, name: str, params: Params | None = None) -> None:
        super().__init__(name, params)
        self._table: tuple[Lattice, tuple[float, bool], _MotionTable] | None = None
        self._heuristic = HeuristicCache()
        #: Nodes the last search expanded (for tests and benchmarks).
        self.expansions = 0

    @property
    def lattice(self) -> Lattice:
        return self.params.lattice()

    def _motion_table(self, lattice: Lattice, resolution: float, reverse: bool) -> _MotionTable:
        """The moves for this lattice (by identity: one object per file version)."""
        cached = self._table
        if cached is None or cached[0] is not lattice or cached[1] != (resolution, reverse):
            cached = (lattice, (resolution, reverse), _MotionTable(lattice, resolution, reverse))
            self._table = cached
        return cached[2]

    # -- nav2_core::GlobalPlanner ------------------------------------------------------------

    def create_plan(
        self,
        start: Pose2D,
        goal: Pose2D,
        costmap: Costmap2D,
        cancel_checker: Callable[[], bool] | None = None,
    ) -> Path:
        p = self.params
        lattice = self.lattice
        res = costmap.resolution
        omni = lattice.motion_model == "omni"
        reverse = p.allow_reverse_expansion and not omni
        table = self._motion_table(lattice, res, reverse)
        checker = GridCollisionChecker(costmap, self.costmap_ros, p.allow_unknown)

        sx, sy = (start.x - costmap.origin_x) / res, (start.y - costmap.origin_y) / res
        gx, gy = (goal.x - costmap.origin_x) / res, (goal.y - costmap.origin_y) / res
        if checker.cell(sx, sy) < 0:
            raise StartOutsideMapBounds(f"start ({start.x:.2f}, {start.y:.2f}) is off the costmap")
        if checker.cell(gx, gy) < 0:
            raise GoalOutsideMapBounds(f"goal ({goal.x:.2f}, {goal.y:.2f}) is off the costmap")
        start_bin, goal_bin = lattice.closest_heading(start.yaw), lattice.closest_heading(goal.yaw)
        yaws = lattice.heading_angles
        if checker.colliding([sx], [sy], [start.yaw])[0]:
            raise StartOccupied("the start pose is in collision")
        if checker.colliding([gx], [gy], [goal.yaw])[0]:
            raise GoalOccupied("the goal pose is in collision")
        if checker.cell(sx, sy) == checker.cell(gx, gy) and start_bin == goal_bin:
            # Nav2's corner case: already there, one pose facing the goal's way.
            return Path(0.0, np.array([[start.x, start.y, goal.yaw]]), costmap.frame_id)

        heuristic = self._heuristic.get(
            costmap, (math.floor(gx), math.floor(gy)), p.cost_penalty,
            p.downsample_obstacle_heuristic, p.cache_obstacle_heuristic,
        )  # fmt: skip
        model: AnalyticModel = "OMNI" if omni else ("REEDS_SHEPP" if reverse else "DUBIN")
        radius = lattice.turning_radius / res
        analytic = AnalyticExpansion(model, radius, checker, p)
        search = SmacSearch(p, checker, heuristic, analytic, lattice.num_of_headings, yaws)
        norms = traversal_norms(costmap, p.use_quadratic_cost_penalty)
        linear = traversal_norms(costmap, False) if p.use_quadratic_cost_penalty else norms
        try:
            found = search.run(
                (sx, sy, start_bin),
                (gx, gy, goal.yaw),
                goal_bin,
                self._expansion(table, checker, norms.tolist(), linear.tolist()),
                cancel_checker,
            )
        finally:
            self.expansions = search.expansions
        poses = self._poses(found.nodes, found.chain(), table, yaws) + found.tail
        world = _without_repeats(cells_to_world(poses, costmap))
        path = Path(0.0, world, costmap.frame_id)
        if not p.smooth_path or self.expansions <= 1:
            return path
        return smooth_path(path, costmap, p.smoother, lattice.turning_radius, holonomic=omni)

    @staticmethod
    def _poses(
        nodes: list[Node], chain: list[int], table: _MotionTable, yaws: tuple[float, ...]
    ) -> list[CellPose]:
        """The searched part of the path: the start, then each primitive's poses."""
        x, y, b = nodes[chain[0]][:3]
        out: list[CellPose] = [(x, y, yaws[b])]
        for parent, child in itertools.pairwise(chain):
            px, py = nodes[parent][0], nodes[parent][1]
            move = table.moves[nodes[child][5]]
            out += [(px + ox, py + oy, yaw) for ox, oy, yaw in move.poses]
        return out

    def _expansion(
        self,
        table: _MotionTable,
        checker: GridCollisionChecker,
        norms: list[float],
        linear: list[float],
    ) -> Callable[[Node, set[int]], list[Child]]:
        """Nav2's NodeLattice::getNeighbors, isNodeValid and getTraversalCost for this plan."""
        p = self.params
        nx, ny = checker.nx, checker.ny
        bins = len(table.by_heading)
        blocked, outline = checker.blocked, checker.outline
        reward = 1.0 - p.retrospective_penalty
        cp, ns, change = p.cost_penalty, p.non_straight_penalty, p.change_penalty
        moves, by_heading = table.moves, table.by_heading
        floor = math.floor

        def expand(node: Node, closed: set[int]) -> list[Child]:
            x, y, b, _, _, came_by, _ = node
            before = moves[came_by] if came_by >= 0 else None
            out: list[Child] = []
            outlines: list[tuple[int, list[tuple[float, float, float]]]] = []
            for m in by_heading[b]:
                move = moves[m]
                cx, cy = x + move.ex, y + move.ey
                mx, my = floor(cx), floor(cy)
                if mx < 0 or my < 0 or mx >= nx or my >= ny:
                    continue
                cell = my * nx + mx
                key = cell * bins + move.end
                if blocked[cell] or key in closed:
                    continue
                worst = norms[cell]
                worst_linear = linear[cell]
                poses: list[tuple[float, float, float]] = []
                for ox, oy, yaw in move.checks:
                    qx, qy = x + ox, y + oy
                    qmx, qmy = floor(qx), floor(qy)
                    if qmx < 0 or qmy < 0 or qmx >= nx or qmy >= ny:
                        break
                    q = qmy * nx + qmx
                    if blocked[q]:
                        break
                    if norms[q] > worst:
                        worst, worst_linear = norms[q], linear[q]
                    if outline is not None and outline[q]:
                        poses.append((qx, qy, yaw))
                else:
                    if before is None:  # the first step: its length alone
                        step = move.length
                    elif move.rotation:
                        step = p.rotation_penalty * (1.0 + cp * worst_linear)
                    else:
                        step = move.length * (reward + cp * worst)
                        if not move.straight:
                            step *= ns if before.left_turn == move.left_turn else ns + change
                        if move.backwards:
                            step *= p.reverse_penalty
                    if poses:
                        outlines.append((len(out), poses))
                    out.append((key, cell, cx, cy, move.end, step, m))
            if outlines:
                flat = [pose for _, poses in outlines for pose in poses]
                hits = checker.outline_hits(
                    [q[0] for q in flat], [q[1] for q in flat], [q[2] for q in flat]
                )
                drop, at = set(), 0
                for j, poses in outlines:
                    if any(hits[at : at + len(poses)]):
                        drop.add(j)
                    at += len(poses)
                out = [c for j, c in enumerate(out) if j not in drop]
            return out

        return expand


def _without_repeats(poses: NDArray[np.float64]) -> NDArray[np.float64]:
    """The path without a pose equal to the one before (an in-place rotation's first pose
    is its parent's last), as Nav2's planner drops them."""
    if len(poses) < 2:
        return poses
    d = np.abs(np.diff(poses, axis=0))
    d[:, 2] = np.abs(np.remainder(d[:, 2] + np.pi, 2.0 * np.pi) - np.pi)
    keep = np.concatenate([[True], ~np.all(d < _SAME_POSE, axis=1)])
    return poses[keep]
