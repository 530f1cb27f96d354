"""`Navigator.from_mission`: the Python API, brought up from a mission file.

The mission layer sits above the navigators, so the brief's `Navigator.from_mission`
lives here, on a subclass; `btnav.Navigator` is this class.
"""

from __future__ import annotations

from collections.abc import Mapping
from os import PathLike
from typing import Any

from ..navigators.basic_navigator import BasicNavigator
from .mission import Mission


class Navigator(BasicNavigator):
    """nav2_simple_commander's BasicNavigator in Python spelling (see `btnav.navigators`)."""

    mission: Mission | None = None

    @classmethod
    def from_mission(
        cls,
        mission: str | PathLike[str] | Mission,
        *,
        seed: int | None = None,
        overrides: Mapping[str, Any] | None = None,
    ) -> Navigator:
        """The mission's world, params, map, localisation, tree and start pose, at t = 0.

        The task is not sent: call `go_to_pose`, `follow_waypoints`, ... (or use
        `btnav.mission.run_mission` to run the mission's own task and write its outputs).
        """
        m = mission
        if not isinstance(m, Mission):
            m = Mission.load(m, seed=seed, overrides=overrides)
        nav = m.navigator(cls)
        nav.mission = m
        return nav
