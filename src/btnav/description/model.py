"""A robot's kinematic tree as a description gives it, whatever its format (URDF or SDF).

Readers (`urdf_reader`, `sdf_reader`) fill this in; everything btnav takes from a
description (footprint, drive, lidars, frames) is computed from it. Every part keeps
the file and line it was written at, for the errors and for `btnav robot show`.
"""

from __future__ import annotations

import xml.etree.ElementTree as ET
from dataclasses import dataclass, field

from ..core.suggest import best_match
from .errors import DescriptionError
from .source_lines import SourceFiles
from .transforms import IDENTITY, Transform, Vec3, compose, inverse


@dataclass(frozen=True)
class Geometry:
    """One collision or visual shape, placed in its link's frame."""

    kind: str  # box | cylinder | sphere | mesh
    #: box (x, y, z); cylinder (radius, length); sphere (radius,); mesh its scale (x, y, z)
    size: tuple[float, ...]
    pose: Transform
    file: str | None
    line: int | None
    uri: str | None = None  # a mesh's file name as written


@dataclass
class Link:
    name: str
    file: str | None
    line: int | None
    collisions: list[Geometry] = field(default_factory=list)
    visuals: list[Geometry] = field(default_factory=list)


@dataclass(frozen=True)
class Joint:
    name: str
    kind: str  # fixed | continuous | revolute | prismatic | floating | planar | ball ...
    parent: str
    child: str
    origin: Transform  # the child link's pose in the parent link
    axis: Vec3  # in the joint frame
    frame: Transform  # the joint frame in the child link (URDF: the child link's own)
    lower: float | None
    upper: float | None
    velocity: float | None
    file: str | None
    line: int | None


@dataclass(frozen=True)
class Block:
    """A Gazebo `<sensor>` or `<plugin>` element, with the link it is attached to."""

    link: str | None
    element: ET.Element
    file: str | None
    line: int | None
    #: A sensor's pose in its link when the reader resolved it (SDF `relative_to`);
    #: None: its own `<pose>`, read as in the link.
    pose: Transform | None = None


@dataclass
class RobotModel:
    name: str
    kind: str  # urdf | sdf
    file: str
    sources: SourceFiles
    links: dict[str, Link]
    joints: list[Joint]
    sensors: list[Block] = field(default_factory=list)
    plugins: list[Block] = field(default_factory=list)

    def __post_init__(self) -> None:
        self._parent: dict[str, Joint] = {}
        self._children: dict[str, list[Joint]] = {name: [] for name in self.links}
        for joint in self.joints:
            self._check_link(joint, "parent", joint.parent)
            self._check_link(joint, "child", joint.child)
            other = self._parent.get(joint.child)
            if other is not None:
                raise DescriptionError(
                    f"link '{joint.child}' has two parents: joint '{other.name}' (line "
                    f"{other.line}) and joint '{joint.name}'; a link has one parent joint",
                    file=joint.file,
                    line=joint.line,
                )
            self._parent[joint.child] = joint
            self._children[joint.parent].append(joint)
        if not self.links:
            raise DescriptionError(
                "the description has no links (a file of macros only is included by the "
                "robot's main file: give that one)",
                file=self.file,
            )
        roots = [name for name in self.links if name not in self._parent]
        if len(roots) != 1:
            if not roots:
                raise DescriptionError(
                    "the joints form a loop: every link has a parent", file=self.file
                )
            shown = ", ".join(f"'{r}' (line {self.links[r].line})" for r in roots[:4])
            raise DescriptionError(
                f"the links form {len(roots)} separate trees (roots {shown}); join them with "
                "joints so one root link remains",
                file=self.file,
                line=self.links[roots[1]].line,
            )
        self.root = roots[0]
        self._check_loops()

    def _check_link(self, joint: Joint, role: str, name: str) -> None:
        if name in self.links:
            return
        raise DescriptionError(
            f"joint '{joint.name}': its {role} link '{name}' is not defined",
            file=joint.file,
            line=joint.line,
            suggestion=best_match(name, self.links),
        )

    def _check_loops(self) -> None:
        seen = {self.root}
        todo = [self.root]
        while todo:
            for j in self._children[todo.pop()]:
                if j.child not in seen:
                    seen.add(j.child)
                    todo.append(j.child)
        loose = [n for n in self.links if n not in seen]
        if loose:
            j = self._parent[loose[0]]
            raise DescriptionError(
                f"joint '{j.name}' closes a loop: link '{loose[0]}' cannot be reached from the "
                f"root link '{self.root}'",
                file=j.file,
                line=j.line,
            )

    def find(self, name: str) -> str | None:
        """Link `name`, else the least nested link of that name in a nested SDF model
        (`robot::base_link` when a wrapper model includes the robot), else None."""
        if name in self.links:
            return name
        nested = [n for n in self.links if n.rsplit("::", 1)[-1] == name]
        return min(nested, key=lambda n: n.count("::"), default=None)

    def parent_joint(self, link: str) -> Joint | None:
        return self._parent.get(link)

    def child_joints(self, link: str) -> list[Joint]:
        return list(self._children.get(link, ()))

    def in_root(self) -> dict[str, Transform]:
        """Every link's pose in the root link's frame, parents before children."""
        out = {self.root: IDENTITY}
        todo = [self.root]
        while todo:
            link = todo.pop(0)
            for j in self._children[link]:
                out[j.child] = compose(out[link], j.origin)
                todo.append(j.child)
        return out

    def relative_to(self, origin: str) -> dict[str, Transform]:
        """Every link's pose in the frame of link `origin` (tree order)."""
        poses = self.in_root()
        back = inverse(poses[origin])
        return {name: compose(back, pose) for name, pose in poses.items()}

    def subtree(self, link: str) -> list[str]:
        """`link` and every link below it."""
        out, todo = [], [link]
        while todo:
            name = todo.pop(0)
            out.append(name)
            todo += [j.child for j in self._children[name]]
        return out
