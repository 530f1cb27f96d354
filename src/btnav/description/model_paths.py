"""Where `model://NAME/...` points: Gazebo's model paths, without Gazebo.

A Gazebo model is a folder `NAME/` holding a `model.config` and the SDF file it names.
`model://NAME` (a description, an `<include>`) and `model://NAME/meshes/x.stl` (a mesh)
are looked up, in this order, in: the folders the user gives (`model_paths:` in a
world's robot), `GZ_SIM_RESOURCE_PATH` (gz-sim), `GAZEBO_MODEL_PATH` (Gazebo classic),
both colon-separated as Gazebo reads them, then the folder that holds the description's
own model folder (so a checkout's `models/robot/model.sdf` finds `models/common/`,
as its launch file's resource path would). The first folder that has the model (or
the file) wins, as in Gazebo.

`model.config` may name several SDF files by `<sdf version="...">`; as sdformat does,
the newest one not newer than the parser's SDF version is read (`SDF_VERSION`, Gazebo
Harmonic's), else the first one listed.
"""

from __future__ import annotations

import os
import xml.etree.ElementTree as ET
from collections.abc import Sequence
from dataclasses import dataclass
from pathlib import Path

from ..core.suggest import best_match
from .errors import DescriptionError

#: The environment variables Gazebo reads its model paths from, in the order searched.
ENV_VARS = ("GZ_SIM_RESOURCE_PATH", "GAZEBO_MODEL_PATH")
#: The SDF version a `model.config` entry may have to be read (sdformat 14, Harmonic).
SDF_VERSION = (1, 11)
SCHEME = "model://"


def _version(text: str | None) -> tuple[int, ...] | None:
    try:
        return tuple(int(p) for p in (text or "").strip().split("."))
    except ValueError:
        return None


def split_uri(uri: str) -> tuple[str, str]:
    """`model://name/meshes/x.stl` -> ("name", "meshes/x.stl")."""
    rest = uri.strip()[len(SCHEME) :].strip("/")
    name, _, tail = rest.partition("/")
    return name, tail


def is_model_folder(folder: Path) -> bool:
    return (folder / "model.config").is_file() or (folder / "model.sdf").is_file()


def model_file(folder: Path) -> Path:
    """The SDF file of a model folder: the one its model.config picks, else model.sdf."""
    config = folder / "model.config"
    if config.is_file():
        try:
            root = ET.fromstring(config.read_bytes())
        except ET.ParseError as exc:
            line = exc.position[0] if exc.position else None
            raise DescriptionError(
                f"model.config is not well-formed XML: {exc}", file=config, line=line
            ) from None
        entries = [e for e in root.iter("sdf") if (e.text or "").strip()]
        best: tuple[tuple[int, ...], ET.Element] | None = None
        for e in entries:
            v = _version(e.get("version"))
            if v is not None and v <= SDF_VERSION and (best is None or v > best[0]):
                best = (v, e)
        chosen = best[1] if best is not None else (entries[0] if entries else None)
        if chosen is not None:
            path = folder / (chosen.text or "").strip()
            if path.is_file():
                return path
            raise DescriptionError(
                f"model.config names {path.name}, which is not in {folder}", file=config
            )
    if (folder / "model.sdf").is_file():
        return folder / "model.sdf"
    raise DescriptionError(
        "a folder is read as a Gazebo model: it needs a model.config (naming its SDF file) "
        "or a model.sdf",
        file=folder,
    )


@dataclass(frozen=True)
class ModelPaths:
    """The folders `model://` is looked up in (see the module docstring)."""

    given: tuple[Path, ...] = ()
    #: The folder holding the description's own model folder (searched last).
    near: Path | None = None

    @classmethod
    def from_list(
        cls, paths: Sequence[str | os.PathLike[str]] | None, base: Path | None = None
    ) -> ModelPaths:
        """Folders, relative ones taken from `base` (a world file's folder)."""
        out = []
        for where in paths or ():
            p = Path(where).expanduser()
            out.append((base / p if base is not None and not p.is_absolute() else p).resolve())
        return cls(tuple(out))

    def beside(self, description: Path) -> ModelPaths:
        """These paths, with the folder above `description`'s own folder searched last."""
        return ModelPaths(self.given, description.resolve().parent.parent)

    def check(self) -> None:
        """Every given model path is a folder (a typo there is the user's to fix)."""
        for path in self.given:
            if not path.is_dir():
                raise DescriptionError(f"model path {path} is not a folder")

    def search(self) -> list[tuple[Path, str]]:
        """(folder, where it came from) in the order they are searched."""
        out = [(p, "model_paths") for p in self.given]
        for var in ENV_VARS:
            out += [(Path(p), var) for p in os.environ.get(var, "").split(os.pathsep) if p]
        if self.near is not None:
            out.append((self.near, "beside the description"))
        return out

    def find_model(self, uri: str) -> Path | None:
        """The folder of model `model://NAME[/sub]`, or None."""
        name, tail = split_uri(uri)
        for folder, _ in self.search():
            candidate = folder / name / tail if tail else folder / name
            if name and candidate.is_dir() and is_model_folder(candidate):
                return candidate
        return None

    def find_file(self, uri: str) -> Path | None:
        """The file `model://NAME/path/to/file` names, or None."""
        name, tail = split_uri(uri)
        for folder, _ in self.search():
            candidate = folder / name / tail
            if name and tail and candidate.is_file():
                return candidate
        return None

    def model_sdf(self, uri: str) -> Path:
        """The SDF file of model `uri` (`model://NAME`), or the located-by-caller error."""
        folder = self.find_model(uri)
        if folder is None:
            raise self.not_found(uri)
        return model_file(folder)

    def searched(self) -> str:
        """The folders searched, each with where it came from, and the unset variables."""
        shown = [f"{p} ({src})" for p, src in self.search()]
        unset = [v for v in ENV_VARS if not os.environ.get(v)]
        text = ", ".join(shown) if shown else "no folders"
        if unset:
            text += f"; {' and '.join(unset)} {'is' if len(unset) == 1 else 'are'} not set"
        return text

    def known(self) -> list[str]:
        """The model names the searched folders hold (for a did-you-mean)."""
        names = set()
        for folder, _ in self.search():
            if folder.is_dir():
                names |= {c.name for c in folder.iterdir() if c.is_dir() and is_model_folder(c)}
        return sorted(names)

    def not_found(self, uri: str, *, file: bool = False) -> DescriptionError:
        """The error for a `model://` no folder has, naming the folders searched."""
        name, tail = split_uri(uri)
        missing = f"{name}/{tail}" if file else f"model folder {name}/"
        return DescriptionError(
            f"{uri} not found: no {missing} in the model paths (searched {self.searched()}); "
            f"add the folder that holds {name}/ to the world's robot `model_paths:` or to "
            "GZ_SIM_RESOURCE_PATH",
            suggestion=best_match(name, self.known()),
        )
