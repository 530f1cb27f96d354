"""Importing this module registers btnav's built-in control plugins (entry point `btnav.plugins`)."""

from . import goal_checkers as _goal_checkers  # noqa: F401
from . import mppi as _mppi  # noqa: F401
from . import path_handler as _path_handler  # noqa: F401
from . import progress_checkers as _progress_checkers  # noqa: F401
from . import regulated_pure_pursuit as _regulated_pure_pursuit  # noqa: F401
from .dwb import local_planner as _dwb_local_planner  # noqa: F401
