"""SDF `<include>`s expanded in place, as sdformat does before a model is read.

An `<include>` names a model by `<uri>`: `model://NAME` (found through the model paths,
see `model_paths`), `file://` or a plain path (a model folder or an SDF file, relative
to the including file). The included file's `<model>` takes the include's place as a
nested model, its elements keeping their own file and line; the include's `<name>`,
`<pose>` (with its `relative_to`) and `<static>` replace the model's own, its
`<plugin>`s are added to the model's, and `merge="true"` (SDF 1.9) puts the model's
contents into the including model's scope instead of a nested one. An included file
holding a `<light>` or an `<actor>` (`model://sun`) is no robot part and is dropped.

btnav reads no network: an `http(s)://` include (a Gazebo Fuel model) is set aside as a
`RemoteInclude`. It is dropped without a word when nothing of the robot refers to it (a
ground plane, a sun); the SDF reader turns a reference to it (a joint to one of its
links) into one error at the include's line, saying how to get the model offline.
"""

from __future__ import annotations

import copy
import xml.etree.ElementTree as ET
from dataclasses import dataclass
from pathlib import Path
from urllib.parse import unquote, urlparse

from .errors import DescriptionError
from .model_paths import SCHEME, ModelPaths, model_file
from .source_lines import SourceFiles, parse_with_lines, read_source, to_element_tree
from .xml_values import child_text, error, tag

#: Set on a nested `<model>` that came from `<include merge="true">`.
MERGE_ATTR = "btnav_merge"

#: Included files holding only one of these are scenery, not robot parts.
NOT_ROBOT_PARTS = ("light", "actor")


@dataclass(frozen=True)
class RemoteInclude:
    """An `http(s)://` include btnav cannot fetch, and the names a reference may give it."""

    uri: str
    names: tuple[str, ...]
    parent: ET.Element  # the <model> that included it
    file: str | None
    line: int | None

    def matches(self, reference: str) -> bool:
        """Whether `reference` (a scope-local name, `NAME` or `NAME::link`) means this model."""
        head = reference.split("::", 1)[0]
        return any(_norm(head) == _norm(n) for n in self.names)

    def error(self, why: str) -> DescriptionError:
        return DescriptionError(
            f"the robot needs the model at {self.uri} ({why}), and btnav reads nothing "
            f"from the network: download it (gz fuel download --url '{self.uri}') and "
            "include the downloaded folder by model:// through the world's robot "
            "`model_paths:`",
            file=self.file,
            line=self.line,
        )


def _norm(name: str) -> str:
    return name.strip().lower().replace(" ", "_")


def _remote_names(uri: str, name: str | None) -> tuple[str, ...]:
    """The include's `<name>`, else Fuel's model name (the address's last part)."""
    parts = [unquote(p) for p in urlparse(uri).path.split("/") if p]
    if len(parts) >= 2 and parts[-2].isdigit():  # .../models/NAME/VERSION
        parts = parts[:-1]
    last = parts[-1] if parts else uri
    return (name,) if name else (last,)


def _target(uri: str, include: ET.Element, sources: SourceFiles, models: ModelPaths) -> Path:
    """The SDF file an include's `<uri>` names (a located error when there is none)."""
    where = include.find("uri")
    if uri.startswith(SCHEME):
        try:
            return models.model_sdf(uri)
        except DescriptionError as err:
            raise error(err.message, where, sources, suggestion=err.suggestion) from None
    if "://" in uri and not uri.startswith("file://"):
        raise error(
            f"cannot include '{uri}': btnav reads model://, file:// and paths", where, sources
        )
    path = Path(unquote(uri.removeprefix("file://"))).expanduser()
    if not path.is_absolute():
        file, _ = sources.place(include)
        path = (Path(file).parent if file else Path.cwd()) / path
    if path.is_dir():
        try:
            return model_file(path)
        except DescriptionError as err:
            raise error(f"cannot include '{uri}': {err.message}", where, sources) from None
    if path.is_file():
        return path
    raise error(f"cannot include '{uri}': no such file or folder {path}", where, sources)


def _replace(parent: ET.Element, old: ET.Element, new: ET.Element | None) -> None:
    index = list(parent).index(old)
    parent.remove(old)
    if new is not None:
        parent.insert(index, new)


def _override(model: ET.Element, include: ET.Element) -> None:
    """The include's name, pose and static over the model's own; its plugins added."""
    name = child_text(include, "name")
    if name:
        model.set("name", name)
    for key in ("pose", "static"):
        given = include.find(key)
        if given is None:
            continue
        for old in model.findall(key):
            model.remove(old)
        model.insert(0, copy.deepcopy(given))
    for plugin in include.findall("plugin"):
        model.append(copy.deepcopy(plugin))
    if (include.get("merge") or "").strip().lower() in ("true", "1"):
        model.set(MERGE_ATTR, "true")


def _included(
    include: ET.Element,
    sources: SourceFiles,
    models: ModelPaths,
    stack: tuple[Path, ...],
    remote: list[RemoteInclude],
    parent: ET.Element,
) -> ET.Element | None:
    """The `<model>` an include stands for, its own includes expanded (None: dropped)."""
    uri = child_text(include, "uri")
    if not uri:
        raise error("<include> needs a <uri>", include, sources)
    if uri.startswith(("http://", "https://")):
        file, line = sources.place(include)
        names = _remote_names(uri, child_text(include, "name"))
        remote.append(RemoteInclude(uri, names, parent, file, line))
        return None
    path = _target(uri, include, sources, models).resolve()
    if path in stack:
        chain = " -> ".join(p.name for p in (*stack, path))
        raise error(f"the includes form a loop: {chain}", include, sources)
    top = to_element_tree(parse_with_lines(read_source(path), str(path), sources.add(path)))
    if tag(top) != "sdf":
        raise error(f"cannot include '{uri}': {path} is not an SDF file", include, sources)
    inner = top.find("model")
    if inner is None:
        if any(top.find(k) is not None for k in NOT_ROBOT_PARTS):
            return None  # model://sun: a light, nothing of a robot
        raise error(f"cannot include '{uri}': {path} holds no <model>", include, sources)
    model = copy.deepcopy(inner)
    _override(model, include)
    placement = include.find("placement_frame")
    if placement is not None:
        # the include's <pose> places this frame of the model (SDF 1.8), not its origin;
        # kept as the model's child, where its line still points at the include
        for old in model.findall("placement_frame"):
            model.remove(old)
        model.append(copy.deepcopy(placement))
    _expand(model, sources, models, (*stack, path), remote)
    return model


def _expand(
    model: ET.Element,
    sources: SourceFiles,
    models: ModelPaths,
    stack: tuple[Path, ...],
    remote: list[RemoteInclude],
) -> None:
    for child in list(model):
        if child.tag == "include":
            _replace(model, child, _included(child, sources, models, stack, remote, model))
        elif child.tag == "model":
            _expand(child, sources, models, stack, remote)


def expand_includes(
    model: ET.Element, file: str, sources: SourceFiles, models: ModelPaths
) -> list[RemoteInclude]:
    """Replace every `<include>` under `model` (in place); the remote ones set aside."""
    remote: list[RemoteInclude] = []
    _expand(model, sources, models, (Path(file).resolve(),), remote)
    return remote
