"""SDF's frames and scopes: every named frame of a model and its nested models, posed.

A nested `<model>` is a scope: its names are `NAME::link` (a `merge="true"` include's
stay in the enclosing scope), its model frame is `NAME` in the enclosing one. Poses are
relative to the element's model frame unless `relative_to` names another frame of the
same scope (or a nested one's, `NAME::link`); a joint's default is its child, a
`<frame>`'s the frame it is `attached_to`. A nested model with a placement frame (an
include's `<placement_frame>`, SDF 1.8) has its `<pose>` place that frame, not its own.
`Frames` resolves each to the top model's
frame, with loops and unknown names as located errors; a name that points into a
remote (Fuel) include is that include's error (see `sdf_include`).
"""

from __future__ import annotations

import xml.etree.ElementTree as ET
from collections.abc import Sequence
from dataclasses import dataclass

from ..core.suggest import best_match
from .errors import DescriptionError
from .gazebo_sensors import sdf_pose
from .sdf_include import MERGE_ATTR, RemoteInclude
from .source_lines import SourceFiles
from .transforms import IDENTITY, Transform, compose, inverse
from .xml_values import child_text, error, required

MODEL_FRAME = "__model__"
#: SDF 1.8's own spelling on a <model>: the frame its <pose> places.
PLACED = "placement_frame"
SCOPE = "::"


def is_true(element: ET.Element | None) -> bool:
    return element is not None and (element.text or "").strip().lower() in ("true", "1")


@dataclass
class Scope:
    """One `<model>`: the prefix of its names and the key of its model frame."""

    element: ET.Element
    name: str
    prefix: str  # "" for the top model, "NAME::" for a nested one (a merged one: its parent's)
    frame: str  # the key of its model frame
    parent: Scope | None
    static: bool  # its own <static>, or its enclosing model's

    def key(self, name: str) -> str:
        """The flat key of a name as this model's elements write it."""
        return self.frame if name == MODEL_FRAME else self.prefix + name


def read_scopes(top: ET.Element, sources: SourceFiles) -> list[Scope]:
    """The top model and every nested one, enclosing models first."""
    out = [
        Scope(top, top.get("name") or "robot", "", MODEL_FRAME, None, is_true(top.find("static")))
    ]

    def walk(scope: Scope) -> None:
        for el in scope.element.findall("model"):
            name = required(el, "name", sources)
            if el.get(MERGE_ATTR) == "true":
                prefix, frame = scope.prefix, f"{scope.prefix}_merged__{name}__model__"
            else:
                prefix = f"{scope.prefix}{name}{SCOPE}"
                frame = prefix + MODEL_FRAME
            child = Scope(
                el, name, prefix, frame, scope, scope.static or is_true(el.find("static"))
            )
            out.append(child)
            walk(child)

    walk(out[0])
    return out


