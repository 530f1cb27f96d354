"""State lattice control sets for SmacPlannerLattice, as Nav2's lattice primitive generator
(nav2_smac_planner/lattice_primitives) makes them, in Nav2's JSON format.

A near-minimal set (Pivtoraiko & Kelly 2005), built in Nav2's steps: headings that point
at lattice points, one arc of at least `turning_radius` between two straights, wavefront
search with Nav2's pruning, the other quadrants mirrored. btnav does the line geometry in
integers (exact instead of rounded to 5 decimals), gives a rightward slide its true length,
and uses core.fmath, so a generated file is the same bits on every CPU. The steps in full:
docs/decisions/0073.

`python -m btnav.planning.lattice_generator --config CONFIG.json --output OUT.json` reads
Nav2's generator config (`config.json`).
"""

from __future__ import annotations

import argparse
import datetime
import itertools
import json
import math
import sys
from collections.abc import Sequence
from dataclasses import dataclass
from os import PathLike
from pathlib import Path
from typing import Any, Literal

import numpy as np
from numpy.typing import NDArray
from pydantic import Field, field_validator

from ..core import fmath
from ..core.errors import BtnavError
from ..core.geometry import TWO_PI
from ..core.validation import validate
from ..core.yaml_io import load_yaml
from ..params.schema import ParamsModel

#: Nav2's generator version, written into every file (its constants.VERSION).
LATTICE_FORMAT_VERSION = 1.0
#: A radius this much (relative) under the minimum is the minimum lost to rounding.
_RADIUS_SLACK = 1e-9
#: In-place rotations are sampled about every 10 degrees, as Nav2's generator does.
_ROTATION_STEP = math.radians(10.0)


class LatticeConfig(ParamsModel):
    """Nav2's generator config (lattice_primitives/config.json); every key but the
    distinctness ratio is required there too (0.0 gives the generator's pre-2026 sets)."""

    motion_model: Literal["ackermann", "diff", "omni"]
    turning_radius: float = Field(gt=0.0, description="m")
    grid_resolution: float = Field(gt=0.0, description="m")
    stopping_threshold: int = Field(ge=1)
    num_of_headings: int = Field(ge=8)
    trajectory_distinctness_ratio: float = Field(0.0, ge=0.0)

    @field_validator("num_of_headings")
    @classmethod
    def _multiple_of_8(cls, value: int) -> int:
        if value % 8:
            raise ValueError(
                "must be a multiple of 8: the headings point at the integer points on a "
                f"square's border, 8 per unit of its half-side (got {value})"
            )
        return value


@dataclass(frozen=True)
class Primitive:
    """One motion primitive as the lattice file stores it (metres, radians in [0, 2 pi))."""

    start_index: int
    end_index: int
    left_turn: bool
    radius: float
    length: float
    arc_length: float
    straight_length: float
    #: (n, 3) x, y, yaw after the start pose (the start itself is (0, 0) at the start
    #: heading; an in-place rotation begins with it, as Nav2's files do).
    poses: NDArray[np.float64]


@dataclass(frozen=True)
class _Shape:
    """A primitive's geometry, in metres: start straight, arc (none when radius is 0), end
    straight, from the origin at heading `start` to `end_point` at heading `end`."""

    start: int
    end: int
    end_point: tuple[float, float]
    radius: float
    left_turn: bool
    arc_start: tuple[float, float]
    arc_end: tuple[float, float]
    centre: tuple[float, float]
    arc_length: float
    start_straight: float
    end_straight: float

    @property
    def length(self) -> float:
        return self.start_straight + self.arc_length + self.end_straight


