"""The error family for a user's mistakes.

A `BtnavError` says where the mistake is (file, line, key path) and, for a
misspelt name, the closest valid spelling, so the CLI can print one line and exit 2.
A navigation failure is never one of these: it is a result with Nav2's error code.
A `BtnavWarning` is placed the same way, for what is probably a mistake but does not
stop a run; the CLI prints each as one `btnav: warning:` line.
"""

from __future__ import annotations

from collections.abc import Sequence
from os import PathLike

#: How every line about a problem starts, wherever it is printed (the CLI, `check_main`).
ERROR_PREFIX, WARNING_PREFIX, NOTE_PREFIX = "btnav: error: ", "btnav: warning: ", "btnav: note: "


def format_key_path(key: str | Sequence[str | int] | None) -> str | None:
    """`("controller_server", "FollowPath", 3)` -> `controller_server.FollowPath[3]`."""
    if key is None or isinstance(key, str):
        return key
    out = ""
    for part in key:
        if isinstance(part, int):
            out += f"[{part}]"
        else:
            out += f".{part}" if out else str(part)
    return out


def format_place(
    file: str | None, line: int | None, key: str | None, message: str, suggestion: str | None
) -> str:
    """`file:line: key.path: message (did you mean 'x'?)`, leaving out what is unknown."""
    where = ""
    if file:
        where = file + (f":{line}" if line else "") + ": "
    elif line:
        where = f"line {line}: "
    hint = f" (did you mean '{suggestion}'?)" if suggestion else ""
    return f"{where}{f'{key}: ' if key else ''}{message}{hint}"


class _Placed:
    """A message with its place (file, line, key path) and a suggested spelling."""

    def __init__(
        self,
        message: str,
        *,
        file: str | PathLike[str] | None = None,
        line: int | None = None,
        key: str | Sequence[str | int] | None = None,
        suggestion: str | None = None,
    ) -> None:
        self.message = message
        self.file = None if file is None else str(file)
        self.line = line
        self.key = format_key_path(key)
        self.suggestion = suggestion
        super().__init__(self.__str__())

    def __str__(self) -> str:
        return format_place(self.file, self.line, self.key, self.message, self.suggestion)


class BtnavError(_Placed, Exception):
    """A user's mistake, located in their files.

    `str(err)` reads `file:line: key.path: message (did you mean 'x'?)`.
    """

    def located(
        self,
        *,
        file: str | PathLike[str] | None = None,
        line: int | None = None,
        key: str | Sequence[str | int] | None = None,
    ) -> BtnavError:
        """Fill in the place if it is not known yet (a loader knows the file, a validator the key)."""
        if self.file is None and file is not None:
            self.file = str(file)
        if self.line is None and line is not None:
            self.line = line
        if self.key is None and key is not None:
            self.key = format_key_path(key)
        self.args = (self.__str__(),)
        return self


class YamlError(BtnavError):
    """A file that is not valid YAML, or uses a tag btnav refuses."""


class ConfigError(BtnavError):
    """A YAML document with a wrong key, type or value (params, world, mission, map)."""


class ParamsError(ConfigError):
    """A Nav2-style params file btnav cannot accept."""


class WorldError(ConfigError):
    """A world file that describes an impossible or invalid scene."""


class MapError(ConfigError):
    """A map_server map that cannot be read or written."""


class UnknownNameError(BtnavError):
    """A name (plugin, node, frame, server) that does not exist; lists the close ones."""


class PluginError(UnknownNameError):
    """A plugin that cannot be found or loaded."""


class FrameError(UnknownNameError):
    """A frame missing from the frame tree; the message lists the frames that exist."""


class BtnavWarning(_Placed, UserWarning):
    """Something in a user's files that is probably a mistake but does not stop a run
    (a moving obstacle whose route goes through a wall, a goal inside an obstacle).

    Raised with `warnings.warn(BtnavWarning(...))`, so the Python API shows it as any
    warning and tests catch it with `pytest.warns`; the CLI prints each one once as
    `btnav: warning: file:line: key: message`.
    """


class BtnavNote(BtnavWarning):
    """Not a mistake: a choice in a user's files that btnav has measured to work against
    them (AMCL's alphas far from the world's odometry noise). The CLI prints it as
    `btnav: note: file:line: key: message`; strict loading leaves it a note."""
