"""A Gazebo model (`model.sdf`) into a `RobotModel`, with SDF's frames and scopes resolved.

In SDF (1.7 and later, and the same for the older files btnav meets) a link's `<pose>`
is in its model's frame unless `relative_to` names another frame of that model (a
link, a `<frame>`, a joint, a nested model or `__model__`); a joint's pose is in its
child link, a frame's in the frame it is `attached_to`; collisions, visuals and sensors
sit in their link. A nested `<model>` (written out, or an `<include>` expanded by
`sdf_include`) is a scope: its names are `NAME::link`, its pose is in the enclosing
model's frame (or `relative_to` one of its frames), and its own poses compose under
it; `NAME` alone is its model frame, and a joint to it joins its canonical link (its
`canonical_link`, else its first link). Each link's pose is resolved in the top model's
frame and turned into the parent-to-child transforms a URDF would write, so
everything after reading is the same for both formats.

A `<static>` model never moves in Gazebo: the top model being static is an error (no
robot), a static nested model that no joint joins is left out with a warning.
"""

from __future__ import annotations

import warnings
import xml.etree.ElementTree as ET

from ..core.errors import BtnavWarning
from ..core.suggest import best_match
from .model import Block, Geometry, Joint, Link, RobotModel
from .model_paths import ModelPaths
from .sdf_frames import MODEL_FRAME, Frames, Scope, is_true, read_scopes
from .sdf_include import expand_includes
from .source_lines import SourceFiles
from .transforms import Vec3, compose, inverse, rotate
from .xml_values import child_number, child_text, error, floats, number, required, tag


def _geometry(
    shape: ET.Element, frames: Frames, link: str, scope: Scope, sources: SourceFiles
) -> Geometry | None:
    geometry = shape.find("geometry")
    if geometry is None:
        raise error(f"<{tag(shape)}> needs a <geometry>", shape, sources)
    kinds = [g for g in geometry if isinstance(g.tag, str)]
    if not kinds:
        return None
    g = kinds[0]
    file, line = sources.place(g)
    pose = frames.placed(shape.find("pose"), link, shape, scope)
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
        uri_el = g.find("uri")
        uri = child_text(g, "uri")
        if not uri:
            raise error("a <mesh> needs a <uri>", g, sources)
        ufile, uline = sources.place(uri_el)
        return Geometry("mesh", scale, pose, ufile or file, uline or line, uri=uri)
    return None  # plane, heightmap, polyline, ...: not a body btnav can project


def _axis(joint: ET.Element, key: str, frames: Frames, scope: Scope, sources: SourceFiles) -> Vec3:
    xyz = joint.find("axis/xyz")
    if xyz is None:
        return (0.0, 0.0, 1.0)
    v = floats(xyz.text, 3, "axis <xyz>", xyz, sources)
    expressed = xyz.get("expressed_in")
    if is_true(joint.find("axis/use_parent_model_frame")):
        expressed = MODEL_FRAME
    if not expressed or scope.key(expressed) == key:
        return (v[0], v[1], v[2])
    in_model = rotate(frames.resolve(scope.key(expressed), xyz)[0], v)
    return rotate(inverse(frames.resolve(key, joint))[0], in_model)  # into the joint frame


def _canonical(scope: Scope, scopes: list[Scope], sources: SourceFiles) -> str | None:
    """A nested model's canonical link: `canonical_link`, else its first link (or a nested one's)."""
    given = scope.element.get("canonical_link")
    if given:
        return scope.key(given)
    for el in scope.element:
        if el.tag == "link":
            return scope.key(required(el, "name", sources))
        if el.tag == "model":
            inner = next(s for s in scopes if s.element is el)
            found = _canonical(inner, scopes, sources)
            if found is not None:
                return found
    return None


