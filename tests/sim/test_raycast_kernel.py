"""The compiled grid-walk caster gives the numpy path's ranges bit for bit, on any CPU.

raycast.py's numpy path is the reference: every scan here is cast both ways and
compared with `np.array_equal` (inf included), in hand-made corner cases, random
scenes and bundled worlds (a moving obstacle, map-image worlds).
"""

from __future__ import annotations

import hashlib
import math
import os
import re
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest

from btnav.sim import raycast, raycast_kernel
from btnav.sim.geometry import Geometry
from btnav.sim.raycast import RayCaster, beam_directions
from btnav.sim.world import World

REPO = Path(__file__).resolve().parents[2]
FULL = np.linspace(-math.pi, math.pi, 360, endpoint=False)
RANGES = (0.5, 3.5, 8.0, math.inf)


def both(geometry: Geometry, origin, dirs, max_range=math.inf, prune=None, kernel=None):
    """The kernel's and the numpy path's ranges (a given `kernel` caster keeps its index)."""
    kernel = RayCaster(method="kernel") if kernel is None else kernel
    got = kernel.cast(geometry, origin, dirs, max_range, prune=prune)
    want = RayCaster(method="numpy").cast(geometry, origin, dirs, max_range, prune=prune)
    return got, want


def assert_same(geometry: Geometry, origin, dirs, max_range=math.inf, prune=None, kernel=None):
    got, want = both(geometry, origin, dirs, max_range, prune, kernel)
    diff = np.flatnonzero(~((got == want) | (np.isnan(got) & np.isnan(want))))
    assert np.array_equal(got, want), (
        f"origin {tuple(origin)}, max_range {max_range}, prune {prune}: beams {diff[:5]}"
        f" read {got[diff[:5]]} against numpy's {want[diff[:5]]}"
    )
    return got


def test_the_kernel_is_the_default_and_shares_the_numpy_paths_tolerances():
    assert RayCaster().method == "kernel"
    assert raycast_kernel.ON_LINE_AREA == raycast.ON_LINE_AREA
    assert raycast_kernel.COLLINEAR_TOL == raycast.COLLINEAR_TOL
    with pytest.raises(ValueError, match="kernel"):
        RayCaster(method="cuda")  # type: ignore[arg-type]


# -- corner cases -------------------------------------------------------------------------


def box(x0: float, y0: float, x1: float, y1: float) -> np.ndarray:
    return np.array([[x0, y0], [x1, y0], [x1, y1], [x0, y1]])  # counter-clockwise


def test_corner_cases_read_as_in_the_numpy_path():
    room = Geometry([box(-2, -2, 2, 2)])
    boxes = Geometry([box(1, 0, 2, 1), box(2, 0, 3, 1), box(-3, -1, -2, 1)], one_sided=True)
    pillars = Geometry([box(-5, -5, 5, 5)], np.array([[0.0, 0.0, 0.5], [1.0, 0.0, 0.25]]))
    eighths = beam_directions(np.arange(8) * math.pi / 4)  # along edges, through corners
    cases = [
        (room, (0.0, 0.0), beam_directions(FULL)),  # every diagonal through a vertex
        (room, (2.0, 0.0), beam_directions(FULL)),  # the origin on an edge: all 0
        (room, (2.0, 2.0), beam_directions(FULL)),  # on a vertex
        (room, (3.0, 2.0), eighths),  # on an edge's line, outside: along the edge
        (room, (-5.0, -2.0), eighths),  # outside the grid, on an edge's line
        (boxes, (0.0, 0.0), eighths),  # along the shared bottom edge of two boxes
        (boxes, (0.0, 1.0), eighths),  # along their top edges
        (boxes, (2.0, 1.0), eighths),  # the vertex two boxes share
        (boxes, (4.0, 0.5), beam_directions(FULL)),
        (pillars, (0.1, 0.0), beam_directions(FULL)),  # inside a circle
        (pillars, (0.5, 0.0), beam_directions(FULL)),  # on its boundary, inside another
        (pillars, (1.0, 0.0), beam_directions(FULL)),  # in two circles
        (pillars, (0.0, -0.5), beam_directions([0.0, math.pi, -math.pi / 2])),  # tangents
        (Geometry(), (0.0, 0.0), eighths),
        (Geometry([], np.array([[3.0, 0.0, 1.0]])), (0.0, 0.0), beam_directions(FULL)),
    ]
    for geometry, origin, dirs in cases:
        for max_range in RANGES:
            for prune in (None, True, False):
                assert_same(geometry, origin, dirs, max_range, prune)
    assert np.all(RayCaster().cast(room, (2.0, 0.0), eighths) == 0.0)


