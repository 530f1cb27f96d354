"""Gazebo SDF worlds as btnav worlds: what a 2D lidar sees of them, placed where Gazebo
puts it, and every mistake named by file and line."""

from __future__ import annotations

import math
import sys
import warnings
from pathlib import Path

import numpy as np
import pytest
from scipy.spatial import cKDTree

from btnav.cli import main
from btnav.core.errors import BtnavError, BtnavWarning
from btnav.core.messages import Twist
from btnav.maps import load_map
from btnav.maps.occupancy_grid import FREE, OCCUPIED
from btnav.mission import Mission, run_mission
from btnav.sim.rasterize import rasterize
from btnav.sim.world import World
from btnav.sim.world_spec import load_world_spec

REPO = Path(__file__).resolve().parents[2]
SDF = REPO / "worlds" / "sdf"
CAFE = SDF / "cafe.world"
BAY = SDF / "warehouse_bay.yaml"
BURGER = REPO / "robots" / "turtlebot3_burger.urdf.xacro"

# -- the cafe's solids, written out from cafe.world and its bistro_table model -----------
# (kind, size, xyz, rpy): box (sx, sy, sz); cylinder (r, length); sphere (r,)
TABLES = [((-3.5, -1.8, 0.0), 0.0), ((-3.5, 1.6, 0.0), 0.0), ((-0.8, -1.8, 0.0), 0.4)]
TABLES.append(((-0.8, 1.6, 0.0), 0.0))
LEGS = [(sx * 0.33, sy * 0.33) for sx in (1, -1) for sy in (1, -1)]
CAFE_SOLIDS = [
    ("box", (10.15, 0.15, 2.5), (0, -3.5, 1.25), (0, 0, 0)),
    ("box", (10.15, 0.15, 2.5), (0, 3.5, 1.25), (0, 0, 0)),
    ("box", (7.15, 0.15, 2.5), (-5, 0, 1.25), (0, 0, math.pi / 2)),
    ("box", (0.15, 7.15, 2.5), (5, 0, 1.25), (0, 0, 0)),
    ("box", (0.12, 4.0, 2.5), (1.5, -1.5, 1.25), (0, 0, 0)),
    ("box", (0.12, 1.8, 2.5), (1.5, 2.6, 1.25), (0, 0, 0)),
    ("cylinder", (0.2, 2.5), (-2.2, 0, 1.25), (0, 0, 0)),
    ("sphere", (0.3,), (0.6, 3.0, 0.3), (0, 0, 0)),
    ("box", (0.6, 2.0, 0.9), (4.5, 1.8, 0.45), (0, 0, 0)),
    ("box", (0.3, 2.0, 0.04), (4.75, -1.0, 1.6), (0, 0, 0)),  # the shelf, above the band
    ("cylinder", (0.25, 0.9), (3.2, -2.8, 0.25), (math.pi / 2, 0, 0)),  # the lying barrel
    ("box", (0.04, 0.8, 1.2), (4.7, -2.2, 0.58), (0, 0.3, 0)),  # the leaning plank
]
for (tx, ty, _), yaw in TABLES:
    c, s = math.cos(yaw), math.sin(yaw)
    CAFE_SOLIDS.append(("box", (0.8, 0.8, 0.04), (tx, ty, 0.75), (0, 0, yaw)))  # the top
    for lx, ly in LEGS:
        at = (tx + c * lx - s * ly, ty + s * lx + c * ly, 0.365)
        CAFE_SOLIDS.append(("cylinder", (0.025, 0.73), at, (0, 0, 0)))
#: The default robot's band: 0.05 m to its lidar (0.25 m) + 0.1 m.
DEFAULT_BAND = (0.05, 0.35)


def rpy(roll: float, pitch: float, yaw: float) -> np.ndarray:
    def rot(axis: int, a: float) -> np.ndarray:
        c, s = math.cos(a), math.sin(a)
        i, j = ((1, 2), (2, 0), (0, 1))[axis]  # the right-handed pair
        m = np.eye(3)
        m[i, i], m[i, j], m[j, i], m[j, j] = c, -s, s, c
        return m

    return rot(2, yaw) @ rot(1, pitch) @ rot(0, roll)


