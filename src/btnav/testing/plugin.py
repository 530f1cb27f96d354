"""The pytest hooks: `--btnav-out DIR`, each test's run folders, and the failure report's path.

A test that makes no btnav run claims no folder, and then these hooks add nothing to
its report and delete nothing: the plugin changes nothing for tests that do not use it.
"""

from __future__ import annotations

from collections.abc import Generator
from pathlib import Path
from typing import Any

import pytest

from . import folders

SECTION = "btnav"


def pytest_addoption(parser: pytest.Parser) -> None:
    group = parser.getgroup("btnav", "btnav run folders")
    group.addoption(
        "--btnav-out",
        metavar="DIR",
        default=None,
        help="keep each failed test's btnav run folder (report.json, trajectory.csv, "
        "bt_log.jsonl, run.png) under DIR/<test id>/; passing tests leave nothing",
    )


def out_root(config: pytest.Config) -> Path | None:
    value = config.getoption("btnav_out", None)
    return Path(value).expanduser().resolve() if value else None


@pytest.hookimpl(hookwrapper=True)
def pytest_runtest_protocol(item: pytest.Item, nextitem: Any) -> Generator[None, Any, None]:
    outer = folders.current()  # a pytester session inside a test has its own
    run_folders = folders.RunFolders(item.nodeid, out_root(item.config))
    folders.set_current(run_folders)
    try:
        yield
    finally:
        folders.set_current(outer)
        run_folders.finish()


@pytest.hookimpl(hookwrapper=True)
def pytest_runtest_makereport(item: pytest.Item, call: Any) -> Generator[None, Any, None]:
    outcome = yield
    report = outcome.get_result()
    run_folders = folders.current()
    if run_folders is None or not report.failed:
        return
    run_folders.failed = True
    if run_folders.claimed:
        report.sections.append((SECTION, run_folders.section()))