class _Headings:
    """The lattice headings: index k in [0, 2 pi) order, its integer direction and angle."""

    def __init__(self, count: int) -> None:
        m = count // 8
        border = {(i, j) for i in range(-m, m + 1) for j in (-m, m)}
        border |= {(i, j) for j in range(-m, m + 1) for i in (-m, m)}
        points = sorted(border)
        signed = fmath.arctan2(
            np.array([float(j) for _, j in points]), np.array([float(i) for i, _ in points])
        ).tolist()
        order = sorted(range(count), key=lambda k: (signed[k] < 0.0, signed[k]))
        self.count = count
        self.directions: list[tuple[int, int]] = [points[k] for k in order]
        #: atan2's angle, in (-pi, pi]: Nav2's generator orders and differences with it.
        self.signed: list[float] = [signed[k] for k in order]
        #: The file's heading_angles, in [0, 2 pi).
        self.angles: list[float] = [a + TWO_PI if a < 0.0 else a for a in self.signed]
        self.norms: list[float] = [math.sqrt(i * i + j * j) for i, j in self.directions]
        self.zero = 0
        self.quarter = count // 4

    def mirror_x(self, k: int) -> int:
        """The heading mirrored across the y axis (x -> -x): pi - angle."""
        return (self.count // 2 - k) % self.count

    def mirror_y(self, k: int) -> int:
        """The heading mirrored across the x axis (y -> -y): -angle."""
        return (self.count - k) % self.count

    def opposite(self, k: int) -> int:
        return (k + self.count // 2) % self.count

    def turn(self, a: int, b: int) -> float:
        """The absolute heading change from a to b (at most pi)."""
        d = abs(self.signed[a] - self.signed[b])
        return d if d <= math.pi else TWO_PI - d


def _cross(ax: float, ay: float, bx: float, by: float) -> float:
    return ax * by - ay * bx


def _shape(
    headings: _Headings, px: int, py: int, start: int, end: int, radius: float, res: float
) -> _Shape | None:
    """The primitive from the origin at heading `start` to the lattice point (px, py) (in
    cells) at heading `end`, or None when no arc of at least `radius` joins the two lines.

    Line 1 leaves the origin along `start`, line 2 reaches the point along `end`; they meet
    at a corner, the arc is tangent to both at the shorter leg's distance from it, and the
    rest of the longer leg is a straight. In cells with integer directions the tests
    (parallel, on the line, ahead) are exact."""
    ux, uy = headings.directions[start]
    vx, vy = headings.directions[end]
    end_point = (px * res, py * res)
    c = _cross(ux, uy, vx, vy)
    if c == 0:  # parallel: a straight, if the point is on line 1 ahead of the origin
        if _cross(px, py, ux, uy) != 0 or px * ux + py * uy <= 0:
            return None
        length = fmath.hypot(*end_point)
        return _Shape(
            start, end, end_point, 0.0, True, end_point, end_point, (0.0, 0.0), 0.0, length, 0.0
        )
    t = _cross(px, py, vx, vy) / c  # the corner is t * u
    if t <= 0.0:
        return None  # the lines meet behind the start
    ix, iy = t * ux, t * uy
    w = ((px - ix) * vx + (py - iy) * vy) / (vx * vx + vy * vy)
    if w <= 0.0:
        return None  # the point is before the corner on line 2
    nu, nv = headings.norms[start], headings.norms[end]
    leg_a, leg_b = t * nu, w * nv  # corner to the origin, corner to the point (cells)
    tan_half = abs(c) / (nu * nv + ux * vx + uy * vy)  # tan of half the heading change
    leg = min(leg_a, leg_b)
    r = leg / tan_half * res
    if r < radius * (1.0 - _RADIUS_SLACK):
        return None
    left = c > 0
    ax, ay = (ix - leg * ux / nu) * res, (iy - leg * uy / nu) * res  # tangent on line 1
    bx, by = (ix + leg * vx / nv) * res, (iy + leg * vy / nv) * res  # tangent on line 2
    side = 1.0 if left else -1.0
    centre = (ax - side * r * uy / nu, ay + side * r * ux / nu)
    return _Shape(
        start,
        end,
        end_point,
        r,
        left,
        (ax, ay),
        (bx, by),
        centre,
        r * headings.turn(start, end),
        (leg_a - leg) * res,
        (leg_b - leg) * res,
    )


def _sample(shape: _Shape, headings: _Headings, step: float) -> NDArray[np.float64]:
    """Poses about every `step` metres after the origin, the end pose exact; yaws unwrapped
    from the start's signed angle (a left arc adds, a right arc subtracts)."""
    total = shape.length
    n = max(1, round(total / step))
    s = np.arange(1, n + 1) * (total / n)
    start_yaw = headings.signed[shape.start]
    end_yaw = start_yaw + (1.0 if shape.left_turn else -1.0) * shape.arc_length / (
        shape.radius or 1.0
    )
    a, b = shape.start_straight, shape.start_straight + shape.arc_length
    x = np.empty(n)
    y = np.empty(n)
    yaw = np.empty(n)
    first, arc = s <= a, (s > a) & (s <= b)
    last = ~(first | arc)
    if a > 0.0:
        f = s[first] / a
        x[first], y[first] = f * shape.arc_start[0], f * shape.arc_start[1]
    yaw[first] = start_yaw
    if arc.any():
        sign = 1.0 if shape.left_turn else -1.0
        yaw[arc] = start_yaw + sign * (s[arc] - a) / shape.radius
        sn, cs = fmath.sincos(yaw[arc])
        x[arc] = shape.centre[0] + sign * shape.radius * sn
        y[arc] = shape.centre[1] - sign * shape.radius * cs
    if last.any():  # (s just past the arc's end by rounding has no straight left: f = 1)
        f = np.minimum((s[last] - b) / max(total - b, 1e-300), 1.0)
        x[last] = shape.arc_end[0] + f * (shape.end_point[0] - shape.arc_end[0])
        y[last] = shape.arc_end[1] + f * (shape.end_point[1] - shape.arc_end[1])
        yaw[last] = end_yaw
    x[-1], y[-1], yaw[-1] = shape.end_point[0], shape.end_point[1], end_yaw
    return np.column_stack([x, y, yaw])


class _Quadrant:
    """The near-minimal set from one first-quadrant start heading, grown wavefront by
    wavefront (Nav2's _compute_for_single_heading)."""

    def __init__(self, headings: _Headings, config: LatticeConfig, start: int) -> None:
        self.h = headings
        self.config = config
        self.start = start
        res = config.grid_resolution
        self.distance_threshold = 0.5 * res
        self.rotation_threshold = 0.5 * (TWO_PI / headings.count)
        ux, uy = headings.directions[start]
        near = [k for k in range(headings.count) if _dot(headings.directions[k], (ux, uy)) >= 0]
        s = headings.signed[start]
        #: Nearest heading change first; of two alike, the larger angle first.
        self.targets = sorted(
            near, key=lambda k: (abs(headings.signed[k] - s), -headings.signed[k])
        )
        self.kept: list[tuple[int, int, int]] = []  # (px, py, end heading)
        self._ends = np.empty((0, 3))
        self._by_heading: dict[int, list[tuple[int, int]]] = {}

    def run(self) -> list[tuple[int, int, int]]:
        # The first wavefront: the shortest turn's length, to the nearest heading.
        ordered = sorted(self.h.signed)
        gap = min(b - a for a, b in itertools.pairwise(ordered))
        p = round(self.config.turning_radius * gap / self.config.grid_resolution)
        empty = 0
        while empty < self.config.stopping_threshold:
            empty += 1
            for px, py in _wavefront(p):
                for end in self.targets:
                    if self._try(px, py, end):
                        empty = 0
            p += 1
        return self.kept

    def _try(self, px: int, py: int, end: int) -> bool:
        cfg = self.config
        res = cfg.grid_resolution
        shape = _shape(self.h, px, py, self.start, end, cfg.turning_radius, res)
        if shape is None:
            return False
        near = cfg.trajectory_distinctness_ratio * shape.length
        for qx, qy in self._by_heading.get(end, ()):
            if fmath.hypot(px - qx, py - qy) * res < near:
                return False
        if len(self._ends) and self._passes_a_kept_end(_sample(shape, self.h, 0.1 * res)):
            return False
        self.kept.append((px, py, end))
        self._by_heading.setdefault(end, []).append((px, py))
        row = np.array([[px * res, py * res, self.h.signed[end]]])
        self._ends = np.vstack([self._ends, row])
        return True

    def _passes_a_kept_end(self, poses: NDArray[np.float64]) -> bool:
        """Whether a segment of the path passes within half a cell of a kept end pose
        while heading within half a bin of it: the path is that primitive and more."""
        p1, p2 = poses[:-1, None, :2], poses[1:, None, :2]
        q = self._ends[None, :, :2]
        d = p2 - p1
        l2 = np.sum(d * d, axis=2)
        with np.errstate(invalid="ignore", divide="ignore"):
            t = np.where(l2 > 0.0, np.sum((q - p1) * d, axis=2) / l2, 0.0)
        t = np.clip(t, 0.0, 1.0)
        gap = q - (p1 + t[..., None] * d)
        close = np.sqrt(np.sum(gap * gap, axis=2)) < self.distance_threshold
        turn = np.abs(poses[:-1, None, 2] - self._ends[None, :, 2])
        turn = np.where(turn <= math.pi, turn, TWO_PI - turn)
        return bool(np.any(close & (turn < self.rotation_threshold)))


def _dot(a: tuple[int, int], b: tuple[int, int]) -> int:
    return a[0] * b[0] + a[1] * b[1]


def _wavefront(p: int) -> list[tuple[int, int]]:
    """The first-quadrant lattice points at Chebyshev distance p, in Nav2's order."""
    points: list[tuple[int, int]] = []
    for i in range(p):
        points += [(p, i), (i, p)]
    return [*points, (p, p)]


def generate_lattice(config: LatticeConfig) -> list[Primitive]:
    """The control set for `config`, primitives in the file's order (by start heading,
    then by end heading as Nav2's generator sorts them)."""
    h = _Headings(config.num_of_headings)
    res = config.grid_resolution
    shapes: dict[int, list[_Shape]] = {k: [] for k in range(h.count)}

    def add(px: int, py: int, start: int, end: int) -> None:
        shape = _shape(h, px, py, start, end, config.turning_radius, res)
        if shape is None:  # a mirror of a valid primitive is valid: rounding broke it
            raise RuntimeError(f"no primitive to ({px}, {py}) from heading {start} to {end}")
        shapes[start].append(shape)

    first_quadrant = [k for k in range(h.count) if 0.0 <= h.signed[k] <= math.pi / 2]
    for start in first_quadrant:
        for px, py, end in _Quadrant(h, config, start).run():
            if start == end == h.zero:  # on the x axis: itself and its opposite
                add(px, py, start, end)
                add(-px, -py, h.opposite(start), h.opposite(end))
            elif start == end == h.quarter:  # on the y axis: itself and its mirror in y
                add(-px, py, start, end)
                add(px, -py, h.mirror_y(start), h.mirror_y(end))
            else:
                add(px, py, start, end)
                add(-px, py, h.mirror_x(start), h.mirror_x(end))
                add(px, -py, h.mirror_y(start), h.mirror_y(end))
                add(-px, -py, h.opposite(start), h.opposite(end))

    out: dict[int, list[Primitive]] = {k: [] for k in range(h.count)}
    for start, group in shapes.items():
        for shape in group:
            poses = _sample(shape, h, res)
            out[start].append(
                Primitive(
                    start,
                    shape.end,
                    shape.left_turn,
                    shape.radius,
                    shape.length,
                    shape.arc_length,
                    shape.start_straight + shape.end_straight,
                    poses,
                )
            )
    if config.motion_model in ("diff", "omni"):
        _add_rotations(h, out)
    if config.motion_model == "omni":
        _add_slides(h, out)
    ordered: list[Primitive] = []
    for start in range(h.count):
        # Nav2's generator sorts by the end heading's signed angle (a stable sort).
        ordered += sorted(out[start], key=lambda prim: h.signed[prim.end_index])
    return ordered


def _add_rotations(h: _Headings, out: dict[int, list[Primitive]]) -> None:
    """A rotation in place to each neighbouring heading (the diff and omni models): poses
    at the origin from the start heading to the next, about every 10 degrees."""
    for start in range(h.count):
        for end, sign in (((start + 1) % h.count, 1.0), ((start - 1) % h.count, -1.0)):
            turn = h.turn(start, end)
            steps = round(turn / _ROTATION_STEP) + 1
            yaw = h.signed[start] + sign * np.linspace(0.0, turn, steps)
            poses = np.column_stack([np.zeros(steps), np.zeros(steps), yaw])
            # Nav2's files mark both rotations left_turn (its straight-line default).
            out[start].append(Primitive(start, end, True, 0.0, 0.0, 0.0, 0.0, poses))


def _add_slides(h: _Headings, out: dict[int, list[Primitive]]) -> None:
    """A slide sideways (omni): the straight primitive of the heading 90 degrees to the
    left or right, driven with the start heading kept."""
    for start in range(h.count):
        for side in (h.quarter, -h.quarter):
            other = (start + side) % h.count
            straight = next(p for p in out[other] if p.end_index == other and p.length > 0.0)
            poses = straight.poses.copy()
            poses[:, 2] = h.signed[start]
            out[start].append(
                Primitive(start, start, True, 0.0, straight.length, 0.0, straight.length, poses)
            )


def _angle_0_2pi(a: float) -> float:
    a = math.fmod(a, TWO_PI)
    return a + TWO_PI if a < 0.0 else a


def lattice_document(
    config: LatticeConfig, primitives: Sequence[Primitive], date: datetime.date | None = None
) -> dict[str, Any]:
    """Nav2's lattice file as a JSON-ready dict (the keys SmacPlannerLattice reads, in the
    generator's order, with its 5-decimal rounding of positions and lengths)."""
    h = _Headings(config.num_of_headings)
    metadata: dict[str, Any] = config.model_dump()
    metadata["heading_angles"] = h.angles
    metadata["number_of_trajectories"] = len(primitives)
    rows = []
    for i, prim in enumerate(primitives):
        poses = [
            [round(float(x), 5) + 0.0, round(float(y), 5) + 0.0, _angle_0_2pi(float(yaw))]
            for x, y, yaw in prim.poses
        ]
        rows.append(
            {
                "trajectory_id": i,
                "start_angle_index": prim.start_index,
                "end_angle_index": prim.end_index,
                "left_turn": prim.left_turn,
                "trajectory_radius": round(prim.radius, 5),
                "trajectory_length": round(prim.length, 5),
                "arc_length": round(prim.arc_length, 5),
                "straight_length": round(prim.straight_length, 5),
                "poses": poses,
            }
        )
    return {
        "version": LATTICE_FORMAT_VERSION,
        "date_generated": (date or datetime.date.today()).isoformat(),
        "lattice_metadata": metadata,
        "primitives": rows,
    }


def write_lattice(
    path: str | PathLike[str], config: LatticeConfig, date: datetime.date | None = None
) -> int:
    """Generate the set for `config` and write it as a lattice file; returns its size."""
    primitives = generate_lattice(config)
    doc = lattice_document(config, primitives, date)
    Path(path).write_text(json.dumps(doc, indent="\t") + "\n")
    return len(primitives)


def read_config(path: str | PathLike[str]) -> LatticeConfig:
    """Nav2's generator config (JSON, read as YAML so a mistake names its line)."""
    return validate(LatticeConfig, load_yaml(path), file=str(path))


def main(argv: Sequence[str] | None = None) -> int:
    parser = argparse.ArgumentParser(
        prog="python -m btnav.planning.lattice_generator",
        description="Generate a state lattice control set for SmacPlannerLattice "
        "(Nav2's lattice primitive generator, its config and output formats).",
    )
    parser.add_argument("--config", required=True, type=Path, help="generator config (JSON)")
    parser.add_argument("--output", required=True, type=Path, help="lattice file to write")
    args = parser.parse_args(argv)
    try:
        config = read_config(args.config)
    except BtnavError as err:
        print(f"btnav: error: {err}", file=sys.stderr)
        return 2
    n = write_lattice(args.output, config)
    print(f"{args.output}: {n} primitives ({config.motion_model}, r={config.turning_radius} m)")
    return 0


if __name__ == "__main__":
    sys.exit(main())
