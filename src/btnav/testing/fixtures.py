"""The fixtures: factories for a mission, a navigator, a tree under test and a world.

Each is a factory (call it with a path and options) so one test can make several, and
each imports btnav's stack only when called: the plugin itself stays cheap to load.
`navigators()` and `trees()` are the same factories as context managers, for use
outside a fixture (the cleanup runs when the block ends).
"""

from __future__ import annotations

from collections.abc import Callable, Iterator, Mapping
from contextlib import contextmanager
from os import PathLike
from typing import Any

import pytest


@contextmanager
def navigators() -> Iterator[Callable[..., Any]]:
    """`make(mission, **overrides) -> Navigator`; every navigator made is closed at the end."""
    made: list[Any] = []

    def make(
        mission: str | PathLike[str] | Any,
        overrides: Mapping[str, Any] | None = None,
        **keywords: Any,
    ) -> Any:
        from ..mission.mission import Mission
        from .folders import claim_folder
        from .missions import load_mission
        from .navigator import RecordedNavigator

        loaded = mission
        if not isinstance(loaded, Mission):
            loaded = load_mission(mission, overrides, **keywords)
        elif overrides or keywords:
            raise TypeError("overrides apply when a mission is loaded: pass its path")
        nav = RecordedNavigator.from_mission(loaded)
        made.append(nav)
        nav.record(claim_folder(loaded.name)[0])
        return nav

    try:
        yield make
    finally:
        for nav in made:
            nav.close()


@contextmanager
def trees() -> Iterator[Callable[..., Any]]:
    """`make(source, **options) -> TreeUnderTest`; at the end each tree's log is closed and
    py_trees' (process-wide) blackboard is put back as it was."""
    from ..bt import blackboard

    saved = blackboard.snapshot()
    made: list[Any] = []

    def make(source: str | PathLike[str], **options: Any) -> Any:
        from .folders import claim_folder
        from .tree import make_tree

        tree = make_tree(source, out_dir=claim_folder("tree")[0], **options)
        made.append(tree)
        return tree

    try:
        yield make
    finally:
        for tree in made:
            tree.close()
        blackboard.restore(saved)


@pytest.fixture
def btnav_mission() -> Callable[..., Any]:
    """`btnav_mission(path, **overrides) -> Mission`: a mission file (or a bundled mission's
    name) loaded and checked, with `--set`-style overrides: dotted params keys
    (`**{"local_costmap.local_costmap.inflation_layer.inflation_radius": 0.4}`) or mission
    keys (`seed=3`, `time_limit=20`, `task={"navigate_to_pose": [3, 2, 1.57]}`)."""
    from .missions import load_mission

    return load_mission


@pytest.fixture
def btnav_navigator() -> Iterator[Callable[..., Any]]:
    """`btnav_navigator(mission, **overrides) -> Navigator`: the mission's bring-up at t = 0
    (no task sent), recording trajectory.csv and bt_log.jsonl into the test's run folder;
    closed at teardown (report.json written if a task ended)."""
    with navigators() as make:
        yield make


@pytest.fixture
def btnav_tree() -> Iterator[Callable[..., Any]]:
    """`btnav_tree(yaml_text_or_file, servers=..., nodes=..., goal=..., navigator=...)`: a
    tree under test on fake servers (each answers SUCCESS unless `servers` says
    otherwise: `{"FollowPath": respond("FAILURE", ticks=3)}`) or on a navigator's real
    ones. py_trees' blackboard is put back as it was at teardown."""
    with trees() as make:
        yield make


@pytest.fixture
def btnav_world() -> Callable[..., Any]:
    """`btnav_world(path_or_yaml_text, seed=0) -> World`; with no argument, an empty world."""

    def make(source: Any = None, seed: int = 0) -> Any:
        from .tree import make_world

        return make_world(source, seed=seed)

    return make
