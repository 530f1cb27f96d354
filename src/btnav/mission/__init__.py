"""Missions: the mission file, `btnav run`, and what a run writes (report, trajectory, tick log).

Importing the package is cheap: each name loads its module on first use, so a process
that only reads a report or a job (a Ray worker, `btnav batch`'s parent) does not
import the navigation stack.
"""

from __future__ import annotations

from typing import TYPE_CHECKING

from ..core.lazy_names import lazy_names

if TYPE_CHECKING:
    from .errors import MissionError
    from .mission import Mission
    from .navigator import Navigator
    from .outputs import RunOutput
    from .report import RunReport
    from .runner import run_mission
    from .spec import MissionSpec

#: Each public name and the module that holds it.
_LAZY = {
    "Mission": "mission",
    "MissionError": "errors",
    "MissionSpec": "spec",
    "Navigator": "navigator",
    "RunOutput": "outputs",
    "RunReport": "report",
    "run_mission": "runner",
}

__all__ = [
    "Mission",
    "MissionError",
    "MissionSpec",
    "Navigator",
    "RunOutput",
    "RunReport",
    "run_mission",
]


__getattr__ = lazy_names(__name__, _LAZY)
