"""btnav: Nav2-style navigation missions in pure Python."""

from .core.errors import BtnavError

__all__ = ["BtnavError", "__version__"]
__version__ = "0.1.0"
