"""Importing this module registers btnav's built-in tree nodes (entry point `btnav.plugins`)."""

from . import controls as _controls  # noqa: F401
from . import decorators as _decorators  # noqa: F401
from . import leaves as _leaves  # noqa: F401
from . import nav2_controls as _nav2_controls  # noqa: F401
from . import nav2_decorators as _nav2_decorators  # noqa: F401