def read_sdf(
    root: ET.Element,
    sources: SourceFiles,
    file: str,
    models: ModelPaths | None = None,
) -> RobotModel:
    """The model of an SDF document holding one `<model>`, its includes expanded."""
    if tag(root) != "sdf":
        raise error(f"an SDF file's top element is <sdf>, not <{tag(root)}>", root, sources)
    model_el = root.find("model")
    if model_el is None:
        if root.find("world") is not None:
            raise error(
                "this SDF file is a Gazebo world; give the robot's model.sdf", root, sources
            )
        raise error("the SDF file has no <model>", root, sources)
    remote = expand_includes(model_el, file, sources, models or ModelPaths())
    scopes = read_scopes(model_el, sources)
    top = scopes[0]
    if top.static:
        raise error(
            f"model '{top.name}' is <static>: Gazebo holds it in place, so it is no robot to "
            "drive (a robot's model is not static)",
            model_el.find("static"),
            sources,
        )
    frames = Frames(scopes, sources, remote)
    links: dict[str, Link] = {}
    scope_of: dict[str, Scope] = {}
    sensors: list[Block] = []
    for s in scopes:
        for el in s.element.findall("link"):
            name = s.key(required(el, "name", sources))
            f, line = sources.place(el)
            if name in links:
                raise error(
                    f"link '{name}' is defined twice (first at line {links[name].line})",
                    el,
                    sources,
                )
            link = Link(name, f, line)
            for c in el.findall("collision"):
                g = _geometry(c, frames, name, s, sources)
                if g is not None:
                    link.collisions.append(g)
            for v in el.findall("visual"):
                g = _geometry(v, frames, name, s, sources)
                if g is not None:
                    link.visuals.append(g)
            links[name] = link
            scope_of[name] = s
            for sensor in el.findall("sensor"):
                sf, sl = sources.place(sensor)
                mount = frames.placed(sensor.find("pose"), name, sensor, s)
                sensors.append(Block(name, sensor, sf, sl, mount))
    if not links and remote:
        raise remote[0].error("the model has no links of its own")
    canonical = {s.frame: _canonical(s, scopes, sources) for s in scopes}

    def link_of(key: str, el: ET.Element, role: str, joint: str) -> str:
        key = frames.alias.get(key, key)
        seen = set()
        while key in frames.attached and key not in seen:  # a <frame>: the link it hangs on
            seen.add(key)
            key = frames.alias.get(frames.attached[key], frames.attached[key])
        if key in canonical and canonical[key] is not None:
            key = canonical[key]  # type: ignore[assignment]
        if key in links:
            return key
        file_, line_ = sources.place(el)
        err = frames.remote_error(key, f"joint '{joint}' at {file_}:{line_} attaches '{key}'")
        if err is not None:
            raise err
        raise error(
            f"joint '{joint}': its {role} link '{key}' is not defined",
            el,
            sources,
            suggestion=best_match(key, links),
        )

    in_model = {name: frames.resolve(name, model_el) for name in links}
    joints: list[Joint] = []
    for s in scopes:
        for el in s.element.findall("joint"):
            name = s.key(required(el, "name", sources))
            kind = required(el, "type", sources)
            parent, child = child_text(el, "parent"), child_text(el, "child")
            if not parent or not child:
                raise error(f"joint '{name}' needs <parent> and <child>", el, sources)
            if parent == "world":
                continue  # fixed to the world: nothing btnav's mobile base has
            f, line = sources.place(el)
            parent = link_of(s.key(parent), el, "parent", name)
            child = link_of(s.key(child), el, "child", name)
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
                    _axis(el, name, frames, s, sources),
                    compose(inverse(in_model[child]), joint_in_model),
                    values["lower"],
                    values["upper"],
                    values["velocity"],
                    f,
                    line,
                )
            )
    dropped = _drop_static(scopes, links, scope_of, joints, sources)
    sensors = [b for b in sensors if b.link not in dropped]
    plugins = []
    for s in scopes:
        if any(scope_of.get(n) is s for n in dropped):
            continue
        for p in s.element.findall("plugin"):
            pf, pl = sources.place(p)
            plugins.append(Block(None, p, pf, pl))
    return RobotModel(top.name, "sdf", file, sources, links, joints, sensors, plugins)


def _drop_static(
    scopes: list[Scope],
    links: dict[str, Link],
    scope_of: dict[str, Scope],
    joints: list[Joint],
    sources: SourceFiles,
) -> set[str]:
    """Leave out (from `links`) each static nested model no joint joins to the robot."""
    dropped: set[str] = set()
    for s in scopes:
        if not s.static or (s.parent is not None and s.parent.static):
            continue  # not where a static part begins

        def inside(link: str, s: Scope = s) -> bool:
            scope: Scope | None = scope_of[link]
            while scope is not None and scope is not s:
                scope = scope.parent
            return scope is s

        members = {n for n in links if inside(n)}
        if not members or any((j.parent in members) != (j.child in members) for j in joints):
            continue
        flag = s.element.find("static")
        file, line = sources.place(flag if flag is not None else s.element)
        warnings.warn(
            BtnavWarning(
                f"nested model '{s.name}' is <static> and no joint joins it to the robot: "
                "Gazebo holds it in place in the world, so btnav leaves it out",
                file=file,
                line=line,
            ),
            stacklevel=3,
        )
        for n in members:
            del links[n]
        joints[:] = [j for j in joints if j.parent not in members]
        dropped |= members
    return dropped
