"""A base that collides as a mesh: its footprint is the hull of the mesh's vertices seen from above.

The meshes are made here by trimesh itself (an STL box, an OBJ cylinder, a COLLADA box
in millimetres), placed, scaled and named as URDF (`package://`, `file://`) and SDF
(`model://`) name them; without trimesh each mesh is one warning and the world's
footprint is used.
"""

from __future__ import annotations

import math
import sys
import warnings
from pathlib import Path

import numpy as np
import pytest

from btnav.core.errors import BtnavWarning
from btnav.description import load_description
from btnav.sim.world import World

from .gazebo_models import line_of, write_model
from .test_world_description import office_world


@pytest.fixture
def trimesh():
    """trimesh (the `btnav[meshes]` extra) makes the meshes: these tests skip without it."""
    return pytest.importorskip("trimesh")


def extent(polygon) -> tuple[float, float, float, float]:
    p = np.asarray(polygon)
    return (*p.min(axis=0), *p.max(axis=0))


def stl_box(trimesh, folder: Path, extents=(0.3, 0.2, 0.1)) -> Path:
    folder.mkdir(parents=True, exist_ok=True)
    path = folder / "box.stl"
    trimesh.creation.box(extents=extents).export(path)
    return path


def urdf(folder: Path, mesh: str, origin: str = "", scale: str = "") -> Path:
    path = folder / "robot.urdf"
    path.write_text(
        '<?xml version="1.0"?>\n<robot name="meshbot">\n  <link name="base_link">\n'
        f"    <collision>{origin}\n"
        f'      <geometry><mesh filename="{mesh}"{scale}/></geometry>\n'
        "    </collision>\n  </link>\n</robot>\n"
    )
    return path


def test_an_stl_box_through_package_uri_scaled_and_turned(tmp_path, monkeypatch, trimesh):
    monkeypatch.delenv("AMENT_PREFIX_PATH", raising=False)
    monkeypatch.delenv("ROS_PACKAGE_PATH", raising=False)
    stl_box(trimesh, tmp_path / "my_robot" / "meshes")
    path = urdf(
        tmp_path,
        "package://my_robot/meshes/box.stl",
        origin=f'<origin xyz="0.05 0 0.05" rpy="0 0 {math.pi / 2}"/>',
        scale=' scale="2 1 1"',
    )
    d = load_description(path, {"my_robot": tmp_path / "my_robot"})
    fp = d.footprint
    assert fp is not None and fp.source == "mesh" and fp.radius is None
    # 0.3 x 0.2 stretched to 0.6 along its x, turned so that x is the robot's y
    assert extent(fp.polygon) == pytest.approx((-0.05, -0.3, 0.15, 0.3), abs=1e-9)
    assert len(fp.polygon) == 4  # a box's outline: its four corners, whatever the triangles
    assert (fp.file, fp.line) == (str(path), line_of(path, "<mesh"))


def test_an_obj_cylinder_through_model_uri(tmp_path, trimesh):
    mesh = trimesh.creation.cylinder(radius=0.2, height=0.1, sections=256)
    write_model(
        tmp_path / "models",
        "cylbot",
        '    <link name="base_link">\n      <collision name="body">\n'
        "        <pose>0.1 0 0.05 0 0 0</pose>\n"
        "        <geometry><mesh><uri>model://cylbot/meshes/body.obj</uri></mesh></geometry>\n"
        "      </collision>\n    </link>\n",
    )
    (tmp_path / "models" / "cylbot" / "meshes").mkdir()
    mesh.export(tmp_path / "models" / "cylbot" / "meshes" / "body.obj")
    d = load_description("model://cylbot", model_paths=[tmp_path / "models"])
    fp = d.footprint
    assert fp is not None and fp.polygon is not None
    (x0, y0, _), (x1, y1, _) = mesh.bounds  # the mesh's own extent, moved by the pose
    assert extent(fp.polygon) == pytest.approx((x0 + 0.1, y0, x1 + 0.1, y1), abs=1e-6)
    r = np.hypot(*(np.asarray(fp.polygon) - (0.1, 0.0)).T)
    assert r.max() == pytest.approx(0.2, abs=1e-6)  # no point outside the cylinder
    assert r.min() > 0.2 - 1e-3  # and none more than MESH_TOLERANCE inside it
    # 256 facets: the points within a millimetre of their neighbours' chord are thinned out
    assert 16 <= len(fp.polygon) < 64


def test_a_mesh_and_a_box_on_one_link_join_one_hull(tmp_path, trimesh):
    box = stl_box(trimesh, tmp_path, (0.2, 0.2, 0.1))
    path = tmp_path / "r.urdf"
    path.write_text(
        '<robot name="r"><link name="base_link">'
        f'<collision><geometry><mesh filename="file://{box}"/></geometry></collision>'
        '<collision><origin xyz="0.3 0 0"/><geometry><box size="0.1 0.1 0.1"/></geometry>'
        "</collision></link></robot>"
    )
    fp = load_description(path).footprint
    assert fp is not None and fp.source == "mesh + box"
    assert extent(fp.polygon) == pytest.approx((-0.1, -0.1, 0.35, 0.1))


