"""Missions: the mission file, `btnav run`, and what a run writes (report, trajectory, tick log)."""

from .mission import Mission
from .navigator import Navigator
from .report import RunReport
from .runner import run_mission
from .spec import MissionError, MissionSpec

__all__ = ["Mission", "MissionError", "MissionSpec", "Navigator", "RunReport", "run_mission"]