def test_a_zero_length_edge_is_a_point_never_hit():
    # A polygon with a repeated vertex has a zero-length edge; with the origin beside
    # it, the numpy path used to read 0 on every beam (the origin "on" that edge).
    g = Geometry([np.array([[1.0, 0.0], [3.0, 0.0], [3.0, 0.0], [3.0, 1.0], [1.0, 1.0]])])
    got = assert_same(g, (-1.0, 0.5), beam_directions(FULL))
    assert np.isfinite(got).any() and not (got == 0).any()
    assert_same(g, (3.0, 0.0), beam_directions(FULL))  # on the repeated vertex itself: 0


def test_ranges_at_exactly_max_range_and_beyond():
    g = Geometry([box(-3.5, -3.5, 3.5, 3.5)], np.array([[0.0, 3.0, 0.5]]))
    for max_range in (2.5, 3.5, 3.5 * math.sqrt(2.0), 5.0, math.inf):
        assert_same(g, (0.0, 0.0), beam_directions(FULL), max_range)


# -- random scenes ------------------------------------------------------------------------


def random_scene(rng: np.random.Generator, n_polys: int, n_circles: int, one_sided: bool):
    polys = []
    for _ in range(n_polys):
        c = rng.uniform(0, 10, 2)
        ang = np.sort(rng.uniform(0, 2 * np.pi, rng.integers(3, 8)))  # counter-clockwise
        r = rng.uniform(0.05, 1.0, len(ang))
        polys.append(c + np.c_[r * np.cos(ang), r * np.sin(ang)])
    circles = np.c_[rng.uniform(0, 10, (n_circles, 2)), rng.uniform(0.05, 0.6, n_circles)]
    return Geometry(polys, circles, one_sided=one_sided)


def hard_origins(rng: np.random.Generator, g: Geometry, n: int) -> list[np.ndarray]:
    """Random points, points on segments and on their lines, vertices, circle insides."""
    out = list(rng.uniform(-1, 11, (n, 2)))
    segs = g.segments
    for s in segs[rng.integers(0, len(segs), n)] if len(segs) else []:
        p, q = s[:2], s[2:]
        out.append(p + rng.choice([0.0, 0.5, 1.0, -0.5, 2.0, rng.uniform(-3, 4)]) * (q - p))
    for c in g.circles[rng.integers(0, len(g.circles), n)] if len(g.circles) else []:
        out.append(c[:2] + rng.uniform(-1.0, 1.0, 2) * c[2] * 0.7)
    return out


def beams_at(rng: np.random.Generator, g: Geometry, origin: np.ndarray) -> np.ndarray:
    """A random fan plus beams aimed exactly at some vertices."""
    dirs = [beam_directions(rng.uniform(-np.pi, np.pi, 120))]
    if len(g.segments):
        v = g.segments[rng.integers(0, len(g.segments), 40), :2] - origin
        n = np.hypot(v[:, 0], v[:, 1])
        dirs.append(v[n > 0] / n[n > 0, None])
    return np.concatenate(dirs)