def test_a_collada_file_s_unit_scales_it_as_gazebo_does(tmp_path, trimesh):
    pytest.importorskip("collada")
    data = trimesh.exchange.dae.export_collada(trimesh.creation.box(extents=(300, 200, 100)))
    text = data.decode() if isinstance(data, bytes) else data
    (tmp_path / "base.dae").write_text(
        text.replace("<asset>", '<asset>\n    <unit name="millimeter" meter="0.001"/>', 1)
    )
    fp = load_description(urdf(tmp_path, "base.dae")).footprint  # a path beside the file
    assert fp is not None
    assert extent(fp.polygon) == pytest.approx((-0.15, -0.1, 0.15, 0.1), abs=1e-9)


def mesh_warnings(caught) -> list[BtnavWarning]:
    return [w.message for w in caught if "collision mesh" in str(w.message)]


def test_without_trimesh_each_mesh_is_one_warning_and_no_footprint(tmp_path, monkeypatch):
    box = tmp_path / "box.stl"
    box.write_bytes(b"solid box\nendsolid box\n")  # never opened: trimesh is missing
    path = tmp_path / "r.urdf"
    path.write_text(
        '<robot name="r">\n  <link name="base_link">\n'
        f'    <collision><geometry><mesh filename="file://{box}"/></geometry></collision>\n'
        '    <collision><geometry><mesh filename="package://btnav_robots/meshes/x.stl"/>'
        "</geometry></collision>\n  </link>\n</robot>\n"
    )
    monkeypatch.setitem(sys.modules, "trimesh", None)  # `import trimesh` fails
    with pytest.warns(BtnavWarning) as caught:
        d = load_description(path)
    assert d.footprint is None
    first, second = mesh_warnings(caught)
    assert (first.file, first.line) == (str(path), 3) and (second.file, second.line) == (
        str(path),
        4,
    )
    assert f"cannot read the collision mesh 'file://{box}' of link 'base_link'" in first.message
    assert "trimesh is not installed (pip install 'btnav[meshes]')" in first.message
    assert "the world's `footprint:` is used" in first.message
    assert "package://btnav_robots/meshes/x.stl" in second.message


def test_a_world_without_trimesh_uses_its_footprint_or_the_default(tmp_path, monkeypatch):
    (tmp_path / "meshes").mkdir()
    (tmp_path / "meshes" / "box.stl").write_bytes(b"solid box\nendsolid box\n")
    urdf(tmp_path, "meshes/box.stl")
    monkeypatch.setitem(sys.modules, "trimesh", None)
    robot = {"description": "../robot.urdf", "pose": [1, 1, 0], "sensors": []}
    with pytest.warns(BtnavWarning) as caught:
        spec = World.from_file(office_world(tmp_path, robot)).spec.robot
    assert spec.footprint.radius == 0.22
    assert len(mesh_warnings(caught)) == 1
    assert any("no collision geometry btnav can read" in str(w.message) for w in caught)
    robot["footprint"] = {"radius": 0.17}
    with pytest.warns(BtnavWarning, match="collision mesh"):
        spec = World.from_file(office_world(tmp_path, robot, "w2.yaml")).spec.robot
    assert spec.footprint.radius == 0.17


def test_with_trimesh_the_world_takes_the_mesh_footprint(tmp_path, trimesh):
    stl_box(trimesh, tmp_path / "meshes")
    urdf(tmp_path, "meshes/box.stl")
    robot = {"description": "../robot.urdf", "pose": [1, 1, 0], "sensors": []}
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        spec = World.from_file(office_world(tmp_path, robot)).spec.robot
    assert extent(spec.footprint.polygon) == pytest.approx((-0.15, -0.1, 0.15, 0.1))


@pytest.mark.parametrize(
    ("name", "content", "reason"),
    [
        ("broken.stl", b"solid x\nnot an stl at all\n", "it holds no vertices"),
        ("shape.xyz9", b"0 0 0", "trimesh cannot read it"),
        ("gone.stl", None, "no such file"),
    ],
)
def test_a_mesh_that_cannot_be_read_is_one_warning(tmp_path, name, content, reason, trimesh):
    if content is not None:
        (tmp_path / name).write_bytes(content)
    path = urdf(tmp_path, name)
    with pytest.warns(BtnavWarning) as caught:
        d = load_description(path)
    (w,) = mesh_warnings(caught)
    assert d.footprint is None and reason in w.message and w.line == line_of(path, "<mesh")


def test_a_model_uri_mesh_that_is_not_there_names_the_folders_searched(tmp_path):
    sdf = write_model(
        tmp_path,
        "bot",
        '    <link name="base_link"><collision name="c"><geometry><mesh>\n'
        "      <uri>model://bot/meshes/base.stl</uri>\n"
        "    </mesh></geometry></collision></link>\n",
    )
    with pytest.warns(BtnavWarning) as caught:
        load_description(sdf)
    (w,) = mesh_warnings(caught)
    assert (w.file, w.line) == (str(sdf), line_of(sdf, "<uri>"))
    assert "no bot/meshes/base.stl in the model paths" in w.message
    assert f"{tmp_path} (beside the description)" in w.message
