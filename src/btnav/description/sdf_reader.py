"""A Gazebo model (`model.sdf`) into a `RobotModel`, with SDF's pose frames resolved.

In SDF a link's `<pose>` is in the model frame unless `relative_to` names another
frame (a link, a `<frame>`, a joint or `__model__`); a joint's pose is in its child
link; collisions, visuals and sensors sit in their link. Each link's pose is resolved
in the model frame and turned into the parent-to-child transforms a URDF would write,
so everything after reading is the same for both formats. Nested models and
`<include>`s are not read (a warning says so).
"""

from __future__ import annotations

import warnings
import xml.etree.ElementTree as ET

from ..core.errors import BtnavWarning
from ..core.suggest import best_match
from .gazebo_sensors import sdf_pose
from .model import Block, Geometry, Joint, Link, RobotModel
from .source_lines import SourceFiles
from .transforms import IDENTITY, Transform, Vec3, compose, inverse, rotate
from .xml_values import child_number, child_text, error, floats, number, required, tag

MODEL_FRAME = "__model__"


class _Frames:
    """The named frames of one model and their poses in the model frame."""

    def __init__(self, model: ET.Element, sources: SourceFiles) -> None:
        self.sources = sources
        #: name -> (pose element, what it is relative to, the element for errors)
        self.defs: dict[str, tuple[ET.Element | None, str, ET.Element]] = {}
        for el in model:
            name = el.get("name")
            if name is None or el.tag not in ("link", "frame", "joint"):
                continue
            pose = el.find("pose")
            default = MODEL_FRAME
            if el.tag == "frame":
                default = el.get("attached_to") or MODEL_FRAME
            elif el.tag == "joint":
                default = child_text(el, "child") or MODEL_FRAME
            rel = default
            if pose is not None:
                rel = pose.get("relative_to") or pose.get("frame") or default
            self.defs[name] = (pose, rel, el)
        self.done: dict[str, Transform] = {MODEL_FRAME: IDENTITY}

    def resolve(self, name: str, asked_by: ET.Element, chain: tuple[str, ...] = ()) -> Transform:
        if name in self.done:
            return self.done[name]
        if name not in self.defs:
            raise error(
                f"relative_to '{name}' names no link, frame or joint of this model",
                asked_by,
                self.sources,
                suggestion=best_match(name, self.defs),
            )
        if name in chain:
            raise error(
                f"the poses' relative_to form a loop: {' -> '.join((*chain, name))}",
                asked_by,
                self.sources,
            )
        pose, rel, el = self.defs[name]
        base = self.resolve(rel, el, (*chain, name)) if rel != name else IDENTITY
        self.done[name] = compose(base, sdf_pose(pose, self.sources))
        return self.done[name]

    def placed(self, pose: ET.Element | None, link: str, el: ET.Element) -> Transform:
        """A collision's, visual's or sensor's pose, in its link's frame."""
        if pose is None:
            return IDENTITY
        rel = pose.get("relative_to") or pose.get("frame")
        local = sdf_pose(pose, self.sources)
        if not rel or rel == link:
            return local
        return compose(inverse(self.resolve(link, el)), compose(self.resolve(rel, el), local))


def _geometry(
    shape: ET.Element, frames: _Frames, link: str, sources: SourceFiles
) -> Geometry | None:
    geometry = shape.find("geometry")
    if geometry is None:
        raise error(f"<{tag(shape)}> needs a <geometry>", shape, sources)
    kinds = [g for g in geometry if isinstance(g.tag, str)]
    if not kinds:
        return None
    g = kinds[0]
    file, line = sources.place(g)
    pose = frames.placed(shape.find("pose"), link, shape)
    kind = tag(g)
    if kind == "box":
        size_el = g.find("size")
        size = floats(
            size_el.text if size_el is not None else None,
            3,
            "box <size>",
            size_el if size_el is not None else g,
            sources,
        )
        if min(size) <= 0.0:
            raise error("box <size> must be positive", g, sources)
        return Geometry("box", size, pose, file, line)
    if kind in ("cylinder", "capsule"):
        radius = child_number(g, "radius", sources, positive=True)
        length = child_number(g, "length", sources, positive=True)
        if radius is None or length is None:
            raise error(f"a {kind} needs <radius> and <length>", g, sources)
        if kind == "capsule":
            length += 2.0 * radius
        return Geometry("cylinder", (radius, length), pose, file, line)
    if kind == "sphere":
        radius = child_number(g, "radius", sources, positive=True)
        if radius is None:
            raise error("a sphere needs a <radius>", g, sources)
        return Geometry("sphere", (radius,), pose, file, line)
    if kind == "mesh":
        scale_el = g.find("scale")
        scale = (1.0, 1.0, 1.0)
        if scale_el is not None:
            scale = floats(scale_el.text, 3, "mesh <scale>", scale_el, sources)
        return Geometry("mesh", scale, pose, file, line, uri=child_text(g, "uri"))
    return None  # plane, heightmap, polyline, ...: not a body btnav can project