@pytest.mark.parametrize("one_sided", [False, True])
@pytest.mark.parametrize("seed", [0, 1, 2])
def test_random_scenes_give_the_same_bits(seed, one_sided):
    rng = np.random.default_rng(seed)
    g = random_scene(
        rng, n_polys=[8, 60, 200][seed], n_circles=[3, 40, 10][seed], one_sided=one_sided
    )
    kernel = RayCaster(method="kernel")
    for i, origin in enumerate(hard_origins(rng, g, 12)):
        dirs = beams_at(rng, g, origin)
        assert_same(g, origin, dirs, RANGES[i % 4], (None, True, False)[i % 3], kernel)


def test_a_lattice_of_boxes_with_origins_and_beams_on_its_lines():
    # Map-like: axis-aligned unit boxes, origins on cell corners and edges, beams along
    # the axes and diagonals: the exact on-line and through-vertex cases, many times over.
    rng = np.random.default_rng(4)
    cells = np.argwhere(rng.random((12, 12)) < 0.3)
    g = Geometry([box(c, r, c + 1.0, r + 1.0) for r, c in cells], one_sided=True)
    dirs = beam_directions(np.arange(16) * math.pi / 8)
    kernel = RayCaster(method="kernel")
    for x in np.arange(0.0, 12.5, 0.5):
        for y in (0.0, 3.0, 6.5, 11.0):
            for max_range in (4.0, math.inf):
                assert_same(g, (x, y), dirs, max_range, kernel=kernel)


@pytest.mark.parametrize("cell", [0.05, 0.25, 1.0, 4.0])
def test_any_cell_size_gives_the_same_bits(monkeypatch, cell):
    # The grid decides only which items a beam meets; its cells' size must not show.
    monkeypatch.setattr(raycast_kernel, "MIN_CELL", cell)
    monkeypatch.setattr(raycast_kernel, "MAX_CELL", cell)
    rng = np.random.default_rng(8)
    cells = np.argwhere(rng.random((8, 8)) < 0.3)
    lattice = Geometry([box(c, r, c + 1.0, r + 1.0) for r, c in cells], one_sided=True)
    scene = random_scene(rng, 40, 10, one_sided=False)
    for g in (lattice, scene):
        kernel = RayCaster(method="kernel")
        for i, origin in enumerate(hard_origins(rng, g, 8)):
            assert_same(g, origin, beams_at(rng, g, origin), RANGES[i % 4], kernel=kernel)
        assert kernel._grid is not None and kernel._grid.index is not None
        assert kernel._grid.index.cell == pytest.approx(cell)


# -- worlds -------------------------------------------------------------------------------


@pytest.mark.parametrize("name", ["small_office", "tb3_sandbox", "depot", "warehouse"])
def test_bundled_worlds_give_the_same_bits(name):
    # tb3_sandbox and depot are map-image worlds (thousands of segments).
    world = World.from_file(REPO / "worlds" / f"{name}.yaml", seed=0)
    g = world.geometry()
    (x0, y0), (x1, y1) = world.bounds
    rng = np.random.default_rng(5)
    kernel = RayCaster(method="kernel")
    dirs = beam_directions(FULL)
    for i, origin in enumerate(rng.uniform((x0, y0), (x1, y1), (24, 2))):
        assert_same(g, origin, dirs, RANGES[i % 4], kernel=kernel)


def test_a_moving_obstacle_is_cast_as_a_small_extra_list():
    # The office's person walks; the caster indexes the static part once more, after
    # the first scan, and then casts the person as a moving item, scan after scan.
    world = World.from_file(REPO / "worlds" / "small_office.yaml", seed=0)
    kernel = RayCaster(method="kernel")
    dirs = beam_directions(FULL)
    for step in range(40):
        for _ in range(25):
            world.step(0.01)
        origin = (5.0 + 0.05 * step, 5.6)  # near the person's route
        assert_same(world.geometry(), origin, dirs, 8.0, kernel=kernel)
    assert kernel._grid is not None and kernel._grid.rebuilds == 2
    _, moving_segments, moving_circles = kernel._grid.split(
        world.geometry().segments, world.geometry().circles
    )
    assert len(moving_segments) == 0 and len(moving_circles) == 1


