"""The errors of a behaviour tree file: each names the file, the line and the node."""

from __future__ import annotations

from ..core.errors import ConfigError, UnknownNameError


class TreeError(ConfigError):
    """A tree file (Nav2 XML or btnav YAML) that cannot be built: bad structure, port or value."""


class UnknownNodeError(TreeError, UnknownNameError):
    """A node type (or SubTree ID, or port) that does not exist; lists the close names."""
