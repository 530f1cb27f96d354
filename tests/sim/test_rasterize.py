"""World -> map: occupied exactly where the world is solid, free elsewhere inside the bounds."""

from __future__ import annotations

import math

import numpy as np
import pytest

from btnav.cli.map import from_world_main
from btnav.core.errors import BtnavError, MapError
from btnav.core.resources import bundled_dir
from btnav.maps import FREE, OCCUPIED, UNKNOWN
from btnav.sim.geometry import Geometry
from btnav.sim.rasterize import rasterize
from btnav.sim.world import World
from btnav.sim.world_spec import WorldSpec, load_world_spec

OFFICE = bundled_dir("worlds") / "small_office.yaml"


def distance_to_geometry(g: Geometry, pts: np.ndarray) -> np.ndarray:
    """Signed-ish distance: 0 inside anything solid, else the distance to the nearest solid."""
    seg = g.segments
    a, b = seg[:, :2], seg[:, 2:]
    ab = b - a
    ap = pts[:, None, :] - a[None, :, :]
    t = np.clip((ap * ab).sum(-1) / (ab * ab).sum(-1), 0, 1)
    d_seg = np.linalg.norm(ap - t[..., None] * ab, axis=-1).min(axis=1)
    d = d_seg
    if len(g.circles):
        dc = np.linalg.norm(pts[:, None, :] - g.circles[None, :, :2], axis=-1) - g.circles[:, 2]
        d = np.minimum(d, np.maximum(dc.min(axis=1), 0))
    from matplotlib.path import Path as MplPath

    inside = np.zeros(len(pts), bool)
    for poly in g.polygons:
        inside |= MplPath(poly).contains_points(pts)
    if len(g.circles):
        inside |= (dc <= 0).any(axis=1)
    return np.where(inside, 0.0, d)


def test_office_map_is_occupied_exactly_where_the_world_is_solid():
    spec = load_world_spec(OFFICE)
    grid = rasterize(spec, resolution=0.05)
    assert grid.resolution == 0.05 and grid.frame_id == "map"
    assert (grid.origin.x, grid.origin.y, grid.origin.yaw) == (-0.2, -0.2, 0.0)
    assert (grid.width, grid.height) == (248, 168)

    world = World(spec)
    g = world.geometry()  # at t = 0: the mover at its start
    rows, cols = np.indices(grid.data.shape)
    centres = grid.cell_to_world(np.stack([rows.ravel(), cols.ravel()], -1))
    d = distance_to_geometry(g, centres).reshape(grid.data.shape)
    half_diagonal = grid.resolution * math.sqrt(2) / 2
    occupied = grid.data == OCCUPIED
    # Every cell whose centre is inside something solid is occupied ...
    assert occupied[d == 0].all()
    # ... every occupied cell touches something solid ...
    assert (d[occupied] <= half_diagonal + 1e-9).all()
    # ... and every cell clear of everything, inside the bounds, is free.
    inside = (
        (centres[:, 0] >= 0) & (centres[:, 0] <= 12) & (centres[:, 1] >= 0) & (centres[:, 1] <= 8)
    )
    inside = inside.reshape(grid.data.shape)
    clear = d > half_diagonal + 1e-9
    assert (grid.data[clear & inside] == FREE).all()
    assert (grid.data[clear & ~inside] == UNKNOWN).all()


@pytest.mark.parametrize(
    ("point", "value"),
    [
        ((6.0, 0.0), OCCUPIED),  # outer wall
        ((4.0, 1.5), OCCUPIED),  # inner wall
        ((2.0, 4.6), OCCUPIED),  # desk
        ((6.0, 5.6), OCCUPIED),  # the moving obstacle where it starts
        ((11.35, 3.0), OCCUPIED),  # the sofa's arm
        ((10.5, 3.3), FREE),  # the notch of the L-shaped sofa
        ((1.0, 1.0), FREE),  # where the robot starts
        ((4.0, 3.5), FREE),  # a doorway
        ((8.5, 4.5), FREE),  # the other doorway
        ((-0.15, 4.0), UNKNOWN),  # outside the bounds
    ],
)
def test_office_map_at_known_places(point, value):
    grid = rasterize(load_world_spec(OFFICE))
    [(r, c)] = grid.world_to_cell([point])
    assert grid.data[r, c] == value


def test_a_wall_thinner_than_a_cell_leaves_no_gap():
    """A 1 cm diagonal wall on a 10 cm grid: every cell its centre line crosses is occupied."""
    spec = WorldSpec.from_text(
        """
bounds: [[0, 0], [5, 5]]
walls:
  - {points: [[0.3, 0.2], [4.7, 4.1]], thickness: 0.01}
robot: {pose: [4, 1, 0], footprint: {radius: 0.1}}
""",
        "thin.yaml",
    )
    grid = rasterize(spec, resolution=0.1, padding=0.0)
    t = np.linspace(0, 1, 5000)[1:-1]
    line = np.array([0.3, 0.2]) + t[:, None] * np.array([4.4, 3.9])
    cells = grid.world_to_cell(line)
    assert (grid.data[cells[:, 0], cells[:, 1]] == OCCUPIED).all()
    assert (grid.data == OCCUPIED).sum() < 1.3 * 2 * 44  # a thin line, not a smear


def test_rasterize_takes_a_world_and_draws_movers_at_their_start():
    world = World.from_file(OFFICE)
    for _ in range(300):
        world.step(0.01)
    assert (rasterize(world).data == rasterize(world.spec).data).all()


def test_a_huge_map_is_refused_with_a_message():
    spec = WorldSpec.from_text(
        "bounds: [[0, 0], [50000, 50000]]\nrobot: {pose: [1, 1, 0]}\n", "big.yaml"
    )
    with pytest.raises(MapError, match="coarser resolution") as info:
        rasterize(spec, resolution=0.05)
    assert info.value.line == 1
    assert rasterize(spec, resolution=10.0).width == 5001


def test_bad_resolution_is_an_error():
    with pytest.raises(BtnavError):
        rasterize(load_world_spec(OFFICE), resolution=0.0)


def test_map_from_world_writes_a_map_server_map(tmp_path, capsys):
    map_io = pytest.importorskip("btnav.maps.map_io")
    out = tmp_path / "office.yaml"
    assert from_world_main(OFFICE, out, 0.05) == 0
    assert "248 x 168" in capsys.readouterr().out
    loaded = map_io.load_map(out)
    expected = rasterize(load_world_spec(OFFICE), 0.05)
    assert (loaded.data == expected.data).all()
    assert loaded.resolution == pytest.approx(0.05)
    assert (loaded.origin.x, loaded.origin.y) == pytest.approx((-0.2, -0.2))