def solid_points(kind: str, size: tuple, xyz: tuple, angles: tuple, step=0.02) -> np.ndarray:
    """Points filling the solid (its surface included), in the world."""
    if kind == "box":
        h = np.array(size) / 2
    elif kind == "cylinder":
        h = np.array([size[0], size[0], size[1] / 2])
    else:
        h = np.array([size[0]] * 3)
    axes = [np.linspace(-v, v, max(3, math.ceil(2 * v / step) + 1)) for v in h]
    local = np.stack(np.meshgrid(*axes, indexing="ij"), -1).reshape(-1, 3)
    if kind == "cylinder":
        local = local[np.hypot(local[:, 0], local[:, 1]) <= size[0] + 1e-9]
    if kind == "sphere":
        local = local[np.linalg.norm(local, axis=1) <= size[0] + 1e-9]
    return local @ rpy(*angles).T + np.array(xyz)


def in_band_points(solids: list, band: tuple[float, float]) -> np.ndarray:
    pts = np.concatenate([solid_points(*s) for s in solids])
    keep = (pts[:, 2] >= band[0]) & (pts[:, 2] <= band[1])
    return pts[keep, :2]


def cell_centres(grid) -> np.ndarray:
    rows, cols = np.indices(grid.data.shape)
    x = grid.origin.x + (cols + 0.5) * grid.resolution
    y = grid.origin.y + (rows + 0.5) * grid.resolution
    return np.stack([x, y], -1)


def test_a_converted_world_s_map_is_its_sdf_geometry_in_the_band(tmp_path, capsys):
    out, png = tmp_path / "cafe.yaml", tmp_path / "cafe_map.yaml"
    assert main(["world", "convert", str(CAFE), "-o", str(out)]) == 0
    assert "height band 0.05-0.35 m" in capsys.readouterr().out
    assert main(["map", "from-world", str(out), "-o", str(png)]) == 0
    grid = load_map(png)
    seen = cKDTree(in_band_points(CAFE_SOLIDS, DEFAULT_BAND))
    centres = cell_centres(grid)
    spec = load_world_spec(out)
    (x0, y0), (x1, y1) = spec.bounds
    inside = (
        (centres[..., 0] > x0)
        & (centres[..., 0] < x1)
        & (centres[..., 1] > y0)
        & (centres[..., 1] < y1)
    )
    near, _ = seen.query(centres.reshape(-1, 2))
    near = near.reshape(grid.data.shape)
    occupied = grid.data == OCCUPIED
    assert occupied.sum() > 1000
    assert near[occupied].max() <= 0.10  # every occupied cell is by the SDF geometry
    far = inside & (near > 0.12)  # 0.10 and the samples' 2 cm spacing
    assert np.all(grid.data[far] == FREE)  # and everything else is free
    for (tx, ty, _), _ in TABLES:  # under each table top, between its legs: free
        (row, col) = grid.world_to_cell([(tx, ty)])[0]
        assert grid.data[row, col] == FREE
    (row, col) = grid.world_to_cell([(4.75, -0.6)])[0]  # under the shelf
    assert grid.data[row, col] == FREE


def test_a_converted_world_reads_back_to_the_same_world(tmp_path):
    out = tmp_path / "bay.yaml"
    assert main(["world", "convert", str(BAY), "-o", str(out)]) == 0
    direct, converted = load_world_spec(BAY), load_world_spec(out)
    assert converted.obstacles == direct.obstacles and converted.bounds == direct.bounds
    assert converted.robot.footprint == direct.robot.footprint  # the Burger's, by description
    assert converted.robot.pose == direct.robot.pose == (1.0, 1.0, 0.0)
    assert np.array_equal(rasterize(converted).data, rasterize(direct).data)


def test_the_bundled_bay_map_is_the_rasterised_world():
    shipped = load_map(REPO / "maps" / "warehouse_bay.yaml")
    fresh = rasterize(load_world_spec(BAY), resolution=0.05)
    assert np.array_equal(shipped.data, fresh.data), (
        "maps/warehouse_bay.* is stale: btnav map from-world "
        "worlds/sdf/warehouse_bay.yaml -o maps/warehouse_bay.yaml"
    )


def table_world(tmp_path: Path, band: str = "") -> Path:
    world = tmp_path / "one_table.world"
    world.write_text(
        '<?xml version="1.0"?>\n<sdf version="1.6"><world name="w">\n'
        "  <include><uri>model://sun</uri></include>\n"
        "  <include><uri>model://bistro_table</uri><pose>1 2 0 0 0 0</pose></include>\n"
        "</world></sdf>\n"
    )
    ref = tmp_path / "one_table.yaml"
    ref.write_text(f"sdf: one_table.world\nmodel_paths: [{SDF / 'models'}]\n{band}")
    return ref


