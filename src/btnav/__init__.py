"""btnav: Nav2-style navigation missions in pure Python."""

from typing import Any

from .core.errors import BtnavError

__all__ = ["BtnavError", "Navigator", "__version__"]
__version__ = "0.1.0"


def __getattr__(name: str) -> Any:
    # `btnav.Navigator` imports the whole stack; the CLI's light commands should not.
    if name == "Navigator":
        from .mission.navigator import Navigator

        return Navigator
    raise AttributeError(f"module 'btnav' has no attribute {name!r}")