def _axis(joint: ET.Element, frame_in_model: Transform, sources: SourceFiles) -> Vec3:
    xyz = joint.find("axis/xyz")
    if xyz is None:
        return (0.0, 0.0, 1.0)
    x, y, z = floats(xyz.text, 3, "axis <xyz>", xyz, sources)
    expressed = xyz.get("expressed_in")
    in_model = expressed == MODEL_FRAME or (
        child_text(joint, "axis/use_parent_model_frame") or ""
    ).lower() in ("true", "1")
    if in_model:  # into the joint frame
        r = inverse(frame_in_model)[0]
        return rotate(r, (x, y, z))
    return (x, y, z)


def read_sdf(root: ET.Element, sources: SourceFiles, file: str) -> RobotModel:
    """The model of an SDF document holding one `<model>`."""
    if tag(root) != "sdf":
        raise error(f"an SDF file's top element is <sdf>, not <{tag(root)}>", root, sources)
    model_el = root.find("model")
    if model_el is None:
        if root.find("world") is not None:
            raise error(
                "this SDF file is a Gazebo world; give the robot's model.sdf", root, sources
            )
        raise error("the SDF file has no <model>", root, sources)
    for nested in [*model_el.findall("model"), *model_el.findall("include")]:
        f, line = sources.place(nested)
        warnings.warn(
            BtnavWarning(f"<{nested.tag}> inside a model is not read by btnav", file=f, line=line),
            stacklevel=3,
        )
    frames = _Frames(model_el, sources)
    links: dict[str, Link] = {}
    sensors: list[Block] = []
    for el in model_el.findall("link"):
        name = required(el, "name", sources)
        f, line = sources.place(el)
        if name in links:
            raise error(
                f"link '{name}' is defined twice (first at line {links[name].line})", el, sources
            )
        link = Link(name, f, line)
        for c in el.findall("collision"):
            g = _geometry(c, frames, name, sources)
            if g is not None:
                link.collisions.append(g)
        for v in el.findall("visual"):
            g = _geometry(v, frames, name, sources)
            if g is not None:
                link.visuals.append(g)
        links[name] = link
        for s in el.findall("sensor"):
            sf, sl = sources.place(s)
            sensors.append(Block(name, s, sf, sl))
    in_model = {name: frames.resolve(name, model_el) for name in links}
    joints: list[Joint] = []
    for el in model_el.findall("joint"):
        name = required(el, "name", sources)
        kind = required(el, "type", sources)
        parent, child = child_text(el, "parent"), child_text(el, "child")
        if not parent or not child:
            raise error(f"joint '{name}' needs <parent> and <child>", el, sources)
        if parent == "world":
            continue  # fixed to the world: nothing btnav's mobile base has
        f, line = sources.place(el)
        for role, link in (("parent", parent), ("child", child)):
            if link not in links:
                raise error(
                    f"joint '{name}': its {role} link '{link}' is not defined",
                    el,
                    sources,
                    suggestion=best_match(link, links),
                )
        joint_in_model = frames.resolve(name, el)
        limit = el.find("axis/limit")
        values = {}
        for key in ("lower", "upper", "velocity"):
            node = limit.find(key) if limit is not None else None
            values[key] = None if node is None else number(node.text, f"<{key}>", node, sources)
        joints.append(
            Joint(
                name,
                kind,
                parent,
                child,
                compose(inverse(in_model[parent]), in_model[child]),
                _axis(el, joint_in_model, sources),
                compose(inverse(in_model[child]), joint_in_model),
                values["lower"],
                values["upper"],
                values["velocity"],
                f,
                line,
            )
        )
    plugins = []
    for p in model_el.findall("plugin"):
        pf, pl = sources.place(p)
        plugins.append(Block(None, p, pf, pl))
    return RobotModel(
        model_el.get("name") or "robot", "sdf", file, sources, links, joints, sensors, plugins
    )
