"""The mission layer's user error."""

from ..core.errors import ConfigError


class MissionError(ConfigError):
    """A mission file btnav cannot run."""
