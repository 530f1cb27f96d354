"""Where `$(find pkg)` and `package://pkg/...` point: package paths without ROS.

A description names the ROS packages its files live in; btnav finds each package, in
this order: the paths the user gives (`package_paths: {name: dir}` in a world's robot,
`--package NAME=DIR` on the command line), `btnav_robots` (the robots/ folder btnav
ships), the package the description itself sits in (a `package.xml` with that name in
a folder above it, as in a ROS workspace checkout), then `AMENT_PREFIX_PATH`
(`<prefix>/share/<pkg>`) and `ROS_PACKAGE_PATH` when they are set. xacrodoc's package
finder does the lookups (it needs no ROS install); `install` sets it up for one load.

`--package` on `btnav run` and `btnav frames` reaches descriptions read deep inside a
mission's validation through `command_line_packages`, as ROS_PACKAGE_PATH would: the
command line wins over a world's `package_paths`.
"""

from __future__ import annotations

import os
from collections.abc import Iterator, Mapping
from contextlib import contextmanager
from contextvars import ContextVar
from dataclasses import dataclass, field
from pathlib import Path

from ..core.suggest import best_match
from .errors import DescriptionError

#: The package name btnav's own robots/ folder answers to (`$(find btnav_robots)`).
BTNAV_ROBOTS = "btnav_robots"

_PKG = Path(__file__).resolve().parents[1]


#: The packages `--package NAME=DIR` gave for the command being run.
_COMMAND_LINE: ContextVar[Mapping[str, Path]] = ContextVar("btnav_command_line_packages")


@contextmanager
def command_line_packages(paths: PackagePaths) -> Iterator[None]:
    """Every description loaded inside finds `paths`' packages first."""
    token = _COMMAND_LINE.set(dict(paths.given))
    try:
        yield
    finally:
        _COMMAND_LINE.reset(token)


def robots_dir() -> Path:
    """btnav's robots/ folder: inside an installed btnav, else the checkout's root folder."""
    installed = _PKG / "data" / "robots"
    if installed.is_dir():
        return installed
    return _PKG.parents[1] / "robots"


def _ament_shares() -> list[Path]:
    return [
        Path(p) / "share" for p in os.environ.get("AMENT_PREFIX_PATH", "").split(os.pathsep) if p
    ]


@dataclass(frozen=True)
class PackagePaths:
    """The packages a user named, by name; `find` and `install` add the default places."""

    given: Mapping[str, Path] = field(default_factory=dict)

    @classmethod
    def from_mapping(
        cls, paths: Mapping[str, str | os.PathLike[str]] | None, base: Path | None = None
    ) -> PackagePaths:
        """`{name: dir}` with relative dirs taken from `base` (a world file's folder)."""
        out: dict[str, Path] = {}
        for name, where in (paths or {}).items():
            p = Path(where).expanduser()
            out[str(name)] = (base / p if base is not None and not p.is_absolute() else p).resolve()
        return cls(out)

    def known(self) -> dict[str, Path]:
        """The packages found without searching: the given ones and btnav_robots."""
        return {BTNAV_ROBOTS: robots_dir(), **self.given, **_COMMAND_LINE.get({})}

    def check(self) -> None:
        """Every given package path is a folder (a typo there is the user's to fix)."""
        for name, path in self.given.items():
            if not path.is_dir():
                raise DescriptionError(f"package '{name}': {path} is not a folder")

    def install(self, near: Path) -> None:
        """Point xacrodoc's package finder at these paths for a load of the file `near`."""
        from xacrodoc import packages

        packages.reset()  # forget an earlier load's packages
        # look_in and walk_up_from put their finder first: the last one added is asked first
        for share in reversed(_ament_shares()):
            if share.is_dir():
                packages.look_in([str(share)])
        packages.walk_up_from(near)
        packages.update_package_cache({k: str(v) for k, v in self.known().items()})

    def not_found(self, name: str) -> DescriptionError:
        """The error for a package no place has, with the close names that do exist."""
        known = sorted(self.known())
        near = best_match(name, known)
        return DescriptionError(
            f"package '{name}' not found (known: {', '.join(known)}); give its folder with "
            f"`package_paths: {{{name}: DIR}}` in the world's robot, or `--package {name}=DIR`",
            suggestion=near,
        )

    def find(self, name: str) -> Path:
        """The folder of package `name` (xacrodoc's finder must be `install`ed)."""
        from xacrodoc import packages

        try:
            return Path(packages.get_path(name))
        except packages.PackageNotFoundError:
            raise self.not_found(name) from None