class Frames:
    """Every named frame of the model and its nested models, posed in the top model frame."""

    def __init__(
        self, scopes: list[Scope], sources: SourceFiles, remote: Sequence[RemoteInclude]
    ) -> None:
        self.sources = sources
        self.remote = remote
        self.prefix_of = {id(s.element): s.prefix for s in scopes}
        #: key -> (pose element, the key it is relative to, the element for errors)
        self.defs: dict[str, tuple[ET.Element | None, str, ET.Element]] = {}
        #: a nested model's name in its parent -> the key of its model frame
        self.alias: dict[str, str] = {}
        #: a nested model's frame key -> (the key of the frame its <pose> places, the
        #: element naming it): SDF 1.8's placement_frame
        self.placement: dict[str, tuple[str, ET.Element]] = {}
        self.attached: dict[str, str] = {}  # a <frame>'s key -> what it is attached to
        for s in scopes:
            if s.parent is not None:
                self._define(s.frame, s.element.find("pose"), s.parent, s.parent.frame, s.element)
                if s.element.get(MERGE_ATTR) != "true":
                    self.alias[s.parent.prefix + s.name] = s.frame
                placed = s.element.find("placement_frame")
                name = (placed.text or "") if placed is not None else s.element.get(PLACED)
                if name and name.strip():
                    named_by = placed if placed is not None else s.element
                    self.placement[s.frame] = (s.key(name.strip()), named_by)
            for el in s.element:
                name = el.get("name")
                if name is None or el.tag not in ("link", "frame", "joint"):
                    continue
                default = s.frame
                if el.tag == "frame":
                    default = s.key(el.get("attached_to") or MODEL_FRAME)
                    self.attached[s.key(name)] = default
                elif el.tag == "joint":
                    default = s.key(child_text(el, "child") or MODEL_FRAME)
                self._define(s.key(name), el.find("pose"), s, default, el)
        self.done: dict[str, Transform] = {MODEL_FRAME: IDENTITY}

    def _define(
        self, key: str, pose: ET.Element | None, scope: Scope, default: str, el: ET.Element
    ) -> None:
        rel = default
        if pose is not None:
            given = pose.get("relative_to") or pose.get("frame")
            if given:
                rel = scope.key(given)
        self.defs[key] = (pose, rel, el)

    def remote_error(self, key: str, why: str) -> DescriptionError | None:
        """The error for a reference into a model btnav could not fetch, if it is one."""
        for r in self.remote:
            prefix = self.prefix_of.get(id(r.parent), "")
            if key.startswith(prefix) and r.matches(key[len(prefix) :]):
                return r.error(why)
        return None

    def missing(self, key: str, asked_by: ET.Element, what: str) -> DescriptionError:
        file, line = self.sources.place(asked_by)
        err = self.remote_error(key, f"{file}:{line} refers to '{key}'")
        if err is not None:
            return err
        known = [*self.defs, *self.alias]
        return error(
            f"{what} '{key}' names no link, frame or joint of this model",
            asked_by,
            self.sources,
            suggestion=best_match(key, known),
        )

    def resolve(self, key: str, asked_by: ET.Element, chain: tuple[str, ...] = ()) -> Transform:
        key = self.alias.get(key, key)
        if key in self.done:
            return self.done[key]
        if key not in self.defs:
            raise self.missing(key, asked_by, "relative_to")
        if key in chain:
            raise error(
                f"the poses' relative_to form a loop: {' -> '.join((*chain, key))}",
                asked_by,
                self.sources,
            )
        pose, rel, el = self.defs[key]
        asker = pose if pose is not None and pose.get("relative_to") else el
        base = self.resolve(rel, asker, (*chain, key)) if rel != key else IDENTITY
        placed = compose(base, sdf_pose(pose, self.sources))
        if key in self.placement:  # the pose is the placement frame's: back to the model's
            frame, named_by = self.placement[key]
            placed = compose(placed, inverse(self._in_model(frame, key, named_by)))
        self.done[key] = placed
        return placed

    def _in_model(self, key: str, model: str, asked_by: ET.Element) -> Transform:
        """Frame `key`'s pose in the model frame `model` it belongs to (a placement frame:
        its chain of relative_to stays inside that model)."""
        pose_of, seen = IDENTITY, [key]
        while key != model:
            key = self.alias.get(key, key)
            if key not in self.defs:
                raise self.missing(key, asked_by, "placement_frame")
            pose, rel, _ = self.defs[key]
            pose_of = compose(sdf_pose(pose, self.sources), pose_of)
            if rel in seen:
                break  # a loop: resolve() reports it where it starts
            key = rel
            seen.append(key)
        return pose_of

    def placed(self, pose: ET.Element | None, link: str, el: ET.Element, scope: Scope) -> Transform:
        """A collision's, visual's or sensor's pose, in its link's frame."""
        if pose is None:
            return IDENTITY
        rel = pose.get("relative_to") or pose.get("frame")
        local = sdf_pose(pose, self.sources)
        if not rel or scope.key(rel) == link:
            return local
        return compose(
            inverse(self.resolve(link, el)), compose(self.resolve(scope.key(rel), el), local)
        )
