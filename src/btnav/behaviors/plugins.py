"""Importing this module registers btnav's built-in behaviours (entry point `btnav.plugins`)."""

from . import assisted_teleop as _assisted_teleop  # noqa: F401
from . import back_up as _back_up  # noqa: F401
from . import drive_on_heading as _drive_on_heading  # noqa: F401
from . import spin as _spin  # noqa: F401
from . import wait as _wait  # noqa: F401