def test_a_scene_of_many_moving_polygons_and_then_another_world():
    rng = np.random.default_rng(6)
    static = random_scene(rng, 30, 5, one_sided=True)
    kernel = RayCaster(method="kernel")
    for _ in range(6):
        moving = random_scene(rng, 3, 2, one_sided=True)
        assert_same(static.merged(moving), (5.0, 5.0), beam_directions(FULL), kernel=kernel)
    other = random_scene(rng, 40, 4, one_sided=True)  # not a prefix: indexed anew
    assert_same(other, (5.0, 5.0), beam_directions(FULL), kernel=kernel)


def test_without_numba_the_caster_falls_back_to_numpy(monkeypatch):
    monkeypatch.setitem(sys.modules, "btnav.sim.raycast_kernel", None)  # import fails
    monkeypatch.setattr(raycast, "_KERNEL_MISSING", [])
    with pytest.warns(UserWarning, match="casting with numpy"):
        caster = RayCaster()
    assert caster.method == "numpy"
    g = Geometry([box(-2, -2, 2, 2)])
    assert np.array_equal(
        caster.cast(g, (0.5, 0.0), beam_directions(FULL)),
        both(g, (0.5, 0.0), beam_directions(FULL))[1],
    )


# -- every CPU the same -------------------------------------------------------------------


def scan_set_bytes() -> bytes:
    """A fixed set of kernel scans (random scenes, the office, a map world), as bytes."""
    out = []
    rng = np.random.default_rng(11)
    for one_sided in (False, True):
        g = random_scene(rng, 80, 20, one_sided)
        kernel = RayCaster(method="kernel")
        for i, origin in enumerate(hard_origins(rng, g, 6)):
            out.append(kernel.cast(g, origin, beams_at(rng, g, origin), RANGES[i % 4]))
    for name in ("small_office", "tb3_sandbox"):
        world = World.from_file(REPO / "worlds" / f"{name}.yaml", seed=0)
        (x0, y0), (x1, y1) = world.bounds
        kernel = RayCaster(method="kernel")
        for origin in rng.uniform((x0, y0), (x1, y1), (10, 2)):
            out.append(kernel.cast(world.geometry(), origin, beam_directions(FULL), 8.0))
    return np.concatenate(out).tobytes()


_SUBPROCESS = """
import re, runpy, hashlib, sys
module = runpy.run_path({path!r})
print(hashlib.sha256(module["scan_set_bytes"]()).hexdigest())
if {asm}:
    from btnav.sim import raycast_kernel as rk
    text = "".join(a for f in (rk._cast, rk._register) for a in f.inspect_asm().values())
    fused = re.findall(r"\\bv?f(?:n?m(?:add|sub))\\w*", text)
    print(len(text), len(fused))
"""


def _run(tmp_path: Path, asm: bool, **env: str) -> list[str]:
    code = _SUBPROCESS.format(path=__file__, asm=asm)
    # A fresh cache: the kernel compiles for this CPU setting (and can show its assembly).
    env = {**os.environ, "NUMBA_CACHE_DIR": str(tmp_path), **env}
    done = subprocess.run(
        [sys.executable, "-c", code], env=env, capture_output=True, text=True, check=True
    )
    return done.stdout.split()


def test_numbas_generic_cpu_build_gives_the_hosts_bytes(tmp_path):
    host = hashlib.sha256(scan_set_bytes()).hexdigest()
    assert _run(tmp_path / "generic", False, NUMBA_CPU_NAME="generic")[0] == host
    digest, n_chars, n_fused = _run(tmp_path / "host", True)
    assert digest == host
    # LLVM was not allowed to contract a * b + c into a fused multiply-add anywhere.
    assert int(n_chars) > 10_000 and int(n_fused) == 0
    assert re.fullmatch("[0-9a-f]{64}", host)
