"""Reading a robot description: URDF, xacro or a Gazebo model, into a `RobotDescription`.

The file is parsed with the line of every element kept; a xacro file (a `.xacro` name,
or a top element that declares the xacro namespace, as ROS 2 TurtleBot3 URDFs do) is
expanded by xacrodoc first. A `<robot>` is read as URDF, an `<sdf>` as a Gazebo model
(its `<include>`s expanded); a Gazebo model folder, or `model://NAME` found through the
model paths, is read through the SDF file its `model.config` picks. The base frame is
the `base_footprint` link, else `base_link` (in a wrapper model, the least nested one),
else the root link; the footprint (collision meshes read through the same package and
model paths), drive, lidars and frames are then computed in it.
"""

from __future__ import annotations

import dataclasses
import os
import xml.dom.minidom
from collections.abc import Mapping, Sequence
from pathlib import Path

from .drive_joints import read_drive_joints
from .footprint import read_footprint
from .gazebo_plugins import read_drive_plugin
from .gazebo_sensors import read_lidars
from .meshes import MeshSources
from .model import RobotModel
from .model_paths import SCHEME, ModelPaths, model_file
from .packages import PackagePaths
from .robot_description import DriveDescription, LinkFrame, RobotDescription
from .sdf_reader import read_sdf
from .source_lines import SourceFiles, parse_with_lines, read_source, to_element_tree
from .transforms import Transform, yaw_of
from .urdf_reader import read_urdf
from .xacro_expand import expand_xacro
from .xml_values import error, tag

BASE_FRAMES = ("base_footprint", "base_link")
#: Frame poses are rounded to a nanometre (see `gazebo_sensors.DECIMALS`).
DECIMALS = 9


def _is_xacro(path: Path, doc: xml.dom.minidom.Document) -> bool:
    """A `.xacro` file, or one whose top element declares the xacro namespace."""
    if path.name.endswith(".xacro"):
        return True
    attrs = doc.documentElement.attributes.items()
    return any(k.startswith("xmlns:") and "xacro" in v for k, v in attrs)


def _drive(model: RobotModel, poses: dict[str, Transform]) -> DriveDescription | None:
    """The drive plugin's drive, its gaps filled from the joints' (same kind only)."""
    found = read_drive_plugin(model)
    joints = read_drive_joints(model, poses)
    if found is None:
        return joints
    drive, _ = found
    if joints is not None and joints.name == drive.name:
        gaps = {
            f.name: getattr(joints, f.name)
            for f in dataclasses.fields(drive)
            if getattr(drive, f.name) is None and f.name not in ("file", "line")
        }
        drive = dataclasses.replace(drive, **gaps)
    return drive


def _frames(model: RobotModel, poses: dict[str, Transform], base: str) -> tuple[LinkFrame, ...]:
    """Every link in the base frame, each with its neighbour toward the base as parent."""
    neighbours: dict[str, list[str]] = {name: [] for name in model.links}
    for j in model.joints:
        neighbours[j.parent].append(j.child)
        neighbours[j.child].append(j.parent)
    out, parent, todo = [], {base: None}, [base]
    while todo:
        name = todo.pop(0)
        (x, y, z), yaw = poses[name][1], yaw_of(poses[name])
        r = [round(v, DECIMALS) + 0.0 for v in (x, y, z, yaw)]
        out.append(LinkFrame(name, parent[name], r[0], r[1], r[2], r[3]))
        for n in neighbours[name]:
            if n not in parent:
                parent[n] = name
                todo.append(n)
    return tuple(out)


def _model_paths(
    given: ModelPaths | Sequence[str | os.PathLike[str]] | None,
) -> ModelPaths:
    return given if isinstance(given, ModelPaths) else ModelPaths.from_list(given)


def load_description(
    path: str | os.PathLike[str],
    package_paths: PackagePaths | Mapping[str, str | os.PathLike[str]] | None = None,
    args: Mapping[str, object] | None = None,
    model_paths: ModelPaths | Sequence[str | os.PathLike[str]] | None = None,
) -> RobotDescription:
    """Read a URDF, xacro or SDF robot description; any mistake is a located `DescriptionError`.

    `path` is a file, a Gazebo model folder or `model://NAME`. `package_paths` maps
    package names to folders (for `$(find ...)` and `package://`), `args` gives xacro
    args (`name:=value` on xacro's command line; values become strings as xacro takes
    them), `model_paths` lists the folders `model://` is looked up in first.
    """
    models = _model_paths(model_paths)
    models.check()
    if str(path).startswith(SCHEME):
        p = models.model_sdf(str(path))
    else:
        p = Path(path)
        if p.is_dir():
            p = model_file(p)
    models = models.beside(p)
    packages = (
        package_paths
        if isinstance(package_paths, PackagePaths)
        else PackagePaths.from_mapping(package_paths)
    )
    packages.check()
    data = read_source(p)
    sources = SourceFiles()
    doc = parse_with_lines(data, str(p), sources.add(p))
    top = to_element_tree(doc)
    kind = "sdf" if tag(top) == "sdf" else "urdf"
    if _is_xacro(p, doc):
        xargs = {
            str(k): ("true" if v is True else "false" if v is False else str(v))
            for k, v in (args or {}).items()
        }
        doc = expand_xacro(p, data, sources, packages, xargs)
        top = to_element_tree(doc)
        kind = "sdf" if tag(top) == "sdf" else "xacro"
    else:
        packages.install(p)  # package:// meshes
    if tag(top) == "robot":
        model = read_urdf(top, sources, str(p))
    elif tag(top) == "sdf":
        model = read_sdf(top, sources, str(p), models)
    else:
        raise error(
            f"<{tag(top)}> is not a robot description: expected a URDF <robot> or an SDF <sdf>",
            top,
            sources,
        )
    base = next((found for b in BASE_FRAMES if (found := model.find(b))), model.root)
    poses = model.relative_to(base)
    return RobotDescription(
        name=model.name,
        file=str(p),
        kind=kind,
        base_frame=base,
        frames=_frames(model, poses, base),
        footprint=read_footprint(model, poses, MeshSources(packages, models)),
        drive=_drive(model, poses),
        lidars=read_lidars(model, poses),
    )
