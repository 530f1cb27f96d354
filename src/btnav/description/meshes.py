"""A collision mesh's vertices: the file its URI names, read by a well-kept mesh library.

The URI is found as ROS and Gazebo find it: `package://PKG/path` through the package
paths (as `$(find PKG)`; then through the model paths, as gz-sim's resource paths do),
`model://NAME/path` through the model paths, `file:///abs/path`, or a plain path
relative to the file that names it. Nothing is fetched from the network.

trimesh reads the file (STL, OBJ, PLY, OFF, GLB/glTF; COLLADA `.dae` through
pycollada), both in the optional `btnav[meshes]` extra. A COLLADA file's `<unit
meter="...">` scales its vertices, as Gazebo's and RViz's loaders do (trimesh records
the unit but leaves the numbers as written). Anything that keeps a mesh from being read
is a `MeshError` with the reason, which the footprint turns into a warning.
"""

from __future__ import annotations

import xml.etree.ElementTree as ET
from dataclasses import dataclass, field
from pathlib import Path
from urllib.parse import unquote

import numpy as np

from ..core.errors import BtnavError
from .model import Geometry
from .model_paths import SCHEME, ModelPaths
from .packages import PackagePaths

PACKAGE = "package://"
INSTALL_HINT = "pip install 'btnav[meshes]'"


class MeshError(Exception):
    """Why a mesh could not be read (its message ends up in a warning)."""


@dataclass(frozen=True)
class MeshSources:
    """Where a description's mesh URIs point (`packages` must be `install`ed)."""

    packages: PackagePaths = field(default_factory=PackagePaths)
    models: ModelPaths = field(default_factory=ModelPaths)

    def scaled_vertices(self, g: Geometry) -> np.ndarray:
        """A mesh geometry's vertices, (N, 3) in metres with its `<scale>` applied (a
        `MeshError` if the file cannot be found or read)."""
        return read_vertices(self.path(g.uri or "", g.file)) * np.asarray(g.size, dtype=float)

    def path(self, uri: str, near: str | None) -> Path:
        """The file `uri` names, as written in the file `near` (a `MeshError` if none)."""
        text = uri.strip()
        if text.startswith(PACKAGE):
            name, _, rest = text[len(PACKAGE) :].partition("/")
            try:
                found = self.packages.find(name) / rest
            except BtnavError as err:
                found = self.models.find_file(SCHEME + text[len(PACKAGE) :])
                if found is None:
                    raise MeshError(err.message) from None
            if not found.is_file():
                raise MeshError(f"no such file {found}")
            return found
        if text.startswith(SCHEME):
            found = self.models.find_file(text)
            if found is None:
                raise MeshError(self.models.not_found(text, file=True).message)
            return found
        if text.startswith(("http://", "https://")):
            raise MeshError("btnav reads nothing from the network; give the mesh as a file")
        path = Path(unquote(text.removeprefix("file://"))).expanduser()
        if not path.is_absolute():
            path = (Path(near).parent if near else Path.cwd()) / path
        if not path.is_file():
            raise MeshError(f"no such file {path}")
        return path


def _collada_unit(path: Path) -> float:
    """A COLLADA file's `<asset><unit meter="...">`, 1.0 when it gives none."""
    try:
        root = ET.parse(path).getroot()
    except (ET.ParseError, OSError) as exc:
        raise MeshError(f"not a readable COLLADA file: {exc}") from None
    ns = root.tag[: root.tag.index("}") + 1] if root.tag.startswith("{") else ""
    unit = root.find(f"{ns}asset/{ns}unit")
    try:
        meter = float(unit.get("meter", "1")) if unit is not None else 1.0
    except ValueError:
        raise MeshError(f"malformed <unit meter='{unit.get('meter')}'>") from None
    if not np.isfinite(meter) or meter <= 0.0:
        raise MeshError(f"<unit meter='{meter:g}'> must be positive")
    return meter


def read_vertices(path: Path) -> np.ndarray:
    """The mesh's vertices, (N, 3) in metres as the file means them (before `<scale>`)."""
    try:
        import trimesh
    except ImportError:
        raise MeshError(f"trimesh is not installed ({INSTALL_HINT})") from None
    suffix = path.suffix.lower()
    try:
        mesh = trimesh.load(str(path), force="mesh", process=False)
    except ImportError as exc:  # a format's own reader: pycollada for .dae
        needs = "pycollada" if suffix == ".dae" else (exc.name or str(exc))
        raise MeshError(f"reading {suffix} files needs {needs} ({INSTALL_HINT})") from None
    except Exception as exc:  # trimesh raises many kinds on files it cannot parse
        raise MeshError(
            f"trimesh cannot read it: {' '.join(str(exc).split()) or type(exc).__name__}"
        ) from None
    vertices = np.asarray(getattr(mesh, "vertices", ()), dtype=float).reshape(-1, 3)
    if len(vertices) == 0:
        raise MeshError("it holds no vertices")
    if not np.isfinite(vertices).all():
        raise MeshError("it holds vertices that are not finite numbers")
    if suffix == ".dae":
        vertices = vertices * _collada_unit(path)
    return vertices
