"""Missions: the mission file, `btnav run`, and what a run writes (report, trajectory, tick log)."""

from .errors import MissionError
from .mission import Mission
from .navigator import Navigator
from .outputs import RunOutput
from .report import RunReport
from .runner import run_mission
from .spec import MissionSpec

__all__ = [
    "Mission",
    "MissionError",
    "MissionSpec",
    "Navigator",
    "RunOutput",
    "RunReport",
    "run_mission",
]
