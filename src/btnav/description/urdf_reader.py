"""URDF (as xacro expands it) into a `RobotModel`: links, joints, shapes and Gazebo blocks.

Only what btnav uses is read, but what is read is checked: a joint to a link that does
not exist, a malformed number in an origin or a shape, a shape without its sizes are
errors at their line. Inertials, materials and transmissions are skipped.
"""

from __future__ import annotations

import xml.etree.ElementTree as ET

from ..core.suggest import best_match
from .model import Block, Geometry, Joint, Link, RobotModel
from .source_lines import SourceFiles
from .transforms import IDENTITY, Transform, from_xyz_rpy
from .xml_values import error, floats, number, required, tag

JOINT_TYPES = ("fixed", "continuous", "revolute", "prismatic", "floating", "planar")


def _origin(parent: ET.Element, sources: SourceFiles) -> Transform:
    origin = parent.find("origin")
    if origin is None:
        return IDENTITY
    xyz = floats(origin.get("xyz", "0 0 0"), 3, "origin xyz", origin, sources)
    rpy = floats(origin.get("rpy", "0 0 0"), 3, "origin rpy", origin, sources)
    return from_xyz_rpy(xyz, rpy)


def _geometry(shape: ET.Element, sources: SourceFiles) -> Geometry:
    geometry = shape.find("geometry")
    if geometry is None:
        raise error(f"<{tag(shape)}> needs a <geometry>", shape, sources)
    kinds = [g for g in geometry if isinstance(g.tag, str)]
    if not kinds:
        raise error("<geometry> needs a shape (box, cylinder, sphere or mesh)", geometry, sources)
    g = kinds[0]  # as urdfdom: the first element is the shape, the rest is ignored
    file, line = sources.place(g)
    pose = _origin(shape, sources)
    kind = tag(g)
    if kind == "box":
        size = floats(required(g, "size", sources), 3, "box size", g, sources)
        if min(size) <= 0.0:
            raise error(f"box size must be positive, got {g.get('size')}", g, sources)
        return Geometry("box", size, pose, file, line)
    if kind == "cylinder":
        radius = number(
            required(g, "radius", sources), "cylinder radius", g, sources, positive=True
        )
        length = number(
            required(g, "length", sources), "cylinder length", g, sources, positive=True
        )
        return Geometry("cylinder", (radius, length), pose, file, line)
    if kind == "sphere":
        radius = number(required(g, "radius", sources), "sphere radius", g, sources, positive=True)
        return Geometry("sphere", (radius,), pose, file, line)
    if kind == "mesh":
        scale = floats(g.get("scale", "1 1 1"), 3, "mesh scale", g, sources)
        return Geometry("mesh", scale, pose, file, line, uri=required(g, "filename", sources))
    if kind == "capsule":  # ROS 2's URDF extension
        radius = number(required(g, "radius", sources), "capsule radius", g, sources, positive=True)
        length = number(required(g, "length", sources), "capsule length", g, sources, positive=True)
        return Geometry("cylinder", (radius, length + 2.0 * radius), pose, file, line)
    raise error(f"unknown shape <{kind}>; URDF has box, cylinder, sphere and mesh", g, sources)


def _link(element: ET.Element, sources: SourceFiles) -> Link:
    file, line = sources.place(element)
    link = Link(required(element, "name", sources), file, line)
    for child in element:
        if child.tag == "collision":
            link.collisions.append(_geometry(child, sources))
        elif child.tag == "visual":
            link.visuals.append(_geometry(child, sources))
    return link


def _link_ref(element: ET.Element, role: str, sources: SourceFiles) -> str:
    ref = element.find(role)
    if ref is None:
        raise error(
            f"joint '{element.get('name')}' needs a <{role} link=\"...\"/>", element, sources
        )
    return required(ref, "link", sources)


def _joint(element: ET.Element, sources: SourceFiles) -> Joint:
    file, line = sources.place(element)
    name = required(element, "name", sources)
    kind = required(element, "type", sources)
    if kind not in JOINT_TYPES:
        raise error(
            f"joint '{name}': unknown type '{kind}'; URDF's are {', '.join(JOINT_TYPES)}",
            element,
            sources,
        )
    axis_el = element.find("axis")
    axis = (1.0, 0.0, 0.0)
    if axis_el is not None:
        x, y, z = floats(axis_el.get("xyz", "1 0 0"), 3, "axis xyz", axis_el, sources)
        axis = (x, y, z)
    lower = upper = velocity = None
    limit = element.find("limit")
    if limit is not None:
        for attr in ("lower", "upper", "velocity"):
            if limit.get(attr) is not None:
                value = number(limit.get(attr), f"limit {attr}", limit, sources)
                if attr == "lower":
                    lower = value
                elif attr == "upper":
                    upper = value
                else:
                    velocity = value
    return Joint(
        name,
        kind,
        _link_ref(element, "parent", sources),
        _link_ref(element, "child", sources),
        _origin(element, sources),
        axis,
        IDENTITY,
        lower,
        upper,
        velocity,
        file,
        line,
    )


def read_urdf(root: ET.Element, sources: SourceFiles, file: str) -> RobotModel:
    """The model of an expanded URDF document (its `<robot>` element)."""
    if tag(root) != "robot":
        raise error(f"a URDF's top element is <robot>, not <{tag(root)}>", root, sources)
    links: dict[str, Link] = {}
    joints: list[Joint] = []
    names: dict[str, int | None] = {}
    gazebo: list[ET.Element] = []
    for child in root:
        if child.tag == "link":
            link = _link(child, sources)
            if link.name in links:
                raise error(
                    f"link '{link.name}' is defined twice (first at "
                    f"{links[link.name].file}:{links[link.name].line})",
                    child,
                    sources,
                )
            links[link.name] = link
        elif child.tag == "joint":
            joint = _joint(child, sources)
            if joint.name in names:
                raise error(
                    f"joint '{joint.name}' is defined twice (first at line {names[joint.name]})",
                    child,
                    sources,
                )
            names[joint.name] = joint.line
            joints.append(joint)
        elif child.tag == "gazebo":
            gazebo.append(child)
    model = RobotModel(root.get("name") or "robot", "urdf", file, sources, links, joints)
    for block in gazebo:
        reference = block.get("reference")
        for item in block:
            if item.tag not in ("sensor", "plugin"):
                continue
            file_, line = sources.place(item)
            if item.tag == "sensor":
                if reference is None:
                    raise error(
                        'a <sensor> sits in a <gazebo reference="LINK"> block naming its link',
                        item,
                        sources,
                    )
                if reference not in links:
                    raise error(
                        f"<gazebo reference=\"{reference}\">: no link '{reference}' to mount "
                        f"the sensor '{item.get('name')}' on",
                        block,
                        sources,
                        suggestion=best_match(reference, links),
                    )
            target = model.sensors if item.tag == "sensor" else model.plugins
            target.append(Block(reference, item, file_, line))
    return model