def test_a_table_top_above_the_lidar_band_leaves_only_its_legs(tmp_path):
    with pytest.warns(BtnavWarning, match="default robot"):
        spec = load_world_spec(table_world(tmp_path))
    assert [o.kind for o in spec.obstacles] == ["circle"] * 4
    centres = sorted(o.shape.center for o in spec.obstacles)
    assert centres == [(0.67, 1.67), (0.67, 2.33), (1.33, 1.67), (1.33, 2.33)]
    assert {o.shape.radius for o in spec.obstacles} == {0.025}
    with pytest.warns(BtnavWarning, match="default robot"):  # a band up to the top
        high = load_world_spec(table_world(tmp_path, "height_band: [0.05, 0.8]\n"))
    assert [o.kind for o in high.obstacles].count("box") == 1


def test_the_band_follows_the_robot_s_lidar(tmp_path):
    from btnav.core.yaml_io import YamlMap
    from btnav.sim.sdf_world_spec import convert_sdf_world

    burger = YamlMap({"description": str(BURGER)})
    conv = convert_sdf_world(CAFE, burger)
    assert conv.band == pytest.approx((0.05, 0.282))  # the LDS-01 at 0.182 m
    assert conv.spec.robot.sensors[0]["lidar"]["frame"] == "base_scan"


def test_poses_compose_through_includes_nested_models_and_frames():
    spec = load_world_spec(BAY)
    by_kind = {}
    for o in spec.obstacles:
        by_kind.setdefault(o.kind, []).append(o.shape)
    # the crate: loading_dock (11, 1) turned 90 deg, its frame `dock` 0.5 m ahead, the
    # pallet 0.6 m left of that frame: (10.4, 1.5); the mesh is 0.6 x 0.4, turned
    crate = next(p for p in by_kind["polygon"] if len(p.points) == 4)
    xs, ys = zip(*crate.points, strict=True)
    assert (min(xs), max(xs), min(ys), max(ys)) == pytest.approx((10.2, 10.6, 1.2, 1.8))
    # rack_4's <pose degrees="true"> turns it half round
    assert any(b.center == (9.0, 5.5) and b.yaw == pytest.approx(math.pi) for b in by_kind["box"])
    # the kerb's polyline keeps its L (concave) shape
    kerb = next(p for p in by_kind["polygon"] if len(p.points) == 6)
    assert kerb.points[3] == (1.0, 3.7)


def test_an_actor_s_trajectory_moves_and_an_unscripted_actor_is_left_out(tmp_path):
    world = World(load_world_spec(BAY))
    start = world.geometry().circles.copy()
    assert start.shape == (1, 3) and tuple(start[0]) == (3.0, 7.2, 0.2)
    world.set_cmd_vel(Twist())
    for _ in range(100):
        world.step(0.05)
    moved = world.geometry().circles[0]
    speed = 7.0 / 14.0  # about: 7 m in 14 s, then 0.64 m in 2 s (the mean is kept)
    assert moved[1] == pytest.approx(7.2) and moved[0] - 3.0 == pytest.approx(5 * speed, rel=0.1)
    text = (SDF / "warehouse_bay.sdf").read_text()
    still = text.replace("<script>", "<!--").replace("</script>", "-->")
    (tmp_path / "bay.sdf").write_text(still)
    (tmp_path / "bay.yaml").write_text(
        BAY.read_text()
        .replace("sdf: warehouse_bay.sdf", "sdf: bay.sdf")
        .replace("[models]", f"[{SDF / 'models'}]")
        .replace("../../robots", str(REPO / "robots"))
    )
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        spec = load_world_spec(tmp_path / "bay.yaml")
    said = [str(w.message) for w in caught if issubclass(w.category, BtnavWarning)]
    assert len(said) == 1 and "actor 'walker' is left out" in said[0]
    assert f"bay.sdf:{line(tmp_path / 'bay.sdf', '<actor')}" in said[0]
    assert not any(o.moves for o in spec.obstacles)


def line(path: Path, text: str) -> int:
    return next(i for i, s in enumerate(path.read_text().splitlines(), 1) if text in s)


def test_scenery_is_silent_and_a_fuel_model_that_is_not_is_one_warning(tmp_path):
    text = (SDF / "warehouse_bay.sdf").read_text()
    chair = "https://fuel.gazebosim.org/1.0/OpenRobotics/models/Chair"
    world = tmp_path / "bay.sdf"
    world.write_text(text.replace("</world>", f"<include><uri>{chair}</uri></include></world>"))
    ref = tmp_path / "bay.yaml"
    ref.write_text(
        f"sdf: bay.sdf\nmodel_paths: [{SDF / 'models'}]\nrobot: {{description: {BURGER}}}\n"
    )
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        load_world_spec(ref)
    said = [str(w.message) for w in caught if issubclass(w.category, BtnavWarning)]
    assert len(said) == 1 and chair in said[0] and "left out" in said[0]


def test_an_unreadable_mesh_is_one_warning_and_left_out(monkeypatch):
    monkeypatch.setitem(sys.modules, "trimesh", None)  # as without the meshes extra
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        spec = load_world_spec(BAY)
    said = [str(w.message) for w in caught if issubclass(w.category, BtnavWarning)]
    assert len(said) == 1 and "crate.obj" in said[0] and "trimesh is not installed" in said[0]
    assert str(SDF / "models" / "crate" / "model.sdf") in said[0]
    assert len([o for o in spec.obstacles if o.kind == "polygon"]) == 1  # the kerb only


def broken_world(tmp_path: Path, body: str) -> Path:
    world = tmp_path / "broken.world"
    world.write_text(
        f'<?xml version="1.0"?>\n<sdf version="1.6">\n<world name="w">\n{body}\n</world>\n</sdf>\n'
    )
    return world


def test_a_missing_model_names_the_include_s_line_the_paths_and_the_close_name(tmp_path, capsys):
    world = broken_world(tmp_path, "  <include>\n    <uri>model://bistro_tabel</uri>\n  </include>")
    models = str(SDF / "models")
    code = main(
        ["world", "convert", str(world), "--model-path", models, "-o", str(tmp_path / "w.yaml")]
    )
    err = capsys.readouterr().err
    assert code == 2
    assert f"btnav: error: {world}:5: model://bistro_tabel not found" in err
    assert models in err and "did you mean 'bistro_table'?" in err


def test_a_malformed_pose_names_its_file_and_line(tmp_path, capsys):
    body = (
        '  <model name="box">\n    <pose>1 2 x 0 0 0</pose>\n'
        '    <link name="l"><collision name="c"><geometry><box><size>1 1 1</size></box>'
        "</geometry></collision></link>\n  </model>"
    )
    world = broken_world(tmp_path, body)
    assert main(["world", "show", str(world), "-o", str(tmp_path / "w.png")]) == 2
    assert f"btnav: error: {world}:5: malformed number 'x' in <pose>" in capsys.readouterr().err
    # a pose in an included model names the model's own file
    model = tmp_path / "models" / "bad"
    model.mkdir(parents=True)
    (model / "model.sdf").write_text(
        '<?xml version="1.0"?>\n<sdf version="1.9"><model name="bad">\n'
        '<link name="l"><pose>0 0</pose></link>\n</model></sdf>\n'
    )
    world = broken_world(tmp_path, "  <include><uri>model://bad</uri></include>")
    with pytest.raises(BtnavError) as info:
        load_world_spec(world, robot={"pose": [5, 5, 0]})
    assert (info.value.file, info.value.line) == (str(model / "model.sdf"), 3)
    assert "<pose> needs 6 numbers, got '0 0'" in info.value.message


def test_the_robot_starts_where_the_world_spawns_it_else_at_the_free_place_nearest_the_origin():
    assert load_world_spec(BAY).robot.pose == (1.0, 1.0, 0.0)  # the `burger` include
    with pytest.warns(BtnavWarning, match="default robot"):
        cafe = load_world_spec(CAFE)
    assert cafe.robot.pose == (0.0, 0.0, 0.0)  # nothing there
    World(cafe)  # and it fits


@pytest.mark.slow
def test_a_burger_tours_the_gazebo_bay_with_nav2_s_params_untouched():
    mission = Mission.load(REPO / "missions" / "sdf_world_tour.yaml")
    assert mission.world.robot.pose == (1.0, 1.0, 0.0)  # spawned by the world
    report = run_mission(mission)
    assert report.status == "succeeded" and not report.missed_waypoints, report.summary()
    assert report.collisions == 0, report.contacts
    assert report.localization_error["rms_xy"] <= 0.25, report.localization_error
